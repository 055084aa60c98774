//! What several GI methods use: spherical harmonics, reflective shadow maps.

pub mod bindings;
pub mod rsm;
pub mod sh;

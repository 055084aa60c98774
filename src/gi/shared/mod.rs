//! What several GI methods use: spherical harmonics, reflective shadow maps, the path-traced
//! image scale-free methods fit themselves to.

pub mod bindings;
pub mod oracle;
pub mod rsm;
pub mod sh;
pub mod triangle_ids;

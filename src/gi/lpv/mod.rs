//! Light propagation volumes: the classic 6-neighbour LPV (Kaplanyan & Dachsbacher 2010) and
//! seed 000's incremental 26-neighbour ILPV, sharing RSM injection, the fitted lattice, the
//! geometry lattice and the lookup.

pub mod cost;
pub mod cpu;
pub mod geometry;
pub mod lattice;
pub mod sh;
pub mod technique;
pub mod transfer;

pub use technique::{Extinction, Lpv, LpvSettings, Scheme};

//! Light propagation volumes: the classic 6-neighbour LPV (Kaplanyan & Dachsbacher 2010) and
//! seed 000's incremental 26-neighbour ILPV, sharing RSM injection, the fitted lattice, the
//! geometry lattice and the lookup.

pub mod autotune;
pub mod bindings;
pub mod cost;
pub mod cpu;
pub mod entry;
pub mod free_path;
pub mod geometry;
pub mod lattice;
pub mod lookup;
pub mod projected;
pub mod technique;
pub mod transfer;
pub mod two_scale;
pub mod upsample;
pub mod visibility;
pub mod void_side;

pub use entry::METHODS;
pub use lookup::{LookupFilter, LookupResolution};
pub use technique::{Extinction, InjectToward, Injection, Kernel, Lpv, LpvSettings, Scheme};

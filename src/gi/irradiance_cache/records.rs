//! The cache's GPU layouts (shaders-glsl/gi/irradiance_cache/ic.glsl) and their decoding into
//! the f64 records of the CPU reference.

use bytemuck::{Pod, Zeroable};
use glam::DVec3;

use super::cpu::Record;

/// One record as the GPU stores it (std430, 144 bytes).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct GpuRecord {
    /// xyz: position; w: harmonic mean distance R (0 until reduced).
    pub position_harmonic: [f32; 4],
    /// xyz: normal; w: world size of a view pixel at the record when it was placed.
    pub normal_footprint: [f32; 4],
    pub irradiance: [f32; 4],
    pub rotation: [[f32; 4]; 3],
    pub translation: [[f32; 4]; 3],
}

/// The cache's counters (GLSL `CacheState`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct CacheState {
    pub count: u32,
    pub first: u32,
    pub end: u32,
    /// Tiles with an uncovered pixel in the last round.
    pub holes: u32,
    /// Candidates refused because the cache was full, since it was emptied.
    pub overflowed: u32,
    /// Records added since the cache was emptied.
    pub placed: u32,
    /// Records the last placement round added.
    pub added: u32,
    /// The generation of the records held: passes of another generation see an empty cache.
    pub generation: u32,
    /// Records `[0, refreshed)` hold this many bounces of light, the others one fewer.
    pub bounce: u32,
    /// Records recomputed for `bounce` so far.
    pub refreshed: u32,
    /// Records in the snapshot of the previous bounce.
    pub previous_count: u32,
    /// 1: this round copies the cache into the snapshot.
    pub snapshot: u32,
    /// 1: the cache holds every bounce asked for (until it is emptied).
    pub done: u32,
    /// Relative change of Σ E over the records from the previous bounce (`--bounces inf`).
    pub change: f32,
}

fn vec3(v: [f32; 4]) -> DVec3 {
    DVec3::new(v[0].into(), v[1].into(), v[2].into())
}

impl GpuRecord {
    /// The record in f64.
    pub fn to_record(&self) -> Record {
        Record {
            position: vec3(self.position_harmonic),
            normal: vec3(self.normal_footprint),
            irradiance: [0, 1, 2].map(|c| self.irradiance[c].into()),
            rotation: self.rotation.map(vec3),
            translation: self.translation.map(vec3),
            harmonic: self.position_harmonic[3].into(),
        }
    }

    /// World size of a view pixel at the record when it was placed.
    pub fn footprint(&self) -> f64 {
        self.normal_footprint[3].into()
    }
}

//! The lattice fitted to the scene: cubic cells, `cells_along_longest` cells on the longest axis
//! of the scene's bounds, and only as many on the other axes as the bounds need (a flat scene
//! gets a flat lattice). Cell (x, y, z) is stored at `(z * ny + y) * nx + x`.

use glam::{DVec3, IVec3, UVec3, Vec3};

use crate::error::InputError;

/// Largest lattice edge vkgi accepts (cells along the longest axis).
pub const MAX_CELLS: u32 = 512;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lattice {
    /// World position of the corner of cell (0, 0, 0).
    pub origin: Vec3,
    /// Edge of a (cubic) cell, world units.
    pub cell_size: f32,
    pub dims: UVec3,
}

impl Lattice {
    /// A lattice over `[min, max]` with `cells` cells along the longest extent, centred on the
    /// bounds.
    pub fn fit(min: Vec3, max: Vec3, cells: u32) -> Result<Lattice, InputError> {
        if cells == 0 || cells > MAX_CELLS {
            return Err(InputError::new(format!(
                "--lattice {cells} is out of range 1..={MAX_CELLS}"
            )));
        }
        let extent = (max - min).max(Vec3::ZERO);
        let longest = extent.max_element();
        if !(longest.is_finite() && longest > 0.0) {
            return Err(InputError::new(
                "the scene has no extent to fit a lattice to",
            ));
        }
        let cell_size = longest / cells as f32;
        // A small tolerance keeps an axis of exactly k cells from rounding up to k + 1.
        let dims = (extent / cell_size * (1.0 - 1e-6))
            .ceil()
            .max(Vec3::ONE)
            .as_uvec3();
        let size = dims.as_vec3() * cell_size;
        let origin = 0.5 * (min + max) - 0.5 * size;
        Ok(Lattice {
            origin,
            cell_size,
            dims,
        })
    }

    pub fn cell_count(&self) -> usize {
        (self.dims.x * self.dims.y * self.dims.z) as usize
    }

    pub fn index(&self, cell: UVec3) -> usize {
        ((cell.z * self.dims.y + cell.y) * self.dims.x + cell.x) as usize
    }

    /// The cell containing world point `p`, if inside the lattice.
    pub fn cell_of(&self, p: Vec3) -> Option<UVec3> {
        let c = ((p - self.origin) / self.cell_size).floor();
        let inside = c.cmpge(Vec3::ZERO).all() && c.cmplt(self.dims.as_vec3()).all();
        inside.then(|| c.as_uvec3())
    }

    /// The cell at integer coordinates, if inside.
    pub fn checked(&self, c: IVec3) -> Option<UVec3> {
        let inside = c.cmpge(IVec3::ZERO).all() && c.cmplt(self.dims.as_ivec3()).all();
        inside.then(|| c.as_uvec3())
    }

    pub fn cell_centre(&self, cell: UVec3) -> DVec3 {
        (self.origin.as_dvec3()) + (cell.as_dvec3() + 0.5) * f64::from(self.cell_size)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cubic_cells_and_only_the_cells_the_bounds_need() {
        let l = Lattice::fit(Vec3::ZERO, Vec3::new(8.0, 2.0, 4.0), 16).unwrap();
        assert_eq!(l.cell_size, 0.5);
        assert_eq!(l.dims, UVec3::new(16, 4, 8));
        let flat = Lattice::fit(Vec3::ZERO, Vec3::new(4.0, 0.0, 4.0), 8).unwrap();
        assert_eq!(flat.dims, UVec3::new(8, 1, 8));
        let odd = Lattice::fit(Vec3::ZERO, Vec3::new(1.0, 0.3, 1.0), 4).unwrap();
        assert_eq!(odd.dims.y, 2);
        // The lattice is centred on the bounds.
        assert!((odd.origin.y - (0.15 - 0.25)).abs() < 1e-6);
    }

    #[test]
    fn cells_and_indices_round_trip() {
        let l = Lattice::fit(Vec3::ZERO, Vec3::new(2.0, 1.0, 1.0), 4).unwrap();
        let c = l.cell_of(Vec3::new(1.9, 0.1, 0.6)).unwrap();
        assert_eq!(c, UVec3::new(3, 0, 1));
        assert_eq!(l.index(c), 2 * 4 + 3);
        assert!(l.cell_of(Vec3::new(2.1, 0.1, 0.1)).is_none());
    }

    #[test]
    fn absurd_lattices_are_input_errors() {
        assert!(Lattice::fit(Vec3::ZERO, Vec3::ONE, 0).is_err());
        assert!(Lattice::fit(Vec3::ZERO, Vec3::ONE, 100_000).is_err());
        assert!(Lattice::fit(Vec3::ZERO, Vec3::ZERO, 8).is_err());
    }
}

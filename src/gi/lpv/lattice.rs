//! The lattice fitted to the scene: cubic cells, `cells_along_longest` cells on the longest axis
//! of the scene's bounds, and only as many on the other axes as the bounds need (a flat scene
//! gets a flat lattice). On the CPU, cell (x, y, z) is at `(z * ny + y) * nx + x`
//! ([`Lattice::index`]); a GPU buffer holds the cells in the lattice's [`CellOrder`].

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

    /// Every cell.
    pub fn all_cells(&self) -> CellBox {
        CellBox {
            min: UVec3::ZERO,
            max: self.dims,
        }
    }

    /// The cells the world box `min`..`max` touches, widened by `margin` cells on every side and
    /// clipped to the lattice; None when nothing of it is inside.
    pub fn cells_touching(&self, min: Vec3, max: Vec3, margin: u32) -> Option<CellBox> {
        let cell = |p: Vec3| ((p - self.origin).as_dvec3() / f64::from(self.cell_size)).floor();
        let clip = |c: DVec3| {
            c.clamp(DVec3::ZERO, self.dims.as_dvec3())
                .as_uvec3()
        };
        let margin = f64::from(margin);
        let cells = CellBox {
            min: clip(cell(min) - margin),
            max: clip(cell(max) + margin + 1.0),
        };
        cells.min.cmplt(cells.max).all().then_some(cells)
    }

    /// The world box the cells of `cells` fill.
    pub fn world_box(&self, cells: &CellBox) -> (Vec3, Vec3) {
        let corner = |c: UVec3| self.origin + c.as_vec3() * self.cell_size;
        (corner(cells.min), corner(cells.max))
    }
}

/// How a GPU buffer of a lattice holds its cells (`gi/lpv/lattice.glsl`'s `lattice_index`,
/// chosen per lattice with [`CellOrder::for_step`]). The CPU side holds rows whatever the
/// buffers hold; the cells are reordered where they cross (uploads and read-backs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum CellOrder {
    /// x fastest, `(z * ny + y) * nx + x`: a row along x is contiguous, so a GPU's neighbouring
    /// lanes, which hold neighbouring x, read neighbouring words.
    Rows,
    /// z fastest, `(y * nx + x) * nz + z`: a column along z is contiguous, so a column kernel's
    /// thread on a CPU walks through consecutive lines, which the cores' prefetchers follow
    /// (rows put a column's cells a plane, 16 KiB at 32³, apart).
    Columns,
}

impl CellOrder {
    /// Columns where a CPU device's step walks whole columns (each thread of a column kernel
    /// its whole column) and nothing copies the lattices into 3-D images (the sampler's lookup
    /// reads images copied from the buffers row by row); rows elsewhere. On lavapipe columns
    /// took a fifth off the whole-column steps and made the split ones (the 2x2 bundles at
    /// 32³, whose threads walk half a column) up to a fifth slower (docs/performance.md).
    pub fn for_step(is_cpu: bool, whole_columns: bool, copied_to_images: bool) -> CellOrder {
        match is_cpu && whole_columns && !copied_to_images {
            true => CellOrder::Columns,
            false => CellOrder::Rows,
        }
    }

    /// 1 for columns, 0 for rows: `lattice.glsl`'s specialisation constant `CELLS_IN_COLUMNS`,
    /// and the order the lookup's field constants carry.
    pub fn columns_flag(self) -> u32 {
        u32::from(self == CellOrder::Columns)
    }

    /// A line for the profile.
    pub fn describe(self) -> &'static str {
        match self {
            CellOrder::Rows => "rows (x fastest)",
            CellOrder::Columns => "columns (z fastest: a column kernel's thread reads consecutive lines)",
        }
    }

    /// Where cell `c` of a lattice of `dims` cells lies in a buffer of this order.
    pub fn index(self, dims: UVec3, c: UVec3) -> usize {
        let i = match self {
            CellOrder::Rows => (c.z * dims.y + c.y) * dims.x + c.x,
            CellOrder::Columns => (c.y * dims.x + c.x) * dims.z + c.z,
        };
        i as usize
    }

    /// `cells` (`per_cell` values a cell, in row order) in this order.
    pub fn from_rows<T: Copy>(self, dims: UVec3, cells: &[T], per_cell: usize) -> Vec<T> {
        self.reorder(dims, cells, per_cell, |rows, order| (order, rows))
    }

    /// `cells` (`per_cell` values a cell, in this order) in row order.
    pub fn to_rows<T: Copy>(self, dims: UVec3, cells: &[T], per_cell: usize) -> Vec<T> {
        self.reorder(dims, cells, per_cell, |rows, order| (rows, order))
    }

    /// `cells` moved cell by cell: `to_from(row index, this order's index)` gives the
    /// (destination, source) cell.
    fn reorder<T: Copy>(
        self,
        dims: UVec3,
        cells: &[T],
        per_cell: usize,
        to_from: impl Fn(usize, usize) -> (usize, usize),
    ) -> Vec<T> {
        if self == CellOrder::Rows {
            return cells.to_vec();
        }
        let mut out = cells.to_vec();
        let all = CellBox {
            min: UVec3::ZERO,
            max: dims,
        };
        for (row, c) in all.cells().enumerate() {
            let (to, from) = to_from(row, self.index(dims, c));
            out[to * per_cell..][..per_cell].copy_from_slice(&cells[from * per_cell..][..per_cell]);
        }
        out
    }

    /// The cells of `region` of a lattice of `dims` as runs that lie consecutively in a buffer
    /// of this order: each run's first cell and its cells' places among the region's
    /// ([`CellBox::local_index`]), in buffer order. Runs that follow on from each other are
    /// one.
    pub fn runs(self, dims: UVec3, region: &CellBox) -> Vec<(UVec3, Vec<usize>)> {
        let mut runs: Vec<(UVec3, Vec<usize>)> = Vec::new();
        let mut next = usize::MAX;
        let cells = match self {
            CellOrder::Rows => region.cells().collect::<Vec<_>>(),
            CellOrder::Columns => region.cells_columns_first().collect(),
        };
        for c in cells {
            let at = self.index(dims, c);
            let local = region.local_index(c).expect("a cell of the region");
            match runs.last_mut() {
                Some((_, run)) if at == next => run.push(local),
                _ => runs.push((c, vec![local])),
            }
            next = at + 1;
        }
        runs
    }
}

/// A box of cells, `min` to `max` exclusive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CellBox {
    pub min: UVec3,
    pub max: UVec3,
}

impl CellBox {
    pub fn count(&self) -> usize {
        let d = self.max - self.min;
        (d.x * d.y * d.z) as usize
    }

    /// Where cell `c` is among the box's cells (x fastest, then y, then z), if inside.
    pub fn local_index(&self, c: UVec3) -> Option<usize> {
        let inside = c.cmpge(self.min).all() && c.cmplt(self.max).all();
        let d = self.max - self.min;
        inside.then(|| {
            let l = c - self.min;
            ((l.z * d.y + l.y) * d.x + l.x) as usize
        })
    }

    /// The box's cells, in the order of [`CellBox::local_index`].
    pub fn cells(&self) -> impl Iterator<Item = UVec3> + '_ {
        (self.min.z..self.max.z).flat_map(move |z| {
            (self.min.y..self.max.y)
                .flat_map(move |y| (self.min.x..self.max.x).map(move |x| UVec3::new(x, y, z)))
        })
    }

    /// The box's cells, z fastest, then x, then y ([`CellOrder::Columns`]' order).
    fn cells_columns_first(&self) -> impl Iterator<Item = UVec3> + '_ {
        (self.min.y..self.max.y).flat_map(move |y| {
            (self.min.x..self.max.x)
                .flat_map(move |x| (self.min.z..self.max.z).map(move |z| UVec3::new(x, y, z)))
        })
    }

    /// Whether the two boxes share a cell or a face (their union wastes little).
    pub fn touches(&self, other: &CellBox) -> bool {
        self.min.cmple(other.max).all() && other.min.cmple(self.max).all()
    }

    pub fn union(&self, other: &CellBox) -> CellBox {
        CellBox {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// `boxes` with every two that touch merged into their union, until none touch.
    pub fn merged(mut boxes: Vec<CellBox>) -> Vec<CellBox> {
        let mut i = 0;
        while i < boxes.len() {
            match (i + 1..boxes.len()).find(|&j| boxes[i].touches(&boxes[j])) {
                Some(j) => {
                    let other = boxes.swap_remove(j);
                    boxes[i] = boxes[i].union(&other);
                    i = 0;
                }
                None => i += 1,
            }
        }
        boxes
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
    fn world_boxes_become_clipped_cell_boxes_that_merge_where_they_touch() {
        let l = Lattice::fit(Vec3::ZERO, Vec3::new(4.0, 2.0, 2.0), 8).unwrap();
        let b = l
            .cells_touching(Vec3::new(1.2, 0.1, 0.6), Vec3::new(1.3, 0.2, 0.9), 1)
            .unwrap();
        assert_eq!((b.min, b.max), (UVec3::new(1, 0, 0), UVec3::new(4, 2, 3)));
        assert_eq!(b.count(), 3 * 2 * 3);
        let order: Vec<usize> = b.cells().map(|c| b.local_index(c).unwrap()).collect();
        assert_eq!(order, (0..b.count()).collect::<Vec<_>>());
        assert_eq!(b.local_index(UVec3::new(4, 0, 0)), None);
        assert!(l.cells_touching(Vec3::splat(9.0), Vec3::splat(10.0), 1).is_none());
        assert_eq!(
            l.cells_touching(Vec3::splat(-9.0), Vec3::splat(9.0), 0),
            Some(l.all_cells())
        );
        let far = l
            .cells_touching(Vec3::new(3.8, 1.8, 1.8), Vec3::new(3.9, 1.9, 1.9), 0)
            .unwrap();
        assert_eq!(CellBox::merged(vec![b, far]).len(), 2);
        let near = CellBox {
            min: UVec3::new(4, 0, 0),
            max: UVec3::new(5, 1, 1),
        };
        assert_eq!(CellBox::merged(vec![b, far, near]), vec![b.union(&near), far]);
    }

    #[test]
    fn columns_only_where_a_cpu_walks_whole_columns_and_no_images_are_copied() {
        for is_cpu in [false, true] {
            for whole_columns in [false, true] {
                for copied_to_images in [false, true] {
                    let order = CellOrder::for_step(is_cpu, whole_columns, copied_to_images);
                    let columns = is_cpu && whole_columns && !copied_to_images;
                    assert_eq!(order == CellOrder::Columns, columns);
                }
            }
        }
    }

    #[test]
    fn cell_orders_place_every_cell_once_and_round_trip() {
        let dims = UVec3::new(5, 3, 4);
        let rows: Vec<u32> = (0..60).collect();
        for order in [CellOrder::Rows, CellOrder::Columns] {
            let placed = order.from_rows(dims, &rows, 1);
            let all = CellBox {
                min: UVec3::ZERO,
                max: dims,
            };
            for (row, c) in all.cells().enumerate() {
                assert_eq!(placed[order.index(dims, c)], rows[row], "{order:?} {c}");
            }
            assert_eq!(order.to_rows(dims, &placed, 1), rows);
        }
        // Columns: z fastest, then x, then y.
        assert_eq!(CellOrder::Columns.index(dims, UVec3::new(0, 0, 1)), 1);
        assert_eq!(CellOrder::Columns.index(dims, UVec3::new(1, 0, 0)), 4);
        assert_eq!(CellOrder::Columns.index(dims, UVec3::new(0, 1, 0)), 20);
        // Several values a cell move together.
        let pairs: Vec<u32> = (0..120).collect();
        let placed = CellOrder::Columns.from_rows(dims, &pairs, 2);
        let i = CellOrder::Columns.index(dims, UVec3::new(1, 0, 0));
        assert_eq!(placed[2 * i..2 * i + 2], [2, 3]);
        assert_eq!(CellOrder::Columns.to_rows(dims, &placed, 2), pairs);
    }

    #[test]
    fn a_regions_runs_are_consecutive_in_the_buffer_and_cover_it_once() {
        let dims = UVec3::new(6, 5, 4);
        let regions = [
            CellBox {
                min: UVec3::new(1, 2, 1),
                max: UVec3::new(4, 4, 3),
            },
            // Whole columns: a row of them is one run.
            CellBox {
                min: UVec3::new(2, 1, 0),
                max: UVec3::new(5, 2, 4),
            },
            CellBox {
                min: UVec3::ZERO,
                max: dims,
            },
        ];
        for order in [CellOrder::Rows, CellOrder::Columns] {
            for region in regions {
                let runs = order.runs(dims, &region);
                let mut seen = vec![false; region.count()];
                for (first, locals) in &runs {
                    let start = order.index(dims, *first);
                    for (k, &local) in locals.iter().enumerate() {
                        let cell = region.cells().nth(local).unwrap();
                        assert_eq!(order.index(dims, cell), start + k, "{order:?}");
                        assert!(!std::mem::replace(&mut seen[local], true));
                    }
                }
                assert!(seen.iter().all(|&s| s), "{order:?} {region:?}");
                if region.max == dims && region.min == UVec3::ZERO {
                    assert_eq!(runs.len(), 1, "{order:?}: the whole lattice is one run");
                }
            }
            let whole_columns = order.runs(dims, &regions[1]).len();
            let expected = match order {
                CellOrder::Rows => 4,
                CellOrder::Columns => 1,
            };
            assert_eq!(whole_columns, expected, "{order:?}");
        }
    }

    #[test]
    fn absurd_lattices_are_input_errors() {
        assert!(Lattice::fit(Vec3::ZERO, Vec3::ONE, 0).is_err());
        assert!(Lattice::fit(Vec3::ZERO, Vec3::ONE, 100_000).is_err());
        assert!(Lattice::fit(Vec3::ZERO, Vec3::ZERO, 8).is_err());
    }
}

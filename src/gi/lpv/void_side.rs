//! Which side of a surface opens onto the void: the orientation of one-way blocking
//! ([`super::geometry::BlockingLobe::Oriented`]). vkgi's surfaces are two-sided and nothing
//! guarantees their winding, so the side is found geometrically: from a point of the surface, a
//! ray along each of ±N is walked through the lattice's occupancy (cells that hold any surface);
//! the side whose ray leaves the lattice without meeting an occupied cell faces the void. A
//! room's walls, floor and ceiling face the void on their outer side and block only light
//! leaving the room; a wall with surfaces on both sides (a partition, a block's face) blocks
//! both ways.

use glam::{DVec3, IVec3};

use super::lattice::Lattice;

/// Cells a ray goes before it looks at the occupancy: a plane and any cell it passes through
/// lie within √3 cells of each other along the normal, so this skips the surface's own cells.
const SKIP_CELLS: f64 = 1.732_050_807_568_877_2;

/// The cells of a lattice that hold any surface.
pub struct Occupancy<'a> {
    lattice: &'a Lattice,
    occupied: Vec<bool>,
}

impl<'a> Occupancy<'a> {
    pub fn new(lattice: &'a Lattice) -> Occupancy<'a> {
        Occupancy {
            lattice,
            occupied: vec![false; lattice.cell_count()],
        }
    }

    /// Mark the cell holding `p` (if any) as occupied.
    pub fn mark(&mut self, p: DVec3) {
        if let Some(c) = self.lattice.cell_of(p.as_vec3()) {
            self.occupied[self.lattice.index(c)] = true;
        }
    }

    /// The side of the surface through `p` with normal `normal` that faces the void, when
    /// exactly one does.
    pub fn outward(&self, p: DVec3, normal: DVec3) -> Option<DVec3> {
        match (self.opens_onto_void(p, normal), self.opens_onto_void(p, -normal)) {
            (true, false) => Some(normal),
            (false, true) => Some(-normal),
            _ => None,
        }
    }

    /// Whether the ray from `from` along the unit `dir` leaves the lattice without entering an
    /// occupied cell after its first [`SKIP_CELLS`] cells (a 3-D DDA).
    fn opens_onto_void(&self, from: DVec3, dir: DVec3) -> bool {
        let d = f64::from(self.lattice.cell_size);
        let origin = self.lattice.origin.as_dvec3();
        let start = (from + dir * (SKIP_CELLS * d) - origin) / d;
        let mut cell = start.floor().as_ivec3();
        let step = IVec3::new(sign(dir.x), sign(dir.y), sign(dir.z));
        let boundary = |i: usize| -> f64 {
            match step[i] {
                1 => (f64::from(cell[i] + 1) - start[i]) / dir[i],
                -1 => (f64::from(cell[i]) - start[i]) / dir[i],
                _ => f64::INFINITY,
            }
        };
        let mut next = DVec3::new(boundary(0), boundary(1), boundary(2));
        let delta = DVec3::new(1.0 / dir.x.abs(), 1.0 / dir.y.abs(), 1.0 / dir.z.abs());
        loop {
            let Some(inside) = self.lattice.checked(cell) else {
                return true;
            };
            if self.occupied[self.lattice.index(inside)] {
                return false;
            }
            let axis = if next.x <= next.y && next.x <= next.z {
                0
            } else if next.y <= next.z {
                1
            } else {
                2
            };
            cell[axis] += step[axis];
            next[axis] += delta[axis];
        }
    }
}

fn sign(v: f64) -> i32 {
    if v > 0.0 {
        1
    } else if v < 0.0 {
        -1
    } else {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn a_room_floor_faces_the_void_below_and_a_partition_neither_side() {
        // A 10-cell box: a floor at y = 0.5, a partition at x = 5.5, the ceiling at y = 9.5.
        let lattice = Lattice::fit(Vec3::ZERO, Vec3::splat(10.0), 10).unwrap();
        let mut occupancy = Occupancy::new(&lattice);
        for a in 0..10 {
            for b in 0..10 {
                let (a, b) = (f64::from(a) + 0.5, f64::from(b) + 0.5);
                occupancy.mark(DVec3::new(a, 0.5, b));
                occupancy.mark(DVec3::new(a, 9.5, b));
                occupancy.mark(DVec3::new(5.5, a, b));
            }
        }
        let floor = DVec3::new(2.3, 0.5, 4.1);
        assert_eq!(occupancy.outward(floor, DVec3::Y), Some(-DVec3::Y));
        assert_eq!(occupancy.outward(floor, -DVec3::Y), Some(-DVec3::Y));
        assert_eq!(occupancy.outward(DVec3::new(2.3, 9.5, 4.1), DVec3::Y), Some(DVec3::Y));
        assert_eq!(occupancy.outward(DVec3::new(5.5, 3.0, 3.0), DVec3::X), None);
        // An oblique ray through the room meets the partition or a wall.
        let n = DVec3::new(1.0, 1.0, 0.3).normalize();
        assert!(!occupancy.opens_onto_void(DVec3::new(1.0, 1.0, 5.0), n));
        assert!(occupancy.opens_onto_void(DVec3::new(1.0, 1.0, 5.0), -n));
    }
}

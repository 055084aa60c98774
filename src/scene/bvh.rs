//! A bounding-volume hierarchy over the scene's triangles, built on the CPU with the binned
//! surface-area heuristic and flattened depth-first with "miss" links (a threaded BVH): a node's
//! first child follows it in the array, and `miss` is where traversal goes when the ray misses
//! the node's box or has finished its subtree. Traversal needs no stack, which suits GPUs that
//! keep per-thread arrays in memory (lavapipe). The layout matches
//! `shaders-glsl/common/bvh_node.glsl`.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

use super::Mesh;
use super::intersect::{Hit, intersect_edges};

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct BvhNode {
    pub min: [f32; 3],
    /// Next node when the box is missed or its subtree is done; [`BVH_END`] ends traversal.
    pub miss: u32,
    pub max: [f32; 3],
    /// 0 for an interior node; for a leaf `first << LEAF_COUNT_BITS | count` (triangles
    /// `triangles[first .. first + count]`).
    pub leaf: u32,
}

/// The `miss` link that ends traversal.
pub const BVH_END: u32 = u32::MAX;
/// Low bits of `BvhNode::leaf` holding the leaf's triangle count.
pub const LEAF_COUNT_BITS: u32 = 5;

impl BvhNode {
    /// The leaf's triangle range, or None for an interior node.
    pub fn leaf_range(&self) -> Option<std::ops::Range<u32>> {
        (self.leaf != 0).then(|| {
            let first = self.leaf >> LEAF_COUNT_BITS;
            first..first + (self.leaf & ((1 << LEAF_COUNT_BITS) - 1))
        })
    }
}

/// A triangle in leaf order as the GPU traverses it: a corner, two edges, and the index of the
/// triangle in the mesh.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct BvhTriangle {
    pub v0: [f32; 3],
    pub index: u32,
    pub e1: [f32; 4],
    pub e2: [f32; 4],
}

pub struct Bvh {
    pub nodes: Vec<BvhNode>,
    /// Triangle indices (into the mesh) in leaf order.
    pub triangles: Vec<u32>,
    /// Each of `triangles` as its first corner and the edges to the other two, as the mesh was
    /// when the BVH was built: rays read these instead of the mesh's indices and positions.
    edges: Vec<(Vec3, Vec3, Vec3)>,
}

const BINS: usize = 16;
const MAX_LEAF: usize = 4;
/// Largest leaf the SAH may prefer over splitting (fits in LEAF_COUNT_BITS).
const MAX_FORCED_LEAF: usize = 16;
/// Cost of a ray-box test relative to a ray-triangle test, for the SAH.
const TRAVERSAL_COST: f32 = 1.0;
const INTERSECTION_COST: f32 = 1.0;

#[derive(Clone, Copy)]
struct Aabb {
    min: Vec3,
    max: Vec3,
}

impl Aabb {
    const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::MAX),
        max: Vec3::splat(f32::MIN),
    };
    fn grow(self, p: Vec3) -> Aabb {
        Aabb {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }
    fn merge(self, o: Aabb) -> Aabb {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }
    fn area(self) -> f32 {
        let d = (self.max - self.min).max(Vec3::ZERO);
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }
}

struct Builder<'a> {
    bounds: Vec<Aabb>,
    centroids: Vec<Vec3>,
    order: &'a mut Vec<u32>,
    nodes: Vec<BvhNode>,
    /// Second child of each interior node (for linking; not stored in the nodes).
    second_child: Vec<u32>,
}

impl Bvh {
    pub fn build(mesh: &Mesh) -> Bvh {
        let n = mesh.triangle_count();
        let bounds: Vec<Aabb> = (0..n)
            .map(|t| mesh.triangle(t).iter().fold(Aabb::EMPTY, |b, &p| b.grow(p)))
            .collect();
        let centroids = bounds.iter().map(|b| 0.5 * (b.min + b.max)).collect();
        let mut order: Vec<u32> = (0..n as u32).collect();
        let mut builder = Builder {
            bounds,
            centroids,
            order: &mut order,
            nodes: Vec::with_capacity(2 * n.max(1)),
            second_child: Vec::with_capacity(2 * n.max(1)),
        };
        builder.build(0, n);
        builder.link(0, BVH_END);
        let nodes = builder.nodes;
        let edges = order
            .iter()
            .map(|&t| {
                let [a, b, c] = mesh.triangle(t as usize);
                (a, b - a, c - a)
            })
            .collect();
        Bvh {
            nodes,
            triangles: order,
            edges,
        }
    }

    /// The triangles in leaf order, laid out for the GPU.
    pub fn gpu_triangles(&self) -> Vec<BvhTriangle> {
        self.triangles
            .iter()
            .zip(&self.edges)
            .map(|(&t, &(a, e1, e2))| BvhTriangle {
                v0: a.to_array(),
                index: t,
                e1: e1.extend(0.0).to_array(),
                e2: e2.extend(0.0).to_array(),
            })
            .collect()
    }

    /// Closest hit along a ray in `(t_min, t_max)`, by following the miss links (as
    /// `trace_ray` in bvh.glsl), against the mesh the BVH was built from.
    pub fn intersect(&self, origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        self.traverse(origin, dir, t_min, t_max, |t, (dist, u, v)| {
            best = Some(Hit {
                t: dist,
                triangle: t as usize,
                uv: (u, v),
            });
            false
        });
        best
    }

    /// Whether anything lies along a ray in `(t_min, t_max)`: the same answer as
    /// `intersect(..).is_some()`, stopping at the first hit found.
    pub fn occluded(&self, origin: Vec3, dir: Vec3, t_min: f32, t_max: f32) -> bool {
        let mut hit = false;
        self.traverse(origin, dir, t_min, t_max, |_, _| {
            hit = true;
            true
        });
        hit
    }

    /// Visit the triangles a ray hits closer than every hit before, in traversal order:
    /// `on_hit(triangle, (t, u, v))` returns whether to stop.
    fn traverse(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_min: f32,
        t_max: f32,
        mut on_hit: impl FnMut(u32, (f32, f32, f32)) -> bool,
    ) {
        let inv = Vec3::ONE / dir;
        let mut limit = t_max;
        let mut node = 0u32;
        while node != BVH_END {
            let n = &self.nodes[node as usize];
            if slab(n, origin, inv, t_min, limit).is_none() {
                node = n.miss;
                continue;
            }
            match n.leaf_range() {
                Some(range) => {
                    for i in range {
                        let i = i as usize;
                        if let Some(hit) = intersect_edges(origin, dir, self.edges[i], t_min, limit)
                        {
                            limit = hit.0;
                            if on_hit(self.triangles[i], hit) {
                                return;
                            }
                        }
                    }
                    node = n.miss;
                }
                None => node += 1,
            }
        }
    }
}

/// Entry distance of a ray into a node's box, if it enters within (t_min, t_max).
fn slab(n: &BvhNode, origin: Vec3, inv: Vec3, t_min: f32, t_max: f32) -> Option<f32> {
    let t0 = (Vec3::from(n.min) - origin) * inv;
    let t1 = (Vec3::from(n.max) - origin) * inv;
    let near = t0.min(t1).max_element().max(t_min);
    let far = t0.max(t1).min_element().min(t_max);
    (near <= far).then_some(near)
}

impl Builder<'_> {
    /// Build the subtree over `order[start..end]`; returns its node index.
    fn build(&mut self, start: usize, end: usize) -> u32 {
        let index = self.nodes.len() as u32;
        self.nodes.push(BvhNode::default());
        self.second_child.push(BVH_END);
        let items = &self.order[start..end];
        let bounds = items
            .iter()
            .fold(Aabb::EMPTY, |b, &t| b.merge(self.bounds[t as usize]));
        let centroid_bounds = items
            .iter()
            .fold(Aabb::EMPTY, |b, &t| b.grow(self.centroids[t as usize]));
        let count = end - start;
        let split = if count <= MAX_LEAF {
            None
        } else {
            self.best_split(start, end, bounds, centroid_bounds)
        };
        let node = &mut self.nodes[index as usize];
        node.min = bounds.min.to_array();
        node.max = bounds.max.to_array();
        match split {
            None => node.leaf = ((start as u32) << LEAF_COUNT_BITS) | count as u32,
            Some(mid) => {
                self.build(start, mid);
                let second = self.build(mid, end);
                self.second_child[index as usize] = second;
            }
        }
        index
    }

    /// Set the miss links of the subtree at `node`, whose traversal continues at `miss`.
    fn link(&mut self, node: u32, miss: u32) {
        self.nodes[node as usize].miss = miss;
        if self.nodes[node as usize].leaf == 0 {
            let second = self.second_child[node as usize];
            self.link(node + 1, second);
            self.link(second, miss);
        }
    }

    /// Partition `order[start..end]` at the cheapest binned SAH split; None if a leaf is cheaper
    /// (or no split separates the centroids and the range is small enough to be one leaf).
    fn best_split(
        &mut self,
        start: usize,
        end: usize,
        bounds: Aabb,
        centroids: Aabb,
    ) -> Option<usize> {
        let count = end - start;
        let extent = centroids.max - centroids.min;
        let leaf_cost = INTERSECTION_COST * count as f32;
        let mut best: Option<(f32, usize, usize)> = None; // (cost, axis, bin boundary)
        for axis in 0..3 {
            if extent[axis] <= 0.0 {
                continue;
            }
            let bin_of = |c: Vec3| {
                (((c[axis] - centroids.min[axis]) / extent[axis]) * BINS as f32)
                    .min(BINS as f32 - 1.0) as usize
            };
            let mut bin_bounds = [Aabb::EMPTY; BINS];
            let mut bin_counts = [0usize; BINS];
            for &t in &self.order[start..end] {
                let b = bin_of(self.centroids[t as usize]);
                bin_bounds[b] = bin_bounds[b].merge(self.bounds[t as usize]);
                bin_counts[b] += 1;
            }
            // Sweep: cost of splitting after bin i.
            let mut right_area = [0.0f32; BINS];
            let mut right_count = [0usize; BINS];
            let (mut acc, mut n) = (Aabb::EMPTY, 0);
            for i in (1..BINS).rev() {
                acc = acc.merge(bin_bounds[i]);
                n += bin_counts[i];
                right_area[i] = acc.area();
                right_count[i] = n;
            }
            let (mut acc, mut n) = (Aabb::EMPTY, 0);
            for i in 0..BINS - 1 {
                acc = acc.merge(bin_bounds[i]);
                n += bin_counts[i];
                if n == 0 || right_count[i + 1] == 0 {
                    continue;
                }
                let cost = TRAVERSAL_COST
                    + INTERSECTION_COST
                        * (acc.area() * n as f32 + right_area[i + 1] * right_count[i + 1] as f32)
                        / bounds.area().max(1e-30);
                if best.is_none_or(|b| cost < b.0) {
                    best = Some((cost, axis, i + 1));
                }
            }
        }
        match best {
            Some((cost, axis, boundary)) if cost < leaf_cost || count > MAX_FORCED_LEAF => {
                let extent_axis = extent[axis];
                let min_axis = centroids.min[axis];
                let centroids_ref = &self.centroids;
                let slice = &mut self.order[start..end];
                let mut left = 0;
                for i in 0..slice.len() {
                    let c = centroids_ref[slice[i] as usize][axis];
                    let bin = (((c - min_axis) / extent_axis) * BINS as f32).min(BINS as f32 - 1.0)
                        as usize;
                    if bin < boundary {
                        slice.swap(i, left);
                        left += 1;
                    }
                }
                Some(start + left)
            }
            Some(_) => None,
            // All centroids coincide: split in the middle if the range is too big for a leaf.
            None if count > MAX_FORCED_LEAF => Some(start + count / 2),
            None => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pseudo-random triangle soup.
    fn soup(n: usize) -> Mesh {
        let mut state = 12345u32;
        let mut next = move || {
            state = state.wrapping_mul(1664525).wrapping_add(1013904223);
            (state >> 8) as f32 / (1 << 24) as f32
        };
        let mut mesh = Mesh::default();
        for _ in 0..n {
            let c = Vec3::new(next(), next(), next()) * 10.0;
            let mut corner = || c + Vec3::new(next(), next(), next()) - 0.5;
            let corners = [corner(), corner(), corner()];
            mesh.push_triangle(corners, [Vec3::Y; 3], 0);
        }
        mesh
    }

    #[test]
    fn every_triangle_is_in_exactly_one_leaf_inside_its_node_bounds() {
        let mesh = soup(500);
        let bvh = Bvh::build(&mesh);
        let mut seen = vec![0; 500];
        for node in &bvh.nodes {
            let Some(range) = node.leaf_range() else {
                continue;
            };
            for i in range {
                let t = bvh.triangles[i as usize] as usize;
                seen[t] += 1;
                for p in mesh.triangle(t) {
                    assert!(
                        p.cmpge(Vec3::from(node.min)).all() && p.cmple(Vec3::from(node.max)).all()
                    );
                }
            }
        }
        assert!(seen.iter().all(|&s| s == 1));
    }

    #[test]
    fn traversal_finds_the_same_hits_as_brute_force() {
        let mesh = soup(300);
        let bvh = Bvh::build(&mesh);
        let mut state = 7u32;
        let mut next = move || {
            state = state.wrapping_mul(1664525).wrapping_add(1013904223);
            (state >> 8) as f32 / (1 << 24) as f32
        };
        for _ in 0..2000 {
            let origin = Vec3::new(next(), next(), next()) * 14.0 - 2.0;
            let dir = (Vec3::new(next(), next(), next()) - 0.5).normalize();
            let brute = mesh.intersect(origin, dir, 1e-4, 1e9);
            let fast = bvh.intersect(origin, dir, 1e-4, 1e9);
            assert_eq!(brute.map(|h| h.triangle), fast.map(|h| h.triangle));
            assert_eq!(bvh.occluded(origin, dir, 1e-4, 1e9), brute.is_some());
            // A segment that ends before the nearest hit is free.
            if let Some(hit) = brute {
                assert!(!bvh.occluded(origin, dir, 1e-4, hit.t * 0.999));
            }
        }
    }
}

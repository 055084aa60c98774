//! Patches, surfaces and elements (spec 004 §2, §3.2): the scene's triangles paired into
//! polygons ("patches": a quad's two triangles, or a lone triangle), each side of a patch that
//! light can reach a radiosity *surface* (a shooter, with its own elements), and each surface a
//! grid of square texels in its plane, the receiving *elements*. A texel's element covers the
//! part of the texel inside the polygon (its area and centroid from 4x4 sub-samples); texels
//! outside keep area 0 and take no part. Baked once on the CPU.

use glam::{Vec2, Vec3};

use crate::scene::bvh::Bvh;
use crate::scene::{LightKind, Scene};

/// Sub-samples per texel side for coverage, area and centroid.
const SUBSAMPLES: usize = 4;
/// Sample points per surface side and rays per point for the reachability test.
const REACH_POINTS: usize = 12;
const REACH_RAYS: usize = 12;
/// Rays from each punctual light that seed the sides it hits.
const LIGHT_RAYS: usize = 2048;

/// Two triangles, or one, in a plane: what the thesis calls a surface (a polygon of the mesh).
#[derive(Clone, Debug)]
pub struct Patch {
    pub triangles: Vec<u32>,
    pub material: u32,
    /// The front normal (by the first triangle's winding).
    pub normal: Vec3,
    /// The rectangle around the polygon in its plane: a corner and unit axes.
    pub origin: Vec3,
    pub axis_t: Vec3,
    pub axis_b: Vec3,
    /// Side lengths of the rectangle along `axis_t` and `axis_b`.
    pub extent: Vec2,
    /// The polygon's area.
    pub area: f64,
}

/// One side of a patch that light can reach: a shooter and the owner of a grid of elements.
#[derive(Clone, Debug)]
pub struct Surface {
    pub patch: u32,
    /// The side's outward normal (the patch's normal, or its opposite for the back).
    pub normal: Vec3,
    pub back: bool,
    /// Index of the first element; the grid is `width x height`, row-major.
    pub first: u32,
    pub width: u32,
    pub height: u32,
    /// Emitted radiosity (W/m² = π times the emitted radiance) per channel.
    pub emission: Vec3,
    /// Sum of its elements' areas.
    pub area: f64,
}

/// A texel of a surface's grid; `area` 0 means the texel lies outside the polygon.
#[derive(Clone, Copy, Debug, Default)]
pub struct Element {
    pub position: Vec3,
    pub area: f32,
    pub albedo: Vec3,
    pub surface: u32,
}

/// The whole discretisation.
#[derive(Clone, Debug)]
pub struct Elements {
    pub patches: Vec<Patch>,
    /// Patch of every mesh triangle.
    pub triangle_patch: Vec<u32>,
    /// Surface of each patch's (front, back) side, `NO_SURFACE` where light never reaches it.
    pub patch_surfaces: Vec<[u32; 2]>,
    pub surfaces: Vec<Surface>,
    pub elements: Vec<Element>,
    /// Side of a texel (scene units).
    pub texel: f32,
}

pub const NO_SURFACE: u32 = u32::MAX;

/// How fine the elements are.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Density {
    /// About this many elements over all reachable surfaces.
    Budget(u32),
    /// Elements per unit area (scene units²).
    PerArea(f64),
}

impl Elements {
    /// Bake the elements of `scene`. `progress` is told the fraction done.
    pub fn bake(scene: &Scene, density: Density, progress: &dyn Fn(f64)) -> Elements {
        let (patches, triangle_patch) = pair_triangles(scene);
        let bvh = Bvh::build(&scene.mesh);
        let reachable = reachable_sides(scene, &bvh, &patches, &triangle_patch, progress);
        let reached_area: f64 = patches
            .iter()
            .zip(&reachable)
            .map(|(p, r)| p.area * r.iter().filter(|&&s| s).count() as f64)
            .sum();
        let texel = match density {
            Density::Budget(n) => (reached_area / f64::from(n.max(1))).sqrt(),
            Density::PerArea(d) => (1.0 / d).sqrt(),
        } as f32;
        let texel = if texel.is_finite() && texel > 0.0 {
            texel
        } else {
            1.0
        };
        let mut out = Elements {
            patch_surfaces: vec![[NO_SURFACE; 2]; patches.len()],
            patches,
            triangle_patch,
            surfaces: Vec::new(),
            elements: Vec::new(),
            texel,
        };
        for (p, sides) in reachable.iter().enumerate() {
            for back in [false, true] {
                if sides[usize::from(back)] {
                    out.add_surface(scene, &bvh, p, back);
                }
            }
        }
        out
    }

    fn add_surface(&mut self, scene: &Scene, bvh: &Bvh, p: usize, back: bool) {
        let patch = &self.patches[p];
        let normal = if back { -patch.normal } else { patch.normal };
        let width = ((patch.extent.x / self.texel).ceil() as u32).max(1);
        let height = ((patch.extent.y / self.texel).ceil() as u32).max(1);
        let index = self.surfaces.len() as u32;
        let first = self.elements.len() as u32;
        let mut grid = texel_grid(scene, patch, self.texel, width, height, index);
        let contact = contact_distance(scene);
        let buried: Vec<bool> = grid
            .iter()
            .map(|e| e.area > 0.0 && buried(scene, bvh, e.position, normal, contact))
            .collect();
        // A reached side cannot be buried whole: then its winding, not a solid, fooled the
        // test (a room whose walls face outward), and every element stays.
        if grid.iter().zip(&buried).any(|(e, &b)| e.area > 0.0 && !b) {
            for (element, _) in grid.iter_mut().zip(&buried).filter(|(_, b)| **b) {
                element.area = 0.0;
            }
        }
        let area = grid.iter().map(|e| f64::from(e.area)).sum();
        self.elements.extend(grid);
        let material = &scene.materials[patch.material as usize];
        let emits = !back || material.two_sided;
        let emission = if emits {
            material.emission * std::f32::consts::PI
        } else {
            Vec3::ZERO
        };
        self.surfaces.push(Surface {
            patch: p as u32,
            normal,
            back,
            first,
            width,
            height,
            emission,
            area,
        });
        self.patch_surfaces[p][usize::from(back)] = index;
    }

    /// The elements of surface `s`, row-major.
    pub fn of(&self, s: usize) -> &[Element] {
        let surface = &self.surfaces[s];
        let first = surface.first as usize;
        &self.elements[first..first + (surface.width * surface.height) as usize]
    }

    /// Elements with a non-zero area.
    pub fn valid_count(&self) -> usize {
        self.elements.iter().filter(|e| e.area > 0.0).count()
    }

    /// The most texels one surface's grid has.
    pub fn largest_grid(&self) -> u32 {
        self.surfaces
            .iter()
            .map(|s| s.width * s.height)
            .max()
            .unwrap_or(1)
    }

    /// The area-weighted mean albedo over every element (the ambient term's ρ_avg).
    pub fn mean_albedo(&self) -> Vec3 {
        let (sum, area) = self
            .elements
            .iter()
            .fold((Vec3::ZERO, 0.0f64), |(s, a), e| {
                (s + e.albedo * e.area, a + f64::from(e.area))
            });
        if area > 0.0 {
            sum / area as f32
        } else {
            Vec3::ZERO
        }
    }
}

/// Pair every triangle with the coplanar neighbour of the same material across its longest
/// edge, when that edge is the neighbour's longest too (a quad's diagonal); the rest stay alone.
fn pair_triangles(scene: &Scene) -> (Vec<Patch>, Vec<u32>) {
    let mesh = &scene.mesh;
    let n = mesh.triangle_count();
    let (lo, hi) = mesh.bounds();
    let scale = (hi - lo).length().max(1e-20);
    let key = |p: Vec3| {
        let q = (p - lo) / scale * 1e6;
        (q.x.round() as i64, q.y.round() as i64, q.z.round() as i64)
    };
    let longest = |t: usize| {
        let c = mesh.triangle(t);
        (0..3)
            .max_by(|&i, &j| {
                let li = (c[(i + 1) % 3] - c[i]).length_squared();
                let lj = (c[(j + 1) % 3] - c[j]).length_squared();
                li.total_cmp(&lj)
            })
            .map(|i| {
                let (a, b) = (key(c[i]), key(c[(i + 1) % 3]));
                if a < b { (a, b) } else { (b, a) }
            })
            .unwrap_or_default()
    };
    let mut by_edge = std::collections::HashMap::new();
    for t in 0..n {
        by_edge.entry(longest(t)).or_insert_with(Vec::new).push(t);
    }
    let mut triangle_patch = vec![u32::MAX; n];
    let mut patches = Vec::new();
    for t in 0..n {
        if triangle_patch[t] != u32::MAX {
            continue;
        }
        let normal = mesh.face_normal(t);
        let partner = by_edge[&longest(t)].iter().copied().find(|&o| {
            o != t
                && triangle_patch[o] == u32::MAX
                && mesh.materials[o] == mesh.materials[t]
                && mesh.face_normal(o).dot(normal) > 0.9999
        });
        let mut triangles = vec![t as u32];
        triangles.extend(partner.map(|o| o as u32));
        for &tri in &triangles {
            triangle_patch[tri as usize] = patches.len() as u32;
        }
        patches.push(patch_of(scene, triangles));
    }
    (patches, triangle_patch)
}

/// The smallest rectangle, aligned with one of the polygon's edges, around its triangles.
fn patch_of(scene: &Scene, triangles: Vec<u32>) -> Patch {
    let mesh = &scene.mesh;
    let first = triangles[0] as usize;
    let normal = mesh.face_normal(first);
    let corners: Vec<Vec3> = triangles
        .iter()
        .flat_map(|&t| mesh.triangle(t as usize))
        .collect();
    let area: f64 = triangles
        .iter()
        .map(|&t| {
            let [a, b, c] = mesh.triangle(t as usize).map(Vec3::as_dvec3);
            0.5 * (b - a).cross(c - a).length()
        })
        .sum();
    let mut best: Option<(f32, Vec3, Vec3, Vec2)> = None;
    for i in 0..corners.len() {
        let edge = corners[(i + 1) % 3 + i / 3 * 3] - corners[i];
        let Some(axis_t) = edge.try_normalize() else {
            continue;
        };
        let axis_b = normal.cross(axis_t).normalize_or_zero();
        let (mut min, mut max) = (Vec2::splat(f32::MAX), Vec2::splat(f32::MIN));
        for &c in &corners {
            let q = Vec2::new(c.dot(axis_t), c.dot(axis_b));
            min = min.min(q);
            max = max.max(q);
        }
        let size = max - min;
        if best.is_none_or(|(a, ..)| size.x * size.y < a) {
            best = Some((size.x * size.y, axis_t, axis_b, size));
        }
    }
    let (_, axis_t, axis_b, extent) = best.unwrap_or((0.0, Vec3::X, Vec3::Y, Vec2::ZERO));
    let min = corners.iter().fold(Vec2::splat(f32::MAX), |m, c| {
        m.min(Vec2::new(c.dot(axis_t), c.dot(axis_b)))
    });
    let origin = axis_t * min.x + axis_b * min.y + normal * normal.dot(corners[0]);
    Patch {
        material: mesh.materials[first],
        triangles,
        normal,
        origin,
        axis_t,
        axis_b,
        extent,
        area,
    }
}

/// Barycentric (u, v) of `p` (in the plane) in triangle `t`, if inside.
fn inside(scene: &Scene, t: u32, p: Vec3) -> Option<(f32, f32)> {
    let [a, b, c] = scene.mesh.triangle(t as usize);
    let (e1, e2, d) = (b - a, c - a, p - a);
    let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let det = d11 * d22 - d12 * d12;
    if det.abs() < 1e-30 {
        return None;
    }
    let (p1, p2) = (d.dot(e1), d.dot(e2));
    let u = (d22 * p1 - d12 * p2) / det;
    let v = (d11 * p2 - d12 * p1) / det;
    let slack = -1e-5;
    (u >= slack && v >= slack && u + v <= 1.0 - slack).then_some((u, v))
}

/// The texels of one surface: coverage area, centroid and mean albedo from sub-samples. A
/// polygon too thin to hold a sub-sample gets one element at its centroid with its whole area.
fn texel_grid(
    scene: &Scene,
    patch: &Patch,
    texel: f32,
    width: u32,
    height: u32,
    surface: u32,
) -> Vec<Element> {
    let sub = texel / SUBSAMPLES as f32;
    let sub_area = sub * sub;
    let mut grid = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            let mut element = Element {
                surface,
                ..Element::default()
            };
            let (mut sum, mut albedo, mut count) = (Vec3::ZERO, Vec3::ZERO, 0u32);
            for sy in 0..SUBSAMPLES {
                for sx in 0..SUBSAMPLES {
                    let s = (x as f32 * texel + (sx as f32 + 0.5) * sub) * patch.axis_t
                        + (y as f32 * texel + (sy as f32 + 0.5) * sub) * patch.axis_b;
                    let p = patch.origin + s;
                    let hit = patch
                        .triangles
                        .iter()
                        .find_map(|&t| inside(scene, t, p).map(|uv| (t, uv)));
                    if let Some((t, uv)) = hit {
                        sum += p;
                        albedo += scene.albedo(t as usize, uv);
                        count += 1;
                    }
                }
            }
            if count > 0 {
                element.position = sum / count as f32;
                element.area = count as f32 * sub_area;
                element.albedo = albedo / count as f32;
            }
            grid.push(element);
        }
    }
    let covered: f64 = grid.iter().map(|e| f64::from(e.area)).sum();
    if covered > 0.0 {
        // Sub-sample counts are coarse on small polygons: keep the polygon's exact area.
        let scale = (patch.area / covered) as f32;
        for element in &mut grid {
            element.area *= scale;
        }
    } else {
        let t = patch.triangles[0] as usize;
        let [a, b, c] = scene.mesh.triangle(t);
        let centroid = (a + b + c) / 3.0;
        let local = centroid - patch.origin;
        let x = ((local.dot(patch.axis_t) / texel) as u32).min(width - 1);
        let y = ((local.dot(patch.axis_b) / texel) as u32).min(height - 1);
        grid[(y * width + x) as usize] = Element {
            position: centroid,
            area: patch.area as f32,
            albedo: scene.albedo(t, (1.0 / 3.0, 1.0 / 3.0)),
            surface,
        };
    }
    grid
}

/// Which sides of each patch light can reach: a side is lit directly (it emits, or a punctual
/// light sees one of its sample points) or a ray from a reached side hits it. Rays shorter than
/// a contact distance (a block standing on the floor) reach nothing.
fn reachable_sides(
    scene: &Scene,
    bvh: &Bvh,
    patches: &[Patch],
    triangle_patch: &[u32],
    progress: &dyn Fn(f64),
) -> Vec<[bool; 2]> {
    let mesh = &scene.mesh;
    let contact = contact_distance(scene);
    let side_index = |p: usize, back: bool| 2 * p + usize::from(back);
    let mut edges: Vec<Vec<usize>> = vec![Vec::new(); 2 * patches.len()];
    let mut seeds = Vec::new();
    for (p, patch) in patches.iter().enumerate() {
        if p % 256 == 0 {
            progress(p as f64 / patches.len() as f64);
        }
        for back in [false, true] {
            let normal = if back { -patch.normal } else { patch.normal };
            let points: Vec<Vec3> = sample_points(scene, patch)
                .into_iter()
                .filter(|&x| !buried(scene, bvh, x, normal, contact))
                .collect();
            let material = &scene.materials[patch.material as usize];
            let emits = material.emission.max_element() > 0.0 && (!back || material.two_sided);
            let lit = scene.lights.iter().any(|light| {
                points.iter().any(|&x| {
                    let to_light = light.position - x;
                    let dir = to_light.normalize_or_zero();
                    normal.dot(dir) > 0.0
                        && (matches!(light.kind, LightKind::Point) || light.profile(-dir) > 0.0)
                        && bvh_visible(bvh, x + normal * contact, light.position)
                })
            });
            if emits || lit {
                seeds.push(side_index(p, back));
            }
            for (i, &x) in points.iter().enumerate() {
                for r in 0..REACH_RAYS {
                    let dir = hemisphere_ray((patch.axis_t, patch.axis_b), normal, i, r, REACH_RAYS);
                    let Some(hit) = bvh.intersect(x + normal * contact, dir, 0.0, f32::MAX)
                    else {
                        continue;
                    };
                    if hit.t < contact {
                        continue;
                    }
                    let q = triangle_patch[hit.triangle] as usize;
                    let facing_back = mesh.face_normal(hit.triangle).dot(dir) > 0.0;
                    edges[side_index(p, back)].push(side_index(q, facing_back));
                }
            }
        }
    }
    // Rays from each punctual light inside its cone seed what it hits (a narrow spot may miss
    // every sample point above).
    for light in &scene.lights {
        let axis = light.axis().map(|a| a.normalize_or(Vec3::Y));
        let directions = (0..LIGHT_RAYS).map(|k| {
            let z = 1.0 - 2.0 * (k as f32 + 0.5) / LIGHT_RAYS as f32;
            let phi = k as f32 * 2.399_963;
            let r = (1.0 - z * z).max(0.0).sqrt();
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        });
        for dir in axis.into_iter().chain(directions) {
            if !matches!(light.kind, LightKind::Point) && light.profile(dir) <= 0.0 {
                continue;
            }
            if let Some(hit) = bvh.intersect(light.position, dir, 0.0, f32::MAX) {
                let facing_back = mesh.face_normal(hit.triangle).dot(dir) > 0.0;
                seeds.push(side_index(triangle_patch[hit.triangle] as usize, facing_back));
            }
        }
    }
    let mut reached = vec![false; 2 * patches.len()];
    let mut stack = seeds;
    while let Some(s) = stack.pop() {
        if std::mem::replace(&mut reached[s], true) {
            continue;
        }
        stack.extend(edges[s].iter().copied().filter(|&o| !reached[o]));
    }
    progress(1.0);
    (0..patches.len())
        .map(|p| [reached[2 * p], reached[2 * p + 1]])
        .collect()
}

fn bvh_visible(bvh: &Bvh, from: Vec3, to: Vec3) -> bool {
    let d = to - from;
    let length = d.length();
    length <= 0.0 || !bvh.occluded(from, d / length, 0.0, length)
}

/// Points spread over the polygon: its triangles' centroids and points toward their corners.
fn sample_points(scene: &Scene, patch: &Patch) -> Vec<Vec3> {
    let mut points = Vec::new();
    let weights = [
        (1.0 / 3.0, 1.0 / 3.0),
        (0.7, 0.15),
        (0.15, 0.7),
        (0.15, 0.15),
        (0.45, 0.45),
        (0.1, 0.45),
    ];
    for &t in &patch.triangles {
        let [a, b, c] = scene.mesh.triangle(t as usize);
        for &(u, v) in &weights {
            points.push(a * (1.0 - u - v) + b * u + c * v);
        }
    }
    points.truncate(REACH_POINTS);
    points
}

/// Ray `r` of `count` over the cosine-weighted hemisphere around `normal` (stratified in
/// elevation, rotated per point `i`).
fn hemisphere_ray((axis_t, axis_b): (Vec3, Vec3), normal: Vec3, i: usize, r: usize, count: usize) -> Vec3 {
    let u1 = (r as f32 + 0.5) / count as f32;
    let u2 = ((i * 7 + r * 5) % count) as f32 / count as f32 + 0.03;
    let (radius, phi) = (u1.sqrt(), std::f32::consts::TAU * u2);
    (axis_t * (radius * phi.cos())
        + axis_b * (radius * phi.sin())
        + normal * (1.0 - u1).max(0.0).sqrt())
    .normalize()
}

/// Rays per point for the buried test.
const BURIED_RAYS: usize = 8;

/// True when every ray from `x` over the hemisphere around `normal` hits the back of a
/// triangle: the point lies inside a closed solid (the floor under a block), where no light
/// can arrive and from where none may leave.
fn buried(scene: &Scene, bvh: &Bvh, x: Vec3, normal: Vec3, contact: f32) -> bool {
    let axes = normal.any_orthonormal_pair();
    (0..BURIED_RAYS).all(|r| {
        let dir = hemisphere_ray(axes, normal, 0, r, BURIED_RAYS);
        bvh.intersect(x + normal * contact, dir, 0.0, f32::MAX)
            .is_some_and(|hit| scene.mesh.face_normal(hit.triangle).dot(dir) > 0.0)
    })
}

/// Hits closer than this are contact (a block standing on the floor), not a view.
fn contact_distance(scene: &Scene) -> f32 {
    let (lo, hi) = scene.mesh.bounds();
    1e-4 * (hi - lo).length()
}

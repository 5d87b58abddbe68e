//! A scene of a few infinite planes, spheres and quads (TP6's box of planes with its spheres and
//! quad light, the glass-and-mirror room's quads) is searched by `Geometry` with vector tests:
//! all the planes in one 8-wide test, the spheres in four lanes, the quads' halves in 4-wide
//! packets or 16 lanes. Each must find what the shapes' own scalar tests find, one after another
//! in the shapes' order: the same shape and, bit for bit, the same distance, point and normals.
//! The rays are those where rounding decides: from points on the surfaces (exactly on them and
//! spawned off them), grazing the planes and the spheres, along the box's edges, at the quads'
//! edges and corners, and through shapes placed twice (equal distances: the first stays).

use glam::Vec3;
use prisma::geometry::{spawn_origin, Geometry, Hit, Plane, Quad, Ray, Shape, ShearedRay, Sphere};

/// A small deterministic generator (PCG-style LCG), so that the test needs no crate.
struct Rng(u64);

impl Rng {
    fn uniform(&mut self, low: f32, high: f32) -> f32 {
        self.0 = self.0.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        low + (high - low) * ((self.0 >> 40) as f32 / (1u64 << 24) as f32)
    }

    fn index(&mut self, count: usize) -> usize {
        (self.uniform(0.0, count as f32) as usize).min(count - 1)
    }

    fn point_in(&mut self, low: Vec3, high: Vec3) -> Vec3 {
        Vec3::new(self.uniform(low.x, high.x), self.uniform(low.y, high.y), self.uniform(low.z, high.z))
    }

    fn unit_vector(&mut self) -> Vec3 {
        loop {
            let v = self.point_in(Vec3::splat(-1.0), Vec3::splat(1.0));
            if (1e-4..=1.0).contains(&v.length_squared()) {
                return v.normalize();
            }
        }
    }
}

/// The nearest hit by each shape's own test, in the shapes' order, at the limit the shapes
/// before it left (the first of equal distances stays).
fn one_by_one(shapes: &[Shape], ray: &Ray, t_max: f32) -> Option<Hit> {
    let sheared = ShearedRay::new(*ray);
    let mut nearest: Option<Hit> = None;
    for (index, shape) in shapes.iter().enumerate() {
        let limit = nearest.map_or(t_max, |hit| hit.t);
        if let Some(hit) = shape.intersect(&[], &sheared, limit, index as u32) {
            nearest = Some(hit);
        }
    }
    nearest
}

/// A hit's bits: t, the shape, the point and both normals.
fn bits(hit: &Hit) -> Vec<u32> {
    let mut bits = vec![hit.t.to_bits(), hit.prim];
    for v in [hit.point, hit.normal, hit.shading_normal] {
        bits.extend(v.to_array().map(f32::to_bits));
    }
    bits
}

/// A TP6-like box: `planes` of the floor, ceiling, side walls, back wall (and, past five, two
/// tilted planes closing the front corners and a second copy of the floor), `spheres` spheres
/// inside (the last one a copy of the first when there are three or more), and `quads` quads: a
/// light just under the ceiling, one lying on the floor plane itself, then panels on the walls
/// (two sharing an edge). No quad is placed twice: among quads at equal distances the first in
/// the BVH's leaf order is kept, which need not be the shapes' order.
/// Planes first, then spheres, then quads: the order in which `Geometry` breaks ties.
fn scene(planes: usize, spheres: usize, quads: usize) -> Vec<Shape> {
    let all_planes = [
        Plane { point: Vec3::ZERO, normal: Vec3::Y },
        Plane { point: Vec3::new(0.0, 4.0, 0.0), normal: -Vec3::Y },
        Plane { point: Vec3::new(-3.0, 0.0, 0.0), normal: Vec3::X },
        Plane { point: Vec3::new(3.0, 0.0, 0.0), normal: -Vec3::X },
        Plane { point: Vec3::new(0.0, 0.0, 8.0), normal: -Vec3::Z },
        Plane { point: Vec3::new(-2.5, 0.0, -1.0), normal: Vec3::new(1.0, 0.0, 1.0).normalize() },
        Plane { point: Vec3::new(2.5, 0.0, -1.0), normal: Vec3::new(-1.0, 0.3, 1.0).normalize() },
        Plane { point: Vec3::ZERO, normal: Vec3::Y },
    ];
    let all_spheres = [
        Sphere { center: Vec3::new(-1.2, 1.0, 4.0), radius: 1.0 },
        Sphere { center: Vec3::new(1.3, 0.8, 5.0), radius: 0.8 },
        Sphere { center: Vec3::new(0.2, 2.5, 3.0), radius: 0.4 },
    ];
    let all_quads = [
        Quad {
            corner: Vec3::new(-0.5, 3.99, 3.5),
            edge1: Vec3::new(1.0, 0.0, 0.0),
            edge2: Vec3::new(0.0, 0.0, 1.0),
        },
        Quad {
            corner: Vec3::new(-2.0, 0.0, 6.0),
            edge1: Vec3::new(0.0, 0.0, 1.5),
            edge2: Vec3::new(1.5, 0.0, 0.0),
        },
        Quad {
            corner: Vec3::new(-2.999, 0.5, 2.0),
            edge1: Vec3::new(0.0, 0.0, 2.0),
            edge2: Vec3::new(0.0, 2.0, 0.0),
        },
        Quad {
            corner: Vec3::new(2.999, 0.5, 2.0),
            edge1: Vec3::new(0.0, 2.0, 0.0),
            edge2: Vec3::new(0.0, 0.0, 2.0),
        },
        Quad {
            corner: Vec3::new(-1.0, 1.0, 7.5),
            edge1: Vec3::new(2.0, 0.0, 0.0),
            edge2: Vec3::new(0.3, 1.5, 0.1),
        },
        Quad {
            corner: Vec3::new(-0.7, 2.5, 7.6),
            edge1: Vec3::new(2.0, 0.0, 0.0),
            edge2: Vec3::new(0.3, 1.5, 0.1),
        },
        Quad {
            corner: Vec3::new(0.5, 2.0, 1.0),
            edge1: Vec3::new(0.7, 0.2, 0.0),
            edge2: Vec3::new(0.0, 0.3, 0.9),
        },
        Quad {
            corner: Vec3::new(-1.5, 1.5, 2.0),
            edge1: Vec3::new(0.4, 0.0, 0.3),
            edge2: Vec3::new(0.0, 0.8, 0.0),
        },
    ];
    let mut shapes: Vec<Shape> = all_planes[..planes].iter().map(|&plane| Shape::Plane(plane)).collect();
    for i in 0..spheres {
        let sphere = if i >= 2 && i + 1 == spheres { all_spheres[0] } else { all_spheres[i.min(2)] };
        shapes.push(Shape::Sphere(sphere));
    }
    shapes.extend(all_quads[..quads].iter().map(|&quad| Shape::Quad(quad)));
    shapes
}

/// A ray where rounding decides, from inside the box: kind `kind` of seven.
fn tricky_ray(rng: &mut Rng, shapes: &[Shape], kind: usize) -> Option<Ray> {
    let inside = |rng: &mut Rng| rng.point_in(Vec3::new(-2.9, 0.05, -1.0), Vec3::new(2.9, 3.95, 7.9));
    let shape = shapes[rng.index(shapes.len())].clone();
    let (origin, dir) = match kind {
        // From anywhere inside, anywhere.
        0 => (inside(rng), rng.unit_vector()),
        // From a point of a surface, exactly (as computed), in any direction.
        1 | 2 => {
            let (on, normal) = match shape {
                Shape::Plane(plane) => {
                    let tangent = plane.normal.cross(rng.unit_vector()).normalize();
                    (plane.point + rng.uniform(-3.0, 3.0) * tangent, plane.normal)
                }
                Shape::Sphere(sphere) => {
                    let normal = rng.unit_vector();
                    (sphere.center + sphere.radius * normal, normal)
                }
                Shape::Quad(quad) => {
                    (quad.point_at(rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0)), quad.normal())
                }
                Shape::Triangle { .. } => unreachable!("no triangles here"),
            };
            let dir = rng.unit_vector();
            // Kind 2 spawns off the surface as the integrators do.
            (if kind == 1 { on } else { spawn_origin(on, normal, dir) }, dir)
        }
        // Grazing a plane: along it, tilted by up to 1e-4, from a point near it.
        3 => {
            let Shape::Plane(plane) = shape else {
                return None;
            };
            let along = plane.normal.cross(rng.unit_vector()).normalize();
            let dir = (along + rng.uniform(-1e-4, 1e-4) * plane.normal).normalize();
            let origin =
                plane.point + rng.uniform(-1e-3, 1e-3) * plane.normal + rng.uniform(-2.0, 2.0) * along;
            (origin, dir)
        }
        // Along an edge of the box: the line where two planes meet, or near it.
        4 => {
            let planes: Vec<Plane> = shapes
                .iter()
                .filter_map(|shape| match shape {
                    Shape::Plane(plane) => Some(*plane),
                    _ => None,
                })
                .collect();
            if planes.len() < 2 {
                return None;
            }
            let (a, b) = (planes[rng.index(planes.len())], planes[rng.index(planes.len())]);
            let dir = a.normal.cross(b.normal).try_normalize()?;
            // A point on both planes: the least-norm solution, from a and b's offsets.
            let (da, db) = (a.point.dot(a.normal), b.point.dot(b.normal));
            let cross = a.normal.cross(b.normal);
            let on = (da * b.normal.cross(cross) + db * cross.cross(a.normal)) / cross.length_squared();
            let nudge = if rng.uniform(0.0, 1.0) < 0.5 { Vec3::ZERO } else { 1e-5 * rng.unit_vector() };
            (on + nudge, if rng.uniform(0.0, 1.0) < 0.5 { dir } else { -dir })
        }
        // Tangent to a sphere, or nearly.
        5 => {
            let Shape::Sphere(sphere) = shape else {
                return None;
            };
            let normal = rng.unit_vector();
            let along = normal.cross(rng.unit_vector()).normalize();
            let dir = (along + rng.uniform(-1e-3, 1e-3) * normal).normalize();
            (sphere.center + sphere.radius * normal - rng.uniform(0.0, 3.0) * dir, dir)
        }
        // At a quad's edge or corner.
        _ => {
            let Shape::Quad(quad) = shape else {
                return None;
            };
            let (u, v) = match rng.index(3) {
                0 => (rng.index(2) as f32, rng.index(2) as f32),
                1 => (rng.uniform(0.0, 1.0), rng.index(2) as f32),
                _ => (rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0)),
            };
            let target = quad.point_at(u, v);
            let origin = inside(rng);
            (origin, (target - origin).try_normalize()?)
        }
    };
    dir.is_finite().then(|| Ray::new(origin, dir))
}

#[test]
fn few_shapes_lanes_find_the_scalar_tests_hits_bit_for_bit() {
    // (planes, spheres, quads): TP6 (five planes, two spheres, its quad light), the room's kind
    // (no plane, five quads: three packets of halves), two quads (one packet), seven and eight
    // quads (the 16-wide lanes), eight planes with the floor twice, three and four spheres with
    // the first twice, one and two planes (tested one by one).
    let mut rng = Rng(2026);
    for (planes, spheres, quads) in
        [(5, 2, 1), (0, 2, 5), (5, 2, 2), (5, 4, 7), (8, 3, 8), (7, 4, 3), (1, 2, 1), (2, 1, 0), (6, 0, 4)]
    {
        let shapes = scene(planes, spheres, quads);
        let geometry = Geometry::build(shapes.clone(), Vec::new());
        let (mut hits, mut rays) = (0, 0);
        for i in 0..30_000 {
            let Some(ray) = tricky_ray(&mut rng, &shapes, i % 7) else { continue };
            rays += 1;
            let t_max = if i % 3 == 0 { rng.uniform(0.01, 10.0) } else { f32::INFINITY };
            let expected = one_by_one(&shapes, &ray, t_max);
            let found = geometry.intersect(&ray, t_max);
            let context = format!("scene {planes}/{spheres}/{quads}, {ray:?}, t_max {t_max}");
            assert_eq!(found.as_ref().map(bits), expected.as_ref().map(bits), "{context}");
            assert_eq!(geometry.occluded(&ray, t_max), expected.is_some(), "{context}");
            hits += usize::from(expected.is_some());
            // A shadow ray toward the first quad (the light), stopped short of it as the
            // integrators stop theirs: that quad may go untested, the answer may not change.
            if let Some(Shape::Quad(light)) = shapes.get(planes + spheres) {
                let target = light.point_at(rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0));
                let Some(dir) = (target - ray.origin).try_normalize() else { continue };
                let reach = (target - ray.origin).length() * (1.0 - 1e-4);
                let shadow = Ray::new(ray.origin, dir);
                let blocked = one_by_one(&shapes, &shadow, reach).is_some();
                assert_eq!(
                    geometry.occluded_except(&shadow, reach, (planes + spheres) as u32),
                    blocked,
                    "{context}: shadow {shadow:?}"
                );
            }
        }
        // Rays from inside a box of planes nearly all hit something; without planes about a
        // third meet a sphere or a quad.
        assert!(hits > rays / 5, "scene {planes}/{spheres}/{quads}: {hits} hits of {rays} rays");
    }
}

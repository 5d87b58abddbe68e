//! [`Packet`]: up to four finite shapes of a BVH leaf, stored by coordinate ("structure of
//! arrays") so that a ray is tested against four triangles with 4-wide vector arithmetic.
//!
//! [`PlanePacket`]s do the same, eight wide, for the infinite planes, which are not in the BVH.
//!
//! A triangle packet holds triangles of meshes and the two halves of quads (a quad is tested
//! as its two triangles, lower half first, exactly as [`super::Quad`] does); a sphere packet
//! holds spheres. Lanes that hold nothing, and triangles or quads that can never be hit
//! because they have no normal, have NaN coordinates, which fail every comparison below.
//!
//! The 4-wide test of a triangle packet ([`Packet::test`]) evaluates, lane by lane, the same
//! f32 operations in the same order as [`intersect_triangle`] (translation, shear, edge
//! functions, determinant, scaled distance and its range check, then the division and the
//! distance's error bound), so it rejects exactly the triangles the scalar test rejects and
//! returns, bit for bit, the hits it returns. The lanes it cannot decide (an edge function
//! that rounds to exactly 0, which the scalar test recomputes in f64) go through
//! [`intersect_triangle`] itself. Watertightness and the conservative distance bound are
//! therefore kept. The division and the error bound are computed only when some lane passed
//! the range check, which most packets a ray meets do not. (Until 2026-12 the 4-wide test
//! stopped at the range check and every lane that passed was recomputed by the scalar test:
//! 7–8 % more instructions per incoherent shadow ray on a 79,600-triangle mesh, by callgrind.)

use glam::{Vec3, Vec4};
use wide::f32x8;

use super::rounding::gamma;
use super::triangle::{intersect_triangle, ShearedRay, TriangleHit};
use super::triangle_lanes::{test_triangles, LanesTest};
use super::{Plane, Quad, Ray, Sphere};

/// Shapes per packet.
pub(crate) const LANES: usize = 4;

/// What a lane of a [`Packet`] holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub(crate) enum Lane {
    /// Nothing (NaN coordinates).
    Empty,
    /// A triangle of a mesh with vertex normals (its hit record interpolates them).
    Triangle,
    /// A triangle of a mesh without vertex normals, whose hit record needs nothing but the
    /// packet (no look-up of the shape and its mesh: one cache miss less per incoherent ray).
    FlatTriangle,
    /// The triangle (corner, corner + e1, corner + e1 + e2) of a quad.
    QuadLower,
    /// The triangle (corner, corner + e1 + e2, corner + e2) of a quad.
    QuadUpper,
    /// A triangle or quad half without a normal: never hit (NaN coordinates).
    NoNormal,
    /// A sphere.
    Sphere,
}

/// Up to four triangles (or quad halves), or up to four spheres: 176 bytes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Packet {
    /// Triangle packets: rows 0–2 hold x, y, z of the first vertex, 3–5 of the second, 6–8 of
    /// the third; sphere packets: rows 0–2 the centre, row 3 the radius. One lane per shape.
    rows: [Vec4; 9],
    /// The index of each lane's shape in the list given to [`super::Geometry::build`].
    ids: [u32; LANES],
    lanes: [Lane; LANES],
    spheres: bool,
}

impl Packet {
    const EMPTY: Packet =
        Packet { rows: [Vec4::NAN; 9], ids: [u32::MAX; LANES], lanes: [Lane::Empty; LANES], spheres: false };

    /// True for a packet of spheres.
    #[inline]
    pub(crate) fn holds_spheres(&self) -> bool {
        self.spheres
    }

    /// What lane `lane` holds.
    #[inline]
    pub(crate) fn lane(&self, lane: usize) -> Lane {
        self.lanes[lane]
    }

    /// The shape index of lane `lane`.
    #[inline]
    pub(crate) fn id(&self, lane: usize) -> u32 {
        self.ids[lane]
    }

    /// Coordinate `row` of lane `lane`.
    #[inline]
    fn at(&self, row: usize, lane: usize) -> f32 {
        self.rows[row].as_ref()[lane]
    }

    /// The vertices of the triangle in lane `lane` of a triangle packet.
    #[inline]
    pub(crate) fn vertices(&self, lane: usize) -> [Vec3; 3] {
        std::array::from_fn(|v| {
            Vec3::new(self.at(3 * v, lane), self.at(3 * v + 1, lane), self.at(3 * v + 2, lane))
        })
    }

    /// The sphere in lane `lane` of a sphere packet.
    #[inline]
    pub(crate) fn sphere(&self, lane: usize) -> Sphere {
        let center = Vec3::new(self.at(0, lane), self.at(1, lane), self.at(2, lane));
        Sphere { center, radius: self.at(3, lane) }
    }

    /// The 4-wide test of a triangle packet against `ray` for hits with t in (0, `t_max`): the
    /// lanes that [`intersect_triangle`] hits, with their hits, and the lanes only it can
    /// decide; it surely misses every other lane (see the module notes). Each line repeats,
    /// four lanes at a time, the operation of [`intersect_triangle`] it is named after, with the
    /// same operands in the same order.
    #[inline(always)]
    pub(crate) fn test(&self, ray: &ShearedRay, t_max: f32) -> PacketTest {
        test_triangles(&self.rows, u32::MAX, ray, t_max)
    }

    /// The exact test of a candidate lane: [`intersect_triangle`] on its vertices.
    #[inline]
    pub(crate) fn intersect_lane(&self, lane: usize, ray: &ShearedRay, t_max: f32) -> Option<TriangleHit> {
        intersect_triangle(ray, &self.vertices(lane), t_max)
    }
}

/// What [`Packet::test`] decided for one ray.
pub(crate) type PacketTest = LanesTest<Vec4>;

/// Infinite planes in one packet: a TP6 box's five, or any scene's first eight.
pub(crate) const PLANE_LANES: usize = 8;

/// Up to eight infinite planes, tested together in one 8-wide vector: 224 bytes.
///
/// [`Self::nearest`] evaluates, eight lanes at a time, exactly the f32 operations of
/// [`Plane::distance`] that decide whether and where it hits (numerator, denominator, their
/// error bounds, the distance) with the same operands in the same order, so the lanes hit what
/// the scalar test hits at the same distance, bit for bit; the hit record is then built by
/// [`Plane::hit_at`]. Unused lanes are NaN and never hit. (Until 2026-12 the packets were four
/// wide, and the nearest lane's plane was tested again by [`Plane::distance`]: two packets and
/// a scalar test for the five planes of a TP6 box instead of one packet.)
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PlanePacket {
    /// x, y, z of a point of each plane.
    point: [f32x8; 3],
    /// x, y, z of each plane's unit normal.
    normal: [f32x8; 3],
    /// The index of each lane's plane in the list given to [`super::Geometry::build`].
    ids: [u32; PLANE_LANES],
}

impl PlanePacket {
    /// Packs `planes` (id, plane) eight at a time.
    pub(crate) fn pack(planes: &[(u32, Plane)]) -> Vec<PlanePacket> {
        planes
            .chunks(PLANE_LANES)
            .map(|chunk| {
                let mut point = [[f32::NAN; PLANE_LANES]; 3];
                let mut normal = [[f32::NAN; PLANE_LANES]; 3];
                let mut ids = [u32::MAX; PLANE_LANES];
                for (lane, (id, plane)) in chunk.iter().enumerate() {
                    ids[lane] = *id;
                    for axis in 0..3 {
                        point[axis][lane] = plane.point[axis];
                        normal[axis][lane] = plane.normal[axis];
                    }
                }
                PlanePacket { point: point.map(f32x8::new), normal: normal.map(f32x8::new), ids }
            })
            .collect()
    }

    /// The plane in lane `lane`, and its index.
    #[inline]
    pub(crate) fn plane(&self, lane: usize) -> (u32, Plane) {
        let at = |row: &[f32x8; 3]| {
            Vec3::new(row[0].as_array()[lane], row[1].as_array()[lane], row[2].as_array()[lane])
        };
        (self.ids[lane], Plane { point: at(&self.point), normal: at(&self.normal) })
    }

    /// A mask of the lanes that [`Plane::distance`] hits with t in (0, `t_max`) (all bits of
    /// the lane set), and their distances. Each line repeats, eight lanes at a time, the operation it
    /// is named after.
    #[inline(always)]
    fn hits(&self, ray: &Ray, t_max: f32) -> (f32x8, f32x8) {
        let [origin_x, origin_y, origin_z] = ray.origin.to_array().map(f32x8::splat);
        let [dir_x, dir_y, dir_z] = ray.dir.to_array().map(f32x8::splat);
        let [normal_x, normal_y, normal_z] = self.normal;
        // to_plane = point − origin.
        let (to_x, to_y, to_z) =
            (self.point[0] - origin_x, self.point[1] - origin_y, self.point[2] - origin_z);
        // Vec3::dot: (x·x' + y·y') + z·z'.
        let numerator = to_x * normal_x + to_y * normal_y + to_z * normal_z;
        let denominator = dir_x * normal_x + dir_y * normal_y + dir_z * normal_z;
        let (abs_x, abs_y, abs_z) = (normal_x.abs(), normal_y.abs(), normal_z.abs());
        let error_numerator =
            f32x8::splat(gamma(4)) * (to_x.abs() * abs_x + to_y.abs() * abs_y + to_z.abs() * abs_z);
        let error_denominator =
            f32x8::splat(gamma(3)) * (dir_x.abs() * abs_x + dir_y.abs() * abs_y + dir_z.abs() * abs_z);
        let t = numerator / denominator;
        let hit = numerator.abs().simd_gt(error_numerator)
            & denominator.abs().simd_gt(error_denominator)
            & t.simd_gt(f32x8::ZERO)
            & t.simd_lt(f32x8::splat(t_max));
        (hit, t)
    }

    /// The lane of the nearest plane hit with t in (0, `t_max`), the first one among equal
    /// distances (as a scan with a shrinking `t_max` finds it), and its distance: bit for bit
    /// what [`Plane::distance`] returns for that plane.
    #[inline(always)]
    pub(crate) fn nearest(&self, ray: &Ray, t_max: f32) -> Option<(usize, f32)> {
        let (hits, t) = self.hits(ray, t_max);
        if !hits.any() {
            return None;
        }
        // The smallest distance among the lanes hit (a tree of minima, without branches: how
        // many planes lie ahead changes from ray to ray), then the first lane at it.
        let t = hits.select(t, f32x8::splat(f32::INFINITY));
        let d = t.as_array();
        let least = |a: f32, b: f32| if b < a { b } else { a };
        let nearest =
            least(least(least(d[0], d[1]), least(d[2], d[3])), least(least(d[4], d[5]), least(d[6], d[7])));
        let lane = t.simd_eq(f32x8::splat(nearest)).to_bitmask().trailing_zeros() as usize;
        Some((lane, nearest))
    }

    /// True when a plane of the packet is hit with t in (0, `t_max`).
    #[inline(always)]
    pub(crate) fn any(&self, ray: &Ray, t_max: f32) -> bool {
        self.hits(ray, t_max).0.any()
    }
}

/// The lanes `shape` takes in the 4-wide tests of a leaf as [`pack_leaf`] packs it (the BVH's
/// cost model, [`super::bvh::BvhPrimitive::lanes`]): a triangle one, a quad its two halves, a
/// sphere a whole packet's worth, since spheres are tested one by one.
pub(crate) fn leaf_lanes(shape: &super::Shape) -> u32 {
    use super::Shape;
    match shape {
        Shape::Sphere(_) => LANES as u32,
        Shape::Quad(_) => 2,
        Shape::Triangle { .. } | Shape::Plane(_) => 1,
    }
}

/// Packs the shapes `(id, shape)` of one leaf, in order: triangles and quads (two lanes each)
/// into triangle packets, spheres into sphere packets. `triangle_of(id)` gives the vertices of a
/// mesh triangle and whether its mesh has vertex normals. Appends to `packets`.
pub(crate) fn pack_leaf<'a>(
    shapes: impl Iterator<Item = (u32, &'a super::Shape)>,
    triangle_of: impl Fn(u32) -> ([Vec3; 3], bool),
    packets: &mut Vec<Packet>,
) {
    use super::Shape;
    let mut triangles = Vec::new();
    let mut spheres = Vec::new();
    for (id, shape) in shapes {
        match shape {
            Shape::Triangle { .. } => {
                let (vertices, smooth) = triangle_of(id);
                triangles.push((id, if smooth { Lane::Triangle } else { Lane::FlatTriangle }, vertices));
            }
            Shape::Quad(quad) => {
                let [lower, upper] = quad.halves();
                // Both halves share the quad's normal, edge1 × edge2 (Quad::hit_record).
                let hittable = quad.edge1.cross(quad.edge2).try_normalize().is_some();
                triangles.push((id, if hittable { Lane::QuadLower } else { Lane::NoNormal }, lower));
                triangles.push((id, if hittable { Lane::QuadUpper } else { Lane::NoNormal }, upper));
            }
            Shape::Sphere(sphere) => spheres.push((id, *sphere)),
            Shape::Plane(_) => unreachable!("planes are not in the BVH"),
        }
    }
    for chunk in triangles.chunks(LANES) {
        let mut packet = Packet::EMPTY;
        for (lane, &(id, kind, vertices)) in chunk.iter().enumerate() {
            let [v0, v1, v2] = vertices;
            let mesh_triangle = matches!(kind, Lane::Triangle | Lane::FlatTriangle);
            let kind = if mesh_triangle && (v1 - v0).cross(v2 - v0).try_normalize().is_none() {
                Lane::NoNormal
            } else {
                kind
            };
            (packet.ids[lane], packet.lanes[lane]) = (id, kind);
            if kind != Lane::NoNormal {
                for (v, vertex) in vertices.iter().enumerate() {
                    for axis in 0..3 {
                        packet.rows[3 * v + axis][lane] = vertex[axis];
                    }
                }
            }
        }
        packets.push(packet);
    }
    for chunk in spheres.chunks(LANES) {
        let mut packet = Packet { spheres: true, ..Packet::EMPTY };
        for (lane, &(id, sphere)) in chunk.iter().enumerate() {
            (packet.ids[lane], packet.lanes[lane]) = (id, Lane::Sphere);
            for axis in 0..3 {
                packet.rows[axis][lane] = sphere.center[axis];
            }
            packet.rows[3][lane] = sphere.radius;
        }
        packets.push(packet);
    }
}

/// The quad parameters (u, v) of a hit on the half in lane kind `lane` (see [`Quad::halves`]).
#[inline]
pub(crate) fn quad_uv(lane: Lane, hit: &TriangleHit) -> (f32, f32) {
    Quad::half_uv(usize::from(lane == Lane::QuadUpper), hit)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::test_util::Rng;
    use crate::geometry::{Mesh, Ray, Shape};

    /// Packs `triangles` (as mesh triangles) into packets.
    fn packets_of(triangles: &[[Vec3; 3]]) -> Vec<Packet> {
        let mesh = Mesh {
            positions: triangles.iter().flatten().copied().collect(),
            normals: None,
            triangles: (0..triangles.len() as u32).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect(),
        };
        let shapes: Vec<Shape> =
            (0..triangles.len() as u32).map(|tri| Shape::Triangle { mesh: 0, tri }).collect();
        let mut packets = Vec::new();
        pack_leaf(
            shapes.iter().enumerate().map(|(id, s)| (id as u32, s)),
            |id| (mesh.triangle(id), false),
            &mut packets,
        );
        packets
    }

    #[test]
    fn packet_test_hits_what_the_scalar_test_hits() {
        // Random triangles (some degenerate: collinear or repeated vertices), rays aimed at
        // their vertices, edges and interiors (where edge functions round to 0 or nearly), with
        // and without a t_max: the 4-wide test's hits are bit for bit those of
        // `intersect_triangle`, and the lanes it leaves to it are decided there.
        let mut rng = Rng::new(31);
        let (mut hits, mut undecided) = (0, 0);
        for _ in 0..2_000 {
            let triangles: Vec<[Vec3; 3]> = (0..7)
                .map(|i| {
                    let centre = rng.point_in(Vec3::splat(-10.0), Vec3::splat(10.0));
                    let size = rng.log_uniform(0.01, 10.0);
                    let [a, b] = [centre + size * rng.unit_vector(), centre + size * rng.unit_vector()];
                    let c = match i {
                        5 => a + 0.5 * (b - a), // collinear
                        6 => a,                 // repeated vertex
                        _ => centre + size * rng.unit_vector(),
                    };
                    [a, b, c]
                })
                .collect();
            let packets = packets_of(&triangles);
            assert_eq!(packets.len(), 2);
            for _ in 0..20 {
                let [a, b, c] = triangles[rng.uniform(0.0, 7.0) as usize];
                let target = match rng.uniform(0.0, 3.0) as u32 {
                    0 => a,
                    1 => a + rng.uniform(0.0, 1.0) * (b - a),
                    _ => {
                        let (u, v) = (rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0));
                        if u + v < 1.0 {
                            a + u * (b - a) + v * (c - a)
                        } else {
                            b + (1.0 - u) * (a - b) + (1.0 - v) * (c - a)
                        }
                    }
                };
                let from = target + rng.log_uniform(0.1, 100.0) * rng.unit_vector();
                let ray = ShearedRay::new(Ray::new(from, (target - from).normalize()));
                let t_max = if rng.uniform(0.0, 1.0) < 0.5 { f32::INFINITY } else { rng.uniform(0.1, 50.0) };
                for (index, packet) in packets.iter().enumerate() {
                    let test = packet.test(&ray, t_max);
                    assert_eq!(test.hits & test.undecided, 0, "a lane both decided and not");
                    for lane in 0..LANES {
                        let bit = 1 << lane;
                        let Some(&vertices) = triangles.get(index * LANES + lane) else {
                            assert_eq!((test.hits | test.undecided) & bit, 0, "an empty lane is never hit");
                            continue;
                        };
                        let expected = intersect_triangle(&ray, &vertices, t_max);
                        if test.undecided & bit != 0 {
                            undecided += 1;
                            assert_eq!(packet.intersect_lane(lane, &ray, t_max), expected);
                        } else {
                            let found = (test.hits & bit != 0).then(|| test.hit(lane));
                            assert_eq!(found, expected, "lane {lane} of {vertices:?}");
                        }
                        hits += usize::from(expected.is_some());
                    }
                }
            }
        }
        assert!(hits > 10_000, "only {hits} hits");
        assert!(undecided > 100, "only {undecided} lanes left to the scalar test");
    }

    #[test]
    fn triangles_without_a_normal_are_never_candidates() {
        // Three collinear vertices: the scalar test never hits them (zero determinant) and the
        // hit record could not be built; the packet marks the lane and fills it with NaN.
        let flat = [Vec3::ZERO, Vec3::X, 2.0 * Vec3::X];
        let packets = packets_of(&[flat]);
        assert_eq!(packets[0].lane(0), Lane::NoNormal);
        assert_eq!(packets[0].lane(1), Lane::Empty);
        let ray = ShearedRay::new(Ray::new(Vec3::new(0.5, 0.0, 1.0), -Vec3::Z));
        let test = packets[0].test(&ray, f32::INFINITY);
        assert_eq!((test.hits, test.undecided), (0, 0));
    }
}

//! [`QuadLanes`]: the two triangles of each of up to eight quads in the sixteen lanes of one
//! vector, so that a ray tests every quad of a small scene (the glass-and-mirror room's walls and
//! light, TP6's quad light) in one pass.
//!
//! The test is [`super::packet::Packet::test`]'s, sixteen lanes wide instead of four: lane by
//! lane the same f32 operations of [`intersect_triangle`] in the same order (translation, shear,
//! edge functions, determinant, scaled distance and its range check, the division and the
//! distance's error bound), so it rejects exactly what the scalar test rejects and returns its
//! hits bit for bit; lanes with an edge function of exactly 0 are left to [`intersect_triangle`]
//! itself, which recomputes it in f64. Watertightness along the quads' shared edges and the
//! conservative distance bound are therefore those of the scalar test. The lanes keep the order
//! of the 4-wide packets they are copied from, so that among hits at equal distances the search
//! keeps the same one. Unused lanes hold NaN, which fails every comparison.
//!
//! Each lane also keeps its quad's corner, edges and unit normal (`edge1 × edge2` normalised, as
//! [`Quad::hit_record`] computes it on every call), so that the hit record of the nearest hit
//! needs neither the shape list nor a square root.

use glam::Vec3;
use wide::f32x16;

use super::packet::{quad_uv, Lane, Packet, LANES as PACKET_LANES};
use super::triangle::{intersect_triangle, ShearedRay, TriangleHit};
use super::triangle_lanes::{test_triangles, LanesTest};
use super::{Hit, Quad};

/// Quad halves tested at once: eight quads.
pub(crate) const LANES: usize = 16;

/// The halves of up to eight quads, by coordinate ("structure of arrays"): 1.7 kB.
#[derive(Clone, Debug)]
pub(crate) struct QuadLanes {
    /// Rows 0–2: x, y, z of each half's first vertex; 3–5 of its second; 6–8 of its third.
    rows: [f32x16; 9],
    /// Each lane's shape index (in the list given to [`super::Geometry::build`]).
    ids: [u32; LANES],
    /// Each lane's half (lower or upper, as [`quad_uv`] reads it).
    halves: [Lane; LANES],
    /// Each lane's quad and its unit normal, for the hit record.
    quads: [(Quad, Vec3); LANES],
    /// The lanes in use.
    used: u32,
}

/// What [`QuadLanes::test`] decided for one ray.
pub(crate) type QuadLanesTest = LanesTest<f32x16>;

impl QuadLanes {
    /// The quad halves of `packets`, in packet and lane order (`quad_of(id)` gives the quad of
    /// shape `id`); `None` if they are more than [`LANES`], or if some lane holds anything but a
    /// half of a quad with a normal.
    pub(crate) fn of<'a>(
        packets: impl Iterator<Item = &'a Packet>,
        quad_of: impl Fn(u32) -> Quad,
    ) -> Option<Self> {
        let mut rows = [[f32::NAN; LANES]; 9];
        let mut ids = [u32::MAX; LANES];
        let mut halves = [Lane::Empty; LANES];
        let mut quads = [(Quad { corner: Vec3::NAN, edge1: Vec3::NAN, edge2: Vec3::NAN }, Vec3::NAN); LANES];
        let mut count = 0;
        for packet in packets {
            for lane in (0..PACKET_LANES).filter(|&lane| packet.lane(lane) != Lane::Empty) {
                if !matches!(packet.lane(lane), Lane::QuadLower | Lane::QuadUpper) || count == LANES {
                    return None;
                }
                let quad = quad_of(packet.id(lane));
                let normal = quad.edge1.cross(quad.edge2).try_normalize()?;
                for (v, vertex) in packet.vertices(lane).iter().enumerate() {
                    for axis in 0..3 {
                        rows[3 * v + axis][count] = vertex[axis];
                    }
                }
                (ids[count], halves[count], quads[count]) =
                    (packet.id(lane), packet.lane(lane), (quad, normal));
                count += 1;
            }
        }
        let used = if count == LANES { u32::MAX >> 16 } else { (1 << count) - 1 };
        Some(Self { rows: rows.map(f32x16::new), ids, halves, quads, used })
    }

    /// The 16-wide test against `ray` for hits with t in (0, `t_max`): the lanes that
    /// [`intersect_triangle`] hits, with their hits, and the lanes only it can decide; it surely
    /// misses every other lane (see the module notes). Each line repeats the operation of
    /// [`intersect_triangle`] (and of [`Packet::test`]) it is named after, with the same
    /// operands in the same order.
    #[inline(always)]
    pub(crate) fn test(&self, ray: &ShearedRay, t_max: f32) -> QuadLanesTest {
        test_triangles(&self.rows, self.used, ray, t_max)
    }

    /// The exact test of a candidate lane: [`intersect_triangle`] on its vertices.
    #[inline]
    pub(crate) fn intersect_lane(&self, lane: usize, ray: &ShearedRay, t_max: f32) -> Option<TriangleHit> {
        let at = |row: usize| self.rows[row].as_array()[lane];
        let vertices = std::array::from_fn(|v| Vec3::new(at(3 * v), at(3 * v + 1), at(3 * v + 2)));
        intersect_triangle(ray, &vertices, t_max)
    }

    /// The nearest hit with t in (0, `t_limit`) among the lanes, as (lane, hit): what testing the
    /// 4-wide packets one after another with a shrinking limit finds (the first of equal
    /// distances; [`LanesTest::nearer`]).
    #[inline(always)]
    pub(crate) fn nearest(&self, ray: &ShearedRay, t_limit: f32) -> Option<(usize, TriangleHit)> {
        let mut nearest = None;
        self.test(ray, t_limit).nearer(
            t_limit,
            |lane, limit| self.intersect_lane(lane, ray, limit),
            |lane, hit| nearest = Some((lane, hit)),
        );
        nearest
    }

    /// Whether some lane is hit with t in (0, `t_max`).
    #[inline(always)]
    pub(crate) fn any(&self, ray: &ShearedRay, t_max: f32) -> bool {
        self.test(ray, t_max).any(|lane| self.intersect_lane(lane, ray, t_max).is_some())
    }

    /// The hit record of `hit` on lane `lane`: [`Quad::hit_record`]'s, bit for bit (the same
    /// point, the normal it computes, kept here).
    #[inline]
    pub(crate) fn hit_record(&self, lane: usize, hit: &TriangleHit) -> Hit {
        let (u, v) = quad_uv(self.halves[lane], hit);
        let (quad, normal) = &self.quads[lane];
        Hit {
            t: hit.t,
            point: quad.point_at(u, v),
            normal: *normal,
            shading_normal: *normal,
            prim: self.ids[lane],
        }
    }
}

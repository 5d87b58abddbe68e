//! [`Geometry`]: every shape of the scene, with a BVH over the finite ones and the infinite planes
//! tested separately.
//!
//! Planes are tested first, eight at a time (a scene has a handful: `PlanePacket`), so that
//! their hit bounds the BVH traversal; then the BVH over spheres, quads and triangles. A scene of
//! at most `FEW_SPHERES` (4) spheres, at most `FEW_QUADS` (8) quads and nothing else finite (the
//! lab and validation scenes, TP6's quad light, the glass-and-mirror room's four walls and light)
//! skips the BVH: its spheres are tested together in four lanes (`SphereLanes`), and its quads'
//! halves in their 4-wide packets one after another when they fill at most `FEW_QUAD_PACKETS`
//! (3: TP6's light, the room's five quads), else all at once sixteen lanes wide (`QuadLanes`);
//! the quads are skipped when there are at most `FEW_PLANE_CHECKS` (2) and the ray leaves every
//! quad's plane. The planes of any scene with at most `FEW_PLANES` (2) are tested one by one.
//! Every vector test repeats its scalar test's f32 operations lane by lane, so the hits are the
//! same, bit for bit. Each ray is prepared once (watertight shear for triangles and quads,
//! inverse direction for the boxes).
//!
//! The finite shapes are copied into the BVH's leaves as `Packet`s of four (a quad as its two
//! triangles), in leaf order, so that a leaf is read from consecutive memory instead of through
//! `Shape` → `Mesh` → vertex indices → positions, and four triangles are tested at once. The
//! exact intersection routines are the shapes' own ([`super::triangle::intersect_triangle`],
//! [`super::Sphere::intersect`]) on the same numbers, so hits are bit-identical to [`Shape::intersect`]'s.
//! For triangles and quads the search keeps only the distance and barycentrics of the nearest
//! candidate; its hit record (normal, shading normal, point) is built once, for the hit that
//! is returned.

use glam::Vec3;

use super::aabb::Aabb;
use super::bvh::{Bvh, BvhPrimitive, BvhStats, PACKET_RAYS};
use super::mesh::flat_hit_record;
use super::packet::{leaf_lanes, pack_leaf, quad_uv, Lane, Packet, PlanePacket};
use super::quad_lanes::QuadLanes;
use super::sphere_lanes::SphereLanes;
use super::triangle::{ShearedRay, TriangleHit};
use super::{Hit, Mesh, Plane, Ray, Shape};

/// At most this many spheres (and no other finite shape but [`FEW_QUADS`] quads) are tested one
/// by one.
const FEW_SPHERES: usize = 4;
/// At most this many quads (beside at most [`FEW_SPHERES`] spheres, and no triangle) are tested
/// one by one: the quad light of a TP6 box, the five quads of the glass-and-mirror room (its
/// walls and light; 1.12–1.14× less CPU per sample there than through its BVH, same hits:
/// validation/bench/PROFILE.md). Eight quads' sixteen halves fill one `QuadLanes`.
const FEW_QUADS: usize = 8;
/// At most this many quads are first checked one by one for a ray that surely misses them all
/// (`Few::quads_missed`): TP6's quad light. The glass-and-mirror room's five quads went 2–3 %
/// faster without the checks (validation/bench/PROFILE.md).
const FEW_PLANE_CHECKS: usize = 2;
/// At most this many 4-wide packets of quad halves (six quads) are tested one after another
/// instead of the 16-wide `QuadLanes`: TP6's one quad in one packet took 19 % less CPU per
/// render, the room's five quads in three packets 4.4 % less, although in a loop of rays alone
/// the 16 lanes test the room's quads faster (validation/bench/PROFILE.md).
const FEW_QUAD_PACKETS: usize = 3;
/// At most this many infinite planes are tested one by one (more go eight at a time, as the
/// plane packets test them: cheaper for the five planes of a TP6 box).
const FEW_PLANES: usize = 2;

/// The nearest candidate found so far, before its hit record is built.
#[derive(Clone, Copy, Debug)]
enum Nearest {
    /// A triangle or quad half: lane `lane` of packet `packet`.
    Triangle { packet: u32, lane: u8, hit: TriangleHit },
    /// A sphere, whose hit record is built by its test.
    Sphere(Hit),
}

/// The nearest plane found so far, before its hit record is built: most rays that meet a
/// floor plane meet a nearer shape too, whose hit then replaces it.
#[derive(Clone, Copy, Debug)]
struct PlaneHit {
    prim: u32,
    plane: Plane,
    t: f32,
}

impl PlaneHit {
    /// The hit record, as [`Plane::intersect`] gives it.
    #[inline(always)]
    fn record(&self, ray: &Ray) -> Hit {
        self.plane.hit_at(ray, self.t, self.prim)
    }
}

/// The intersectable scene.
#[derive(Debug, Clone)]
pub struct Geometry {
    shapes: Vec<Shape>,
    meshes: Vec<Mesh>,
    /// The infinite planes, four to a packet.
    planes: Vec<PlanePacket>,
    /// Over every other shape; its leaves are runs of `packets`.
    bvh: Bvh,
    /// The finite shapes in leaf order.
    packets: Vec<Packet>,
    /// The packets of the BVH's only leaf, when it has one (a scene of a handful of finite
    /// shapes, which the builder keeps in one leaf): rays test them directly, without preparing
    /// the 8-wide box tests for a root node whose one box holds everything. A third of the
    /// instructions of a ray in the bundled scenes went to that traversal.
    single_leaf: Option<(u32, u32)>,
    /// The spheres and quads, when the finite shapes are at most [`FEW_SPHERES`] spheres and
    /// [`FEW_QUADS`] quads (the TP6 and validation scenes of spheres, planes, quad walls and a quad light):
    /// rays test them and the planes one after another, in the order given, without the packets
    /// and the BVH, whose bookkeeping cost more than the tests (17 % of the instructions of the
    /// ball-lens caustic benchmark; a third of the geometry's time in TP6 with its quad light).
    few: Option<Few>,
    /// The infinite planes one by one, in order (tested so when there are at most
    /// [`FEW_PLANES`]).
    plane_list: Vec<(u32, Plane)>,
}

/// The finite shapes of a scene small enough to test one by one (see `Geometry::few`).
#[derive(Debug, Clone)]
struct Few {
    /// The spheres, tested together (`SphereLanes`).
    spheres: SphereLanes,
    /// Each quad's id, corner and unit normal (`edge1 × edge2` normalised; none is degenerate),
    /// for [`leaves_quad_plane`].
    quads: Vec<(u32, Vec3, Vec3)>,
    /// The quads' halves, by the test that searches them.
    halves: FewQuads,
}

/// How a small scene's quad halves are searched (see `Few`).
// One per scene: the lanes' size costs nothing, a box would add a load to every ray.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone)]
enum FewQuads {
    /// The 4-wide packets that hold them, in leaf order, one after another: when they are at
    /// most [`FEW_QUAD_PACKETS`].
    Packets(Vec<Packet>),
    /// All of them in one 16-wide pass (the scalar test of each half costs more): when there
    /// are more packets.
    Lanes(QuadLanes),
}

impl Few {
    /// The spheres and quads of `shapes`, if they are all its finite shapes, at most
    /// [`FEW_SPHERES`] and [`FEW_QUADS`] of them, and no quad is degenerate; `packets` are the
    /// BVH's leaves.
    fn of(shapes: &[Shape], packets: &[Packet]) -> Option<Self> {
        let mut spheres = Vec::new();
        let mut quads = Vec::new();
        for (id, shape) in shapes.iter().enumerate() {
            match shape {
                Shape::Plane(_) => {}
                Shape::Sphere(sphere) => spheres.push((id as u32, *sphere)),
                Shape::Quad(quad) => {
                    quads.push((id as u32, quad.corner, quad.edge1.cross(quad.edge2).try_normalize()?))
                }
                Shape::Triangle { .. } => return None,
            }
        }
        if spheres.len() > FEW_SPHERES || quads.len() > FEW_QUADS {
            return None;
        }
        let quad_of = |id: u32| match shapes[id as usize] {
            Shape::Quad(quad) => quad,
            _ => unreachable!("quad lanes hold quads"),
        };
        let quad_packets: Vec<Packet> =
            packets.iter().filter(|packet| !packet.holds_spheres()).copied().collect();
        let halves = if quad_packets.len() <= FEW_QUAD_PACKETS {
            FewQuads::Packets(quad_packets)
        } else {
            FewQuads::Lanes(QuadLanes::of(quad_packets.iter(), quad_of)?)
        };
        Some(Self { spheres: SphereLanes::of(&spheres)?, quads, halves })
    }

    /// Whether every quad but `except` (a shape id, or `u32::MAX` for none) is surely missed by
    /// `ray` ([`leaves_quad_plane`]), checked only for at most [`FEW_PLANE_CHECKS`] quads: for
    /// more, the checks cost more than the 16-wide test they may save (most rays of a room of
    /// quads start on one of them, whose plane they do not surely leave).
    #[inline(always)]
    fn quads_missed(&self, ray: &Ray, except: u32) -> bool {
        self.quads.len() <= FEW_PLANE_CHECKS
            && self.quads.iter().all(|&(id, corner, normal)| {
                id == except || leaves_quad_plane(ray.origin, ray.dir, corner, normal)
            })
    }
}

/// Whether a ray from `origin` along `dir` surely misses the plane of a quad (corner `corner`,
/// unit normal `normal`) at every t > 0: the origin lies off the plane by more than 10⁻⁴ of its
/// distance to the corner (a thousand times the rounding of the signed distance) and the ray
/// moves away from it. The watertight test then finds no hit either (its t would be negative by
/// far more than its rounding), so skipping it changes no hit.
#[inline(always)]
fn leaves_quad_plane(origin: Vec3, dir: Vec3, corner: Vec3, normal: Vec3) -> bool {
    let offset = origin - corner;
    let side = offset.dot(normal);
    let heading = dir.dot(normal);
    side * heading > 0.0 && side.abs() > 1e-4 * offset.abs().max_element()
}

impl Geometry {
    /// Builds the acceleration structure over `shapes` (triangles refer into `meshes`).
    ///
    /// # Panics
    /// If there are 2³² shapes or more, if a triangle refers to a mesh or triangle that does not
    /// exist, or if a mesh fails [`Mesh::validate`] (meshes from [`Mesh::load_obj`] and
    /// [`Mesh::triangular_prism`] always pass).
    pub fn build(shapes: Vec<Shape>, meshes: Vec<Mesh>) -> Self {
        assert!(u32::try_from(shapes.len()).is_ok(), "{} shapes: at most 2³² − 1", shapes.len());
        for (index, mesh) in meshes.iter().enumerate() {
            if let Err(error) = mesh.validate() {
                panic!("mesh {index} is invalid: {error}");
            }
        }
        let mut planes = Vec::new();
        let mut primitives = Vec::with_capacity(shapes.len());
        for (index, shape) in shapes.iter().enumerate() {
            if let Shape::Triangle { mesh, tri } = *shape {
                let exists = meshes.get(mesh as usize).is_some_and(|m| (tri as usize) < m.triangles.len());
                assert!(exists, "shape {index} is triangle {tri} of mesh {mesh}, which does not exist");
            }
            match shape.bounds(&meshes) {
                Some(bounds) => {
                    primitives.push(BvhPrimitive { id: index as u32, bounds, lanes: leaf_lanes(shape) })
                }
                None => match shape {
                    Shape::Plane(plane) => planes.push((index as u32, *plane)),
                    _ => unreachable!("only planes are unbounded"),
                },
            }
        }
        let (mut bvh, ids) = Bvh::build(primitives);
        let triangle_of = |id: u32| match shapes[id as usize] {
            Shape::Triangle { mesh, tri } => {
                let mesh = &meshes[mesh as usize];
                (mesh.triangle(tri), mesh.normals.is_some())
            }
            _ => unreachable!("only triangles are looked up in meshes"),
        };
        // Each leaf, in leaf order, becomes its own run of packets.
        let mut leaves = bvh.leaves();
        leaves.sort_unstable();
        let mut packets = Vec::with_capacity(ids.len().div_ceil(super::packet::LANES));
        let mut runs = Vec::with_capacity(leaves.len());
        for &(first, count) in &leaves {
            let start = packets.len() as u32;
            let leaf = &ids[first as usize..(first + count) as usize];
            pack_leaf(leaf.iter().map(|&id| (id, &shapes[id as usize])), triangle_of, &mut packets);
            runs.push((start, packets.len() as u32 - start));
        }
        bvh.map_leaves(|first, _| {
            let leaf = leaves.binary_search_by_key(&first, |&(first, _)| first).expect("a leaf of the BVH");
            runs[leaf]
        });
        let packets = super::huge_pages::on_huge_pages(packets);
        let single_leaf = match bvh.leaves()[..] {
            [leaf] => Some(leaf),
            _ => None,
        };
        let few = Few::of(&shapes, &packets);
        Self {
            shapes,
            meshes,
            planes: PlanePacket::pack(&planes),
            plane_list: planes,
            bvh,
            packets,
            single_leaf,
            few,
        }
    }

    /// The nearest hit with t in (0, `t_max`).
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let Some(few) = &self.few else {
            return self.intersect_bvh(ray, t_max);
        };
        let (plane, mut t_limit) = self.nearest_plane(ray, t_max);
        let sphere = few.spheres.nearest(ray, t_limit);
        if let Some(sphere) = &sphere {
            t_limit = sphere.t;
        }
        if !few.quads_missed(ray, u32::MAX) {
            let sheared = ShearedRay::new(*ray);
            match &few.halves {
                FewQuads::Packets(packets) => {
                    let mut nearest = None;
                    for packet in packets {
                        t_limit = packet.test(&sheared, t_limit).nearer(
                            t_limit,
                            |lane, limit| packet.intersect_lane(lane, &sheared, limit),
                            |lane, hit| nearest = Some((packet, lane, hit)),
                        );
                    }
                    if let Some((packet, lane, hit)) = nearest {
                        let (u, v) = quad_uv(packet.lane(lane), &hit);
                        return match self.shapes[packet.id(lane) as usize] {
                            Shape::Quad(quad) => quad.hit_record(hit.t, u, v, packet.id(lane)),
                            _ => None,
                        };
                    }
                }
                FewQuads::Lanes(lanes) => {
                    if let Some((lane, hit)) = lanes.nearest(&sheared, t_limit) {
                        return Some(lanes.hit_record(lane, &hit));
                    }
                }
            }
        }
        match sphere {
            Some(sphere) => Some(sphere.record()),
            None => plane.map(|plane| plane.record(ray)),
        }
    }

    /// [`Self::intersect`] for any scene but a few spheres and planes: the planes, then the BVH
    /// (or its single leaf). Kept apart so that the few-spheres test above does not pay this
    /// search's register saves on every call.
    #[inline(never)]
    fn intersect_bvh(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let (nearest_plane, t_limit) = self.nearest_plane(ray, t_max);
        // Prepared on the first triangle packet: rays that meet only spheres never need it.
        let mut sheared: Option<ShearedRay> = None;
        let mut nearest: Option<Nearest> = None;
        let found = match self.single_leaf {
            Some((first, count)) => {
                self.nearest_in_leaf(ray, &mut sheared, first, count, t_limit, &mut nearest).is_some()
            }
            None => self.bvh.closest_hit(ray, t_limit, |first, count, t_limit| {
                self.nearest_in_leaf(ray, &mut sheared, first, count, t_limit, &mut nearest)
            }),
        };
        if found {
            nearest.and_then(|nearest| self.hit_record(nearest))
        } else {
            nearest_plane.map(|plane| plane.record(ray))
        }
    }

    /// The nearest hits of up to [`PACKET_RAYS`] rays traced together (`hits[i]` for `rays[i]`
    /// with `t_max[i]`): what [`Self::intersect`] finds for each, but with one visit of a BVH
    /// node for all the rays that enter it, which pays for coherent rays (neighbouring camera
    /// rays: see [`super::bvh`]'s packet traversal). Among hits at exactly the same distance,
    /// the one reported may differ from [`Self::intersect`]'s.
    ///
    /// # Panics
    /// If `rays` holds more than [`PACKET_RAYS`] rays, or `t_max` or `hits` another number.
    pub fn intersect_packet(&self, rays: &[Ray], t_max: &[f32], hits: &mut [Option<Hit>]) {
        let count = rays.len();
        assert!(count <= PACKET_RAYS, "{count} rays: a packet holds at most {PACKET_RAYS}");
        assert!(t_max.len() == count && hits.len() == count, "one t_max and one hit per ray");
        let Some(&first) = rays.first() else {
            return;
        };
        let packet: [Ray; PACKET_RAYS] = std::array::from_fn(|lane| rays.get(lane).copied().unwrap_or(first));
        let lanes = Bvh::coherent_lanes(&packet, (1u32 << count) - 1);
        for lane in (0..count).filter(|&lane| lanes & (1 << lane) == 0) {
            hits[lane] = self.intersect(&rays[lane], t_max[lane]);
        }
        if lanes == 0 {
            return;
        }
        let mut nearest_plane = [None; PACKET_RAYS];
        let mut t_limit = [0.0; PACKET_RAYS];
        for lane in (0..count).filter(|&lane| lanes & (1 << lane) != 0) {
            (nearest_plane[lane], t_limit[lane]) = self.nearest_plane(&packet[lane], t_max[lane]);
        }
        let mut sheared = [None; PACKET_RAYS];
        let mut nearest = [None; PACKET_RAYS];
        let found =
            self.bvh.closest_hit_packet(&packet, lanes, &mut t_limit, |lane, first, leaf, t_limit| {
                self.nearest_in_leaf(
                    &packet[lane],
                    &mut sheared[lane],
                    first,
                    leaf,
                    t_limit,
                    &mut nearest[lane],
                )
            });
        for (lane, hit) in hits.iter_mut().enumerate().filter(|&(lane, _)| lanes & (1 << lane) != 0) {
            *hit = if found & (1 << lane) != 0 {
                nearest[lane].and_then(|nearest| self.hit_record(nearest))
            } else {
                nearest_plane[lane].map(|plane| plane.record(&packet[lane]))
            };
        }
    }

    /// The nearest infinite plane hit with t in (0, `t_max`), and the distance the BVH search
    /// must then beat (its t, or `t_max`): the first among equal distances, whether the planes
    /// are few enough to be tested one by one or go eight at a time.
    #[inline(always)]
    fn nearest_plane(&self, ray: &Ray, t_max: f32) -> (Option<PlaneHit>, f32) {
        let mut nearest_plane = None;
        let mut t_limit = t_max;
        if self.plane_list.len() <= FEW_PLANES {
            for &(prim, plane) in &self.plane_list {
                if let Some(t) = plane.distance(ray, t_limit) {
                    t_limit = t;
                    nearest_plane = Some(PlaneHit { prim, plane, t });
                }
            }
            return (nearest_plane, t_limit);
        }
        for packet in &self.planes {
            // The packet repeats Plane::distance's arithmetic: its t is the scalar test's.
            if let Some((lane, t)) = packet.nearest(ray, t_limit) {
                let (prim, plane) = packet.plane(lane);
                t_limit = t;
                nearest_plane = Some(PlaneHit { prim, plane, t });
            }
        }
        (nearest_plane, t_limit)
    }

    /// True when an infinite plane is hit with t in (0, `t_max`).
    #[inline(always)]
    fn planes_occlude(&self, ray: &Ray, t_max: f32) -> bool {
        if self.plane_list.len() <= FEW_PLANES {
            self.plane_list.iter().any(|(_, plane)| plane.distance(ray, t_max).is_some())
        } else {
            self.planes.iter().any(|packet| packet.any(ray, t_max))
        }
    }

    /// The leaf test of the nearest-hit search: the packets `first..first + count`, for hits
    /// closer than `t_limit`. Records the nearest in `nearest` and returns its distance, if
    /// any; `sheared` is `ray` prepared for triangles, made on the first triangle packet.
    #[inline(always)]
    fn nearest_in_leaf(
        &self,
        ray: &Ray,
        sheared: &mut Option<ShearedRay>,
        first: u32,
        count: u32,
        mut t_limit: f32,
        nearest: &mut Option<Nearest>,
    ) -> Option<f32> {
        let mut found = None;
        for index in first..first + count {
            let packet = &self.packets[index as usize];
            if packet.holds_spheres() {
                for lane in 0..super::packet::LANES {
                    if packet.lane(lane) != Lane::Sphere {
                        continue;
                    }
                    if let Some(hit) = packet.sphere(lane).intersect(ray, t_limit, packet.id(lane)) {
                        t_limit = hit.t;
                        found = Some(hit.t);
                        *nearest = Some(Nearest::Sphere(hit));
                    }
                }
                continue;
            }
            let sheared = sheared.get_or_insert_with(|| ShearedRay::new(*ray));
            // A hit of the 4-wide test stands while the limit it was tested against does; after
            // a closer hit in the same packet, the scalar test decides, as it would ray by ray.
            t_limit = packet.test(sheared, t_limit).nearer(
                t_limit,
                |lane, limit| packet.intersect_lane(lane, sheared, limit),
                |lane, hit| {
                    found = Some(hit.t);
                    *nearest = Some(Nearest::Triangle { packet: index, lane: lane as u8, hit });
                },
            );
        }
        found
    }

    /// The hit record of the nearest BVH candidate (`None` only for a shape without a normal,
    /// which the packets never report).
    fn hit_record(&self, nearest: Nearest) -> Option<Hit> {
        let (packet, lane, hit) = match nearest {
            Nearest::Sphere(hit) => return Some(hit),
            Nearest::Triangle { packet, lane, hit } => (&self.packets[packet as usize], lane as usize, hit),
        };
        let prim = packet.id(lane);
        if packet.lane(lane) == Lane::FlatTriangle {
            return flat_hit_record(&packet.vertices(lane), &hit, prim);
        }
        match (packet.lane(lane), &self.shapes[prim as usize]) {
            (Lane::Triangle, Shape::Triangle { mesh, tri }) => {
                self.meshes[*mesh as usize].hit_record(*tri, &packet.vertices(lane), &hit, prim)
            }
            (half @ (Lane::QuadLower | Lane::QuadUpper), Shape::Quad(quad)) => {
                let (u, v) = quad_uv(half, &hit);
                quad.hit_record(hit.t, u, v, prim)
            }
            (lane, shape) => unreachable!("packet lane {lane:?} holds {shape:?}"),
        }
    }

    /// True when anything is hit with t in (0, `t_max`) (shadow rays).
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.occluded_except(ray, t_max, u32::MAX)
    }

    /// [`Self::occluded`] for a shadow ray that ends short of a point on the planar shape
    /// `except` (a quad light's own quad, by its index in the shapes given to [`Self::build`]):
    /// a segment that ends before reaching a plane from off it cannot cross it, so `except` may
    /// be left untested (it is, in a scene of a few spheres and quads). Same answer as
    /// [`Self::occluded`] for such a ray.
    pub fn occluded_except(&self, ray: &Ray, t_max: f32, except: u32) -> bool {
        let Some(few) = &self.few else {
            return self.occluded_bvh(ray, t_max);
        };
        if self.planes_occlude(ray, t_max) || few.spheres.any(ray, t_max) {
            return true;
        }
        if few.quads_missed(ray, except) {
            return false;
        }
        let sheared = ShearedRay::new(*ray);
        match &few.halves {
            FewQuads::Packets(packets) => packets.iter().any(|packet| {
                packet
                    .test(&sheared, t_max)
                    .any(|lane| packet.intersect_lane(lane, &sheared, t_max).is_some())
            }),
            FewQuads::Lanes(lanes) => lanes.any(&sheared, t_max),
        }
    }

    /// [`Self::occluded`] for any scene but a few spheres and planes (kept apart as
    /// [`Self::intersect_bvh`] is).
    #[inline(never)]
    fn occluded_bvh(&self, ray: &Ray, t_max: f32) -> bool {
        if self.planes_occlude(ray, t_max) {
            return true;
        }
        let mut sheared: Option<ShearedRay> = None;
        match self.single_leaf {
            Some((first, count)) => self.occluded_in_leaf(ray, &mut sheared, first, count, t_max),
            None => self.bvh.any_hit(ray, t_max, |first, count, t_max| {
                self.occluded_in_leaf(ray, &mut sheared, first, count, t_max)
            }),
        }
    }

    /// [`Self::occluded`] for up to [`PACKET_RAYS`] rays traced together (`rays[i]` with
    /// `t_max[i]`): bit i of the result is set when `rays[i]` is occluded. See
    /// [`Self::intersect_packet`].
    ///
    /// # Panics
    /// If `rays` holds more than [`PACKET_RAYS`] rays, or `t_max` another number.
    pub fn occluded_packet(&self, rays: &[Ray], t_max: &[f32]) -> u32 {
        let count = rays.len();
        assert!(count <= PACKET_RAYS, "{count} rays: a packet holds at most {PACKET_RAYS}");
        assert_eq!(t_max.len(), count, "one t_max per ray");
        let Some(&first) = rays.first() else {
            return 0;
        };
        let packet: [Ray; PACKET_RAYS] = std::array::from_fn(|lane| rays.get(lane).copied().unwrap_or(first));
        let limits: [f32; PACKET_RAYS] = std::array::from_fn(|lane| t_max.get(lane).copied().unwrap_or(0.0));
        let all = (1u32 << count) - 1;
        let lanes = Bvh::coherent_lanes(&packet, all);
        let alone = (0..count)
            .filter(|&lane| lanes & (1 << lane) == 0 && self.occluded(&rays[lane], t_max[lane]))
            .fold(0, |mask, lane| mask | 1 << lane);
        if lanes == 0 {
            return alone;
        }
        let by_planes = (0..count)
            .filter(|&lane| lanes & (1 << lane) != 0)
            .filter(|&lane| self.planes_occlude(&rays[lane], t_max[lane]))
            .fold(0, |mask, lane| mask | 1 << lane);
        let mut sheared = [None; PACKET_RAYS];
        alone
            | by_planes
            | self.bvh.any_hit_packet(&packet, lanes & !by_planes, &limits, |lane, first, leaf, t_max| {
                self.occluded_in_leaf(&packet[lane], &mut sheared[lane], first, leaf, t_max)
            })
    }

    /// The leaf test of the any-hit search: whether anything in the packets
    /// `first..first + count` is hit with t in (0, `t_max`); `sheared` as in
    /// [`Self::nearest_in_leaf`].
    #[inline(always)]
    fn occluded_in_leaf(
        &self,
        ray: &Ray,
        sheared: &mut Option<ShearedRay>,
        first: u32,
        count: u32,
        t_max: f32,
    ) -> bool {
        for packet in &self.packets[first as usize..(first + count) as usize] {
            if packet.holds_spheres() {
                if spheres_occlude(packet, ray, t_max) {
                    return true;
                }
                continue;
            }
            let sheared = sheared.get_or_insert_with(|| ShearedRay::new(*ray));
            if packet.test(sheared, t_max).any(|lane| packet.intersect_lane(lane, sheared, t_max).is_some()) {
                return true;
            }
        }
        false
    }

    /// The shapes in the order given to [`Self::build`].
    pub fn shapes(&self) -> &[Shape] {
        &self.shapes
    }

    /// The meshes given to [`Self::build`].
    pub fn meshes(&self) -> &[Mesh] {
        &self.meshes
    }

    /// The bounding box (lower, upper corner; scene units) of the finite shapes; `None` when
    /// there are none (only planes, or nothing).
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        self.bvh.bounds().map(|Aabb { min, max }| (min, max))
    }

    /// Size of the BVH over the finite shapes: node count, depth, bytes per primitive (bytes per
    /// triangle for a mesh scene) of the nodes, and separately of the packets that hold the
    /// primitives in leaf order. Excludes the shapes and meshes themselves.
    pub fn bvh_stats(&self) -> BvhStats {
        BvhStats { primitive_bytes: std::mem::size_of_val(self.packets.as_slice()), ..self.bvh.stats() }
    }
}

/// Whether `ray` hits a sphere of the sphere packet `packet` with t in (0, `t_max`). Kept out
/// of line: the any-hit leaf loop, inlined into the traversal, stays small.
#[inline(never)]
fn spheres_occlude(packet: &Packet, ray: &Ray, t_max: f32) -> bool {
    (0..super::packet::LANES).any(|lane| {
        packet.lane(lane) == Lane::Sphere && packet.sphere(lane).intersect(ray, t_max, 0).is_some()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::sphere::tests::check_far_side;
    use crate::geometry::test_util::Rng;
    use crate::geometry::{spawn_origin, Plane, Quad, Sphere};

    /// A random soup: spheres, quads and triangles of sizes 0.01 to 10 in a 100-unit cube.
    fn random_soup(rng: &mut Rng, count: usize) -> Geometry {
        let mut shapes = Vec::with_capacity(count);
        let mut mesh = Mesh::default();
        for _ in 0..count {
            let centre = rng.point_in(Vec3::splat(-50.0), Vec3::splat(50.0));
            let size = rng.log_uniform(0.01, 10.0);
            match rng.uniform(0.0, 3.0) as u32 {
                0 => shapes.push(Shape::Sphere(Sphere { center: centre, radius: size })),
                1 => shapes.push(Shape::Quad(Quad {
                    corner: centre,
                    edge1: size * rng.unit_vector(),
                    edge2: size * rng.unit_vector(),
                })),
                _ => {
                    let first = mesh.positions.len() as u32;
                    for _ in 0..3 {
                        mesh.positions.push(centre + size * rng.unit_vector());
                    }
                    shapes.push(Shape::Triangle { mesh: 0, tri: mesh.triangles.len() as u32 });
                    mesh.triangles.push([first, first + 1, first + 2]);
                }
            }
        }
        Geometry::build(shapes, vec![mesh])
    }

    /// The nearest hit by testing every shape.
    fn linear_scan(geometry: &Geometry, ray: &Ray, t_max: f32) -> Option<Hit> {
        let sheared = ShearedRay::new(*ray);
        let mut nearest: Option<Hit> = None;
        for (index, shape) in geometry.shapes().iter().enumerate() {
            let limit = nearest.map_or(t_max, |hit| hit.t);
            if let Some(hit) = shape.intersect(geometry.meshes(), &sheared, limit, index as u32) {
                nearest = Some(hit);
            }
        }
        nearest
    }

    fn random_ray(rng: &mut Rng) -> Ray {
        let origin = rng.point_in(Vec3::splat(-80.0), Vec3::splat(80.0));
        let target = rng.point_in(Vec3::splat(-50.0), Vec3::splat(50.0));
        Ray::new(origin, (target - origin).normalize())
    }

    #[test]
    fn bvh_agrees_with_a_linear_scan() {
        // Same nearest primitive and the same distance (1e-5 relative) for 20 000 random rays
        // through a soup of 3000 shapes, with and without a t_max.
        let mut rng = Rng::new(2024);
        let geometry = random_soup(&mut rng, 3_000);
        let mut hits = 0;
        for i in 0..20_000 {
            let ray = random_ray(&mut rng);
            let t_max = if i % 2 == 0 { f32::INFINITY } else { rng.uniform(1.0, 100.0) };
            let expected = linear_scan(&geometry, &ray, t_max);
            let found = geometry.intersect(&ray, t_max);
            match (expected, found) {
                (None, None) => {}
                (Some(e), Some(f)) => {
                    assert_eq!(e.prim, f.prim, "ray {ray:?}");
                    assert!((e.t - f.t).abs() <= 1e-5 * e.t, "t {} vs {}", e.t, f.t);
                    hits += 1;
                }
                _ => panic!("ray {ray:?}: linear {expected:?}, BVH {found:?}"),
            }
            assert_eq!(geometry.occluded(&ray, t_max), expected.is_some(), "occlusion of {ray:?}");
        }
        // The soup is dense enough that most rays hit something.
        assert!(hits > 10_000, "only {hits} hits");
    }

    #[test]
    fn planes_are_tested_outside_the_bvh() {
        // A floor plane and a sphere above it: rays down hit the sphere first where it is, the
        // floor elsewhere; the scene bounds ignore the infinite plane.
        let shapes = vec![
            Shape::Plane(Plane { point: Vec3::ZERO, normal: Vec3::Y }),
            Shape::Sphere(Sphere { center: Vec3::new(0.0, 1.0, 0.0), radius: 0.5 }),
        ];
        let geometry = Geometry::build(shapes, Vec::new());
        let down = |x: f32| Ray::new(Vec3::new(x, 5.0, 0.0), -Vec3::Y);
        let on_sphere = geometry.intersect(&down(0.0), f32::INFINITY).expect("hit");
        assert_eq!((on_sphere.prim, on_sphere.t), (1, 3.5));
        let on_floor = geometry.intersect(&down(2.0), f32::INFINITY).expect("hit");
        assert_eq!((on_floor.prim, on_floor.t), (0, 5.0));
        assert!(!geometry.occluded(&down(2.0), 4.9));
        assert!(geometry.occluded(&down(2.0), 5.1));
        assert_eq!(geometry.bounds(), Some((Vec3::new(-0.5, 0.5, -0.5), Vec3::new(0.5, 1.5, 0.5))));
        assert_eq!(
            Geometry::build(vec![Shape::Plane(Plane { point: Vec3::ZERO, normal: Vec3::Y })], Vec::new())
                .bounds(),
            None
        );
        assert_eq!(Geometry::build(Vec::new(), Vec::new()).intersect(&down(0.0), f32::INFINITY), None);
    }

    #[test]
    fn a_few_spheres_quads_and_planes_are_tested_directly_with_the_same_hits() {
        // No plane, one (tested alone) or three (as a packet), two overlapping spheres and none,
        // one, two, five or eight quads, as in the TP6 scenes and the glass-and-mirror room (four
        // walls and a light) (the direct path); forcing the packets and the BVH
        // instead must give the same hits, bit for bit, and so must a linear scan. Half the rays
        // are aimed at a quad, some of them from points on it, so that the quads' plane test
        // (`leaves_quad_plane`) is met on both sides.
        let mut rng = Rng::new(77);
        for (planes, quads) in [(1, 0), (3, 0), (1, 1), (3, 2), (0, 5), (1, 8)] {
            let mut shapes: Vec<Shape> = (0..planes)
                .map(|_| {
                    Shape::Plane(Plane {
                        point: rng.point_in(Vec3::splat(-40.0), Vec3::splat(40.0)),
                        normal: rng.unit_vector(),
                    })
                })
                .collect();
            for _ in 0..2 {
                let center = rng.point_in(Vec3::splat(-10.0), Vec3::splat(10.0));
                shapes.push(Shape::Sphere(Sphere { center, radius: rng.uniform(2.0, 15.0) }));
            }
            let mut quad_list = Vec::new();
            for _ in 0..quads {
                let quad = Quad {
                    corner: rng.point_in(Vec3::splat(-20.0), Vec3::splat(20.0)),
                    edge1: rng.unit_vector() * rng.uniform(1.0, 10.0),
                    edge2: rng.unit_vector() * rng.uniform(1.0, 10.0),
                };
                quad_list.push(quad);
                shapes.push(Shape::Quad(quad));
            }
            let direct = Geometry::build(shapes, Vec::new());
            assert!(direct.few.is_some(), "a handful of spheres and quads takes the direct path");
            let packets = Geometry { few: None, ..direct.clone() };
            for i in 0..20_000 {
                let mut ray = random_ray(&mut rng);
                if let Some(quad) = quad_list.get(i % 4) {
                    let target = quad.point_at(rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0));
                    let origin = if i % 8 == 0 {
                        quad.point_at(rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0))
                    } else {
                        ray.origin
                    };
                    let dir = if i % 8 == 0 { ray.dir } else { (target - origin).normalize() };
                    ray = Ray::new(origin, dir);
                }
                if let (Some(quad), true) = (quad_list.get(i % 4), i % 8 != 0) {
                    // A shadow ray toward the quad, stopped short of it as the integrators stop
                    // theirs: the quad itself may go untested.
                    let id = (planes + 2 + i % 4) as u32;
                    let target = quad.point_at(rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0));
                    let reach = (target - ray.origin).length() * (1.0 - 1e-4);
                    let shadow = Ray::new(ray.origin, (target - ray.origin).normalize());
                    let blocked = packets.occluded(&shadow, reach);
                    assert_eq!(direct.occluded_except(&shadow, reach, id), blocked, "ray {shadow:?}");
                    assert_eq!(direct.occluded(&shadow, reach), blocked, "ray {shadow:?}");
                }
                let t_max = if i % 2 == 0 { f32::INFINITY } else { rng.uniform(1.0, 100.0) };
                let hit = direct.intersect(&ray, t_max);
                assert_eq!(hit, packets.intersect(&ray, t_max), "ray {ray:?}");
                assert_eq!(hit, linear_scan(&direct, &ray, t_max), "ray {ray:?}");
                assert_eq!(direct.occluded(&ray, t_max), hit.is_some(), "ray {ray:?}");
                assert_eq!(packets.occluded(&ray, t_max), hit.is_some(), "ray {ray:?}");
            }
        }
        // Any triangle keeps the packets and the BVH.
        assert!(random_soup(&mut rng, 30).few.is_none());
    }

    #[test]
    fn a_closed_box_of_quads_leaks_at_no_edge_or_corner() {
        // A closed box of six quads (the glass-and-mirror room's walls, closed, at its
        // coordinates) and two spheres inside, tested directly (the quads' halves in their three
        // 4-wide packets, one after another): rays from inside aimed exactly at the box's twelve
        // edges and eight corners, and at the quads' diagonals, must all hit a wall (a miss is
        // light leaking through a seam; the quads share their corners exactly, which the
        // watertight test needs) and find, bit for bit, what the BVH's packets and a linear scan
        // find.
        let (low, high) = (Vec3::new(-3.0, 0.0, -4.0), Vec3::new(3.0, 3.5, 6.0));
        let size = high - low;
        let (x, y, z) = (Vec3::X * size.x, Vec3::Y * size.y, Vec3::Z * size.z);
        let walls = [
            Quad { corner: low, edge1: x, edge2: z },
            Quad { corner: low + y, edge1: z, edge2: x },
            Quad { corner: low, edge1: y, edge2: x },
            Quad { corner: low + z, edge1: x, edge2: y },
            Quad { corner: low, edge1: z, edge2: y },
            Quad { corner: low + x, edge1: y, edge2: z },
        ];
        let mut shapes: Vec<Shape> = walls.iter().map(|&quad| Shape::Quad(quad)).collect();
        shapes.push(Shape::Sphere(Sphere { center: Vec3::new(1.1, 0.8, 3.0), radius: 0.8 }));
        shapes.push(Shape::Sphere(Sphere { center: Vec3::new(-1.1, 0.8, 3.4), radius: 0.8 }));
        let direct = Geometry::build(shapes, Vec::new());
        assert!(direct.few.is_some(), "six quads and two spheres take the direct path");
        let packets = Geometry { few: None, ..direct.clone() };
        let corners: Vec<Vec3> = (0..8)
            .map(|c| low + Vec3::new((c & 1) as f32, ((c >> 1) & 1) as f32, (c >> 2) as f32) * size)
            .collect();
        let mut rng = Rng::new(5);
        let mut wall_hits = 0;
        for i in 0..40_000 {
            let origin = rng.point_in(low + Vec3::splat(0.01), high - Vec3::splat(0.01));
            let a = corners[rng.uniform(0.0, 8.0) as usize];
            let target = match i % 3 {
                // A corner.
                0 => a,
                // A point of an edge (or of a face's diagonal: both end on corners).
                _ => a + rng.uniform(0.0, 1.0) * (corners[rng.uniform(0.0, 8.0) as usize] - a),
            };
            let Some(dir) = (target - origin).try_normalize() else { continue };
            let ray = Ray::new(origin, dir);
            let hit = direct.intersect(&ray, f32::INFINITY).unwrap_or_else(|| panic!("{ray:?} leaks"));
            assert_eq!(Some(hit), packets.intersect(&ray, f32::INFINITY), "ray {ray:?}");
            assert_eq!(Some(hit), linear_scan(&direct, &ray, f32::INFINITY), "ray {ray:?}");
            wall_hits += usize::from(hit.prim < 6);
            // Shadow rays to the targets stopped short of them, as the integrators stop theirs.
            let reach = (target - origin).length() * (1.0 - 1e-4);
            assert_eq!(direct.occluded(&ray, reach), packets.occluded(&ray, reach), "ray {ray:?}");
        }
        // The spheres hide the targets from about 14 % of the origins (34,448 rays reach a wall
        // with this seed); far fewer would mean the rays do not test the seams.
        assert!(wall_hits > 30_000, "only {wall_hits} rays reached a wall");
    }

    /// Every spawned ray is checked against the primitive it starts on: planar primitives must
    /// never be re-hit; a sphere only on its far side.
    fn check_spawned_rays(geometry: &Geometry, hit: &Hit, rng: &mut Rng, rays: usize) {
        let shape = &geometry.shapes()[hit.prim as usize];
        for _ in 0..rays {
            let dir = rng.unit_vector();
            let origin = spawn_origin(hit.point, hit.normal, dir);
            let sheared = ShearedRay::new(Ray::new(origin, dir));
            let again = shape.intersect(geometry.meshes(), &sheared, f32::INFINITY, hit.prim);
            match shape {
                Shape::Sphere(sphere) if dir.dot(hit.normal) < 0.0 => {
                    check_far_side(sphere, origin, dir, again)
                }
                _ => assert_eq!(again, None, "{shape:?}: re-hit from {origin} along {dir}"),
            }
        }
    }

    #[test]
    fn spawned_rays_never_re_hit_their_surface() {
        // Spheres of radius 0.01 to 1000, quads, triangles and planes anywhere within 1000 units
        // of the origin, hit by random rays from outside (and, for spheres, inside); 8 rays
        // spawned from each hit in random directions on both sides.
        let mut rng = Rng::new(99);
        let mut checked = 0;
        for _ in 0..4_000 {
            let centre = rng.point_in(Vec3::splat(-1000.0), Vec3::splat(1000.0));
            let size = rng.log_uniform(0.01, 1000.0);
            let mut mesh = Mesh::default();
            let shape = match rng.uniform(0.0, 4.0) as u32 {
                0 => Shape::Sphere(Sphere { center: centre, radius: size }),
                1 => Shape::Quad(Quad {
                    corner: centre,
                    edge1: size * rng.unit_vector(),
                    edge2: size * rng.unit_vector(),
                }),
                2 => Shape::Plane(Plane { point: centre, normal: rng.unit_vector() }),
                _ => {
                    mesh.positions = (0..3).map(|_| centre + size * rng.unit_vector()).collect();
                    mesh.triangles.push([0, 1, 2]);
                    Shape::Triangle { mesh: 0, tri: 0 }
                }
            };
            let geometry = Geometry::build(vec![shape], vec![mesh]);
            // Aim at a point near the shape, from outside or (half the time) from a nearby point.
            let target = centre + size * rng.uniform(0.0, 0.7) * rng.unit_vector();
            let distance =
                if rng.uniform(0.0, 1.0) < 0.5 { rng.log_uniform(0.01, 1000.0) } else { 0.1 * size };
            let from = target + distance * rng.unit_vector();
            let Some(hit) = geometry.intersect(&Ray::new(from, (target - from).normalize()), f32::INFINITY)
            else {
                continue;
            };
            check_spawned_rays(&geometry, &hit, &mut rng, 8);
            checked += 1;
        }
        assert!(checked > 2_000, "only {checked} hits to spawn from");
    }

    #[test]
    fn closed_prism_does_not_leak() {
        // Rays refracted into a glass prism stay inside until they leave through another face.
        // From hit points all over the surface (vertices included), rays spawned towards a random
        // interior point cross the interior (the prism is convex), so they must hit the prism
        // again beyond that point.
        let prism = Mesh::triangular_prism(std::f32::consts::FRAC_PI_3, 2.0, 3.0);
        let vertices = prism.positions.clone();
        let shapes = (0..prism.triangles.len() as u32).map(|tri| Shape::Triangle { mesh: 0, tri }).collect();
        let geometry = Geometry::build(shapes, vec![prism]);
        let mut rng = Rng::new(5);
        let mut inside_rays = 0;
        for _ in 0..5_000 {
            let from = 10.0 * rng.unit_vector();
            let target = if rng.uniform(0.0, 1.0) < 0.2 {
                vertices[rng.uniform(0.0, 6.0) as usize]
            } else {
                rng.point_in(Vec3::splat(-1.0), Vec3::splat(1.0))
            };
            let Some(hit) = geometry.intersect(&Ray::new(from, (target - from).normalize()), f32::INFINITY)
            else {
                continue;
            };
            for _ in 0..4 {
                // A convex combination of the vertices, shrunk towards the centroid (the origin):
                // strictly inside.
                let weights: Vec<f32> = (0..6).map(|_| rng.uniform(0.01, 1.0)).collect();
                let total: f32 = weights.iter().sum();
                let interior =
                    0.9 * vertices.iter().zip(&weights).map(|(v, w)| *v * (*w / total)).sum::<Vec3>();
                let dir = (interior - hit.point).normalize();
                let inner = Ray::new(spawn_origin(hit.point, hit.normal, dir), dir);
                let exit = geometry.intersect(&inner, f32::INFINITY);
                // The exit lies beyond the interior point. One exception, at edges where faces meet
                // at less than 90° (all three of this prism): the push along one face's normal
                // leaves the origin a few ULPs outside the neighbouring face, which then catches
                // the ray at t ~ 1e-7. The ray is still stopped by the mesh, not leaked.
                let beyond = (interior - hit.point).length();
                let caught = exit.is_some_and(|e| e.t > beyond || (e.prim != hit.prim && e.t < 1e-5));
                assert!(caught, "leak from {} along {dir}: {exit:?}", hit.point);
                inside_rays += 1;
            }
        }
        assert!(inside_rays > 5_000);
    }

    #[test]
    fn grazing_ray_near_a_corner_does_not_jump_through_the_wall() {
        // Floor y = 0 and a wall x = 1 meeting at a corner. A ray leaving the floor 1e-4 before
        // the wall, almost parallel to the floor, must hit the wall ~1e-4 further on.
        let floor = Quad {
            corner: Vec3::new(-1.0, 0.0, -1.0),
            edge1: Vec3::new(0.0, 0.0, 2.0),
            edge2: Vec3::new(2.0, 0.0, 0.0),
        };
        let wall = Quad {
            corner: Vec3::new(1.0, 0.0, -1.0),
            edge1: Vec3::new(0.0, 2.0, 0.0),
            edge2: Vec3::new(0.0, 0.0, 2.0),
        };
        let geometry = Geometry::build(vec![Shape::Quad(floor), Shape::Quad(wall)], Vec::new());
        let point = Vec3::new(1.0 - 1e-4, 0.0, 0.0);
        let dir = Vec3::new(1.0, 1e-3, 0.0).normalize();
        let ray = Ray::new(spawn_origin(point, floor.normal(), dir), dir);
        let hit = geometry.intersect(&ray, f32::INFINITY).expect("hits the wall");
        assert_eq!(hit.prim, 1);
        assert!((hit.t - 1e-4).abs() < 1e-6, "t = {}", hit.t);
    }

    fn tessellated_sphere(rings: u32, segments: u32) -> Mesh {
        Mesh::displaced_sphere(rings, segments)
    }

    #[test]
    fn tessellated_mesh_builds_and_is_hit() {
        // 20 000 triangles: every ray from outside aimed at the centre hits (the bumpy surface
        // encloses the centre), at a distance between 10 − 1.1 and 10 − 0.9.
        let mesh = tessellated_sphere(100, 100);
        let shapes = (0..mesh.triangles.len() as u32).map(|tri| Shape::Triangle { mesh: 0, tri }).collect();
        let geometry = Geometry::build(shapes, vec![mesh]);
        let stats = geometry.bvh_stats();
        assert_eq!(stats.primitives, 20_000);
        // Nodes: 256 bytes for every ~5 leaves of up to 8 triangles, about 14 bytes per
        // triangle. Packets: 176 bytes per 4 lanes, about 44 per triangle when full; leaves
        // whose size is not a multiple of 4 leave lanes empty (46 bytes when this was written).
        assert!(stats.bytes_per_primitive() < 20.0, "{stats:?}");
        assert!(stats.total_bytes_per_primitive() < 70.0, "{stats:?}");
        let mut rng = Rng::new(8);
        for _ in 0..2_000 {
            let from = 10.0 * rng.unit_vector();
            let hit =
                geometry.intersect(&Ray::new(from, -from.normalize()), f32::INFINITY).expect("closed mesh");
            assert!(hit.t > 8.85 && hit.t < 9.15, "t = {}", hit.t);
        }
    }

    #[test]
    fn packets_agree_with_single_rays() {
        // A soup with a floor plane and a smooth (vertex-normal) mesh besides the flat one:
        // packets of 1 to 16 rays, coherent fans from one origin and random rays, with random
        // t_max, give exactly the hit records and occlusions of the rays traced one by one.
        let mut rng = Rng::new(99);
        let soup = random_soup(&mut rng, 2_000);
        let mut shapes = soup.shapes().to_vec();
        let mut meshes = soup.meshes().to_vec();
        shapes.push(Shape::Plane(Plane { point: Vec3::new(0.0, -40.0, 0.0), normal: Vec3::Y }));
        let mut smooth = Mesh::displaced_sphere(24, 48);
        smooth.normals = Some(smooth.positions.iter().map(|p| p.normalize()).collect());
        for position in &mut smooth.positions {
            *position = Vec3::new(10.0, 5.0, -3.0) + 12.0 * *position;
        }
        shapes.extend((0..smooth.triangles.len() as u32).map(|tri| Shape::Triangle { mesh: 1, tri }));
        meshes.push(smooth);
        let geometry = Geometry::build(shapes, meshes);
        let mut coherent = 0;
        for i in 0..600 {
            let count = 1 + i % PACKET_RAYS;
            let origin = rng.point_in(Vec3::splat(-80.0), Vec3::splat(80.0));
            let axis = (rng.point_in(Vec3::splat(-30.0), Vec3::splat(30.0)) - origin).normalize();
            let rays: Vec<Ray> = (0..count)
                .map(|_| match i % 3 {
                    0 => random_ray(&mut rng),
                    _ => Ray::new(origin, (axis + 0.05 * rng.unit_vector()).normalize()),
                })
                .collect();
            let t_max: Vec<f32> = (0..count)
                .map(|_| if rng.uniform(0.0, 1.0) < 0.5 { f32::INFINITY } else { rng.uniform(1.0, 150.0) })
                .collect();
            let mut hits = vec![None; count];
            geometry.intersect_packet(&rays, &t_max, &mut hits);
            let occluded = geometry.occluded_packet(&rays, &t_max);
            assert_eq!(occluded >> count, 0, "only the packet's lanes");
            for (lane, ray) in rays.iter().enumerate() {
                assert_eq!(
                    hits[lane],
                    geometry.intersect(ray, t_max[lane]),
                    "{ray:?}, t_max {}",
                    t_max[lane]
                );
                assert_eq!(occluded & 1 << lane != 0, geometry.occluded(ray, t_max[lane]), "{ray:?}");
            }
            let mut full = [*rays.first().expect("a ray"); PACKET_RAYS];
            full[..count].copy_from_slice(&rays);
            coherent += Bvh::coherent_lanes(&full, (1 << count) - 1).count_ones();
        }
        assert!(coherent > 2_000, "only {coherent} rays traversed in packets");
        let mut none: [Option<Hit>; 0] = [];
        geometry.intersect_packet(&[], &[], &mut none);
        assert_eq!(geometry.occluded_packet(&[], &[]), 0);
    }
}

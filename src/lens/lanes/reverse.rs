//! A scene ray traced back through the lens to the sensor at every wavelength lane, in SIMD, with
//! each lane's Mueller matrix: `reverse::LensTracer::trace_lanes_to_sensor` followed by
//! `reverse::ReverseTrace::sample` for the lanes that pass, operation for operation
//! ([`super::vec3`]), so the same numbers to the bit. For the camera's shared scene path
//! ([`crate::camera::LensCamera::sample_shared_path`]).

use wide::f64x8;

use super::path::PathLanes;
use super::surface::{cross_lanes, index_lanes, transmission_lanes};
use super::vec3::{first_lanes, lane_set, Mask, V3};
use crate::lens::reverse::MAX_REVERSE_SURFACES;
use crate::lens::trace::{LensSample, LensTracer, Ray, TraceOptions, MAX_LANES, T_MIN_MM};

/// One lane of a scene ray traced back to the sensor: the camera ray (p, t) that leaves the
/// lens along it at the lane's wavelength, and what [`LensTracer::trace_from_sensor`] gives for
/// that camera ray (to rounding: the reverse walk's own rounding of p and t).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReverseLane {
    /// p: where the camera ray starts on the sensor (x, y, mm, lens coordinates).
    pub sensor_mm: [f64; 2],
    /// t: where it crosses the plane of the rear vertex (x, y, mm).
    pub target_mm: [f64; 2],
    /// The scene ray (the one traced back), the lens's transmission and Mueller matrix along
    /// the path, per the options' `fresnel`, `up` and `full_mueller` (no ghosts).
    pub sample: LensSample,
}

/// One surface met on the way back, every lane (`reverse::Step`).
#[derive(Clone, Copy)]
struct StepLanes {
    normal: V3,
    light_out: V3,
    cos_camera: f64x8,
    n_before: f64x8,
    n_after: f64x8,
}

impl StepLanes {
    const ZERO: Self = Self {
        normal: V3 { x: f64x8::ZERO, y: f64x8::ZERO, z: f64x8::ZERO },
        light_out: V3 { x: f64x8::ZERO, y: f64x8::ZERO, z: f64x8::ZERO },
        cos_camera: f64x8::ZERO,
        n_before: f64x8::ZERO,
        n_after: f64x8::ZERO,
    };
}

impl LensTracer {
    /// The scene ray `exit` (lens coordinates, mm: its origin on the first surface, its unit
    /// direction into the scene, as [`LensSample::origin_mm`] and [`LensSample::dir`] give it)
    /// traced back through the lens at each wavelength of `lambdas_nm` (nm, at most
    /// [`MAX_LANES`]) to the sensor, into `out[i]` (`None`: blocked on the way, or a lens of more
    /// than [`MAX_REVERSE_SURFACES`] surfaces), with the camera ray's lens sample per `options`
    /// (its `fresnel`, `up` and `full_mueller`; ghosts off): the numbers of
    /// [`Self::trace_lanes_to_sensor`] and [`crate::lens::ReverseTrace::sample`], to the bit,
    /// computed in SIMD over the lanes.
    pub fn trace_lanes_back_to_sensor(
        &self,
        exit: Ray,
        lambdas_nm: &[f64],
        options: &TraceOptions,
        out: &mut [Option<ReverseLane>],
    ) {
        let lanes = lambdas_nm.len();
        assert!(lanes <= MAX_LANES && out.len() >= lanes, "{lanes} lanes");
        out[..lanes].fill(None);
        let surfaces = &self.system.surfaces;
        if lanes == 0 || surfaces.len() > MAX_REVERSE_SURFACES {
            return;
        }
        let lambdas: [f64; MAX_LANES] =
            std::array::from_fn(|lane| lambdas_nm[if lane < lanes { lane } else { 0 }]);
        let lambda = f64x8::from(lambdas);
        let mut live: Mask = first_lanes(lanes);
        let mut steps = [StepLanes::ZERO; MAX_REVERSE_SURFACES];
        // The light arrives along −dir at the exit point, on surface 0.
        let mut origin = V3::splat(exit.origin);
        let mut dir = V3::splat(-exit.dir);
        let mut n_before = index_lanes(self.system.medium_before(0), lambda, &lambdas);
        for (at, surface) in surfaces.iter().enumerate() {
            let n_after = index_lanes(&surface.medium, lambda, &lambdas);
            let crossing = cross_lanes(surface, self.vertex_z_mm[at], origin, dir, n_before / n_after, live);
            live = crossing.live;
            if live.to_bitmask() == 0 {
                return;
            }
            // |normal·light_out|.min(1).
            let cos_abs = crossing.normal.dot(crossing.dir_out).abs();
            let cos_camera = cos_abs.simd_gt(f64x8::ONE).select(f64x8::ONE, cos_abs);
            steps[at] = StepLanes {
                normal: crossing.normal,
                light_out: crossing.dir_out,
                cos_camera,
                n_before,
                n_after,
            };
            origin = crossing.point;
            dir = crossing.dir_out;
            n_before = n_after;
        }
        // On to the sensor plane, toward +z.
        let (image_z, rear_z) = (f64x8::splat(self.image_z_mm()), f64x8::splat(self.rear_vertex_z_mm()));
        let t = (image_z - origin.z) / dir.z;
        live &= dir.z.simd_gt(f64x8::ZERO) & t.is_finite() & t.simd_ge(f64x8::splat(T_MIN_MM));
        if live.to_bitmask() == 0 {
            return;
        }
        let sensor = origin.plus(dir.scaled(t));
        let back = (rear_z - image_z) / dir.z;
        let target_x = sensor.x + back * dir.x;
        let target_y = sensor.y + back * dir.y;
        // The Mueller matrix from the sensor end (ReverseTrace::sample): the camera ray leaves
        // the sensor along −(the last light_out) and meets the surfaces rear to front.
        let rows = if options.full_mueller { 4 } else { 1 };
        let last = surfaces.len() - 1;
        let mut path = PathLanes::start_lanes(steps[last].light_out.neg(), options.up, rows, live);
        if options.fresnel {
            for at in (0..surfaces.len()).rev() {
                let step = &steps[at];
                let light_in = if at == 0 { V3::splat(-exit.dir) } else { steps[at - 1].light_out };
                let (n_in, n_other) = (step.n_after, step.n_before);
                let element =
                    transmission_lanes(&surfaces[at], step.cos_camera, n_in, n_other, &lambdas, live);
                path.visit(step.normal, step.light_out.neg(), light_in.neg(), &element);
            }
        }
        let mueller = path.finish(V3::splat(exit.dir), options.up, live, options.fresnel);
        let (sensor_x, sensor_y) = (sensor.x.to_array(), sensor.y.to_array());
        let (target_x, target_y) = (target_x.to_array(), target_y.to_array());
        for lane in 0..lanes {
            if lane_set(live, lane) {
                out[lane] = Some(ReverseLane {
                    sensor_mm: [sensor_x[lane], sensor_y[lane]],
                    target_mm: [target_x[lane], target_y[lane]],
                    sample: LensSample {
                        origin_mm: exit.origin,
                        dir: exit.dir,
                        throughput: mueller[lane][0][0],
                        mueller: mueller[lane],
                        reflections: 0,
                    },
                });
            }
        }
    }
}

//! A camera sample's wavelength lanes traced through the lens together, in SIMD: every
//! quantity of the trace one [`wide::f64x8`] over the 8 lanes (two AVX2 halves: `.cargo/config.toml`
//! builds for the host, without AVX-512, which measured 12–16 % slower for the lens), in f64,
//! for [`LensTracer::trace_lanes_from_sensor`] (the transmitted branch, no ghosts) and, backward
//! from a scene ray to the sensor with each lane's Mueller matrix, for
//! [`LensTracer::trace_lanes_back_to_sensor`] (the camera's shared scene path).
//!
//! Per surface, from the rear element to the front: the ray–surface hit (sphere, plane or
//! conic in vectors; an even asphere's Newton iteration lane by lane), the clear aperture as a
//! lane mask, the indices of both media (each glass's dispersion formula in vectors), Snell's
//! law with total internal reflection masked, the exact s/p Fresnel transmission (a coated
//! surface's stack lane by lane) and the Mueller chain, row 0 only for unpolarised light, the
//! whole matrix for polarised, with the rotation into each interface's s frame.
//!
//! **The scalar trace's numbers to the bit.** Each vector operation is the scalar code's
//! operation in the same order ([`vec3`]): IEEE multiplication, addition, division and square
//! root are correctly rounded in either form, and neither uses fused multiply-adds, so each lane
//! is [`LensTracer::trace_from_sensor`] at its wavelength, blocked or passing alike
//! (`tests/lens_lanes_simd.rs` compares them over random camera rays through every shipped
//! lens). What it saves is the scalar code's per-lane instructions and branches: one vector
//! instruction does the 8 lanes' arithmetic, and the lanes' independent latency chains were
//! already overlapped.

mod path;
mod reverse;
mod surface;
mod vec3;

pub use self::reverse::ReverseLane;

use wide::f64x8;

use self::path::PathLanes;
use self::surface::{cross_lanes, index_lanes, transmission_lanes};
use self::vec3::{first_lanes, lane_set, V3};
use super::trace::{LensSample, LensTracer, TraceOptions, MAX_LANES};

impl LensTracer {
    /// [`Self::trace_from_sensor`] without ghosts (`options.max_ghost_reflections` is ignored:
    /// the transmitted branch only) for several wavelengths at once, `lambdas_nm[i]` (nm, at
    /// most [`MAX_LANES`]) into `out[i]` (`out` at least as long): the same numbers, to the bit,
    /// as a trace per wavelength, computed in SIMD over the lanes (module documentation).
    pub fn trace_lanes_from_sensor(
        &self,
        sensor_mm: [f64; 2],
        target_mm: [f64; 2],
        lambdas_nm: &[f64],
        options: &TraceOptions,
        out: &mut [Option<LensSample>],
    ) {
        assert!(out.len() >= lambdas_nm.len() && lambdas_nm.len() <= MAX_LANES, "{} lanes", lambdas_nm.len());
        let lanes = lambdas_nm.len();
        out[..lanes].fill(None);
        let Some(start) = self.camera_ray(sensor_mm, target_mm) else { return };
        if lanes == 0 {
            return;
        }
        // Lanes past `lanes` trace the first lane's wavelength, masked off.
        let lambdas: [f64; MAX_LANES] =
            std::array::from_fn(|lane| lambdas_nm[if lane < lanes { lane } else { 0 }]);
        let lambda = f64x8::from(lambdas);
        let mut live = first_lanes(lanes);
        let mut origin = V3::splat(start.origin);
        let mut dir = V3::splat(start.dir);
        let mut path = PathLanes::start(start.dir, options.up, if options.full_mueller { 4 } else { 1 });
        let surfaces = &self.system.surfaces;
        // The index behind the surface met next (the camera ray's side of it).
        let mut n_in = index_lanes(&surfaces[surfaces.len() - 1].medium, lambda, &lambdas);
        for at in (0..surfaces.len()).rev() {
            let surface = &surfaces[at];
            let n_other = index_lanes(self.system.medium_before(at), lambda, &lambdas);
            let crossing = cross_lanes(surface, self.vertex_z_mm[at], origin, dir, n_in / n_other, live);
            live = crossing.live;
            if live.to_bitmask() == 0 {
                return;
            }
            if options.fresnel {
                let element = transmission_lanes(surface, crossing.cos_i, n_in, n_other, &lambdas, live);
                path.visit(crossing.normal, dir, crossing.dir_out, &element);
            }
            origin = crossing.point;
            dir = crossing.dir_out;
            n_in = n_other;
        }
        let mueller = path.finish(dir, options.up, live, options.fresnel);
        let (origins, dirs) = (origin.lanes(), dir.lanes());
        for lane in 0..lanes {
            if lane_set(live, lane) {
                out[lane] = Some(LensSample {
                    origin_mm: origins[lane],
                    dir: dirs[lane],
                    throughput: mueller[lane][0][0],
                    mueller: mueller[lane],
                    reflections: 0,
                });
            }
        }
    }
}

//! A scene ray traced backward through a [`LensSystem`] to the sensor at one wavelength: the
//! inverse of the lens map T_λ that [`LensTracer::trace_from_sensor`] applies (transmitted
//! branch only, no ghosts), for the camera's hero-wavelength estimator
//! ([`crate::camera::LensCamera`]).
//!
//! Given the ray a camera sample sent into the scene (its origin on the first surface, its
//! direction toward −z) and a wavelength λ, the reverse trace follows the light: from the first
//! surface to the rear one, refracting at each (Snell's law, [`super::trace::refract`], the
//! indices of λ), then to the sensor plane. It gives the camera ray (p, t) at λ that leaves the
//! lens along the same scene ray: p on the sensor, t where that ray crosses the plane of the
//! rear vertex (the pair [`super::pupil`] aims with). Refraction is reversible and each meeting
//! is on the same surface patch, so a ray blocked one way (missed, vignetted, totally
//! reflected) is blocked the other way.
//!
//! **The lens's Mueller matrix from the same walk.** Light travels scene → sensor, and
//! [`LensTracer::trace_from_sensor`] builds the path's matrix from the sensor end, P ← P·Rot·E
//! surface by surface from the rear to the front. The reverse walk meets the surfaces front to
//! rear, so it stores each meeting (point, normal, directions, indices and the cosine of the
//! camera-side incidence) and [`ReverseTrace::sample`] replays them in the forward order
//! through the same code (`trace::CameraPath`), each surface's Fresnel coefficients computed
//! as the forward trace computes them (incidence from the sensor side, coatings crossed toward
//! the object). The energy transmittances T_s, T_p of an interface are the same in both
//! directions (Stokes' relations), so this is the light's own transmission; computing them from
//! the camera's side makes the result the forward trace's to rounding: the same function of
//! the same numbers, those numbers differing only by the rounding of the two walks (tested).
//!
//! No stored meetings beyond [`MAX_REVERSE_SURFACES`]: a longer lens is traced lane by lane
//! by the camera (it says so where it decides).

use glam::DVec3;

use super::fresnel_stack::{coated_interface_fresnel, interface_fresnel};
use super::surface_geometry::{intersect, within_aperture};
use super::trace::{
    refract, Blocked, CameraPath, Interaction, LensSample, LensTracer, MediumIndices, Ray, TraceOptions,
    T_MIN_MM,
};

/// The most surfaces a [`ReverseTrace`] stores (a camera lens has at most a few dozen; the
/// double Gauss 50 mm has 11).
pub const MAX_REVERSE_SURFACES: usize = 32;

/// One surface met on the way back.
#[derive(Clone, Copy, Debug)]
struct Step {
    /// The unit surface normal there, toward +z.
    normal: DVec3,
    /// The light's direction after the surface (toward the sensor).
    light_out: DVec3,
    /// The unsigned cosine of incidence of the camera ray (the reverse of the light) there.
    cos_camera: f64,
    /// The index in front of the surface (object side).
    n_before: f64,
    /// The index behind it (image side).
    n_after: f64,
}

impl Step {
    /// A step not yet taken.
    const NONE: Self =
        Self { normal: DVec3::Z, light_out: DVec3::Z, cos_camera: 1.0, n_before: 1.0, n_after: 1.0 };
}

/// A scene ray traced back to the sensor at one wavelength: the camera ray (p, t) that leaves
/// the lens along it, and the surfaces met, for [`ReverseTrace::sample`].
#[derive(Clone, Debug)]
pub struct ReverseTrace {
    steps: [Step; MAX_REVERSE_SURFACES],
    surfaces: usize,
    lambda_nm: f64,
    /// The scene ray (origin on the first surface, direction into the scene).
    exit: Ray,
    /// p: where the camera ray starts on the sensor (x, y, mm, lens coordinates).
    pub sensor_mm: [f64; 2],
    /// t: where it crosses the plane of the rear vertex (x, y, mm).
    pub target_mm: [f64; 2],
}

impl ReverseTrace {
    /// A trace not yet made (a constant, so that an array of them is written in place).
    pub const EMPTY: Self = Self {
        steps: [Step::NONE; MAX_REVERSE_SURFACES],
        surfaces: 0,
        lambda_nm: 0.0,
        exit: Ray { origin: DVec3::ZERO, dir: DVec3::NEG_Z },
        sensor_mm: [0.0; 2],
        target_mm: [0.0; 2],
    };
}

impl Default for ReverseTrace {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl LensTracer {
    /// Traces the scene ray `exit` (lens coordinates, mm: its origin on the first surface, its
    /// unit direction into the scene, toward −z, as [`LensSample::origin_mm`] and
    /// [`LensSample::dir`] give it) back through the lens at `lambda_nm` (nm) to the sensor,
    /// into `into`: the camera ray (p, t) that [`Self::trace_from_sensor`] would send out along
    /// it at that wavelength. An error when the light is blocked on the way (or the lens has
    /// more than [`MAX_REVERSE_SURFACES`] surfaces: `Missed` at the first one it cannot store).
    pub fn trace_to_sensor(&self, exit: Ray, lambda_nm: f64, into: &mut ReverseTrace) -> Result<(), Blocked> {
        let mut blocked = [None];
        self.trace_lanes_to_sensor(exit, &[lambda_nm], std::slice::from_mut(into), &mut blocked);
        blocked[0].map_or(Ok(()), Err)
    }

    /// [`Self::trace_to_sensor`] for several wavelengths at once, `lambdas_nm[i]` (nm) into
    /// `into[i]` with `blocked[i]` set to why it is blocked (`None`: it passes): the same
    /// numbers as a call per wavelength, computed surface by surface for all of them together
    /// so that the processor overlaps their independent chains of divisions and square roots
    /// (as [`Self::trace_lanes_from_sensor`]). `into` and `blocked` at least as long as
    /// `lambdas_nm`.
    pub fn trace_lanes_to_sensor(
        &self,
        exit: Ray,
        lambdas_nm: &[f64],
        into: &mut [ReverseTrace],
        blocked: &mut [Option<Blocked>],
    ) {
        const LANES: usize = super::trace::MAX_LANES;
        let lanes = lambdas_nm.len();
        assert!(lanes <= LANES && into.len() >= lanes && blocked.len() >= lanes, "{lanes} lanes");
        let surfaces = &self.system.surfaces;
        let mut indices: [MediumIndices; LANES] = std::array::from_fn(|lane| {
            MediumIndices::new(&self.system, lambdas_nm.get(lane).copied().unwrap_or(0.0))
        });
        blocked[..lanes].fill(None);
        // The light arrives along −dir at the exit point, which is on surface 0: its meeting
        // there is at t = 0 to rounding, which T_MIN_MM accepts.
        let mut rays = [Ray { origin: exit.origin, dir: -exit.dir }; LANES];
        for (at, surface) in surfaces.iter().enumerate() {
            for lane in 0..lanes {
                if blocked[lane].is_some() {
                    continue;
                }
                match self.step_back(at, surface, &rays[lane], &mut indices[lane]) {
                    Ok((hit_point, step)) => match into[lane].steps.get_mut(at) {
                        Some(slot) => {
                            *slot = step;
                            rays[lane] = Ray { origin: hit_point, dir: step.light_out };
                        }
                        None => blocked[lane] = Some(Blocked::Missed(at)),
                    },
                    Err(why) => blocked[lane] = Some(why),
                }
            }
        }
        // On to the sensor plane, toward +z.
        let at = surfaces.len();
        for lane in 0..lanes {
            if blocked[lane].is_some() {
                continue;
            }
            let ray = rays[lane];
            let t = (self.image_z_mm() - ray.origin.z) / ray.dir.z;
            if !(ray.dir.z > 0.0 && t.is_finite() && t >= T_MIN_MM) {
                blocked[lane] = Some(Blocked::Missed(at));
                continue;
            }
            let sensor = ray.origin + t * ray.dir;
            // Back along the ray to the rear vertex plane (Δ in front of the sensor).
            let back = (self.rear_vertex_z_mm() - self.image_z_mm()) / ray.dir.z;
            let trace = &mut into[lane];
            trace.surfaces = at;
            trace.lambda_nm = lambdas_nm[lane];
            trace.exit = exit;
            trace.sensor_mm = [sensor.x, sensor.y];
            trace.target_mm = [sensor.x + back * ray.dir.x, sensor.y + back * ray.dir.y];
        }
    }

    /// The light's meeting with surface `at` (`surface`) going toward the image: where, and its
    /// direction after (refracted).
    #[inline]
    fn step_back(
        &self,
        at: usize,
        surface: &super::Surface,
        ray: &Ray,
        indices: &mut MediumIndices,
    ) -> Result<(DVec3, Step), Blocked> {
        let hit = intersect(surface, self.vertex_z_mm[at], ray.origin, ray.dir, T_MIN_MM)
            .ok_or(Blocked::Missed(at))?;
        if !within_aperture(surface, hit.point) {
            return Err(Blocked::Vignetted(at));
        }
        let (n_before, n_after) = (indices.before(at), indices.after(at));
        let cos_signed = hit.normal.dot(ray.dir);
        let facing = if cos_signed < 0.0 { hit.normal } else { -hit.normal };
        let cos_i = cos_signed.abs().min(1.0);
        let light_out = refract(ray.dir, facing, cos_i, n_before / n_after)
            .ok_or(Blocked::TotalInternalReflection(at))?;
        Ok((
            hit.point,
            Step {
                normal: hit.normal,
                light_out,
                cos_camera: hit.normal.dot(light_out).abs().min(1.0),
                n_before,
                n_after,
            },
        ))
    }
}

impl ReverseTrace {
    /// The [`LensSample`] of the traced camera ray, as [`LensTracer::trace_from_sensor`] gives
    /// it from (`sensor_mm`, `target_mm`) at the traced wavelength (to rounding): the scene ray,
    /// the lens's transmission and Mueller matrix per `options` (its `fresnel`, `up` and
    /// `full_mueller`; the wavelength is the traced one and ghosts are off), replayed from the
    /// sensor end through the forward code. `tracer` is the one that traced it. `None` when the
    /// path carries nothing (as the forward trace).
    pub fn sample(&self, tracer: &LensTracer, options: &TraceOptions) -> Option<LensSample> {
        let options = TraceOptions { lambda_nm: self.lambda_nm, max_ghost_reflections: 0, ..*options };
        let steps = &self.steps[..self.surfaces];
        let last = steps.last()?;
        let mut path = CameraPath::start(-last.light_out, &options);
        for (at, step) in steps.iter().enumerate().rev() {
            let light_in = if at == 0 { -self.exit.dir } else { steps[at - 1].light_out };
            // The camera ray's incidence, as the forward trace meets the surface: from the image
            // side (n_in behind the surface), crossing a coating toward the object.
            let (n_in, n_other) = (step.n_after, step.n_before);
            let fresnel = match &tracer.system.surfaces[at].coating {
                None => interface_fresnel(step.cos_camera, n_in, n_other),
                Some(coating) => {
                    coated_interface_fresnel(step.cos_camera, n_in, n_other, coating, false, self.lambda_nm)
                }
            };
            path.visit(&Interaction {
                surface: at,
                // Not stored: the path's matrix does not depend on where the surface is met.
                point: DVec3::NAN,
                normal: step.normal,
                dir_in: -step.light_out,
                dir_out: -light_in,
                n_in,
                n_other,
                fresnel,
                reflected: false,
            });
        }
        path.finish(self.exit, &options)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lens::read_lens_file;

    /// A stream of numbers in [0, 1) (an additive recurrence with the plastic number's
    /// reciprocal, well spread in 1D; the test needs coverage, not independence).
    fn uniforms(seed: f64) -> impl FnMut() -> f64 {
        let mut x = seed;
        move || {
            x = (x + 0.754_877_666_246_692_7).fract();
            x
        }
    }

    /// The largest absolute difference of two Mueller matrices.
    fn mueller_difference(a: &crate::lens::Mueller4, b: &crate::lens::Mueller4) -> f64 {
        a.iter().flatten().zip(b.iter().flatten()).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
    }

    /// Forward-traces camera rays (sensor points over a 36 × 24 mm frame, pupil targets over
    /// the rear disc, wavelengths 360–830 nm) through the double Gauss (bare and coated) and
    /// the N-BK7 singlet; reverse-traces each scene ray that came out, at the same wavelength:
    /// the same (p, t), transmission and Mueller matrix (polarised and row 0 alone). Then the
    /// same scene ray at another wavelength: where the reverse trace passes, the forward trace
    /// from its (p, t) must pass and come out along the same scene ray with the same matrix.
    /// Blocked ↔ blocked follows: a forward ray that passes is never blocked backward (first
    /// check), and a backward ray that passes is never blocked forward (second check), so the
    /// passing sets correspond one to one and so do their complements. And eight wavelengths
    /// traced back together give each one's numbers alone, to the bit.
    ///
    /// Tolerances: positions 1e-11 mm, matrix entries 1e-13 (measured worst: 5e-14 mm and
    /// 2e-15). The two walks compute the same geometry in f64 (~1e-16 relative per operation)
    /// in opposite orders, so they differ by rounding alone, accumulated over ~11 refractions
    /// and carried to the sensor ~50 mm away: a few hundred ulps of a 20 mm coordinate
    /// (3.6e-15 mm each) is ~1e-12 mm, and the bound leaves a factor 10 above that, while any
    /// error of formula (a wrong index, a surface skipped) moves the sensor point by
    /// micrometres. A transmission or Mueller entry is a product of ~11 factors, each a smooth
    /// function of cos θ and n that inherit the same relative rounding: 1e-13 is ~500 ulps.
    #[test]
    fn reverse_trace_is_the_forward_trace_backward() {
        let lenses = ["dgauss50.dat", "dgauss50_coated.dat", "singlet_nbk7.dat"];
        let (mut compared, mut passed_other, mut blocked_other) = (0, 0, 0);
        let (mut worst_position, mut worst_matrix) = (0.0_f64, 0.0_f64);
        for name in lenses {
            let path =
                std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/data/lenses")).join(name);
            let tracer = LensTracer::new(read_lens_file(&path).expect("a shipped lens"));
            let rear = crate::lens::RearDisc::new(&tracer);
            let mut next = uniforms(0.3);
            let mut reverse = ReverseTrace::default();
            for i in 0..600 {
                let sensor = [18.0 * (2.0 * next() - 1.0), 12.0 * (2.0 * next() - 1.0)];
                let pupil = rear.sample(sensor, [next(), next()]);
                let lambda_nm = 360.0 + 470.0 * next();
                let other_nm = 360.0 + 470.0 * next();
                let full_mueller = i % 2 == 0;
                let options = TraceOptions { full_mueller, ..TraceOptions::new(lambda_nm) };
                let Some(forward) = tracer.trace_from_sensor(sensor, pupil.target_mm, &options, &mut || 0.0)
                else {
                    continue;
                };
                let exit = Ray { origin: forward.origin_mm, dir: forward.dir };
                // All lanes together give each lane's numbers alone, to the bit.
                let lambdas: [f64; 8] =
                    std::array::from_fn(|k| 360.0 + 67.0 * k as f64 + (lambda_nm - 360.0) / 8.0);
                let mut traces = [ReverseTrace::EMPTY; 8];
                let mut blocked = [None; 8];
                tracer.trace_lanes_to_sensor(exit, &lambdas, &mut traces, &mut blocked);
                for lane in 0..8 {
                    let alone = tracer.trace_to_sensor(exit, lambdas[lane], &mut reverse);
                    assert_eq!(alone.err(), blocked[lane], "{name} ray {i} lane {lane}");
                    if blocked[lane].is_none() {
                        assert_eq!(
                            (reverse.sensor_mm, reverse.target_mm),
                            (traces[lane].sensor_mm, traces[lane].target_mm)
                        );
                        assert_eq!(reverse.sample(&tracer, &options), traces[lane].sample(&tracer, &options));
                    }
                }
                tracer.trace_to_sensor(exit, lambda_nm, &mut reverse).expect("the forward ray's way back");
                let back = reverse.sample(&tracer, &options).expect("passes");
                let position = (0..2)
                    .map(|k| {
                        (reverse.sensor_mm[k] - sensor[k])
                            .abs()
                            .max((reverse.target_mm[k] - pupil.target_mm[k]).abs())
                    })
                    .fold(0.0, f64::max);
                worst_position = worst_position.max(position);
                worst_matrix = worst_matrix.max(mueller_difference(&back.mueller, &forward.mueller));
                assert!((back.throughput - forward.throughput).abs() < 1e-13, "{name} ray {i}");
                assert_eq!(back.dir, forward.dir);
                compared += 1;
                // The same scene ray at another wavelength, most often near the rim of the
                // passing set (below), so that both outcomes are met.
                let other = TraceOptions { lambda_nm: other_nm, ..options };
                match tracer.trace_to_sensor(exit, other_nm, &mut reverse) {
                    Ok(()) => {
                        let again = tracer
                            .trace_from_sensor(reverse.sensor_mm, reverse.target_mm, &other, &mut || 0.0)
                            .expect("a preimage that passes backward passes forward");
                        let back = reverse.sample(&tracer, &other).expect("passes");
                        let position = (again.origin_mm - exit.origin).abs().max_element();
                        worst_position = worst_position.max(position);
                        assert!((again.dir - exit.dir).abs().max_element() < 1e-12, "{name} ray {i}");
                        worst_matrix = worst_matrix.max(mueller_difference(&back.mueller, &again.mueller));
                        passed_other += 1;
                    }
                    Err(_) => blocked_other += 1,
                }
            }
            // Rays on the rim of the passing set at one end of the spectrum, reversed at the
            // other end: the rim moves with the wavelength (vignetting by elements other than
            // the stop), so some are blocked there.
            for i in 0..300 {
                let sensor = [18.0 * (2.0 * next() - 1.0), 12.0 * (2.0 * next() - 1.0)];
                let phi = std::f64::consts::TAU * next();
                let (lambda_nm, other_nm) = if i % 2 == 0 { (360.0, 830.0) } else { (830.0, 360.0) };
                let options = TraceOptions { full_mueller: true, ..TraceOptions::new(lambda_nm) };
                let aim = |radius: f64| [radius * phi.cos(), radius * phi.sin()];
                let passes =
                    |radius: f64| tracer.trace_from_sensor(sensor, aim(radius), &options, &mut || 0.0);
                // The rim along this azimuth: bisect between a passing and a blocked radius.
                let (mut inside, mut outside) = (0.0, rear.radius_mm(sensor[0].hypot(sensor[1])));
                if passes(inside).is_none() || passes(outside).is_some() {
                    continue;
                }
                for _ in 0..40 {
                    let middle = 0.5 * (inside + outside);
                    if passes(middle).is_some() {
                        inside = middle;
                    } else {
                        outside = middle;
                    }
                }
                // 1e-6 mm inside: clear of the rim's rounding at this wavelength, far closer to it
                // than the rim moves across the spectrum.
                let Some(forward) = passes(inside - 1e-6) else { continue };
                let exit = Ray { origin: forward.origin_mm, dir: forward.dir };
                tracer.trace_to_sensor(exit, lambda_nm, &mut reverse).expect("the forward ray's way back");
                let other = TraceOptions { lambda_nm: other_nm, ..options };
                match tracer.trace_to_sensor(exit, other_nm, &mut reverse) {
                    Ok(()) => {
                        tracer
                            .trace_from_sensor(reverse.sensor_mm, reverse.target_mm, &other, &mut || 0.0)
                            .expect("a preimage that passes backward passes forward");
                        passed_other += 1;
                    }
                    Err(_) => blocked_other += 1,
                }
            }
        }
        eprintln!(
            "{compared} compared; at another wavelength {passed_other} passed, {blocked_other} blocked; \
             worst |Δp|, |Δt| {worst_position:e} mm, worst |ΔM| {worst_matrix:e}"
        );
        assert!(worst_position < 1e-11, "{worst_position}");
        assert!(worst_matrix < 1e-13, "{worst_matrix}");
        assert!(
            compared > 600 && passed_other > 600 && blocked_other > 20,
            "{compared}, {passed_other}, {blocked_other}"
        );
    }
}

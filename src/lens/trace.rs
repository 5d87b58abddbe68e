//! Real rays through a [`LensSystem`] at one wavelength, in f64: sequential surface by
//! surface, each surface met on its vertex patch ([`super::surface_geometry`]), blocked
//! outside its clear semi-diameter, refracted by Snell's law in vector form (Glassner, *An
//! Introduction to Ray Tracing*, §5.2; the residual n(d × N) = n′(d′ × N) is tested) or, for
//! ghosts, reflected, with the exact s/p Fresnel coefficients of [`super::fresnel_stack`] (a
//! coated surface's from its stack, [`super::coating`]).
//!
//! Two directions of travel:
//! - [`LensTracer::trace_from_object`]: a ray from object space (z < 0, toward +z) to the image
//!   plane, the direction of the light: spot diagrams, intercepts, the paraxial limit;
//! - [`LensTracer::trace_from_sensor`]: a camera ray from a point on the sensor toward the rear
//!   element, back out into the scene (the direction pbrt's realistic camera traces), with the
//!   Mueller matrix of the light's path from the scene to the sensor and, optionally, ghosts;
//!   [`LensTracer::trace_lanes_from_sensor`] ([`super::lanes`]) traces it for several
//!   wavelengths at once in SIMD (no ghosts), the same numbers to the bit.
//!
//! Cost (issue 40, validation/bench/RESULTS.md): each medium's index is evaluated once per
//! surface and trace; the path's Mueller matrix is carried row by row (r ← r·Rot·E, the 4×4
//! products' own arithmetic without their zero terms), only row 0 for unpolarised light
//! ([`TraceOptions::full_mueller`]). A render without ghosts traces a camera sample's 8 lanes in
//! SIMD (`super::lanes`, the same numbers to the bit); this scalar trace is the reference, and
//! what ghosts, the shared path's hero lane and the analyses use.
//!
//! # Ghosts: the branch estimator
//! At each surface the camera ray either reflects, with probability R (the unpolarised Fresnel
//! reflectance at that incidence, 1 under total internal reflection), or is transmitted, with
//! probability 1 − R, as long as fewer than `max_ghost_reflections` reflections have been
//! taken; after that it is always transmitted (probability 1). The estimate is the path's
//! Mueller matrix M divided by the product p of the probabilities of its choices. Every
//! sequence of choices with at most `max_ghost_reflections` reflections has p > 0 whenever its
//! M ≠ 0 (R = 0 ⇒ M_reflect = 0; T = 0 ⇒ M_transmit = 0), so E[M/p] = Σ over those paths of
//! M: unbiased for the sum of all paths with up to that many reflections; paths with more are
//! left out (the truncation is the only approximation, and it is by design). With
//! `max_ghost_reflections` = 0 the only path is the transmitted one, estimate = its M (weight
//! Π T at normal incidence). Unpolarised light sees the (0,0) entry; since the choice
//! probabilities are the unpolarised R and T, M₀₀/p is exactly 1 for an unpolarising path
//! (normal incidence), and close to 1 otherwise: low variance. A path whose reflections leave
//! it travelling toward the sensor ends on the sensor and carries no scene light: `None`.
//! Reflections come in pairs for every path that reaches the scene, so a budget of 2k lets
//! through the k-fold ghosts.

use glam::DVec3;

use super::fresnel_stack::{
    camera_stokes_x, coated_interface_fresnel, interface_fresnel, rotate_row, rotate_then_element,
    rotation_angle, s_axis, DiagonalElement, InterfaceFresnel, Mueller4, MUELLER_IDENTITY,
};
use super::surface_geometry::{intersect, within_aperture};
use super::LensSystem;

/// Accept a surface hit this far behind the ray's origin (mm): only surfaces that touch the
/// previous one at the origin (a zero-thickness stop, cemented edges) produce such hits, and
/// their t is 0 to rounding (1e-15 of a 100 mm coordinate is 1e-13 mm).
pub(crate) const T_MIN_MM: f64 = -1e-9;

/// A ray in lens coordinates (mm): `origin + t·dir`, `dir` a unit vector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// The origin (mm).
    pub origin: DVec3,
    /// The unit direction.
    pub dir: DVec3,
}

/// Why a ray does not get through.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Blocked {
    /// It does not meet the surface (index) at all.
    Missed(usize),
    /// It meets the surface (index) outside its clear semi-diameter.
    Vignetted(usize),
    /// Total internal reflection at the surface (index) where it had to be transmitted.
    TotalInternalReflection(usize),
    /// Its reflections sent it back where it came from (a ghost path that ends on the sensor,
    /// or a forward ray that returns to object space).
    Returned,
}

/// One meeting of a ray with a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interaction {
    /// The surface's index.
    pub surface: usize,
    /// The point (mm).
    pub point: DVec3,
    /// The unit surface normal there, toward +z.
    pub normal: DVec3,
    /// The traced ray's direction before.
    pub dir_in: DVec3,
    /// The traced ray's direction after.
    pub dir_out: DVec3,
    /// The index on the incoming side.
    pub n_in: f64,
    /// The index on the other side of the surface (the one a transmitted ray enters).
    pub n_other: f64,
    /// The Fresnel coefficients of this incidence.
    pub fresnel: InterfaceFresnel,
    /// Whether the ray was reflected (a ghost bounce) rather than transmitted.
    pub reflected: bool,
}

/// Options of a trace.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceOptions {
    /// The wavelength (nm).
    pub lambda_nm: f64,
    /// Weight by the Fresnel coefficients (`false`: an ideal lossless, non-polarising lens of
    /// the same geometry, for normalisation and the "no Fresnel losses" fault).
    pub fresnel: bool,
    /// The most reflections a camera ray may take (0: the transmitted branch only).
    pub max_ghost_reflections: u32,
    /// The "up" vector (lens coordinates) of the camera's Stokes frames: x = normalize(dir × up)
    /// for a camera ray of direction dir (see [`crate::camera::Camera::stokes_x`]).
    pub up: DVec3,
    /// Carry the whole Mueller matrix (a polarised render); `false`: only its row 0, all that
    /// unpolarised light sees (the exact (0,0) entry of the same product), the other rows of
    /// [`LensSample::mueller`] left 0, about a quarter of the work.
    pub full_mueller: bool,
}

impl TraceOptions {
    /// Fresnel on, no ghosts, up = +y, at `lambda_nm`.
    pub fn new(lambda_nm: f64) -> Self {
        Self { lambda_nm, fresnel: true, max_ghost_reflections: 0, up: DVec3::Y, full_mueller: true }
    }
}

/// A camera ray after the lens: where it leaves toward the scene, and what the lens does to
/// the light that comes back along it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LensSample {
    /// Where it leaves the first surface (mm, lens coordinates).
    pub origin_mm: DVec3,
    /// Its unit direction into the scene (toward −z).
    pub dir: DVec3,
    /// The radiance weight for unpolarised scene light: `mueller[0][0]`, the fraction of the
    /// scene radiance along the ray that reaches the sensor point along the traced path,
    /// divided by the probability of the branch choices. The (n_sensor/n_scene)² factor of
    /// the radiance theorem is left out: both are air in a camera.
    pub throughput: f64,
    /// The path's Mueller matrix divided by the probability of the branch choices, from the
    /// scene-side Stokes frame (light travelling along −`dir`, x = normalize(`dir` × up)) to the
    /// sensor frame (light travelling along −d₀ with d₀ the ray's first direction from the
    /// sensor, x = normalize(d₀ × up)); `up` from [`TraceOptions`]. Only row 0 when
    /// [`TraceOptions::full_mueller`] is false (rows 1–3 are then 0).
    pub mueller: Mueller4,
    /// How many ghost reflections the path took (even).
    pub reflections: u32,
}

/// The end of a traced ray.
#[derive(Clone, Debug, PartialEq)]
pub struct TracedRay {
    /// The ray after its last surface: for a ray to the image, its origin is on the image
    /// plane; for a ray to the scene, on the first surface.
    pub ray: Ray,
    /// Every surface it met, in the order met.
    pub interactions: Vec<Interaction>,
}

/// A lens system prepared for tracing (its vertex positions computed once); it owns its copy
/// of the prescription, so that a camera can hold it.
#[derive(Clone, Debug)]
pub struct LensTracer {
    /// The lens.
    pub system: LensSystem,
    /// z of each vertex and, last, of the image plane (mm).
    pub vertex_z_mm: Vec<f64>,
}

/// Which way a ray is going through the sequence of surfaces.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Heading {
    /// Toward +z (surface i + 1 next).
    ToImage,
    /// Toward −z (surface i − 1 next).
    ToObject,
}

impl LensTracer {
    /// Prepares `system` for tracing.
    pub fn new(system: LensSystem) -> Self {
        let vertex_z_mm = system.vertex_z_mm();
        Self { system, vertex_z_mm }
    }

    /// z of the image (sensor) plane (mm).
    pub fn image_z_mm(&self) -> f64 {
        self.vertex_z_mm[self.system.surfaces.len()]
    }

    /// z of the last (rear) vertex (mm).
    pub fn rear_vertex_z_mm(&self) -> f64 {
        self.vertex_z_mm[self.system.surfaces.len() - 1]
    }

    /// Traces `ray` (object space, toward +z) to the image plane at `lambda_nm`, always
    /// transmitted (no ghosts). The interactions carry the Fresnel coefficients.
    pub fn trace_from_object(&self, ray: Ray, lambda_nm: f64) -> Result<TracedRay, Blocked> {
        let mut interactions = Vec::with_capacity(self.system.surfaces.len());
        let ray =
            self.walk(ray, Heading::ToImage, lambda_nm, 0, &mut || 0.0, &mut |i| interactions.push(*i))?;
        Ok(TracedRay { ray, interactions })
    }

    /// Traces `ray` from the image side (toward −z) out to object space, always transmitted.
    pub fn trace_to_object(&self, ray: Ray, lambda_nm: f64) -> Result<TracedRay, Blocked> {
        let mut interactions = Vec::with_capacity(self.system.surfaces.len());
        let ray =
            self.walk(ray, Heading::ToObject, lambda_nm, 0, &mut || 0.0, &mut |i| interactions.push(*i))?;
        Ok(TracedRay { ray, interactions })
    }

    /// A camera ray from the sensor point (`sensor_mm`, on the image plane) toward the point
    /// `target_mm` of the plane of the rear vertex, traced out into the scene per
    /// [`TraceOptions`], with ghost branches chosen by the uniform numbers in [0, 1) that
    /// `next_uniform` returns (one per surface met while reflections are allowed). `None` when
    /// the ray is blocked or its path ends on the sensor. See the module header for the
    /// estimator.
    pub fn trace_from_sensor(
        &self,
        sensor_mm: [f64; 2],
        target_mm: [f64; 2],
        options: &TraceOptions,
        next_uniform: &mut dyn FnMut() -> f64,
    ) -> Option<LensSample> {
        let ray = self.camera_ray(sensor_mm, target_mm)?;
        let mut path = CameraPath::start(ray.dir, options);
        let budget = path.budget;
        let exit = self
            .walk(ray, Heading::ToObject, options.lambda_nm, budget, next_uniform, &mut |interaction| {
                path.visit(interaction)
            })
            .ok()?;
        path.finish(exit, options)
    }

    /// The camera ray from the sensor point toward the target on the rear vertex plane, or
    /// `None` when it does not head toward the lens.
    pub(crate) fn camera_ray(&self, sensor_mm: [f64; 2], target_mm: [f64; 2]) -> Option<Ray> {
        let origin = DVec3::new(sensor_mm[0], sensor_mm[1], self.image_z_mm());
        let target = DVec3::new(target_mm[0], target_mm[1], self.rear_vertex_z_mm());
        let dir = (target - origin).normalize();
        if !dir.is_finite() || dir.z >= 0.0 {
            return None;
        }
        Some(Ray { origin, dir })
    }

    /// The sequential walk: from `ray` heading `heading`, surface by surface, until it leaves
    /// toward object space (ToObject past surface 0: the ray from the first surface) or
    /// reaches the image plane (ToImage past the last surface: the ray from the image plane).
    /// While fewer than `budget` reflections are taken, each surface draws a number from
    /// `next_uniform` and reflects when it is below R. A walk that ends on the side it
    /// started from is [`Blocked::Returned`].
    fn walk<U, V>(
        &self,
        ray: Ray,
        heading: Heading,
        lambda_nm: f64,
        budget: u32,
        next_uniform: &mut U,
        visit: &mut V,
    ) -> Result<Ray, Blocked>
    where
        U: FnMut() -> f64 + ?Sized,
        V: FnMut(&Interaction),
    {
        let surfaces = &self.system.surfaces;
        let mut indices = MediumIndices::new(&self.system, lambda_nm);
        let start = heading;
        let mut heading = heading;
        let mut ray = ray;
        let mut reflections = 0;
        let mut index = match heading {
            Heading::ToImage => 0_isize,
            Heading::ToObject => surfaces.len() as isize - 1,
        };
        loop {
            if index < 0 {
                return if start == Heading::ToObject { Ok(ray) } else { Err(Blocked::Returned) };
            }
            let at = index as usize;
            if at >= surfaces.len() {
                if start == Heading::ToObject {
                    return Err(Blocked::Returned);
                }
                let t = (self.image_z_mm() - ray.origin.z) / ray.dir.z;
                if !(t.is_finite() && t >= T_MIN_MM) {
                    return Err(Blocked::Missed(at));
                }
                return Ok(Ray { origin: ray.origin + t * ray.dir, dir: ray.dir });
            }
            let meeting = self.meet(at, heading, &ray, &mut indices)?;
            let (fresnel, cos_i, facing) = (meeting.fresnel, meeting.cos_i, meeting.facing);
            let reflect = if reflections < budget && fresnel.reflectance() > 0.0 {
                next_uniform() < fresnel.reflectance()
            } else {
                false
            };
            let dir_out = if reflect {
                reflections += 1;
                heading = match heading {
                    Heading::ToImage => Heading::ToObject,
                    Heading::ToObject => Heading::ToImage,
                };
                (ray.dir + 2.0 * cos_i * facing).normalize()
            } else {
                refract(ray.dir, facing, cos_i, meeting.n_in / meeting.n_other)
                    .ok_or(Blocked::TotalInternalReflection(at))?
            };
            visit(&meeting.interaction(at, ray.dir, dir_out, reflect));
            ray = Ray { origin: meeting.point, dir: dir_out };
            index += match heading {
                Heading::ToImage => 1,
                Heading::ToObject => -1,
            };
        }
    }
}

/// Wavelength lanes [`LensTracer::trace_lanes_from_sensor`] traces together at most (the
/// renderer's lanes per camera sample).
pub const MAX_LANES: usize = 8;

impl LensTracer {
    /// A ray's meeting with surface `at` going `heading`: where, the indices on either side and
    /// the Fresnel coefficients of the incidence; the direction out (reflected or refracted) is
    /// the caller's choice.
    #[inline]
    fn meet(
        &self,
        at: usize,
        heading: Heading,
        ray: &Ray,
        indices: &mut MediumIndices,
    ) -> Result<Meeting, Blocked> {
        let surface = &self.system.surfaces[at];
        let hit = intersect(surface, self.vertex_z_mm[at], ray.origin, ray.dir, T_MIN_MM)
            .ok_or(Blocked::Missed(at))?;
        if !within_aperture(surface, hit.point) {
            return Err(Blocked::Vignetted(at));
        }
        let n_before = indices.before(at);
        let n_after = indices.after(at);
        let (n_in, n_other) = match heading {
            Heading::ToImage => (n_before, n_after),
            Heading::ToObject => (n_after, n_before),
        };
        // The normal facing the incoming ray.
        let cos_signed = hit.normal.dot(ray.dir);
        let facing = if cos_signed < 0.0 { hit.normal } else { -hit.normal };
        let cos_i = cos_signed.abs().min(1.0);
        let fresnel = match &surface.coating {
            None => interface_fresnel(cos_i, n_in, n_other),
            Some(coating) => coated_interface_fresnel(
                cos_i,
                n_in,
                n_other,
                coating,
                heading == Heading::ToImage,
                indices.lambda_nm,
            ),
        };
        Ok(Meeting { point: hit.point, normal: hit.normal, facing, cos_i, n_in, n_other, fresnel })
    }
}

/// What [`LensTracer::meet`] finds at a surface.
#[derive(Clone, Copy)]
struct Meeting {
    point: DVec3,
    normal: DVec3,
    /// The unit normal facing the incoming ray.
    facing: DVec3,
    cos_i: f64,
    n_in: f64,
    n_other: f64,
    fresnel: InterfaceFresnel,
}

impl Meeting {
    #[inline]
    fn interaction(&self, surface: usize, dir_in: DVec3, dir_out: DVec3, reflected: bool) -> Interaction {
        Interaction {
            surface,
            point: self.point,
            normal: self.normal,
            dir_in,
            dir_out,
            n_in: self.n_in,
            n_other: self.n_other,
            fresnel: self.fresnel,
            reflected,
        }
    }
}

/// A camera ray's path through the lens as it is traced from the sensor: its Mueller matrix in
/// light order, built from the sensor end (P ← P·Rot·E at each interface, see
/// super::fresnel_stack; row by row, each row r ← r·Rot·E with the 4×4 products' own
/// arithmetic without their zero terms, and only row 0 unless the whole matrix is asked for),
/// the frame of the previous interface, and the probability of its branch choices.
#[derive(Clone, Copy)]
pub(crate) struct CameraPath {
    path: Mueller4,
    rows: usize,
    previous_x: DVec3,
    probability: f64,
    reflections: u32,
    fresnel: bool,
    budget: u32,
}

impl CameraPath {
    /// The path of a camera ray leaving the sensor along `dir`.
    pub(crate) fn start(dir: DVec3, options: &TraceOptions) -> Self {
        let fresnel = options.fresnel;
        Self {
            path: MUELLER_IDENTITY,
            rows: if options.full_mueller { 4 } else { 1 },
            previous_x: camera_stokes_x(dir, options.up),
            probability: 1.0,
            reflections: 0,
            fresnel,
            budget: if fresnel { options.max_ghost_reflections } else { 0 },
        }
    }

    /// Adds an interface.
    #[inline]
    pub(crate) fn visit(&mut self, interaction: &Interaction) {
        let f = &interaction.fresnel;
        if interaction.reflected {
            self.reflections += 1;
            self.probability *= f.reflectance();
        } else if self.reflections < self.budget {
            self.probability *= 1.0 - f.reflectance();
        }
        if !self.fresnel {
            return;
        }
        // The light goes the other way: it arrives along −dir_out and leaves along −dir_in.
        let light_in = -interaction.dir_out;
        let light_out = -interaction.dir_in;
        let s = s_axis(interaction.normal, light_in, self.previous_x);
        let element = if interaction.reflected {
            DiagonalElement::reflection(f)
        } else {
            DiagonalElement::transmission(f)
        };
        let (cos_2, sin_2) = rotation_angle(light_out, s, self.previous_x);
        for row in &mut self.path[..self.rows] {
            *row = rotate_then_element(*row, cos_2, sin_2, &element);
        }
        self.previous_x = s;
    }

    /// The sample of the path that left the lens as `exit`; `None` for a path of probability 0.
    pub(crate) fn finish(mut self, exit: Ray, options: &TraceOptions) -> Option<LensSample> {
        if self.probability <= 0.0 {
            return None;
        }
        if self.fresnel {
            let scene_x = camera_stokes_x(exit.dir, options.up);
            let (cos_2, sin_2) = rotation_angle(-exit.dir, scene_x, self.previous_x);
            for row in &mut self.path[..self.rows] {
                *row = rotate_row(*row, cos_2, sin_2);
            }
        }
        if !options.full_mueller {
            // Rows 1–3 were never carried: 0 rather than the identity's.
            self.path[1..].fill([0.0; 4]);
        }
        let probability = self.probability;
        let mueller = self.path.map(|row| row.map(|value| value / probability));
        Some(LensSample {
            origin_mm: exit.origin,
            dir: exit.dir,
            throughput: mueller[0][0],
            mueller,
            reflections: self.reflections,
        })
    }
}

/// Surfaces whose medium's index a walk keeps once evaluated (farther ones, in lenses longer
/// than any camera lens, are evaluated at each meeting).
const CACHED_SURFACES: usize = 32;

/// The index of each surface's medium at one wavelength, evaluated (its dispersion formula) the
/// first time a walk needs it and kept: once per surface and trace instead of twice per surface
/// met. The same function of the same numbers, so the same bits.
pub(crate) struct MediumIndices<'a> {
    system: &'a LensSystem,
    lambda_nm: f64,
    /// The index behind surface i, NaN until evaluated.
    after: [f64; CACHED_SURFACES],
}

impl<'a> MediumIndices<'a> {
    pub(crate) fn new(system: &'a LensSystem, lambda_nm: f64) -> Self {
        Self { system, lambda_nm, after: [f64::NAN; CACHED_SURFACES] }
    }

    /// The index behind surface `at` (toward +z).
    #[inline]
    pub(crate) fn after(&mut self, at: usize) -> f64 {
        let Some(slot) = self.after.get_mut(at) else {
            return self.system.surfaces[at].medium.n_at_nm(self.lambda_nm);
        };
        if slot.is_nan() {
            *slot = self.system.surfaces[at].medium.n_at_nm(self.lambda_nm);
        }
        *slot
    }

    /// The index in front of surface `at` (air before the first).
    #[inline]
    pub(crate) fn before(&mut self, at: usize) -> f64 {
        if at == 0 {
            self.system.medium_before(0).n_at_nm(self.lambda_nm)
        } else {
            self.after(at - 1)
        }
    }
}

/// Snell's law in vector form: the refracted unit direction of the unit `dir` meeting a
/// surface of unit normal `facing` (against `dir`, cos θi = −dir·facing = `cos_i`) with
/// `eta` = n_in / n_out; `None` under total internal reflection.
pub fn refract(dir: DVec3, facing: DVec3, cos_i: f64, eta: f64) -> Option<DVec3> {
    let cos_t_sqr = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    if cos_t_sqr < 0.0 {
        return None;
    }
    Some((eta * dir + (eta * cos_i - cos_t_sqr.sqrt()) * facing).normalize())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lens::read_lens_file;

    #[test]
    fn row_zero_alone_is_the_full_matrix_row_zero() {
        // An unpolarised trace carries only row 0 of the path's matrix; it must be the full
        // trace's row 0 to the bit (the same arithmetic, row by row), ghosts on and off.
        let file = concat!(env!("CARGO_MANIFEST_DIR"), "/data/lenses/dgauss50.dat");
        let tracer = LensTracer::new(read_lens_file(std::path::Path::new(file)).expect("dgauss50"));
        let mut compared = 0;
        for ghosts in [0, 2] {
            for i in 0..200 {
                let a = i as f64 * 0.618_033_988_7;
                let sensor = [8.0 * (a * 3.1).sin(), 8.0 * (a * 1.7).cos()];
                let target = [6.0 * (a * 2.3).cos(), 6.0 * (a * 0.9).sin()];
                let lambda_nm = 400.0 + 300.0 * a.fract();
                let full = TraceOptions { max_ghost_reflections: ghosts, ..TraceOptions::new(lambda_nm) };
                let row = TraceOptions { full_mueller: false, ..full };
                let uniforms = |seed: f64| {
                    let mut x = seed;
                    move || {
                        x = (x + 0.754_877_666_2).fract();
                        x
                    }
                };
                let a_sample = tracer.trace_from_sensor(sensor, target, &full, &mut uniforms(a.fract()));
                let b_sample = tracer.trace_from_sensor(sensor, target, &row, &mut uniforms(a.fract()));
                assert_eq!(a_sample.is_some(), b_sample.is_some());
                if let (Some(a_sample), Some(b_sample)) = (a_sample, b_sample) {
                    assert_eq!(a_sample.mueller[0], b_sample.mueller[0]);
                    assert_eq!(a_sample.throughput, b_sample.throughput);
                    assert_eq!(a_sample.dir, b_sample.dir);
                    assert!(b_sample.mueller[1..].iter().flatten().all(|&v| v == 0.0));
                    compared += 1;
                }
            }
        }
        // Most of these rays pass (the test is not empty).
        assert!(compared > 100, "{compared}");
    }

    #[test]
    fn lanes_traced_together_are_the_lanes_traced_alone() {
        // trace_lanes_from_sensor must give each wavelength the numbers of its own
        // trace_from_sensor to the bit (passing and blocked alike), both Mueller modes.
        let file = concat!(env!("CARGO_MANIFEST_DIR"), "/data/lenses/dgauss50.dat");
        let tracer = LensTracer::new(read_lens_file(std::path::Path::new(file)).expect("dgauss50"));
        let lambdas = [361.0, 420.5, 486.13, 530.0, 587.56, 640.0, 700.0, 829.0];
        let (mut passed, mut blocked) = (0, 0);
        for full_mueller in [false, true] {
            for i in 0..300 {
                let a = i as f64 * 0.618_033_988_7;
                let sensor = [9.0 * (a * 3.1).sin(), 9.0 * (a * 1.7).cos()];
                let target = [7.0 * (a * 2.3).cos(), 7.0 * (a * 0.9).sin()];
                let options = TraceOptions { full_mueller, ..TraceOptions::new(550.0) };
                let lanes = 1 + i % MAX_LANES;
                let mut together = [None; MAX_LANES];
                tracer.trace_lanes_from_sensor(sensor, target, &lambdas[..lanes], &options, &mut together);
                for (lane, lambda_nm) in lambdas[..lanes].iter().enumerate() {
                    let alone = TraceOptions { lambda_nm: *lambda_nm, ..options };
                    let expected = tracer.trace_from_sensor(sensor, target, &alone, &mut || 0.0);
                    assert_eq!(together[lane], expected, "ray {i}, lane {lane}");
                    if expected.is_some() {
                        passed += 1;
                    } else {
                        blocked += 1;
                    }
                }
            }
        }
        // Both kinds are compared.
        assert!(passed > 100 && blocked > 100, "{passed} passed, {blocked} blocked");
    }
}

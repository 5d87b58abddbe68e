//! Aiming camera rays at the lens, and the weight that makes the image radiometric.
//!
//! A camera ray leaves a sensor point p toward a point t of the plane of the rear vertex,
//! z_r, a distance Δ = z_image − z_r in front of the sensor. With θ the ray's angle to the axis,
//! the solid angle of dA at t is cos θ dA / |t − p|² = cos³θ dA / Δ², so the sensor irradiance is
//! ```text
//! E(p) = ∫ L(ray) τ(ray) cos θ dω = ∫ L τ cos⁴θ / Δ² dA,
//! ```
//! τ the lens's transmission along the ray (the (0,0) entry of its Mueller matrix; 0 when
//! blocked). A target drawn with area density pdf(t) (mm⁻²) estimates it by L τ cos⁴θ/(Δ² pdf).
//!
//! Normalisation: the image reads E/K with K = ∫ cos θ dω over the directions from the sensor's
//! centre that an ideal lossless lens of the same geometry (Fresnel off, at a reference
//! wavelength) lets through: a uniform radiance L through that lens reads exactly L at the
//! image centre, and elsewhere L times the relative illumination (cos⁴ falloff, vignetting,
//! pupil distortion), times τ for a real lens (Fresnel losses, so an uncoated lens reads darker
//! than its ideal twin). For a lens whose passing set from the centre is the cone of half-angle
//! α, K = π sin²α (≈ π/(4N²) for an aplanatic lens of f-number N focused at infinity).
//! [`Normalisation::sensor_weight`] is cos⁴θ/(Δ² pdf K); the camera multiplies it by
//! [`super::LensSample::throughput`] (or the Mueller matrix) and by L.
//!
//! Two ways to draw t, both with their exact pdf:
//! - [`RearDisc`]: uniform on a disc of the rear vertex plane that contains every ray from p
//!   that can meet the rear surface within its clear semi-diameter (the semi-diameter widened by
//!   the surface's sag, see [`RearDisc::radius_mm`]); simple, and many rays miss.
//! - [`ExitPupilBounds`]: pbrt-v4's exit-pupil bounds (Pharr, Jakob & Humphreys, *Physically
//!   Based Rendering*, 4th ed., §5.3.3): for bands of sensor radius, the bounding rectangle of
//!   the rear-plane points whose rays pass, found from a grid of test rays (at the shortest,
//!   the reference and the longest wavelength, so that dispersion cannot move the pupil out of
//!   it) and widened by two grid cells; drawn uniformly after rotating it to the sensor
//!   point's azimuth. Where the disc about the rectangle's centre that holds the same points
//!   is smaller (round pupils, near the axis) it is drawn from instead. A region of passing rays thinner than the widening could be missed (the
//!   one approximation, as in pbrt); the tests check the irradiance against the disc's.
//!
//! With ghosts on, the bounds are not enough: they hold the rays whose *transmitted* path
//! passes, and a ghost path can start outside them (a ray that would be vignetted further in
//! is reflected back before it gets there). [`GhostMixture`] then aims with the bounds or the
//! whole disc and weights by the mixture's density, so that every ghost path is drawn
//! (tests/lens_ghosts.rs checks its ghost light against the disc's alone, and that the bounds
//! alone miss some).

use glam::DVec3;

use super::paraxial::LAMBDA_D_NM;
use super::surface_geometry::sag;
use super::trace::{LensSample, LensTracer, TraceOptions};
use super::LensSystem;

/// The wavelengths (nm) at which pupil bounds are measured: the ends of the visible range a
/// spectral render samples and the d line.
pub const PUPIL_WAVELENGTHS_NM: [f64; 3] = [360.0, LAMBDA_D_NM, 830.0];

/// A target on the rear vertex plane and its density.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PupilSample {
    /// The target (x, y) on the plane z = rear vertex (mm).
    pub target_mm: [f64; 2],
    /// Its area density (mm⁻²).
    pub pdf_per_mm2: f64,
}

/// Uniform sampling of a disc of the rear vertex plane that contains every ray able to meet the
/// rear surface inside its clear aperture.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RearDisc {
    /// The rear surface's clear semi-diameter (mm).
    pub semi_diameter_mm: f64,
    /// The lowest and highest sag of the rear surface within it (mm, relative to its vertex).
    pub sag_range_mm: (f64, f64),
    /// Δ: the sensor plane's distance behind the rear vertex (mm).
    pub sensor_distance_mm: f64,
}

/// Steps over the rear semi-diameter at which the sag range is sampled; the sags of camera
/// lenses are monotone or nearly so, and the range is widened by 1% of its span for what
/// falls between the samples.
const SAG_SAMPLES: usize = 256;

impl RearDisc {
    /// The disc of `tracer`'s rear surface.
    pub fn new(tracer: &LensTracer) -> Self {
        let rear = &tracer.system.surfaces[tracer.system.surfaces.len() - 1];
        let semi = rear.semi_diameter_mm;
        let (mut low, mut high) = (0.0_f64, 0.0_f64);
        for step in 0..=SAG_SAMPLES {
            let r = semi * step as f64 / SAG_SAMPLES as f64;
            if let Some(z) = sag(rear, r * r) {
                low = low.min(z);
                high = high.max(z);
            }
        }
        let widen = 0.01 * (high - low);
        Self {
            semi_diameter_mm: semi,
            sag_range_mm: (low - widen, high + widen),
            sensor_distance_mm: tracer.image_z_mm() - tracer.rear_vertex_z_mm(),
        }
    }

    /// The radius (mm) of the disc for a sensor point `sensor_radius_mm` off axis. A ray from p
    /// to a point q of the surface (|q| ≤ a, sag s) crosses the vertex plane at
    /// p + λ(q − p) with λ = Δ/(Δ − s): for s ≤ 0 between p and q, so within
    /// a + (1 − λ_min)(|p| − a)⁺; for s > 0 beyond q, within λ_max a + (λ_max − 1)|p|.
    pub fn radius_mm(&self, sensor_radius_mm: f64) -> f64 {
        let (delta, a, p) = (self.sensor_distance_mm, self.semi_diameter_mm, sensor_radius_mm);
        let (low, high) = self.sag_range_mm;
        let lambda_min = delta / (delta - low.min(0.0));
        let lambda_max = delta / (delta - high.max(0.0));
        let near = a + (1.0 - lambda_min) * (p - a).max(0.0);
        let far = lambda_max * a + (lambda_max - 1.0) * p;
        near.max(far)
    }

    /// A uniform point of the disc for the sensor point `sensor_mm` from the uniform pair `u`.
    pub fn sample(&self, sensor_mm: [f64; 2], u: [f64; 2]) -> PupilSample {
        let radius = self.radius_mm(sensor_mm[0].hypot(sensor_mm[1]));
        let r = radius * u[0].sqrt();
        let phi = 2.0 * std::f64::consts::PI * u[1];
        PupilSample {
            target_mm: [r * phi.cos(), r * phi.sin()],
            pdf_per_mm2: 1.0 / (std::f64::consts::PI * radius * radius),
        }
    }
}

/// The region of the rear vertex plane a band's camera rays are drawn from (for sensor points
/// on the +x axis; turned to the point's azimuth when drawn).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PupilRegion {
    /// The rectangle (x_min, y_min, x_max, y_max), mm: pbrt's bounds.
    Rectangle([f64; 4]),
    /// The disc of centre (x, y) and radius r, mm: tighter than the rectangle for round pupils
    /// (on and near the axis), where the rectangle wastes 1 − π/4 of its rays.
    Disc([f64; 3]),
}

impl PupilRegion {
    /// Its area (mm²).
    pub fn area_mm2(&self) -> f64 {
        match *self {
            PupilRegion::Rectangle([x0, y0, x1, y1]) => (x1 - x0) * (y1 - y0),
            PupilRegion::Disc([_, _, r]) => std::f64::consts::PI * r * r,
        }
    }

    /// Whether it holds the point `xy` (mm).
    pub fn contains(&self, xy: [f64; 2]) -> bool {
        match *self {
            PupilRegion::Rectangle([x0, y0, x1, y1]) => {
                (x0..=x1).contains(&xy[0]) && (y0..=y1).contains(&xy[1])
            }
            PupilRegion::Disc([x, y, r]) => (xy[0] - x).hypot(xy[1] - y) <= r,
        }
    }

    /// A uniform point of it from the uniform pair `u`.
    fn point(&self, u: [f64; 2]) -> [f64; 2] {
        match *self {
            PupilRegion::Rectangle([x0, y0, x1, y1]) => [x0 + (x1 - x0) * u[0], y0 + (y1 - y0) * u[1]],
            PupilRegion::Disc([x, y, r]) => {
                let (radius, phi) = (r * u[0].sqrt(), 2.0 * std::f64::consts::PI * u[1]);
                [x + radius * phi.cos(), y + radius * phi.sin()]
            }
        }
    }
}

/// pbrt-v4's exit-pupil bounds: per band of sensor radius, a region of the rear vertex plane
/// (for sensor points on the +x axis) outside which no ray passes: pbrt's bounding rectangle,
/// or the bounding disc about its centre when that is smaller.
#[derive(Clone, Debug, PartialEq)]
pub struct ExitPupilBounds {
    /// The largest sensor radius covered (mm); farther points use the last band.
    pub max_sensor_radius_mm: f64,
    /// Per band [i·r/n, (i+1)·r/n], its region, or `None` when no test ray passed.
    pub bands: Vec<Option<PupilRegion>>,
}

impl ExitPupilBounds {
    /// Measures the bounds for sensor radii up to `max_sensor_radius_mm` in `bands` bands, with
    /// `grid`² test targets (over the square of side 2·[`RearDisc::radius_mm`]) and `grid`
    /// sensor radii spread over each band, at [`PUPIL_WAVELENGTHS_NM`], Fresnel off. Each
    /// region is widened by two grid cells.
    pub fn measure(tracer: &LensTracer, max_sensor_radius_mm: f64, bands: usize, grid: usize) -> Self {
        let disc = RearDisc::new(tracer);
        let mut out = Vec::with_capacity(bands);
        for band in 0..bands {
            let r0 = max_sensor_radius_mm * band as f64 / bands as f64;
            let r1 = max_sensor_radius_mm * (band + 1) as f64 / bands as f64;
            let half = disc.radius_mm(r1);
            let cell = 2.0 * half / grid as f64;
            let mut passing = Vec::new();
            for i in 0..grid {
                let x = -half + (i as f64 + 0.5) * cell;
                for j in 0..grid {
                    let y = -half + (j as f64 + 0.5) * cell;
                    // The sensor radius runs through the band along the grid's diagonals
                    // (stratified: each target row meets every part of the band).
                    let sensor = r0 + (r1 - r0) * (((i + j) % grid) as f64 + 0.5) / grid as f64;
                    let passes = PUPIL_WAVELENGTHS_NM.iter().any(|&lambda_nm| {
                        let options = TraceOptions { fresnel: false, ..TraceOptions::new(lambda_nm) };
                        tracer.trace_from_sensor([sensor, 0.0], [x, y], &options, &mut || 0.0).is_some()
                    });
                    if passes {
                        passing.push([x, y]);
                    }
                }
            }
            out.push(bounding_region(&passing, 2.0 * cell));
        }
        Self { max_sensor_radius_mm, bands: out }
    }

    /// The band's region of the sensor point `sensor_mm` (for points on the +x axis) and the
    /// sine and cosine of the point's azimuth.
    fn region_of(&self, sensor_mm: [f64; 2]) -> (Option<PupilRegion>, f64, f64) {
        let radius = sensor_mm[0].hypot(sensor_mm[1]);
        let bands = self.bands.len();
        let band = ((radius / self.max_sensor_radius_mm * bands as f64) as usize).min(bands - 1);
        let (sin, cos) =
            if radius > 0.0 { (sensor_mm[1] / radius, sensor_mm[0] / radius) } else { (0.0, 1.0) };
        (self.bands[band], sin, cos)
    }

    /// A target for the sensor point `sensor_mm` from the uniform pair `u`: uniform in the
    /// band's region turned to the point's azimuth; `None` when no ray of that band passes.
    pub fn sample(&self, sensor_mm: [f64; 2], u: [f64; 2]) -> Option<PupilSample> {
        let (region, sin, cos) = self.region_of(sensor_mm);
        let region = region?;
        let [x, y] = region.point(u);
        // Rotate from the +x axis to the sensor point's azimuth.
        Some(PupilSample {
            target_mm: [cos * x - sin * y, sin * x + cos * y],
            pdf_per_mm2: 1.0 / region.area_mm2(),
        })
    }

    /// The area density (mm⁻²) with which [`Self::sample`] draws `target_mm` for the sensor
    /// point `sensor_mm`: 1/area inside the band's region (turned to the point's azimuth), 0
    /// outside it or when no ray of the band passes.
    pub fn pdf_per_mm2(&self, sensor_mm: [f64; 2], target_mm: [f64; 2]) -> f64 {
        let (region, sin, cos) = self.region_of(sensor_mm);
        let Some(region) = region else { return 0.0 };
        // Rotate from the sensor point's azimuth back to the +x axis.
        let [x, y] = target_mm;
        if region.contains([cos * x + sin * y, -sin * x + cos * y]) {
            1.0 / region.area_mm2()
        } else {
            0.0
        }
    }
}

/// Share of camera rays aimed inside the exit-pupil bounds when ghosts are on
/// ([`SensorSampler::sample`]); the rest are aimed over the whole [`RearDisc`]. The bounds hold
/// every transmitted path and most ghost light, so most rays go there; the disc's quarter
/// reaches the ghost paths that start outside them. The transmitted image's noise grows by at
/// most the ratio of the densities inside the bounds, 1/0.75 in variance.
pub const GHOST_BOUNDS_SHARE: f64 = 0.75;

/// Ghost aiming: a one-sample mixture of the exit-pupil bounds (with probability
/// [`GHOST_BOUNDS_SHARE`]) and the whole rear disc, weighted by the mixture's density (the
/// balance heuristic of Veach & Guibas 1995 in its one-sample form: the estimate
/// f(t)/(c·pdf_bounds(t) + (1 − c)·pdf_disc(t)) whichever part drew t). The disc holds
/// every ray that can meet the rear surface inside its clear aperture, which every camera ray
/// through the lens must, ghost or not; so every path of positive contribution has positive
/// density, and the estimate is unbiased for ghost paths whose first segment leaves the
/// transmitted light's bounds (a ray vignetted further in on its way out that is reflected
/// back before it gets there).
#[derive(Clone, Copy, Debug)]
pub struct GhostMixture<'a> {
    /// The exit-pupil bounds of the transmitted light.
    pub bounds: &'a ExitPupilBounds,
    /// The rear element's disc.
    pub rear: &'a RearDisc,
}

impl GhostMixture<'_> {
    /// A target for `sensor_mm` from the uniform pair `u`: u[0] picks the part (below
    /// [`GHOST_BOUNDS_SHARE`]: the bounds) and is stretched back to [0, 1) for it, so that the
    /// camera sample uses the same two numbers as without ghosts. `None` when the bounds are
    /// picked and no transmitted ray of the band passes (a sample of contribution 0: the
    /// disc's part still reaches whatever ghost paths there are).
    pub fn sample(&self, sensor_mm: [f64; 2], u: [f64; 2]) -> Option<PupilSample> {
        let share = GHOST_BOUNDS_SHARE;
        let target_mm = if u[0] < share {
            self.bounds.sample(sensor_mm, [u[0] / share, u[1]])?.target_mm
        } else {
            self.rear.sample(sensor_mm, [(u[0] - share) / (1.0 - share), u[1]]).target_mm
        };
        Some(PupilSample { target_mm, pdf_per_mm2: self.pdf_per_mm2(sensor_mm, target_mm) })
    }

    /// The mixture's area density (mm⁻²) at `target_mm` for `sensor_mm`.
    pub fn pdf_per_mm2(&self, sensor_mm: [f64; 2], target_mm: [f64; 2]) -> f64 {
        let radius = self.rear.radius_mm(sensor_mm[0].hypot(sensor_mm[1]));
        let disc = if target_mm[0].hypot(target_mm[1]) <= radius {
            1.0 / (std::f64::consts::PI * radius * radius)
        } else {
            0.0
        };
        GHOST_BOUNDS_SHARE * self.bounds.pdf_per_mm2(sensor_mm, target_mm) + (1.0 - GHOST_BOUNDS_SHARE) * disc
    }
}

/// The smaller of the bounding rectangle and the bounding disc about its centre of `points`,
/// widened by `margin` (mm); `None` for no points.
fn bounding_region(points: &[[f64; 2]], margin: f64) -> Option<PupilRegion> {
    let first = points.first()?;
    let mut b = [first[0], first[1], first[0], first[1]];
    for p in points {
        b = [b[0].min(p[0]), b[1].min(p[1]), b[2].max(p[0]), b[3].max(p[1])];
    }
    let rectangle = PupilRegion::Rectangle([b[0] - margin, b[1] - margin, b[2] + margin, b[3] + margin]);
    let centre = [0.5 * (b[0] + b[2]), 0.5 * (b[1] + b[3])];
    let reach = points.iter().map(|p| (p[0] - centre[0]).hypot(p[1] - centre[1])).fold(0.0, f64::max);
    let disc = PupilRegion::Disc([centre[0], centre[1], reach + margin]);
    Some(if disc.area_mm2() < rectangle.area_mm2() { disc } else { rectangle })
}

/// The normalisation K of the sensor weight (see the module header).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Normalisation {
    /// K = ∫ cos θ dω over the directions from the sensor's centre that pass the ideal lossless
    /// lens (sr).
    pub projected_solid_angle_sr: f64,
    /// Δ: the sensor's distance behind the rear vertex (mm).
    pub sensor_distance_mm: f64,
}

/// Radial steps of the scan for the passing set from the sensor centre (then each edge is
/// bisected to 1e-12 of the disc): a passing ring thinner than 1/4096 of the disc could be
/// missed; camera lenses have one disc.
const NORMALISATION_STEPS: usize = 4096;

impl Normalisation {
    /// K for `tracer`'s lens at `lambda_nm` (nm; the camera's focus wavelength).
    pub fn measure(tracer: &LensTracer, lambda_nm: f64) -> Self {
        let disc = RearDisc::new(tracer);
        let delta = disc.sensor_distance_mm;
        let options = TraceOptions { fresnel: false, ..TraceOptions::new(lambda_nm) };
        let passes =
            |rho: f64| tracer.trace_from_sensor([0.0, 0.0], [rho, 0.0], &options, &mut || 0.0).is_some();
        let radius = disc.radius_mm(0.0);
        let step = radius / NORMALISATION_STEPS as f64;
        // ∫ 2πρ Δ²/(Δ² + ρ²)² dρ = −πΔ²/(Δ² + ρ²): the projected solid angle of a ring.
        let ring = |a: f64, b: f64| {
            std::f64::consts::PI
                * delta
                * delta
                * (1.0 / (delta * delta + a * a) - 1.0 / (delta * delta + b * b))
        };
        let edge = |inside: f64, outside: f64| {
            let (mut inside, mut outside) = (inside, outside);
            while (outside - inside).abs() > 1e-12 * radius {
                let middle = 0.5 * (inside + outside);
                if passes(middle) {
                    inside = middle;
                } else {
                    outside = middle;
                }
            }
            0.5 * (inside + outside)
        };
        let mut total = 0.0;
        let mut previous = passes(0.0);
        let mut start = 0.0;
        for i in 1..=NORMALISATION_STEPS {
            let rho = step * i as f64;
            let now = passes(rho);
            if now != previous {
                let at = if previous { edge(rho - step, rho) } else { edge(rho, rho - step) };
                if previous {
                    total += ring(start, at);
                } else {
                    start = at;
                }
                previous = now;
            }
        }
        if previous {
            total += ring(start, radius);
        }
        Self { projected_solid_angle_sr: total, sensor_distance_mm: delta }
    }

    /// The weight cos⁴θ/(Δ² pdf K) of a camera ray from `sensor_mm` to `sample`'s target; the
    /// camera multiplies it by the lens's throughput and the scene radiance.
    pub fn sensor_weight(&self, sensor_mm: [f64; 2], sample: &PupilSample) -> f64 {
        let delta = self.sensor_distance_mm;
        let offset =
            DVec3::new(sample.target_mm[0] - sensor_mm[0], sample.target_mm[1] - sensor_mm[1], -delta);
        let cos_theta = delta / offset.length();
        cos_theta.powi(4) / (delta * delta * sample.pdf_per_mm2 * self.projected_solid_angle_sr)
    }
}

impl Normalisation {
    /// 1/[`Self::sensor_weight`] without the division by the pdf: Δ² pdf K / cos⁴θ, the density
    /// (times K) of the camera ray from `sensor_mm` to `sample`'s target per unit étendue and
    /// per unit sensor density (0 where the pdf is 0): what the camera's hero-wavelength
    /// estimator sums over the lanes.
    pub fn inverse_sensor_weight(&self, sensor_mm: [f64; 2], sample: &PupilSample) -> f64 {
        let delta = self.sensor_distance_mm;
        let offset =
            DVec3::new(sample.target_mm[0] - sensor_mm[0], sample.target_mm[1] - sensor_mm[1], -delta);
        let cos_theta = delta / offset.length();
        delta * delta * sample.pdf_per_mm2 * self.projected_solid_angle_sr / cos_theta.powi(4)
    }
}

/// A camera ray with its weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CameraRay {
    /// The ray out of the lens and the lens's effect on the light along it.
    pub sample: LensSample,
    /// cos⁴θ/(Δ² pdf K) ([`Normalisation::sensor_weight`]): multiply the Mueller matrix
    /// `sample.mueller` by it for the polarised image.
    pub sensor_weight: f64,
    /// `sensor_weight` × `sample.throughput`: what multiplies the scene radiance (unpolarised
    /// light) to give the normalised sensor reading.
    pub weight: f64,
}

/// Bands of sensor radius of [`SensorSampler::new`]'s exit-pupil bounds.
pub const DEFAULT_PUPIL_BANDS: usize = 32;
/// Test-ray grid per band of [`SensorSampler::new`]: 96² targets, the regions widened by two
/// cells (1/24 of the rear disc's radius).
pub const DEFAULT_PUPIL_GRID: usize = 96;

/// What a lens camera needs to turn a sensor point and two uniform numbers into a weighted ray:
/// the tracer, the exit-pupil bounds and the normalisation, measured once.
#[derive(Clone, Debug)]
pub struct SensorSampler {
    /// The lens, prepared for tracing (its last thickness is the sensor distance).
    pub tracer: LensTracer,
    /// Where rays are aimed.
    pub bounds: ExitPupilBounds,
    /// The rear element's disc: with ghosts on, part of the rays are aimed over all of it
    /// ([`GhostMixture`]).
    pub rear: RearDisc,
    /// The normalisation K.
    pub normalisation: Normalisation,
}

impl SensorSampler {
    /// Measures the bounds (for sensor points up to `sensor_half_diagonal_mm` off axis, with
    /// [`DEFAULT_PUPIL_BANDS`] and [`DEFAULT_PUPIL_GRID`]) and the normalisation at
    /// `reference_lambda_nm` (the focus wavelength) of `system`, focused as it is.
    pub fn new(system: LensSystem, sensor_half_diagonal_mm: f64, reference_lambda_nm: f64) -> Self {
        let tracer = LensTracer::new(system);
        let bounds = ExitPupilBounds::measure(
            &tracer,
            sensor_half_diagonal_mm,
            DEFAULT_PUPIL_BANDS,
            DEFAULT_PUPIL_GRID,
        );
        let normalisation = Normalisation::measure(&tracer, reference_lambda_nm);
        let rear = RearDisc::new(&tracer);
        Self { tracer, bounds, rear, normalisation }
    }

    /// The ghost aiming of this lens: its bounds and rear disc.
    pub fn ghost_mixture(&self) -> GhostMixture<'_> {
        GhostMixture { bounds: &self.bounds, rear: &self.rear }
    }

    /// The camera ray from `sensor_mm` (x, y on the sensor, mm, lens coordinates) aimed by the
    /// uniform pair `u_pupil`, traced per `options` with `next_uniform` for ghost branches;
    /// `None` when it does not reach the scene (its contribution is 0, and the estimator stays
    /// unbiased: the pdf covers every passing ray). Aimed inside the exit-pupil bounds without
    /// ghosts, by the [`GhostMixture`] with them (`options.max_ghost_reflections` > 0 and
    /// Fresnel on).
    pub fn sample(
        &self,
        sensor_mm: [f64; 2],
        u_pupil: [f64; 2],
        options: &TraceOptions,
        next_uniform: &mut dyn FnMut() -> f64,
    ) -> Option<CameraRay> {
        let pupil = if options.fresnel && options.max_ghost_reflections > 0 {
            self.ghost_mixture().sample(sensor_mm, u_pupil)?
        } else {
            self.bounds.sample(sensor_mm, u_pupil)?
        };
        let sample = self.tracer.trace_from_sensor(sensor_mm, pupil.target_mm, options, next_uniform)?;
        let sensor_weight = self.normalisation.sensor_weight(sensor_mm, &pupil);
        Some(CameraRay { sample, sensor_weight, weight: sensor_weight * sample.throughput })
    }
}

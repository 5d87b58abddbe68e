//! What an optical engineer checks first of a lens, beyond its paraxial numbers: spot diagrams
//! per wavelength and field, the chief ray, the on-axis transmission against Π(1 − R) (with and
//! without the surfaces' coatings), and the
//! relative illumination and transmission across the field. `prisma lens` prints and plots
//! them.
//!
//! Definitions (those of the design codes the lenses are checked against, e.g. rayoptics):
//! - fields are angles θ of an object at infinity; rays start on a plane a little in front of
//!   the first surface with direction (0, sin θ, cos θ), so the image lies at +y;
//! - the **chief ray** of a field passes the centre of the aperture stop (real-ray aiming:
//!   secant iteration on its start height, from the paraxial entrance pupil's aim);
//! - a **spot diagram** traces a cell-centred N×N grid over the d-line paraxial entrance pupil
//!   (points inside the unit circle), offset by the chief ray's start; the RMS radius is taken
//!   about the centroid of the rays that pass every clear aperture;
//! - **illumination** is the sensor irradiance of a uniform radiance at infinity,
//!   E = ∫ L τ cos⁴θ/Δ² dA over the rear vertex plane ([`super::pupil`]), integrated on a
//!   stratified grid of [`ExitPupilBounds`] targets at the image height of each field's chief
//!   ray: relative illumination E(θ)/E(0) with the lens lossless (vignetting, cos⁴, pupil
//!   distortion), and the transmission ∫τ·w / ∫w (Fresnel losses, exact s/p per surface through
//!   the path's Mueller matrix, a coated surface's from its stack, no ghosts).

use glam::DVec3;

use super::paraxial::LAMBDA_D_NM;
use super::pupil::ExitPupilBounds;
use super::trace::{LensTracer, Ray, TraceOptions};
use super::{LensError, LensSystem};

/// The F, d and C lines (nm): hydrogen F, helium d, hydrogen C.
pub const FRAUNHOFER_FDC_NM: [(char, f64); 3] = [('F', 486.1327), ('d', LAMBDA_D_NM), ('C', 656.2725)];

/// Cells per side of a spot diagram's pupil grid (812 of the 32² cell centres fall inside the
/// unit circle, none on its rim).
pub const SPOT_GRID: usize = 32;

/// Target cells per side of the illumination integral over the exit-pupil bounds.
const ILLUMINATION_GRID: usize = 96;

/// A spot diagram: where the rays of one field and wavelength meet the image plane.
#[derive(Clone, Debug, PartialEq)]
pub struct Spot {
    /// The wavelength (nm).
    pub lambda_nm: f64,
    /// The field angle (degrees).
    pub field_deg: f64,
    /// Image-plane intercepts (x, y) in mm of the rays that pass.
    pub points: Vec<[f64; 2]>,
    /// Grid rays inside the pupil.
    pub rays_in_pupil: usize,
    /// Centroid of `points` (mm).
    pub centroid_mm: [f64; 2],
    /// RMS distance of `points` from the centroid (mm).
    pub rms_radius_mm: f64,
    /// The chief ray's image intercept (mm), when the chief ray passes.
    pub chief_mm: Option<[f64; 2]>,
}

/// Illumination at one field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Illumination {
    /// The field angle (degrees).
    pub field_deg: f64,
    /// Image height of the field's chief ray at the d line (mm).
    pub image_height_mm: f64,
    /// E(θ)/E(0) of the lossless lens: vignetting, cos⁴ and pupil distortion.
    pub relative: f64,
    /// E(θ)/E(0) with the Fresnel losses of the uncoated surfaces.
    pub relative_with_fresnel: f64,
    /// The Fresnel transmission at this field, ∫τ·w / ∫w (unpolarised light).
    pub transmission: f64,
}

/// A lens prepared for analysis: tracer, the d-line entrance pupil, the start plane.
pub struct Analysis {
    tracer: LensTracer,
    /// The surfaces up to the stop, apertures open: what the chief ray is aimed through.
    to_stop: LensTracer,
    entrance_pupil_z_mm: f64,
    entrance_pupil_radius_mm: f64,
    start_z_mm: f64,
}

impl Analysis {
    /// Prepares `system` (its image plane where its last thickness puts it).
    pub fn new(system: &LensSystem) -> Result<Self, LensError> {
        let paraxial = system.paraxial(LAMBDA_D_NM)?;
        // In front of the first surface's whole clear aperture, however it bulges.
        let first = &system.surfaces[0];
        let start_z_mm = -(10.0 + first.semi_diameter_mm);
        let stop = system.stop_index().ok_or_else(|| LensError::System {
            file: system.source.display().to_string(),
            message: "no aperture stop is marked".into(),
        })?;
        let mut to_stop =
            LensSystem { surfaces: system.surfaces[..=stop].to_vec(), source: system.source.clone() };
        for surface in &mut to_stop.surfaces {
            surface.semi_diameter_mm = f64::INFINITY;
        }
        Ok(Self {
            tracer: LensTracer::new(system.clone()),
            to_stop: LensTracer::new(to_stop),
            entrance_pupil_z_mm: paraxial.entrance_pupil_z_mm,
            entrance_pupil_radius_mm: 0.5 * paraxial.entrance_pupil_diameter_mm,
            start_z_mm,
        })
    }

    /// The tracer.
    pub fn tracer(&self) -> &LensTracer {
        &self.tracer
    }

    fn ray(&self, field_deg: f64, x_mm: f64, y_mm: f64) -> Ray {
        let theta = field_deg.to_radians();
        Ray {
            origin: DVec3::new(x_mm, y_mm, self.start_z_mm),
            dir: DVec3::new(0.0, theta.sin(), theta.cos()),
        }
    }

    /// The start height (mm, on the start plane) of the chief ray of `field_deg` at
    /// `lambda_nm`: the ray through the stop's centre. `None` when no ray near the paraxial aim
    /// reaches the stop.
    pub fn chief_start_y_mm(&self, field_deg: f64, lambda_nm: f64) -> Option<f64> {
        let theta = field_deg.to_radians();
        // Paraxial aim: through the entrance pupil's centre.
        let guess = -(self.entrance_pupil_z_mm - self.start_z_mm) * theta.tan();
        if field_deg == 0.0 {
            return Some(0.0);
        }
        let to_stop = &self.to_stop;
        let stop_y = |y: f64| -> Option<f64> {
            let traced = to_stop.trace_from_object(self.ray(field_deg, 0.0, y), lambda_nm).ok()?;
            Some(traced.interactions.last()?.point.y)
        };
        let scale = self.entrance_pupil_radius_mm.max(1e-3);
        let (mut y0, mut y1) = (guess, guess + 1e-3 * scale);
        let (mut f0, mut f1) = (stop_y(y0)?, stop_y(y1)?);
        for _ in 0..50 {
            if f1 == f0 {
                break;
            }
            let y2 = y1 - f1 * (y1 - y0) / (f1 - f0);
            (y0, f0) = (y1, f1);
            y1 = y2;
            f1 = stop_y(y1)?;
            if f1.abs() <= 1e-13 * scale {
                break;
            }
        }
        Some(y1)
    }

    /// The spot diagram of `field_deg` at `lambda_nm` on the image plane.
    pub fn spot(&self, field_deg: f64, lambda_nm: f64) -> Spot {
        let chief_y = self.chief_start_y_mm(field_deg, lambda_nm);
        let chief_mm = chief_y.and_then(|y| {
            let traced = self.tracer.trace_from_object(self.ray(field_deg, 0.0, y), lambda_nm).ok()?;
            Some([traced.ray.origin.x, traced.ray.origin.y])
        });
        let centre_y = chief_y.unwrap_or(0.0);
        let radius = self.entrance_pupil_radius_mm;
        let mut points = Vec::new();
        let mut rays_in_pupil = 0;
        for i in 0..SPOT_GRID {
            for j in 0..SPOT_GRID {
                let px = -1.0 + (2.0 * i as f64 + 1.0) / SPOT_GRID as f64;
                let py = -1.0 + (2.0 * j as f64 + 1.0) / SPOT_GRID as f64;
                if px * px + py * py > 1.0 {
                    continue;
                }
                rays_in_pupil += 1;
                let ray = self.ray(field_deg, px * radius, centre_y + py * radius);
                if let Ok(traced) = self.tracer.trace_from_object(ray, lambda_nm) {
                    points.push([traced.ray.origin.x, traced.ray.origin.y]);
                }
            }
        }
        let count = points.len().max(1) as f64;
        let centroid_mm = [
            points.iter().map(|p| p[0]).sum::<f64>() / count,
            points.iter().map(|p| p[1]).sum::<f64>() / count,
        ];
        let rms_radius_mm = (points
            .iter()
            .map(|p| (p[0] - centroid_mm[0]).powi(2) + (p[1] - centroid_mm[1]).powi(2))
            .sum::<f64>()
            / count)
            .sqrt();
        Spot { lambda_nm, field_deg, points, rays_in_pupil, centroid_mm, rms_radius_mm, chief_mm }
    }

    /// Sensor irradiance at image height `height_mm` (on +y) of a uniform unit radiance, per
    /// the normalisation-free integral E = ∫ τ cos⁴θ/Δ² dA: (lossless, with Fresnel).
    fn irradiance(&self, bounds: &ExitPupilBounds, height_mm: f64) -> (f64, f64) {
        let sensor = [0.0, height_mm];
        let delta = self.tracer.image_z_mm() - self.tracer.rear_vertex_z_mm();
        let lossless = TraceOptions { fresnel: false, ..TraceOptions::new(LAMBDA_D_NM) };
        let real = TraceOptions::new(LAMBDA_D_NM);
        let (mut geometric, mut fresnel) = (0.0, 0.0);
        let n = ILLUMINATION_GRID;
        for i in 0..n {
            for j in 0..n {
                let u = [(i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64];
                let Some(sample) = bounds.sample(sensor, u) else { continue };
                let offset = DVec3::new(sample.target_mm[0], sample.target_mm[1] - height_mm, -delta);
                let cos_theta = delta / offset.length();
                let weight = cos_theta.powi(4) / (delta * delta * sample.pdf_per_mm2);
                if self.tracer.trace_from_sensor(sensor, sample.target_mm, &lossless, &mut || 0.0).is_some() {
                    geometric += weight;
                }
                if let Some(passed) =
                    self.tracer.trace_from_sensor(sensor, sample.target_mm, &real, &mut || 0.0)
                {
                    fresnel += weight * passed.throughput;
                }
            }
        }
        let cells = (n * n) as f64;
        (geometric / cells, fresnel / cells)
    }

    /// Relative illumination and transmission at each of `fields_deg` (the first should be 0,
    /// the reference), at the d line.
    pub fn illumination(&self, fields_deg: &[f64]) -> Vec<Illumination> {
        let heights: Vec<f64> = fields_deg
            .iter()
            .map(|&field| {
                self.chief_start_y_mm(field, LAMBDA_D_NM)
                    .and_then(|y| self.tracer.trace_from_object(self.ray(field, 0.0, y), LAMBDA_D_NM).ok())
                    .map_or(f64::NAN, |traced| traced.ray.origin.y)
            })
            .collect();
        let max_height = heights.iter().copied().filter(|h| h.is_finite()).fold(0.0, f64::max);
        let bounds = ExitPupilBounds::measure(&self.tracer, max_height.max(1e-3) * 1.001, 32, 48);
        // Both columns are relative to the lossless lens's axis.
        let (axis, _) = self.irradiance(&bounds, 0.0);
        fields_deg
            .iter()
            .zip(&heights)
            .map(|(&field_deg, &height)| {
                let (geometric, fresnel) =
                    if height.is_finite() { self.irradiance(&bounds, height) } else { (0.0, 0.0) };
                Illumination {
                    field_deg,
                    image_height_mm: height,
                    relative: geometric / axis,
                    relative_with_fresnel: fresnel / axis,
                    transmission: if geometric > 0.0 { fresnel / geometric } else { f64::NAN },
                }
            })
            .collect()
    }
}

/// The on-axis transmission of the lens with its coatings at normal incidence, Π(1 − R) with
/// R the coating stack's reflectance at normal incidence on a coated surface
/// ([`super::coating::Coating::normal_reflectance`]) and ((n₁ − n₂)/(n₁ + n₂))² on a bare one,
/// at `lambda_nm`: what the traced on-axis transmission tends to as the aperture closes. Equal
/// to [`normal_incidence_transmission`] for an uncoated lens.
pub fn coated_normal_incidence_transmission(system: &LensSystem, lambda_nm: f64) -> f64 {
    (0..system.surfaces.len())
        .map(|i| {
            let n1 = system.medium_before(i).n_at_nm(lambda_nm);
            let n2 = system.surfaces[i].medium.n_at_nm(lambda_nm);
            match &system.surfaces[i].coating {
                Some(coating) => 1.0 - coating.normal_reflectance(n1, n2, lambda_nm),
                None => 1.0 - ((n1 - n2) / (n1 + n2)).powi(2),
            }
        })
        .product()
}

/// The on-axis transmission of the lens without its coatings at normal incidence, Π(1 − R)
/// with R = ((n₁ − n₂)/(n₁ + n₂))² at every surface, at `lambda_nm`: the closed form the traced
/// on-axis transmission of an uncoated lens tends to as the aperture closes.
pub fn normal_incidence_transmission(system: &LensSystem, lambda_nm: f64) -> f64 {
    (0..system.surfaces.len())
        .map(|i| {
            let n1 = system.medium_before(i).n_at_nm(lambda_nm);
            let n2 = system.surfaces[i].medium.n_at_nm(lambda_nm);
            1.0 - ((n1 - n2) / (n1 + n2)).powi(2)
        })
        .product()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lens::{Medium, Surface};

    fn surface(radius_mm: f64, thickness_mm: f64, medium: Medium, semi: f64, is_stop: bool) -> Surface {
        Surface::spherical(radius_mm, thickness_mm, medium, semi, is_stop)
    }

    /// A biconvex singlet of constant index 1.5 (f ≈ 100 mm) behind a stop 5 mm in front.
    fn singlet() -> LensSystem {
        let mut system = LensSystem {
            surfaces: vec![
                surface(0.0, 5.0, Medium::Air, 5.0, true),
                surface(100.0, 4.0, Medium::constant(1.5), 12.0, false),
                surface(-100.0, 0.0, Medium::Air, 12.0, false),
            ],
            source: "singlet".into(),
        };
        let focus = system.focus_thickness_mm(f64::INFINITY, LAMBDA_D_NM).expect("a converging lens");
        system.surfaces[2].thickness_mm = focus;
        system
    }

    /// The chief ray passes the stop's centre; with the stop at the first surface it starts
    /// where a straight line through the stop centre would.
    #[test]
    fn chief_ray_passes_the_stop_centre() {
        let system = singlet();
        let analysis = Analysis::new(&system).unwrap();
        let y = analysis.chief_start_y_mm(5.0, LAMBDA_D_NM).unwrap();
        // The stop is the first surface (flat, z = 0) in air: the ray reaches it unrefracted.
        let expected = -(0.0 - analysis.start_z_mm) * 5f64.to_radians().tan();
        assert!((y - expected).abs() < 1e-9, "{y} vs {expected}");
    }

    /// On axis the spot is centred on the axis, and its RMS radius shrinks as the pupil closes
    /// toward the paraxial focus (spherical aberration ∝ aperture³).
    #[test]
    fn on_axis_spot_is_centred() {
        let system = singlet();
        let analysis = Analysis::new(&system).unwrap();
        let spot = analysis.spot(0.0, LAMBDA_D_NM);
        assert_eq!(spot.rays_in_pupil, 812, "the 32² grid's cell centres inside the unit circle");
        assert_eq!(spot.points.len(), 812, "nothing is vignetted on axis");
        assert!(spot.centroid_mm[0].abs() < 1e-12 && spot.centroid_mm[1].abs() < 1e-12);
        assert!(spot.rms_radius_mm > 0.0 && spot.rms_radius_mm < 0.1, "{}", spot.rms_radius_mm);
    }

    /// On axis the lossless relative illumination is 1 by definition, and the Fresnel
    /// transmission is close to Π(1 − R) at normal incidence (rays at up to f/10 meet the
    /// surfaces within a few degrees of the normal, where R changes by < 1e-3 of itself).
    #[test]
    fn on_axis_transmission_is_the_normal_incidence_product() {
        let system = singlet();
        let analysis = Analysis::new(&system).unwrap();
        let rows = analysis.illumination(&[0.0, 5.0]);
        assert!((rows[0].relative - 1.0).abs() < 1e-12);
        let closed = normal_incidence_transmission(&system, LAMBDA_D_NM);
        assert!((closed - 0.96f64 * 0.96).abs() < 1e-12, "R = 0.04 per glass surface at n = 1.5: {closed}");
        assert!((rows[0].transmission / closed - 1.0).abs() < 1e-3, "{} vs {closed}", rows[0].transmission);
        assert!(rows[1].relative < 1.0, "cos⁴ falloff off axis: {}", rows[1].relative);
    }
}

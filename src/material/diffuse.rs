//! [`Diffuse`]: Lambertian reflection `f = ρ/π`, or the Oren–Nayar microfacet model for rough
//! diffuse surfaces (Oren & Nayar, "Generalization of Lambert's reflectance model", SIGGRAPH 1994,
//! the "qualitative" model of their eq. 30):
//!
//! f = ρ/π · (A + B · max(0, cos(φ_i − φ_o)) · sin α · tan β),
//! A = 1 − 0.5 σ²/(σ² + 0.33), B = 0.45 σ²/(σ² + 0.09), α = max(θ_i, θ_o), β = min(θ_i, θ_o),
//! with σ the standard deviation of the facet slope angle in radians. σ = 0 gives Lambert.
//!
//! ```toml
//! [materials.clay]
//! type = "diffuse"
//! albedo = { rgb = [0.8, 0.6, 0.4] }
//! roughness_deg = 20        # optional Oren–Nayar σ
//! ```

use glam::Vec3;

use crate::spectrum::DenseSpectrum;

/// A diffuse reflector.
#[derive(Debug, Clone)]
pub struct Diffuse {
    /// Albedo ρ(λ) in [0, 1].
    pub albedo: DenseSpectrum,
    /// Oren–Nayar (A, B) when the surface is rough; `None` for Lambert.
    oren_nayar: Option<(f32, f32)>,
}

impl Diffuse {
    /// A diffuse material with albedo `albedo` and Oren–Nayar roughness `sigma_rad` (radians,
    /// ≥ 0; 0 is Lambert).
    pub fn new(albedo: DenseSpectrum, sigma_rad: f32) -> Self {
        let oren_nayar = (sigma_rad > 0.0).then(|| {
            let s2 = sigma_rad * sigma_rad;
            (1.0 - 0.5 * s2 / (s2 + 0.33), 0.45 * s2 / (s2 + 0.09))
        });
        Self { albedo, oren_nayar }
    }

    /// The factor multiplying ρ/π for light arriving from `to_light` and leaving toward
    /// `to_viewer`, both unit vectors on the side of the unit `normal` (1 for Lambert).
    #[inline]
    pub fn shape_factor(&self, normal: Vec3, to_light: Vec3, to_viewer: Vec3) -> f32 {
        let Some((a, b)) = self.oren_nayar else {
            return 1.0;
        };
        let cos_i = normal.dot(to_light).clamp(-1.0, 1.0);
        let cos_o = normal.dot(to_viewer).clamp(-1.0, 1.0);
        let sin_i = (1.0 - cos_i * cos_i).max(0.0).sqrt();
        let sin_o = (1.0 - cos_o * cos_o).max(0.0).sqrt();
        // cos(φi − φo) from the tangential components of the two directions.
        let tangent_i = to_light - cos_i * normal;
        let tangent_o = to_viewer - cos_o * normal;
        let denom = sin_i * sin_o;
        let cos_phi_diff = if denom > 1e-8 { tangent_i.dot(tangent_o) / denom } else { 0.0 };
        // sin α tan β with α = max(θi, θo), β = min(θi, θo).
        let (sin_alpha, tan_beta) =
            if cos_i > cos_o { (sin_o, sin_i / cos_i.max(1e-8)) } else { (sin_i, sin_o / cos_o.max(1e-8)) };
        a + b * cos_phi_diff.max(0.0) * sin_alpha * tan_beta
    }

    /// A direction scattered from the side of the unit `normal` the light leaves on, drawn with
    /// the cosine density cos θ/π (Malley's method: a point of the unit disk by Shirley and
    /// Chiu's concentric map, lifted onto the hemisphere), from two uniform numbers in [0, 1).
    /// Used for Lambert and for Oren–Nayar alike: their ratio f·cos θ/pdf is
    /// ρ·[`Self::shape_factor`], bounded for both. Returns the direction and its density per
    /// steradian ([`Self::pdf`]).
    // Always inlined: as a call of its own from the path tracer's loop (another codegen unit)
    // it cost 3 % more CPU per sample on the glass-and-mirror room (validation/bench/PROFILE.md).
    #[inline(always)]
    pub fn sample(normal: Vec3, u: (f32, f32)) -> (Vec3, f32) {
        Self::lift(normal, concentric_disk(u))
    }

    /// [`Self::sample`] with the concentric map's sine and cosine by polynomials
    /// ([`concentric_disk_polynomial`]): the same directions to within f32 rounding (a few units
    /// in the last place), at the cost of a few multiplications instead of a call of the
    /// library's `sincosf` (7.6 % of the path tracer's CPU time on TP6 with its quad light,
    /// validation/bench/PROFILE.md). The path tracer's bounce; the light tracer keeps
    /// [`Self::sample`] so that Whitted's renders with caustics stay the same bit for bit.
    #[inline(always)]
    pub fn sample_polynomial(normal: Vec3, u: (f32, f32)) -> (Vec3, f32) {
        Self::lift(normal, concentric_disk_polynomial(u))
    }

    /// The point (x, y) of the unit disc lifted to the hemisphere about `normal` (Malley's
    /// method: cosine-distributed where the disc's points are uniform), with its density.
    #[inline(always)]
    fn lift(normal: Vec3, (x, y): (f32, f32)) -> (Vec3, f32) {
        let z = (1.0 - x * x - y * y).max(0.0).sqrt();
        let (tangent, bitangent) = normal.any_orthonormal_pair();
        let dir = (tangent * x + bitangent * y + normal * z).normalize();
        (dir, Self::pdf(normal, dir))
    }

    /// The density of [`Self::sample`] per steradian at `dir`: cos θ/π on the side of `normal`,
    /// 0 below it.
    #[inline]
    pub fn pdf(normal: Vec3, dir: Vec3) -> f32 {
        normal.dot(dir).max(0.0) * std::f32::consts::FRAC_1_PI
    }
}

/// Shirley and Chiu's concentric map of [0, 1)² onto the unit disk ("A low distortion map
/// between disk and square", 1997): area-preserving, so uniform numbers give uniform points.
#[inline]
pub(crate) fn concentric_disk((u1, u2): (f32, f32)) -> (f32, f32) {
    let (a, b) = (2.0 * u1 - 1.0, 2.0 * u2 - 1.0);
    if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    }
    let quarter = std::f32::consts::FRAC_PI_4;
    let (r, phi) =
        if a.abs() > b.abs() { (a, quarter * (b / a)) } else { (b, 2.0 * quarter - quarter * (a / b)) };
    (r * phi.cos(), r * phi.sin())
}

/// [`concentric_disk`] with the sine and cosine of its angle by [`sin_cos_quarter`]: the map's
/// angle is π/4·t or π/2 − π/4·t with |t| ≤ 1, so only |x| ≤ π/4 is ever needed, where Taylor
/// polynomials need no range reduction.
#[inline]
pub(crate) fn concentric_disk_polynomial((u1, u2): (f32, f32)) -> (f32, f32) {
    let (a, b) = (2.0 * u1 - 1.0, 2.0 * u2 - 1.0);
    if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    }
    // The two wedges by selects rather than branches: which one a sample falls in is a coin
    // toss the processor cannot predict. In the second, φ = π/2 − x: cos φ = sin x, sin φ = cos x.
    let second = a.abs() <= b.abs();
    let (r, ratio) = if second { (b, a / b) } else { (a, b / a) };
    let (sin, cos) = sin_cos_quarter(std::f32::consts::FRAC_PI_4 * ratio);
    let (x, y) = (r * cos, r * sin);
    if second {
        (y, x)
    } else {
        (x, y)
    }
}

/// sin x and cos x for |x| ≤ π/4, by their Taylor polynomials to x⁹ and x¹⁰: the first omitted
/// terms are below (π/4)¹¹/11! = 1.8e-9 and (π/4)¹²/12! = 1.2e-10, far under f32's half unit in
/// the last place (3e-8 near 1), so the error is Horner's rounding, a few units in the last place.
#[inline(always)]
fn sin_cos_quarter(x: f32) -> (f32, f32) {
    let x2 = x * x;
    let sin =
        x * (1.0 + x2 * (-1.0 / 6.0 + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362_880.0)))));
    let cos = 1.0
        + x2 * (-0.5
            + x2 * (1.0 / 24.0 + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40_320.0 + x2 * (-1.0 / 3_628_800.0)))));
    (sin, cos)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The polynomial map gives the library's points to within f32 rounding, over a grid of
    /// [0, 1)² that includes both branches, the diagonals between them and the centre.
    /// Tolerance 4e-7: a few units in the last place of coordinates of magnitude up to 1 (ulp
    /// 6e-8 near 1 for the library's `sincosf`, and Horner's five roundings for the
    /// polynomials).
    #[test]
    fn polynomial_concentric_map_is_the_librarys() {
        let n = 512;
        let mut worst = 0.0f32;
        for i in 0..n {
            for j in 0..n {
                let u = (i as f32 / n as f32, j as f32 / n as f32);
                let (x, y) = concentric_disk(u);
                let (px, py) = concentric_disk_polynomial(u);
                worst = worst.max((x - px).abs()).max((y - py).abs());
            }
        }
        assert!(worst < 4e-7, "worst difference {worst}");
        for x in [-std::f32::consts::FRAC_PI_4, -0.3, 0.0, 1e-3, 0.5, std::f32::consts::FRAC_PI_4] {
            let (sin, cos) = sin_cos_quarter(x);
            assert!((sin - x.sin()).abs() < 2e-7 && (cos - x.cos()).abs() < 2e-7, "{x}: {sin} {cos}");
        }
    }

    fn dir(theta_deg: f32, phi_deg: f32) -> Vec3 {
        let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
        Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
    }

    /// The sampled directions lie on the normal's side, with the density `pdf` reports, whose
    /// integral over the hemisphere is 1 (midpoint rule in cos θ and φ).
    #[test]
    fn sampling_stays_above_the_surface_with_a_normalised_density() {
        let normal = Vec3::new(0.3, -0.5, 0.8).normalize();
        for i in 0..64 {
            for j in 0..64 {
                let u = ((i as f32 + 0.5) / 64.0, (j as f32 + 0.5) / 64.0);
                let (dir, pdf) = Diffuse::sample(normal, u);
                assert!((dir.length() - 1.0).abs() < 1e-5);
                assert!(normal.dot(dir) >= 0.0);
                assert!((pdf - normal.dot(dir) / std::f32::consts::PI).abs() < 1e-6);
            }
        }
        let (n_theta, n_phi) = (400, 64);
        let mut integral = 0.0f64;
        for i in 0..n_theta {
            let cos = (i as f64 + 0.5) / n_theta as f64;
            let sin = (1.0 - cos * cos).sqrt();
            for j in 0..n_phi {
                let phi = (j as f64 + 0.5) / n_phi as f64 * std::f64::consts::TAU;
                let dir = Vec3::new((sin * phi.cos()) as f32, (sin * phi.sin()) as f32, cos as f32);
                integral += f64::from(Diffuse::pdf(Vec3::Z, dir));
            }
        }
        integral *= std::f64::consts::TAU / (n_theta * n_phi) as f64;
        assert!((integral - 1.0).abs() < 1e-4, "{integral}");
        assert_eq!(Diffuse::pdf(Vec3::Z, -Vec3::Z), 0.0);
    }

    #[test]
    fn zero_roughness_is_lambert() {
        let d = Diffuse::new(DenseSpectrum::constant(0.5), 0.0);
        for (ti, to, dp) in [(10.0, 70.0, 0.0), (60.0, 30.0, 180.0), (85.0, 5.0, 45.0)] {
            assert_eq!(d.shape_factor(Vec3::Z, dir(ti, 0.0), dir(to, dp)), 1.0);
        }
    }

    /// Values worked by hand from Oren & Nayar's eq. 30 for σ = 20° = 0.349066 rad:
    /// σ² = 0.121847, A = 1 − 0.5·0.121847/0.451847 = 0.865170,
    /// B = 0.45·0.121847/0.211847 = 0.258824.
    #[test]
    fn oren_nayar_matches_hand_values() {
        let d = Diffuse::new(DenseSpectrum::constant(0.5), 20f32.to_radians());
        // Normal incidence and exit: sin α = 0, so f/(ρ/π) = A.
        assert!((d.shape_factor(Vec3::Z, Vec3::Z, Vec3::Z) - 0.865170).abs() < 1e-5);
        // θi = 60°, θo = 30°, same azimuth: A + B·sin 60°·tan 30° = 0.865170 + 0.258824·0.5.
        let f = d.shape_factor(Vec3::Z, dir(60.0, 0.0), dir(30.0, 0.0));
        assert!((f - (0.865170 + 0.129412)).abs() < 1e-5, "{f}");
        // Opposite azimuths: cos(φi − φo) = −1 is clamped to 0, leaving A.
        let f = d.shape_factor(Vec3::Z, dir(60.0, 0.0), dir(30.0, 180.0));
        assert!((f - 0.865170).abs() < 1e-5, "{f}");
        // 90° apart in azimuth: cos = 0, again A.
        let f = d.shape_factor(Vec3::Z, dir(45.0, 0.0), dir(45.0, 90.0));
        assert!((f - 0.865170).abs() < 1e-5, "{f}");
    }
}

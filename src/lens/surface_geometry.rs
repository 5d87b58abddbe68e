//! The shape of one lens surface: its sag, where a ray meets it and its normal there, for
//! spheres, conics and even aspheres (Zemax's `STANDARD` and `EVENASPH`), in f64 and mm.
//!
//! With ρ = x² + y² (the squared distance from the axis), c = 1/R and k the conic constant,
//! the surface relative to its vertex is
//! ```text
//! z(ρ) = c ρ / (1 + √(1 − (1 + k) c² ρ)) + Σᵢ αᵢ ρⁱ          (i = 1, 2, …)
//! ```
//! (Zemax's even asphere; Welford, *Aberrations of Optical Systems*, §2.5 for the conic).
//! Without the αᵢ the surface is the quadric `c(ρ + (1 + k) z²) − 2z = 0`, which a ray meets
//! in closed form (Spencer & Murty 1962, JOSA 52, 672, their stable root); with them Newton's
//! method refines the conic's root. Of the quadric's two sheets (a sphere's two hemispheres)
//! the lens surface is the patch through the vertex, where the quadric's gradient has a
//! positive z component; a ray that meets the quadric only on the far side misses the lens.

use glam::DVec3;

use super::Surface;

/// Newton's method on an asphere stops when a step moves the ray parameter by less than this
/// (mm): far below any tolerance of the traces (1e-9 of a lens's scale) and still ~100 ulps of
/// a 100 mm coordinate, so it is reached without stalling on rounding.
const NEWTON_STEP_MM: f64 = 1e-13;
/// At most this many Newton steps: from the conic's root the iteration converges
/// quadratically within a handful; one that has not converged by then has no root nearby.
const NEWTON_MAX_STEPS: usize = 60;

/// Where a ray meets a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// The ray parameter t (mm for a unit direction) of the hit: origin + t·dir.
    pub t: f64,
    /// The point, in lens coordinates (mm).
    pub point: DVec3,
    /// The unit normal there, pointing toward +z (toward the image) on the vertex patch.
    pub normal: DVec3,
}

/// The sag z(ρ) of `surface` relative to its vertex (mm) at ρ = x² + y² (mm²); `None` where
/// the conic's square root is negative (beyond the edge of a sphere or an ellipsoid).
pub fn sag(surface: &Surface, rho_mm2: f64) -> Option<f64> {
    let c = surface.curvature_per_mm();
    let mut root = 1.0 - (1.0 + surface.conic) * c * c * rho_mm2;
    // At the edge itself (ρ = R² on a hemisphere) c²ρ rounds to 1 ± a few ulp.
    if root < 0.0 && root > -4.0 * f64::EPSILON {
        root = 0.0;
    }
    if root.is_nan() || root < 0.0 {
        return None;
    }
    let conic = c * rho_mm2 / (1.0 + root.sqrt());
    Some(conic + polynomial(&surface.aspheric_mm, rho_mm2).0)
}

/// Σ αᵢ ρⁱ and its derivative Σ i αᵢ ρ^{i−1}, by Horner's scheme.
fn polynomial(alphas: &[f64], rho: f64) -> (f64, f64) {
    let (mut value, mut slope) = (0.0, 0.0);
    for (index, alpha) in alphas.iter().enumerate().rev() {
        let power = (index + 1) as f64;
        value = (value + alpha) * rho;
        slope = slope * rho + power * alpha;
    }
    (value, slope)
}

/// The first hit of the ray `origin + t·dir` (t > `t_min`, mm) with `surface` whose vertex is
/// at z = `vertex_z_mm`, on the patch through the vertex; `None` when it misses. The clear
/// aperture is not checked here (see [`within_aperture`]).
pub fn intersect(surface: &Surface, vertex_z_mm: f64, origin: DVec3, dir: DVec3, t_min: f64) -> Option<Hit> {
    let local = origin - DVec3::new(0.0, 0.0, vertex_z_mm);
    // 1/R once for the root and the normal.
    let c = surface.curvature_per_mm();
    let conic_hit = intersect_conic(surface, c, local, dir, t_min)?;
    let t = if surface.aspheric_mm.is_empty() {
        conic_hit
    } else {
        newton_asphere(surface, local, dir, conic_hit)?
    };
    if t.is_nan() || t <= t_min || t.is_infinite() {
        return None;
    }
    let point_local = local + t * dir;
    let normal = normal_local(surface, c, point_local)?;
    Some(Hit { t, point: point_local + DVec3::new(0.0, 0.0, vertex_z_mm), normal })
}

/// Whether `point` lies within the clear semi-diameter of `surface`, its rim included: a ray
/// aimed exactly at the rim (a marginal ray) passes although rounding of its position (~1e-16
/// relative) may put it a hair outside, hence the relative slack of 1e-12 on ρ.
pub fn within_aperture(surface: &Surface, point: DVec3) -> bool {
    const RIM_SLACK: f64 = 1e-12;
    let semi_squared = surface.semi_diameter_mm * surface.semi_diameter_mm;
    point.x * point.x + point.y * point.y <= semi_squared * (1.0 + RIM_SLACK)
}

/// The first root (t > `t_min`) of the quadric c(x² + y² + (1 + k) z²) − 2z = 0 along
/// `local + t·dir` that lies on the patch through the vertex, or `None`; `c` is the surface's
/// curvature (1/mm).
fn intersect_conic(surface: &Surface, c: f64, local: DVec3, dir: DVec3, t_min: f64) -> Option<f64> {
    let k1 = 1.0 + surface.conic;
    // With A = c(dx² + dy² + k1 dz²), B = dz − c(x dx + y dy + k1 z dz),
    // C = c(x² + y² + k1 z²) − 2z the equation is A t² − 2B t + C = 0; its roots are
    // q/A and C/q with q = B + sign(B)·√(B² − AC), free of cancellation (the second tends to
    // the plane's root C/(2B) as A → 0).
    let a = c * (dir.x * dir.x + dir.y * dir.y + k1 * dir.z * dir.z);
    let b = dir.z - c * (local.x * dir.x + local.y * dir.y + k1 * local.z * dir.z);
    let cc = c * (local.x * local.x + local.y * local.y + k1 * local.z * local.z) - 2.0 * local.z;
    let discriminant = b * b - a * cc;
    if discriminant < 0.0 {
        return None;
    }
    let q = b + if b < 0.0 { -discriminant.sqrt() } else { discriminant.sqrt() };
    // The vertex patch: the gradient (−c x, −c y, 1 − c k1 z) points toward +z there.
    let on_patch = |t: f64| t.is_finite() && t > t_min && 1.0 - c * k1 * (local.z + t * dir.z) > 0.0;
    let roots = [if q != 0.0 { cc / q } else { f64::NAN }, if a != 0.0 { q / a } else { f64::NAN }];
    roots.into_iter().filter(|&t| on_patch(t)).min_by(f64::total_cmp)
}

/// Newton's method on g(t) = z(t) − sag(ρ(t)) from the conic's root `t0`.
fn newton_asphere(surface: &Surface, local: DVec3, dir: DVec3, t0: f64) -> Option<f64> {
    let mut t = t0;
    for _ in 0..NEWTON_MAX_STEPS {
        let p = local + t * dir;
        let rho = p.x * p.x + p.y * p.y;
        let (value, slope) = sag_and_slope(surface, rho)?;
        let g = p.z - value;
        // dρ/dt = 2(x dx + y dy).
        let dg = dir.z - slope * 2.0 * (p.x * dir.x + p.y * dir.y);
        if dg == 0.0 || !dg.is_finite() {
            return None;
        }
        let step = g / dg;
        t -= step;
        if step.abs() < NEWTON_STEP_MM {
            return Some(t);
        }
    }
    None
}

/// The sag and dz/dρ at ρ, `None` beyond the conic's edge.
fn sag_and_slope(surface: &Surface, rho: f64) -> Option<(f64, f64)> {
    let c = surface.curvature_per_mm();
    let root = 1.0 - (1.0 + surface.conic) * c * c * rho;
    if root <= 0.0 {
        return None;
    }
    let sqrt = root.sqrt();
    let (poly, poly_slope) = polynomial(&surface.aspheric_mm, rho);
    // d/dρ [cρ/(1 + √u)] with u = 1 − (1+k)c²ρ simplifies to c / (2√u).
    Some((c * rho / (1.0 + sqrt) + poly, c / (2.0 * sqrt) + poly_slope))
}

/// The unit normal toward +z at `local` (relative to the vertex); `c` is the surface's
/// curvature (1/mm).
fn normal_local(surface: &Surface, c: f64, local: DVec3) -> Option<DVec3> {
    if surface.aspheric_mm.is_empty() && (surface.conic == 0.0 || c == 0.0) {
        // A sphere (or a plane): on c(x² + y² + z²) = 2z the gradient (−c x, −c y, 1 − c z)
        // has |g|² = 1 + c·(c(x² + y² + z²) − 2z) = 1 to the rounding of the hit (its residual
        // ~1e-15 mm times c), so it is the unit normal without a square root and a division.
        let normal = DVec3::new(-c * local.x, -c * local.y, 1.0 - c * local.z);
        return normal.is_finite().then_some(normal);
    }
    let gradient = if surface.aspheric_mm.is_empty() {
        DVec3::new(-c * local.x, -c * local.y, 1.0 - c * (1.0 + surface.conic) * local.z)
    } else {
        let rho = local.x * local.x + local.y * local.y;
        let (_, slope) = sag_and_slope(surface, rho)?;
        DVec3::new(-2.0 * slope * local.x, -2.0 * slope * local.y, 1.0)
    };
    let normal = gradient.normalize();
    normal.is_finite().then_some(normal)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lens::Medium;

    fn surface(radius_mm: f64, conic: f64, aspheric_mm: Vec<f64>) -> Surface {
        Surface {
            conic,
            aspheric_mm,
            ..Surface::spherical(radius_mm, 5.0, Medium::constant(1.5), 10.0, false)
        }
    }

    #[test]
    fn sphere_sag_is_the_circle() {
        // z = R − √(R² − r²) for a sphere of radius R centred at z = R.
        for radius in [25.0, -40.0] {
            let s = surface(radius, 0.0, vec![]);
            for r in [0.0, 1.0, 7.5, 20.0_f64] {
                let expected = radius - radius.signum() * (radius * radius - r * r).sqrt();
                let got = sag(&s, r * r).unwrap();
                assert!((got - expected).abs() < 1e-12, "R {radius}, r {r}: {got} vs {expected}");
            }
        }
    }

    #[test]
    fn paraboloid_sag_is_r_squared_over_2r() {
        // k = −1: z = r²/(2R) exactly, at every height.
        let s = surface(30.0, -1.0, vec![]);
        for r in [0.0, 3.0, 50.0_f64] {
            assert!((sag(&s, r * r).unwrap() - r * r / 60.0).abs() < 1e-12);
        }
    }

    #[test]
    fn hits_lie_on_the_surface_with_the_gradient_normal() {
        // Every hit satisfies z = sag(ρ) (the residual is the test); the normal is
        // perpendicular to the surface's tangents, checked by finite differences of the sag.
        let shapes = [
            surface(25.0, 0.0, vec![]),
            surface(-25.0, 0.0, vec![]),
            surface(0.0, 0.0, vec![]),
            surface(30.0, -1.0, vec![]),
            surface(30.0, 0.6, vec![]),
            surface(-30.0, -2.5, vec![]),
            surface(40.0, -0.5, vec![1e-3, -2e-5, 3e-8]),
        ];
        let rays = [
            (DVec3::new(0.3, -0.2, -10.0), DVec3::new(0.05, 0.02, 1.0)),
            (DVec3::new(5.0, 4.0, -3.0), DVec3::new(-0.2, -0.1, 1.0)),
            (DVec3::new(-2.0, 1.0, 12.0), DVec3::new(0.1, 0.0, -1.0)),
        ];
        for s in &shapes {
            for (origin, dir) in rays {
                let dir = dir.normalize();
                let hit = intersect(s, 2.0, origin, dir, 0.0).expect("hit");
                let local = hit.point - DVec3::new(0.0, 0.0, 2.0);
                let rho = local.x * local.x + local.y * local.y;
                let residual = local.z - sag(s, rho).unwrap();
                assert!(residual.abs() < 1e-12, "{s:?}: residual {residual}");
                assert!(((origin + hit.t * dir) - hit.point).length() < 1e-12);
                // Tangent along x and y by central differences (step 1e-5 mm, error ~1e-10).
                let h = 1e-5;
                let z_at = |x: f64, y: f64| sag(s, x * x + y * y).unwrap();
                let tx = DVec3::new(2.0 * h, 0.0, z_at(local.x + h, local.y) - z_at(local.x - h, local.y));
                let ty = DVec3::new(0.0, 2.0 * h, z_at(local.x, local.y + h) - z_at(local.x, local.y - h));
                assert!(hit.normal.dot(tx.normalize()).abs() < 1e-8, "{s:?}");
                assert!(hit.normal.dot(ty.normalize()).abs() < 1e-8, "{s:?}");
                assert!(hit.normal.z > 0.0 && (hit.normal.length() - 1.0).abs() < 1e-14);
            }
        }
    }

    #[test]
    fn only_the_vertex_hemisphere_is_hit() {
        // A ray along the axis from far behind a sphere of radius 10 (centre at z = 10)
        // meets its vertex patch at z = 0, not the far pole at z = 20, from either side.
        let s = surface(10.0, 0.0, vec![]);
        for (origin, dir) in
            [(DVec3::new(0.0, 0.0, -50.0), DVec3::Z), (DVec3::new(0.0, 0.0, 50.0), -DVec3::Z)]
        {
            let hit = intersect(&s, 0.0, origin, dir, 0.0).unwrap();
            assert!(hit.point.z.abs() < 1e-12, "{hit:?}");
        }
        // A ray parallel to the axis farther out than R misses the sphere altogether.
        assert!(intersect(&s, 0.0, DVec3::new(11.0, 0.0, -50.0), DVec3::Z, 0.0).is_none());
        // A ray that meets only the far hemisphere (starting inside the sphere, beyond its
        // centre, heading away from the vertex) misses the lens surface.
        assert!(intersect(&s, 0.0, DVec3::new(0.0, 0.0, 15.0), DVec3::Z, 0.0).is_none());
    }
}

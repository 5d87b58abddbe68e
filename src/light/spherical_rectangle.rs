//! [`SphericalRectangle`]: a rectangle as seen from a point, sampled uniformly in solid angle by
//! the area-preserving parametrisation of Ureña, Fajardo & King (2013), "An area-preserving
//! parametrization for spherical rectangles" (Computer Graphics Forum 32(4)), §3–4.
//!
//! The rectangle is placed in a local frame whose x and y axes run along its edges and whose z
//! axis points away from the viewing point, so that the viewing point is the origin and the
//! rectangle spans [x0, x1] × [y0, y1] in the plane z = z0 < 0 (the paper's convention). Its
//! solid angle is the area of the spherical quadrilateral, Ω = γ0 + γ1 + γ2 + γ3 − 2π (the
//! interior angles γ from the normals of the four great-circle planes); a sample (u, v) ∈ [0, 1)²
//! first picks the x coordinate whose sub-rectangle [x0, x] has solid angle u·Ω, then y along
//! that column by a uniform height on the unit sphere. Every cell of [0, 1)² maps to a region of
//! solid angle (cell area)·Ω, so stratified points stay stratified.
//!
//! Arithmetic is in f64: Ω is a small difference of angles near 2π when the rectangle is far
//! or seen at grazing incidence (Ω = 1e-4 sr leaves f32 a relative error near 1 %, which would
//! bias the estimate that divides by it).

use glam::{DVec3, Vec3};

/// Edges whose cosine of the angle between them is below this are orthogonal (a rectangle). A
/// scene's edges written as exact integers are orthogonal to rounding (about 1e-7 in f32).
const ORTHOGONAL_COSINE: f64 = 1e-5;

/// A rectangle seen from a point (the origin of its local frame); see the module's doc.
#[derive(Debug, Clone, Copy)]
pub struct SphericalRectangle {
    /// The viewing point (world, scene units).
    origin: DVec3,
    /// The local frame's unit axes in world coordinates: along the first edge, along the
    /// second, and away from the viewing point.
    axes: [DVec3; 3],
    /// The rectangle's extent in the local frame: x0, x1, y0, y1 (scene units).
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
    /// The (negative) distance of the rectangle's plane along the local z axis.
    z0: f64,
    /// The z components of the normals of the planes through the edges at y0 and y1.
    b0: f64,
    b1: f64,
    /// 2π − γ2 − γ3 (the paper's k).
    k: f64,
    /// Solid angle, sr.
    solid_angle: f64,
}

impl SphericalRectangle {
    /// The rectangle `corner + s·edge1 + t·edge2` (s, t ∈ [0, 1]) seen from `point`. `None`
    /// when the edges are not orthogonal (a parallelogram), degenerate, or when `point` lies in
    /// the rectangle's plane (no solid angle).
    pub fn new(point: Vec3, corner: Vec3, edge1: Vec3, edge2: Vec3) -> Option<Self> {
        let (origin, corner, edge1, edge2) =
            (point.as_dvec3(), corner.as_dvec3(), edge1.as_dvec3(), edge2.as_dvec3());
        let (length1, length2) = (edge1.length(), edge2.length());
        if !(length1 > 0.0 && length2 > 0.0) || !(length1 * length2).is_finite() {
            return None;
        }
        let (x, y) = (edge1 / length1, edge2 / length2);
        if x.dot(y).abs() > ORTHOGONAL_COSINE {
            return None;
        }
        let mut z = x.cross(y).normalize();
        let d = corner - origin;
        let mut z0 = d.dot(z);
        if z0 > 0.0 {
            z = -z;
            z0 = -z0;
        }
        if z0 >= 0.0 || !z0.is_finite() {
            return None;
        }
        let (x0, y0) = (d.dot(x), d.dot(y));
        let (x1, y1) = (x0 + length1, y0 + length2);
        let v00 = DVec3::new(x0, y0, z0);
        let v01 = DVec3::new(x0, y1, z0);
        let v10 = DVec3::new(x1, y0, z0);
        let v11 = DVec3::new(x1, y1, z0);
        let n0 = v00.cross(v10).normalize();
        let n1 = v10.cross(v11).normalize();
        let n2 = v11.cross(v01).normalize();
        let n3 = v01.cross(v00).normalize();
        let angle = |a: DVec3, b: DVec3| (-a.dot(b)).clamp(-1.0, 1.0).acos();
        let (g0, g1, g2, g3) = (angle(n0, n1), angle(n1, n2), angle(n2, n3), angle(n3, n0));
        let k = 2.0 * std::f64::consts::PI - g2 - g3;
        let solid_angle = g0 + g1 - k;
        if !(solid_angle > 0.0) || !solid_angle.is_finite() {
            return None;
        }
        Some(Self { origin, axes: [x, y, z], x0, x1, y0, y1, z0, b0: n0.z, b1: n2.z, k, solid_angle })
    }

    /// The solid angle the rectangle subtends, sr.
    pub fn solid_angle(&self) -> f64 {
        self.solid_angle
    }

    /// The point on the rectangle (world) of sample (u, v) ∈ [0, 1)²: uniform in solid angle.
    pub fn sample(&self, (u, v): (f32, f32)) -> Vec3 {
        let (u, v) = (f64::from(u), f64::from(v));
        // The x coordinate whose sub-rectangle [x0, x] subtends u·Ω (paper, eq. 13–16).
        let au = u * self.solid_angle + self.k;
        let (sin_au, cos_au) = au.sin_cos();
        let fu = (cos_au * self.b0 - self.b1) / sin_au;
        let cu = if fu.is_finite() {
            (fu.signum() / (fu * fu + self.b0 * self.b0).sqrt()).clamp(-1.0, 1.0)
        } else {
            0.0
        };
        let sin_cu = (1.0 - cu * cu).max(0.0).sqrt();
        let xu = if sin_cu > 0.0 { -(cu * self.z0) / sin_cu } else { self.x1 };
        let xu = if xu.is_finite() { xu.clamp(self.x0, self.x1) } else { self.x1 };
        // y along that column, uniform in the height on the unit sphere (eq. 17–18).
        let d = (xu * xu + self.z0 * self.z0).sqrt();
        let h0 = self.y0 / (d * d + self.y0 * self.y0).sqrt();
        let h1 = self.y1 / (d * d + self.y1 * self.y1).sqrt();
        let hv = h0 + v * (h1 - h0);
        let hv_sq = hv * hv;
        let yv = if hv_sq < 1.0 { (hv * d / (1.0 - hv_sq).sqrt()).clamp(self.y0, self.y1) } else { self.y1 };
        let [ax, ay, az] = self.axes;
        (self.origin + ax * xu + ay * yv + az * self.z0).as_vec3()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The solid angle of an a × b rectangle in the plane z = h seen from the origin, with
    /// corners at (x0, y0) and (x1, y1): Ω = Σ ± atan(x·y / (h·√(x² + y² + h²))) over the
    /// corners (the classical form factor of a rectangle; e.g. Gardner & Carnesale, or the
    /// integral of h/r³ over the rectangle), signs + at (x1, y1) and (x0, y0).
    fn closed_form(x0: f64, x1: f64, y0: f64, y1: f64, h: f64) -> f64 {
        let a = |x: f64, y: f64| (x * y / (h * (x * x + y * y + h * h).sqrt())).atan();
        a(x1, y1) - a(x0, y1) - a(x1, y0) + a(x0, y0)
    }

    #[test]
    fn solid_angle_matches_closed_form() {
        // Above, to the side, far, at grazing incidence, tilted frames.
        let cases = [
            ((-1.0, 1.0, -0.5, 0.5), 1.0),
            ((0.3, 2.3, 0.1, 1.1), 0.2),
            ((-7.0, -5.0, 3.0, 5.24), 4.0),
            ((10.0, 12.0, 10.0, 13.0), 0.05),
            ((-1.0, 1.0, -1.0, 1.0), 100.0),
        ];
        for ((x0, x1, y0, y1), h) in cases {
            let expected = closed_form(x0, x1, y0, y1, h);
            for flip in [false, true] {
                let z = if flip { -h } else { h };
                let corner = Vec3::new(x0 as f32, y0 as f32, z as f32);
                let edge1 = Vec3::new((x1 - x0) as f32, 0.0, 0.0);
                let edge2 = Vec3::new(0.0, (y1 - y0) as f32, 0.0);
                let rect = SphericalRectangle::new(Vec3::ZERO, corner, edge1, edge2).expect("a rectangle");
                // Relative 1e-5: the inputs are rounded to f32 (relative 6e-8 each); Ω's
                // sensitivity to them is at most a few times that over these cases.
                let relative = (rect.solid_angle() - expected).abs() / expected;
                assert!(relative < 1e-5, "{x0} {x1} {y0} {y1} {h}: {} vs {expected}", rect.solid_angle());
            }
        }
    }

    #[test]
    fn parallelogram_and_plane_points_are_refused() {
        let corner = Vec3::new(-1.0, -1.0, 1.0);
        assert!(SphericalRectangle::new(Vec3::ZERO, corner, Vec3::X * 2.0, Vec3::new(1.0, 2.0, 0.0)).is_none());
        assert!(SphericalRectangle::new(Vec3::new(0.0, 0.0, 1.0), corner, Vec3::X * 2.0, Vec3::Y * 2.0).is_none());
    }

    /// Every sample lies on the rectangle (its plane, within its edges).
    #[test]
    fn samples_lie_on_the_rectangle() {
        let corner = Vec3::new(1.0, 5.0, -2.0);
        let (edge1, edge2) = (Vec3::new(-2.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 2.0));
        let point = Vec3::new(0.3, -3.0, 4.0);
        let rect = SphericalRectangle::new(point, corner, edge1, edge2).expect("a rectangle");
        let normal = edge1.cross(edge2).normalize();
        for i in 0..=16 {
            for j in 0..=16 {
                let p = rect.sample((i as f32 / 16.0, j as f32 / 16.0));
                let local = p - corner;
                // 1e-5 scene units: f32 coordinates of size ~5 (ulp 5e-7), a few roundings.
                assert!(local.dot(normal).abs() < 1e-5, "{p}");
                let s = local.dot(edge1) / edge1.length_squared();
                let t = local.dot(edge2) / edge2.length_squared();
                assert!((-1e-5..=1.0 + 1e-5).contains(&s) && (-1e-5..=1.0 + 1e-5).contains(&t), "{s} {t}");
            }
        }
    }
}

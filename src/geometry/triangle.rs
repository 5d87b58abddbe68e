//! Watertight ray–triangle intersection.
//!
//! The algorithm of S. Woop, C. Benthin, I. Wald, "Watertight Ray/Triangle Intersection",
//! *JCGT* 2(1), 2013: the vertices are translated to the ray origin and sheared so that the ray
//! becomes the +z axis; the three 2D edge functions then decide inside/outside. An edge
//! function depends only on its two vertices (and flips sign exactly when they are swapped), so a
//! ray through the shared edge of two triangles hits at least one of them: closed meshes do not
//! leak. Edge functions that round to exactly 0 are recomputed in f64, as the paper recommends.
//!
//! The hit distance is accepted only when it is larger than its rounding-error bound (PBR 3rd ed.
//! §3.9.6, "conservative ray–triangle t"), so a ray starting on the triangle never re-hits it.
//! Intersection is two-sided; [`super::Quad`] reuses this test on its two halves.

use glam::Vec3;

use super::rounding::gamma;
use super::Ray;

/// A ray prepared for many triangle tests: the axis permutation and shear of the watertight test.
#[derive(Clone, Copy, Debug)]
pub struct ShearedRay {
    /// The ray itself.
    pub ray: Ray,
    /// Indices of the axes that become x, y and z (z: the largest |dir| component).
    axes: [usize; 3],
    /// The origin's coordinates along those axes.
    origin: [f32; 3],
    /// Shear (−dir_x/dir_z, −dir_y/dir_z in the permuted axes) and the z scale 1/dir_z.
    shear: [f32; 3],
}

impl ShearedRay {
    /// Precomputes the permutation and shear for `ray`.
    #[inline]
    pub fn new(ray: Ray) -> Self {
        let dir = ray.dir.to_array();
        let z = ray.dir.abs().max_position();
        let mut x = (z + 1) % 3;
        let mut y = (x + 1) % 3;
        // Swapping x and y when the ray runs along −z keeps the winding, hence the sign of the
        // edge functions, consistent.
        if dir[z] < 0.0 {
            std::mem::swap(&mut x, &mut y);
        }
        let shear = [-dir[x] / dir[z], -dir[y] / dir[z], 1.0 / dir[z]];
        let origin = ray.origin.to_array();
        Self { ray, axes: [x, y, z], origin: [origin[x], origin[y], origin[z]], shear }
    }
}

impl ShearedRay {
    /// The axis permutation, the permuted origin and the shear, for the 4-wide filter of
    /// [`super::packet`], which must round exactly as [`intersect_triangle`].
    #[inline]
    pub(crate) fn parts(&self) -> ([usize; 3], [f32; 3], [f32; 3]) {
        (self.axes, self.origin, self.shear)
    }
}

/// Where a ray meets a triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    /// Distance along the ray (scene units).
    pub t: f32,
    /// Barycentric weights of the three vertices (non-negative, summing to 1).
    pub barycentric: [f32; 3],
}

impl TriangleHit {
    /// The hit point interpolated from the vertices, as `v0 + b1·(v1 − v0) + b2·(v2 − v0)`: its
    /// rounding error is one ULP of the point plus a few ULPs of the triangle's size, and not
    /// the error of `origin + t·dir` far from the ray origin.
    #[inline]
    pub fn point(&self, vertices: &[Vec3; 3]) -> Vec3 {
        let [v0, v1, v2] = *vertices;
        v0 + self.barycentric[1] * (v1 - v0) + self.barycentric[2] * (v2 - v0)
    }
}

/// The intersection of `ray` with the triangle `vertices`, for t in (0, `t_max`), from either
/// side. Degenerate (zero-area) triangles are never hit.
#[inline]
pub fn intersect_triangle(ray: &ShearedRay, vertices: &[Vec3; 3], t_max: f32) -> Option<TriangleHit> {
    let [kx, ky, kz] = ray.axes;
    let [origin_x, origin_y, origin_z] = ray.origin;
    let [shear_x, shear_y, shear_z] = ray.shear;
    // Vertices relative to the origin, permuted so that the ray runs along z, then sheared so
    // that it is the z axis: (x, y) are the 2D positions the ray sees. The coordinates are read
    // by index from the vertex arrays (glam's `Vec3` indexing is a branchy `match`, which
    // showed in profiles); the rounding is that of `(v − origin)[k]`, one subtraction each.
    // (Written out per vertex: `[T; 3]::map` does not always inline here.)
    let relative = |v: &Vec3| {
        let v: &[f32; 3] = v.as_ref();
        let z = v[kz] - origin_z;
        (((v[kx] - origin_x) + shear_x * z, (v[ky] - origin_y) + shear_y * z), z)
    };
    let (a, a_z) = relative(&vertices[0]);
    let (b, b_z) = relative(&vertices[1]);
    let (c, c_z) = relative(&vertices[2]);
    let mut edges = [edge_function(c, b), edge_function(a, c), edge_function(b, a)];
    if edges[0] == 0.0 || edges[1] == 0.0 || edges[2] == 0.0 {
        // An exact zero in f32 may hide the sign; f64 holds the products exactly and rounds
        // the difference once, so the sign is right and shared edges stay consistent.
        edges = [edge_function_f64(c, b), edge_function_f64(a, c), edge_function_f64(b, a)];
    }
    let [e0, e1, e2] = edges;
    let any_negative = e0 < 0.0 || e1 < 0.0 || e2 < 0.0;
    let any_positive = e0 > 0.0 || e1 > 0.0 || e2 > 0.0;
    if any_negative && any_positive {
        return None;
    }
    let det = e0 + e1 + e2;
    if det == 0.0 {
        return None;
    }
    let z = [shear_z * a_z, shear_z * b_z, shear_z * c_z];
    let t_scaled = e0 * z[0] + e1 * z[1] + e2 * z[2];
    // t = t_scaled / det must lie in (0, t_max); compare before dividing.
    let in_range = if det > 0.0 {
        t_scaled > 0.0 && t_scaled < t_max * det
    } else {
        t_scaled < 0.0 && t_scaled > t_max * det
    };
    if !in_range {
        return None;
    }
    let inv_det = 1.0 / det;
    let t = t_scaled * inv_det;
    // t may still round up to t_max; and it must exceed its own error bound to be surely > 0.
    let accepted = t < t_max && t > distance_error_bound(&[a, b, c], &z, &edges, inv_det);
    if !accepted {
        return None;
    }
    Some(TriangleHit { t, barycentric: [e0 * inv_det, e1 * inv_det, e2 * inv_det] })
}

/// Twice the signed area of the 2D triangle (origin, p, q): positive when the origin sees p
/// then q counter-clockwise.
#[inline]
fn edge_function(p: (f32, f32), q: (f32, f32)) -> f32 {
    p.0 * q.1 - p.1 * q.0
}

/// [`edge_function`] evaluated in f64 and rounded once.
fn edge_function_f64(p: (f32, f32), q: (f32, f32)) -> f32 {
    (f64::from(p.0) * f64::from(q.1) - f64::from(p.1) * f64::from(q.0)) as f32
}

/// Bound on the rounding error of the computed t (PBR 3rd ed. §3.9.6): from the errors of the
/// translated and sheared coordinates (γ(3) for z, γ(5) for x and y), through the edge
/// functions, to the weighted sum of z and the division by the determinant. Generic over the
/// lanes, so that the 4-wide packet test (`super::packet`) evaluates exactly these operations.
#[inline(always)]
pub(crate) fn distance_error_bound<T: BoundLanes>(
    xy: &[(T, T); 3],
    z: &[T; 3],
    edges: &[T; 3],
    inv_det: T,
) -> T {
    let zero = T::splat(0.0);
    let max_x = xy.iter().fold(zero, |m, p| m.max(p.0.abs()));
    let max_y = xy.iter().fold(zero, |m, p| m.max(p.1.abs()));
    let max_z = z.iter().fold(zero, |m, v| m.max(v.abs()));
    let max_e = edges.iter().fold(zero, |m, v| m.max(v.abs()));
    let delta_z = T::splat(gamma(3)) * max_z;
    let delta_x = T::splat(gamma(5)) * (max_x + max_z);
    let delta_y = T::splat(gamma(5)) * (max_y + max_z);
    let delta_e = T::splat(2.0) * (T::splat(gamma(2)) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    T::splat(3.0) * (T::splat(gamma(3)) * max_e * max_z + delta_e * max_z + delta_z * max_e) * inv_det.abs()
}

/// One f32 or several lanes of them, for [`distance_error_bound`]. Where the values are finite
/// (always, for the lanes whose bound is used) `max` is exact, so f32's and the vector's agree.
pub(crate) trait BoundLanes:
    Copy + std::ops::Add<Output = Self> + std::ops::Mul<Output = Self>
{
    /// Every lane `value`.
    fn splat(value: f32) -> Self;
    /// Lane-wise absolute value.
    fn abs(self) -> Self;
    /// Lane-wise maximum.
    fn max(self, other: Self) -> Self;
}

impl BoundLanes for f32 {
    #[inline(always)]
    fn splat(value: f32) -> Self {
        value
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f32::abs(self)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        f32::max(self, other)
    }
}

impl BoundLanes for glam::Vec4 {
    #[inline(always)]
    fn splat(value: f32) -> Self {
        glam::Vec4::splat(value)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        glam::Vec4::abs(self)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        glam::Vec4::max(self, other)
    }
}

impl BoundLanes for wide::f32x16 {
    #[inline(always)]
    fn splat(value: f32) -> Self {
        wide::f32x16::splat(value)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        wide::f32x16::abs(self)
    }
    /// The plain vector maximum (no NaN handling: the bound is used only where every value is
    /// finite, and there it equals f32's).
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        wide::f32x16::fast_max(self, other)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::spawn_origin;
    use crate::geometry::test_util::Rng;

    const TRIANGLE: [Vec3; 3] =
        [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];

    fn intersect(origin: Vec3, dir: Vec3, vertices: &[Vec3; 3]) -> Option<TriangleHit> {
        let ray = ShearedRay::new(Ray::new(origin, dir.normalize()));
        intersect_triangle(&ray, vertices, f32::INFINITY)
    }

    #[test]
    fn hit_from_the_front_and_from_the_back() {
        // The triangle lies in z = 0. From z = 2 straight down through (0.25, 0.25): t = 2 and
        // weights (0.5, 0.25, 0.25) since the point is v0 + 0.25·e1 + 0.25·e2.
        let front = intersect(Vec3::new(0.25, 0.25, 2.0), -Vec3::Z, &TRIANGLE).expect("front hit");
        assert_eq!(front.t, 2.0);
        assert_eq!(front.barycentric, [0.5, 0.25, 0.25]);
        // Two-sided: the same from below.
        let back = intersect(Vec3::new(0.25, 0.25, -3.0), Vec3::Z, &TRIANGLE).expect("back hit");
        assert_eq!(back.t, 3.0);
        assert_eq!(back.point(&TRIANGLE), Vec3::new(0.25, 0.25, 0.0));
    }

    #[test]
    fn misses_outside_behind_and_beyond_t_max() {
        // Outside the hypotenuse x + y = 1.
        assert!(intersect(Vec3::new(0.6, 0.6, 1.0), -Vec3::Z, &TRIANGLE).is_none());
        // The triangle is behind the ray.
        assert!(intersect(Vec3::new(0.2, 0.2, 1.0), Vec3::Z, &TRIANGLE).is_none());
        // In front but further than t_max = 0.5.
        let ray = ShearedRay::new(Ray::new(Vec3::new(0.2, 0.2, 1.0), -Vec3::Z));
        assert!(intersect_triangle(&ray, &TRIANGLE, 0.5).is_none());
    }

    #[test]
    fn parallel_ray_and_degenerate_triangle_miss() {
        // A ray in the plane of the triangle sees it edge-on: zero determinant.
        assert!(intersect(Vec3::new(-1.0, 0.2, 0.0), Vec3::X, &TRIANGLE).is_none());
        // Three collinear vertices enclose nothing.
        let flat = [Vec3::ZERO, Vec3::X, 2.0 * Vec3::X];
        assert!(intersect(Vec3::new(0.5, 0.0, 1.0), -Vec3::Z, &flat).is_none());
    }

    #[test]
    fn grazing_ray_hits_at_the_right_distance() {
        // Descending 1 in 1000 over the triangle towards (0.5, 0.25): t = √(1000² + 1)·0.5e-3
        // from a start 0.5 units before the point in x, 0.5e-3 above it.
        let target = Vec3::new(0.5, 0.25, 0.0);
        let dir = Vec3::new(1.0, 0.0, -1e-3).normalize();
        let start = target - Vec3::new(0.5, 0.0, -0.5e-3);
        let hit = intersect(start, dir, &TRIANGLE).expect("grazing hit");
        assert!((hit.t - 0.5 * (1.0f32 + 1e-6).sqrt()).abs() < 1e-5, "t = {}", hit.t);
        assert!((hit.point(&TRIANGLE) - target).length() < 1e-5);
    }

    #[test]
    fn shared_edge_is_watertight() {
        // Two triangles sharing the diagonal (1,0,0)–(0,1,0) of the unit square. Rays through
        // points exactly on that edge, from random directions, must hit at least one of them.
        let first = TRIANGLE;
        let second = [Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
        let mut rng = Rng::new(7);
        for _ in 0..10_000 {
            let s = rng.uniform(0.0, 1.0);
            let on_edge = Vec3::new(1.0 - s, s, 0.0);
            let mut dir = rng.unit_vector();
            if dir.z.abs() < 1e-3 {
                dir = Vec3::Z;
            }
            let origin = on_edge - 5.0 * dir;
            let hits = [intersect(origin, dir, &first), intersect(origin, dir, &second)];
            assert!(hits.iter().any(Option::is_some), "leak at {on_edge} along {dir}");
        }
    }

    #[test]
    fn ray_starting_on_the_triangle_does_not_hit_it() {
        // Origins on a tilted triangle near the world origin, without any push: every t would
        // be ~0 and the error bound rejects it, in both directions. (Far from the world origin,
        // the rounding of the point's coordinates exceeds the triangle's own error bound and
        // the push of spawn_origin is needed: see the next test and accel.rs.)
        let vertices = [Vec3::new(0.3, 0.2, -0.7), Vec3::new(1.5, 0.4, 0.1), Vec3::new(0.2, 1.9, -0.5)];
        let mut rng = Rng::new(11);
        for _ in 0..10_000 {
            let b1 = rng.uniform(0.0, 0.5);
            let b2 = rng.uniform(0.0, 0.5);
            let on_surface = TriangleHit { t: 0.0, barycentric: [1.0 - b1 - b2, b1, b2] }.point(&vertices);
            let dir = rng.unit_vector();
            assert_eq!(intersect(on_surface, dir, &vertices), None, "re-hit from {on_surface} along {dir}");
        }
    }

    #[test]
    fn spawned_ray_does_not_hit_its_triangle() {
        // Hit points of real intersections with a small triangle 100 units away, pushed with
        // spawn_origin, sent to either side in random directions.
        let vertices =
            [Vec3::new(100.0, 3.0, -7.0), Vec3::new(101.5, 3.2, -6.0), Vec3::new(100.2, 4.9, -6.5)];
        let normal = (vertices[1] - vertices[0]).cross(vertices[2] - vertices[0]).normalize();
        let mut rng = Rng::new(13);
        for _ in 0..2_000 {
            let b1 = rng.uniform(0.0, 0.5);
            let b2 = rng.uniform(0.0, 0.5);
            let target = TriangleHit { t: 0.0, barycentric: [1.0 - b1 - b2, b1, b2] }.point(&vertices);
            let from = target + 10.0 * rng.unit_vector();
            let Some(hit) = intersect(from, target - from, &vertices) else {
                continue;
            };
            let point = hit.point(&vertices);
            for _ in 0..5 {
                let dir = rng.unit_vector();
                let origin = spawn_origin(point, normal, dir);
                assert_eq!(intersect(origin, dir, &vertices), None, "re-hit from {origin} along {dir}");
            }
        }
    }
}

//! [`SphereLanes`]: up to four spheres in the four lanes of one vector, so that a ray tests every
//! sphere of a small scene (TP6's two, the glass-and-mirror room's glass and mirror) in one pass
//! instead of one after another.
//!
//! Lane by lane the test evaluates the f32 operations of [`Sphere::intersect`] with the same
//! operands in the same order (the offset from the centre, b, the perpendicular offset and the
//! discriminant, c, q, the roots' error bounds and checks, the nearer kept root, the offset from
//! the centre at that root), so each lane keeps exactly the root the scalar test keeps, bit for
//! bit. Negation and `copysign` are the scalar ones' sign-bit operations; the square root and the
//! division are IEEE's, correctly rounded in both. Unused lanes hold NaN, which fails every
//! comparison. The normal is then normalised by the scalar `try_normalize` on the lane's offset,
//! as [`Sphere::intersect`] does; where that fails (a sphere of no size, a ray from its very
//! centre) the scalar test misses that sphere, and the spheres are searched again one by one.
//! When no lane has real roots (most rays miss every sphere) the test stops there, before the
//! square root and the divisions, as the scalar test does.
//!
//! Testing the spheres one after another with a shrinking limit finds the first of the nearest:
//! a sphere tested at a smaller limit hits exactly when its hit at the larger limit lies below
//! the smaller one (its roots do not depend on the limit), so [`SphereLanes::nearest`] tests all
//! lanes at one limit and keeps the first lane of the smallest distance. Its hit record is built
//! only when it is the ray's nearest hit (a quad may still be nearer).

use glam::Vec3;
use wide::f32x4;

use super::rounding::gamma;
use super::{Hit, Ray, Sphere};

/// Spheres tested at once.
pub(crate) const LANES: usize = 4;

/// Up to four spheres, by coordinate ("structure of arrays").
#[derive(Clone, Debug)]
pub(crate) struct SphereLanes {
    /// x, y, z of each sphere's centre.
    center: [f32x4; 3],
    /// Each sphere's radius.
    radius: f32x4,
    /// Each lane's shape index (in the list given to [`super::Geometry::build`]).
    ids: [u32; LANES],
}

/// The nearest sphere hit of [`SphereLanes::nearest`], before its hit record is built.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SphereHit {
    /// Distance along the ray.
    pub(crate) t: f32,
    /// The hit's unit normal, as [`Sphere::intersect`] computes it.
    normal: Vec3,
    /// The sphere's centre and radius, for the hit point.
    sphere: Sphere,
    /// The sphere's shape index.
    prim: u32,
}

impl SphereHit {
    /// The hit record: [`Sphere::intersect`]'s, bit for bit.
    #[inline(always)]
    pub(crate) fn record(&self) -> Hit {
        let point = self.sphere.center + self.sphere.radius * self.normal;
        Hit { t: self.t, point, normal: self.normal, shading_normal: self.normal, prim: self.prim }
    }
}

/// What [`SphereLanes::test`] found: the lanes with a root kept (bit i for lane i), the nearer
/// kept root of each (+∞ for none) and the offset from the centre to the ray's point at that root
/// (the normal before its normalisation, which may still fail).
struct Roots {
    kept: u32,
    t: f32x4,
    offset: [f32x4; 3],
}

/// −x, as f32's `Neg`: the sign bit flipped (not 0 − x, which differs for ±0).
#[inline(always)]
fn negate(x: f32x4) -> f32x4 {
    x ^ f32x4::splat(-0.0)
}

/// `magnitude` with the sign of `sign`, as `f32::copysign`: sign bits copied.
#[inline(always)]
fn copysign(magnitude: f32x4, sign: f32x4) -> f32x4 {
    let sign_bit = f32x4::splat(-0.0);
    (magnitude & !sign_bit) | (sign & sign_bit)
}

impl SphereLanes {
    /// `spheres` (shape index, sphere) in lane order; `None` if they are more than [`LANES`].
    pub(crate) fn of(spheres: &[(u32, Sphere)]) -> Option<Self> {
        if spheres.len() > LANES {
            return None;
        }
        let mut center = [[f32::NAN; LANES]; 3];
        let mut radius = [f32::NAN; LANES];
        let mut ids = [u32::MAX; LANES];
        for (lane, (id, sphere)) in spheres.iter().enumerate() {
            for (row, coordinate) in center.iter_mut().zip(sphere.center.to_array()) {
                row[lane] = coordinate;
            }
            radius[lane] = sphere.radius;
            ids[lane] = *id;
        }
        Some(Self { center: center.map(f32x4::new), radius: f32x4::new(radius), ids })
    }

    /// The sphere in lane `lane`.
    #[inline(always)]
    fn sphere(&self, lane: usize) -> Sphere {
        let at = |row: &f32x4| row.as_array()[lane];
        Sphere {
            center: Vec3::new(at(&self.center[0]), at(&self.center[1]), at(&self.center[2])),
            radius: at(&self.radius),
        }
    }

    /// The lanes whose nearer root [`Sphere::intersect`] keeps with t in (0, `t_max`), before
    /// the normalisation of the normal; `None` when no lane has real roots (most rays miss every
    /// sphere: the square root and the division are then skipped, as the scalar test returns
    /// there). Each line repeats, four lanes at a time, the operation of [`Sphere::intersect`]
    /// it is named after.
    #[inline(always)]
    fn test(&self, ray: &Ray, t_max: f32) -> Option<Roots> {
        let [dir_x, dir_y, dir_z] = ray.dir.to_array().map(f32x4::splat);
        let [origin_x, origin_y, origin_z] = ray.origin.to_array().map(f32x4::splat);
        // to_origin = origin − centre.
        let (to_x, to_y, to_z) =
            (origin_x - self.center[0], origin_y - self.center[1], origin_z - self.center[2]);
        let r2 = self.radius * self.radius;
        // b = −(to_origin·dir), Vec3::dot: (x·x' + y·y') + z·z'.
        let b = negate(to_x * dir_x + to_y * dir_y + to_z * dir_z);
        // perpendicular = to_origin + b·dir.
        let (perpendicular_x, perpendicular_y, perpendicular_z) =
            (to_x + b * dir_x, to_y + b * dir_y, to_z + b * dir_z);
        let perpendicular2 = perpendicular_x * perpendicular_x
            + perpendicular_y * perpendicular_y
            + perpendicular_z * perpendicular_z;
        let discriminant = r2 - perpendicular2;
        let real_roots = discriminant.simd_ge(f32x4::ZERO);
        if real_roots.to_bitmask() == 0 {
            return None;
        }
        let f2 = to_x * to_x + to_y * to_y + to_z * to_z;
        let c = f2 - r2;
        let q = b + copysign(discriminant.sqrt(), b);
        let error_b = f32x4::splat(gamma(4))
            * (to_x.abs() * dir_x.abs() + to_y.abs() * dir_y.abs() + to_z.abs() * dir_z.abs());
        let error_c = f32x4::splat(gamma(6)) * (f2 + r2);
        let sign_of_c_known = c.abs().simd_gt(error_c);
        let near_root = c / q;
        let t_max = f32x4::splat(t_max);
        let near_ok = sign_of_c_known & near_root.simd_gt(f32x4::ZERO) & near_root.simd_lt(t_max);
        let far_known = b.abs().simd_gt(error_b) | (sign_of_c_known & c.simd_lt(f32x4::ZERO));
        let far_ok = far_known & q.simd_gt(f32x4::ZERO) & q.simd_lt(t_max);
        // Both kept roots are finite and positive; a root not kept is +∞, which means no hit.
        let infinity = f32x4::splat(f32::INFINITY);
        let t = near_ok.select(near_root, infinity).min(far_ok.select(q, infinity));
        let kept = (real_roots & t.simd_ne(infinity)).to_bitmask();
        // The normal before normalisation: to_origin + t·dir.
        let offset = [to_x + t * dir_x, to_y + t * dir_y, to_z + t * dir_z];
        Some(Roots { kept, t, offset })
    }

    /// The nearest sphere hit with t in (0, `t_max`), the first among equal distances: what
    /// testing the spheres one after another with a shrinking limit finds (see the module notes).
    #[inline(always)]
    pub(crate) fn nearest(&self, ray: &Ray, t_max: f32) -> Option<SphereHit> {
        let roots = self.test(ray, t_max)?;
        if roots.kept == 0 {
            return None;
        }
        let distances = roots.t.as_array();
        let mut lanes = roots.kept;
        let mut nearest = lanes.trailing_zeros() as usize;
        lanes &= lanes - 1;
        while lanes != 0 {
            let lane = lanes.trailing_zeros() as usize;
            lanes &= lanes - 1;
            if distances[lane] < distances[nearest] {
                nearest = lane;
            }
        }
        let at = |row: &f32x4| row.as_array()[nearest];
        // Sphere::intersect's try_normalize; where it fails (a sphere of no size, a ray from its
        // very centre) that sphere is no hit and another may be: the spheres one by one decide.
        let Some(normal) =
            Vec3::new(at(&roots.offset[0]), at(&roots.offset[1]), at(&roots.offset[2])).try_normalize()
        else {
            return self.one_by_one(ray, t_max);
        };
        Some(SphereHit {
            t: distances[nearest],
            normal,
            sphere: self.sphere(nearest),
            prim: self.ids[nearest],
        })
    }

    /// [`Self::nearest`] by [`Sphere::intersect`] on each sphere in turn, at the limit its
    /// predecessors left.
    #[cold]
    #[inline(never)]
    fn one_by_one(&self, ray: &Ray, t_max: f32) -> Option<SphereHit> {
        let mut nearest = None;
        let mut t_limit = t_max;
        for lane in (0..LANES).filter(|&lane| self.ids[lane] != u32::MAX) {
            let sphere = self.sphere(lane);
            if let Some(hit) = sphere.intersect(ray, t_limit, self.ids[lane]) {
                t_limit = hit.t;
                nearest = Some(SphereHit { t: hit.t, normal: hit.normal, sphere, prim: hit.prim });
            }
        }
        nearest
    }

    /// Whether some sphere is hit with t in (0, `t_max`).
    #[inline(always)]
    pub(crate) fn any(&self, ray: &Ray, t_max: f32) -> bool {
        let Some(roots) = self.test(ray, t_max) else {
            return false;
        };
        // Sphere::intersect's try_normalize decides the lanes with a root kept.
        let mut lanes = roots.kept;
        while lanes != 0 {
            let lane = lanes.trailing_zeros() as usize;
            lanes &= lanes - 1;
            let at = |row: &f32x4| row.as_array()[lane];
            if Vec3::new(at(&roots.offset[0]), at(&roots.offset[1]), at(&roots.offset[2]))
                .try_normalize()
                .is_some()
            {
                return true;
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::spawn_origin;
    use crate::geometry::test_util::Rng;

    /// The scalar search: each sphere in turn at the limit its predecessors left.
    fn one_by_one(spheres: &[(u32, Sphere)], ray: &Ray, t_max: f32) -> Option<Hit> {
        let mut nearest = None;
        let mut t_limit = t_max;
        for (id, sphere) in spheres {
            if let Some(hit) = sphere.intersect(ray, t_limit, *id) {
                t_limit = hit.t;
                nearest = Some(hit);
            }
        }
        nearest
    }

    fn bits(hit: &Hit) -> [u32; 11] {
        let [px, py, pz] = hit.point.to_array().map(f32::to_bits);
        let [nx, ny, nz] = hit.normal.to_array().map(f32::to_bits);
        let [sx, sy, sz] = hit.shading_normal.to_array().map(f32::to_bits);
        [hit.t.to_bits(), hit.prim, px, py, pz, nx, ny, nz, sx, sy, sz]
    }

    #[test]
    fn lanes_find_the_scalar_tests_nearest_hit_bit_for_bit() {
        // One to four spheres (some overlapping, some the same sphere twice, so that equal
        // distances meet), rays from far away, from inside, from points on a sphere (spawned
        // and not: the rounding-error checks decide there), tangent and grazing rays, with and
        // without a limit: the same hit, bit for bit (t, prim, point, normal), and the same
        // answer to "any hit".
        let mut rng = Rng::new(41);
        let (mut hits, mut on_surface) = (0, 0);
        for _ in 0..4_000 {
            let count = 1 + rng.uniform(0.0, 4.0) as usize;
            let mut spheres: Vec<(u32, Sphere)> = (0..count)
                .map(|i| {
                    let center = rng.point_in(Vec3::splat(-3.0), Vec3::splat(3.0));
                    (i as u32 * 3 + 1, Sphere { center, radius: rng.log_uniform(0.01, 3.0) })
                })
                .collect();
            if count > 1 && rng.uniform(0.0, 1.0) < 0.2 {
                spheres[count - 1].1 = spheres[0].1;
            }
            let lanes = SphereLanes::of(&spheres).expect("at most four");
            for _ in 0..25 {
                let (_, sphere) = spheres[rng.uniform(0.0, count as f32) as usize];
                let on = sphere.center + sphere.radius * rng.unit_vector();
                let (origin, dir) = match rng.uniform(0.0, 5.0) as u32 {
                    0 => {
                        let from = rng.point_in(Vec3::splat(-20.0), Vec3::splat(20.0));
                        (from, (on - from).normalize())
                    }
                    1 => (sphere.center + 0.5 * sphere.radius * rng.unit_vector(), rng.unit_vector()),
                    2 => {
                        on_surface += 1;
                        (on, rng.unit_vector())
                    }
                    3 => {
                        let normal = (on - sphere.center).normalize();
                        let dir = rng.unit_vector();
                        (spawn_origin(on, normal, dir), dir)
                    }
                    _ => {
                        // Tangent at `on`, or nearly: along the surface, tilted by up to 1e-3.
                        let normal = (on - sphere.center).normalize();
                        let along = normal.cross(rng.unit_vector()).normalize();
                        let dir = (along + rng.uniform(-1e-3, 1e-3) * normal).normalize();
                        (on - rng.uniform(0.0, 5.0) * dir, dir)
                    }
                };
                if !dir.is_finite() {
                    continue;
                }
                let ray = Ray::new(origin, dir);
                let t_max = if rng.uniform(0.0, 1.0) < 0.5 { f32::INFINITY } else { rng.uniform(0.01, 10.0) };
                let expected = one_by_one(&spheres, &ray, t_max);
                let found = lanes.nearest(&ray, t_max).map(|hit| hit.record());
                assert_eq!(
                    found.as_ref().map(bits),
                    expected.as_ref().map(bits),
                    "{spheres:?}, {ray:?}, {t_max}"
                );
                let any = spheres.iter().any(|(_, sphere)| sphere.intersect(&ray, t_max, 0).is_some());
                assert_eq!(lanes.any(&ray, t_max), any, "{spheres:?}, {ray:?}, {t_max}");
                hits += usize::from(expected.is_some());
            }
        }
        assert!(hits > 40_000, "only {hits} hits");
        assert!(on_surface > 10_000, "only {on_surface} rays from a surface");
    }

    #[test]
    fn five_spheres_do_not_fit() {
        let sphere = Sphere { center: Vec3::ZERO, radius: 1.0 };
        assert!(SphereLanes::of(&[(0, sphere); 5]).is_none());
        assert!(SphereLanes::of(&[])
            .is_some_and(|lanes| lanes.nearest(&Ray::new(Vec3::Z, -Vec3::Z), 9.0).is_none()));
    }
}

//! Robust origins for secondary rays.
//!
//! A hit point is rounded to f32, so it lies a little off the true surface, on either side. A
//! reflected or refracted ray started from it could re-hit the surface it leaves at t ≈ 0 ("shadow
//! acne", rays that never enter glass). prisma defends against this in two places:
//!
//! 1. [`spawn_origin`] pushes the point off the surface, along the geometric normal and to the
//!    side the new ray travels to, by a bound on the rounding of the point's own coordinates
//!    (γ(2)·|p| per coordinate, projected on the normal), then rounds every coordinate one more
//!    float away from the surface so that the rounding of the addition cannot undo the push.
//!    This is the offset of Pharr, Jakob, Humphreys, *Physically Based Rendering*, 3rd ed.
//!    (2016), §3.9.5 "Robust spawned ray origins", with an error bound that depends on the
//!    point alone (the signature carries no per-hit error). As in Wächter & Binder, "A Fast and
//!    Robust Method for Avoiding Self-Intersection" (*Ray Tracing Gems*, ch. 6, 2019), the push
//!    scales with the magnitude of each coordinate, so it is a few ULPs wherever the scene sits.
//! 2. Every intersection routine rejects a hit whose distance is not provably positive given the
//!    rounding of its own arithmetic (PBR 3rd ed. §3.9.6, "Avoiding intersections behind ray
//!    origins", for triangles and quadrics). This covers the error that comes from the size
//!    of the shape rather than from the coordinates of the point (a point near the world origin
//!    on a sphere of radius 1000 centred at x = 1000 is only known to ~10⁻⁴), which a push
//!    computed from the point alone cannot know.
//!
//! The push is tiny (a few ULPs of the coordinates: about 2·10⁻⁴ at 1000 scene units, 2·10⁻⁷
//! at 1), so a ray spawned near a corner at a grazing angle does not jump through the
//! neighbouring surface. Limitation: at an edge where two faces meet at less than 90° (a prism's
//! edges), the push along one face's normal can leave an origin within a few ULPs of the edge
//! just outside the other face, which then stops the ray at t ~ 10⁻⁷ (see
//! `accel::tests::closed_prism_does_not_leak`: 240 of 336 000 rays, all aimed exactly at
//! vertices).

use glam::Vec3;

use super::rounding::gamma;

/// Roundings of a hit point's coordinates covered by the push: the final rounding of the point
/// (the sphere's `c + r·n`, the triangle's `v0 + b1·e1 + b2·e2`, the plane's reprojection) is one;
/// the second is margin for a normal that is unit only to within rounding.
const POINT_ROUNDINGS: u32 = 2;

/// Origin for a ray leaving the surface point `point` (with unit geometric normal `normal`) in
/// direction `dir`: `point` pushed off the surface, to the side `dir` points to, by a distance
/// that scales with the floating-point error of `point`, so that the new ray never re-hits the
/// surface it starts on.
///
/// A `dir` tangent to the surface (`dir · normal = 0`) is pushed to the side of `normal`. The
/// push is along the geometric normal (`Hit::normal`), whichever side the ray arrived from; do
/// not pass the shading normal, which may point into the surface.
#[inline]
pub fn spawn_origin(point: Vec3, normal: Vec3, dir: Vec3) -> Vec3 {
    let side = if dir.dot(normal) < 0.0 { -normal } else { normal };
    // Bound on the error of `point` projected on the normal: Σ |n_i|·γ(2)·|p_i|.
    let distance = normal.abs().dot(point.abs() * gamma(POINT_ROUNDINGS));
    let pushed = point + distance * side;
    Vec3::new(round_away(pushed.x, side.x), round_away(pushed.y, side.y), round_away(pushed.z, side.z))
}

/// `value` moved to the next float in the direction of the sign of `direction` (unchanged when
/// `direction` is zero), so that the push survives the rounding of `point + distance·side`.
///
/// For finite `value` this is `next_up` / `next_down`, written on the bits with fewer branches
/// (the standard functions also handle NaN and infinities, which a hit point never is): away
/// from zero the magnitude grows by one unit in the last place, towards zero it shrinks by one,
/// and ±0 becomes the smallest subnormal of the direction's sign.
#[inline]
fn round_away(value: f32, direction: f32) -> f32 {
    debug_assert!(value.is_finite(), "pushing a non-finite coordinate {value}");
    if direction == 0.0 || direction.is_nan() {
        return value;
    }
    let bits = value.to_bits();
    if bits & 0x7fff_ffff == 0 {
        return f32::from_bits(1).copysign(direction);
    }
    let away_from_zero = (value > 0.0) == (direction > 0.0);
    f32::from_bits(if away_from_zero { bits + 1 } else { bits - 1 })
}

#[cfg(test)]
mod tests {
    //! The push itself. That spawned rays do not re-hit their surface is tested with the shapes
    //! and with the whole scene in `accel.rs`, where hits are real.
    use super::*;

    #[test]
    fn push_goes_to_the_side_of_the_direction() {
        // Reflection (dir along +normal) moves the point to the normal side; transmission (dir
        // against the normal) moves it to the other side.
        let point = Vec3::new(3.0, 1.0, -2.0);
        let normal = Vec3::Y;
        let out = spawn_origin(point, normal, Vec3::new(0.6, 0.8, 0.0));
        let inside = spawn_origin(point, normal, Vec3::new(0.6, -0.8, 0.0));
        assert!(out.y > point.y);
        assert!(inside.y < point.y);
        // Coordinates along which the normal has no component do not move.
        assert_eq!(out.x, point.x);
        assert_eq!(inside.z, point.z);
    }

    #[test]
    fn push_is_a_few_ulps_of_the_coordinates() {
        // At y = 1000 one ULP is 2⁻¹⁴ ≈ 6.1e-5. The push is γ(2)·1000 ≈ 1.2e-4 (two ULPs, rounded
        // to the float grid) plus one more float: at most 4 ULPs, at least 1.
        let point = Vec3::new(0.0, 1000.0, 0.0);
        let pushed = spawn_origin(point, Vec3::Y, Vec3::Y);
        let ulp = 1000f32.next_up() - 1000.0;
        let moved = pushed.y - point.y;
        assert!(moved >= ulp && moved <= 4.0 * ulp, "moved {moved}, ulp {ulp}");
    }

    #[test]
    fn tangent_direction_goes_to_the_normal_side() {
        // dir · normal = 0: the documented choice is the side of the normal.
        let pushed = spawn_origin(Vec3::new(1.0, 2.0, 3.0), Vec3::Z, Vec3::X);
        assert!(pushed.z > 3.0);
    }

    #[test]
    fn round_away_is_next_up_and_next_down() {
        // Zeros of both signs, subnormals, the normal range, ±MAX (next_up(MAX) = ∞), values
        // around powers of two (where the spacing changes), all against the standard library.
        let mut values = vec![0.0, -0.0, f32::from_bits(1), -f32::from_bits(1), f32::MIN_POSITIVE, f32::MAX];
        values.extend([-f32::MIN_POSITIVE, -f32::MAX, 1.0, -1.0, 1.0f32.next_down(), 2.0, 1000.0, -0.1]);
        values.extend((0..2000u32).map(|i| f32::from_bits(i.wrapping_mul(2_147_483).wrapping_add(12_345))));
        values.retain(|v| v.is_finite());
        for value in values {
            assert_eq!(round_away(value, 1.0).to_bits(), value.next_up().to_bits(), "up from {value:e}");
            assert_eq!(round_away(value, -2.0).to_bits(), value.next_down().to_bits(), "down from {value:e}");
            assert_eq!(round_away(value, 0.0).to_bits(), value.to_bits());
            assert_eq!(round_away(value, -0.0).to_bits(), value.to_bits());
        }
    }

    #[test]
    fn point_at_the_world_origin_still_moves() {
        // |p| = 0 gives a zero error bound; the final rounding still moves the origin by the
        // smallest subnormal to the correct side (the intersection routines cover the rest).
        let pushed = spawn_origin(Vec3::ZERO, Vec3::Y, -Vec3::Y);
        assert!(pushed.y < 0.0);
        assert_eq!(pushed.x, 0.0);
    }
}

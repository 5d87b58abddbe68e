//! Robust origins for secondary rays.
//!
//! A hit point is rounded to f32, so it lies a little off the true surface, on either side. A
//! reflected or refracted ray started from it could re-hit the surface it leaves at t ≈ 0 ("shadow
//! acne", rays that never enter glass). prisma defends against this in two places:
//!
//! 1. [`spawn_origin`] pushes the point off the surface, along the geometric normal and to the
//!    side the new ray travels to, by a bound on the rounding of the point's own coordinates
//!    (γ(2)·|p| per coordinate, projected on the normal), then rounds every coordinate one more
//!    float away from the surface so that the rounding of the addition cannot undo the push
//!    (to ±2⁻⁴⁰ where that float would be subnormal or zero: [`MIN_PUSHED_COORDINATE`]).
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
    push_coordinates(pushed, side)
}

/// Where a pushed coordinate that would be subnormal or zero goes instead, to the side of the
/// push: 2⁻⁴⁰ ≈ 9.1·10⁻¹³ scene units.
///
/// A coordinate that is exactly 0 (a point on a plane through the origin, reprojected onto it)
/// has a zero error bound, and one float away from 0 is the smallest subnormal, 1.4·10⁻⁴⁵.
/// Arithmetic on subnormals takes a microcode assist of about a hundred cycles per operation on
/// x86 (without flush-to-zero, which prisma does not set: it would change results), and every
/// ray leaving such a floor carried one into each intersection test: 13–15 % of the time of the
/// caustic bench (`validation/bench/caustics_bench.py`, `perf record`: the plane test of the
/// shadow rays). 2⁻⁴⁰ keeps the products the tests form (squares, γ(n) ≈ n·2⁻²⁴ times a
/// coordinate times a direction component) in the normal range, and is still a million times
/// smaller than the push at a coordinate of 1.
pub const MIN_PUSHED_COORDINATE: f32 = 1.0 / (1u64 << 40) as f32;

/// Each coordinate of `value` moved to the next float in the direction of the sign of the same
/// coordinate of `direction` (unchanged where that is zero or NaN), so that the push survives the
/// rounding of `point + distance·side`; where that next float is subnormal or zero (from ±0 and
/// the smallest normals), to ±[`MIN_PUSHED_COORDINATE`] instead, farther to the same side.
///
/// For finite coordinates the step is `next_up` / `next_down`, written on the bits without
/// branches (the standard functions also handle NaN and infinities, which a hit point never
/// is): away from zero the magnitude grows by one unit in the last place, towards zero it
/// shrinks by one. On x86-64 the three coordinates go through SSE2 lanes together (the scalar
/// form took about 70 instructions of spawn_origin's 100, and spawn_origin 6 % of a caustic
/// render's); elsewhere one by one. Both give the same bits (tested against `next_up` and
/// `next_down`).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn push_coordinates(value: Vec3, direction: Vec3) -> Vec3 {
    use std::arch::x86_64::{
        __m128, __m128i, _mm_add_epi32, _mm_and_si128, _mm_andnot_si128, _mm_castps_si128, _mm_castsi128_ps,
        _mm_cmpeq_ps, _mm_cmplt_epi32, _mm_cmpunord_ps, _mm_or_ps, _mm_or_si128, _mm_set1_epi32,
        _mm_setzero_ps, _mm_srai_epi32, _mm_xor_si128,
    };
    debug_assert!(value.is_finite(), "pushing a non-finite point {value}");
    // SAFETY: SSE2 is part of the x86-64 baseline, so these intrinsics exist on every x86-64
    // CPU; they compute on registers only (no memory access).
    let out = unsafe {
        // Lanes x, y, z, and a fourth that the conversion back to Vec3 drops.
        let value: __m128 = glam::Vec3A::from(value).into();
        let direction: __m128 = glam::Vec3A::from(direction).into();
        let (bits, direction_bits) = (_mm_castps_si128(value), _mm_castps_si128(direction));
        let select = |mask: __m128i, yes: __m128i, no: __m128i| {
            _mm_or_si128(_mm_and_si128(mask, yes), _mm_andnot_si128(mask, no))
        };
        // +1 where the signs agree (the magnitude grows), −1 where they differ.
        let step = _mm_or_si128(_mm_srai_epi32::<31>(_mm_xor_si128(bits, direction_bits)), _mm_set1_epi32(1));
        let stepped = _mm_add_epi32(bits, step);
        let magnitude = _mm_and_si128(stepped, _mm_set1_epi32(i32::MAX));
        let subnormal = _mm_cmplt_epi32(magnitude, _mm_set1_epi32(f32::MIN_POSITIVE.to_bits() as i32));
        let zero = _mm_castps_si128(_mm_cmpeq_ps(value, _mm_setzero_ps()));
        let floor = _mm_or_si128(
            _mm_set1_epi32(MIN_PUSHED_COORDINATE.to_bits() as i32),
            _mm_and_si128(direction_bits, _mm_set1_epi32(i32::MIN)),
        );
        let pushed = select(_mm_or_si128(subnormal, zero), floor, stepped);
        let keep =
            _mm_or_ps(_mm_cmpeq_ps(direction, _mm_setzero_ps()), _mm_cmpunord_ps(direction, direction));
        let out = select(_mm_castps_si128(keep), bits, pushed);
        _mm_castsi128_ps(out)
    };
    Vec3::from(glam::Vec3A::from(out))
}

/// [`push_coordinates`] one coordinate at a time, where SSE2 is not there.
#[cfg(not(target_arch = "x86_64"))]
#[inline(always)]
fn push_coordinates(value: Vec3, direction: Vec3) -> Vec3 {
    Vec3::new(
        push_coordinate(value.x, direction.x),
        push_coordinate(value.y, direction.y),
        push_coordinate(value.z, direction.z),
    )
}

/// One coordinate of [`push_coordinates`].
#[cfg(not(target_arch = "x86_64"))]
#[inline(always)]
fn push_coordinate(value: f32, direction: f32) -> f32 {
    debug_assert!(value.is_finite(), "pushing a non-finite coordinate {value}");
    let bits = value.to_bits();
    // Same sign bits (value ≠ 0): the magnitude grows.
    let away_from_zero = (bits ^ direction.to_bits()) >> 31 == 0;
    let stepped = f32::from_bits(if away_from_zero { bits.wrapping_add(1) } else { bits.wrapping_sub(1) });
    let pushed = if value == 0.0 || stepped.abs() < f32::MIN_POSITIVE {
        MIN_PUSHED_COORDINATE.copysign(direction)
    } else {
        stepped
    };
    if direction == 0.0 || direction.is_nan() {
        value
    } else {
        pushed
    }
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
    fn push_coordinate_is_next_up_and_next_down() {
        // Zeros of both signs, subnormals, the normal range, ±MAX (next_up(MAX) = ∞), values
        // around powers of two (where the spacing changes), all against the standard library;
        // where the next float is subnormal or zero, ±MIN_PUSHED_COORDINATE instead.
        let mut values = vec![0.0, -0.0, f32::from_bits(1), -f32::from_bits(1), f32::MIN_POSITIVE, f32::MAX];
        values.extend([-f32::MIN_POSITIVE, -f32::MAX, 1.0, -1.0, 1.0f32.next_down(), 2.0, 1000.0, -0.1]);
        values.extend([f32::MIN_POSITIVE.next_up(), -f32::MIN_POSITIVE.next_up(), MIN_PUSHED_COORDINATE]);
        values.extend((0..2000u32).map(|i| f32::from_bits(i.wrapping_mul(2_147_483).wrapping_add(12_345))));
        values.retain(|v| v.is_finite());
        let expected = |next: f32, direction: f32| {
            if next.abs() < f32::MIN_POSITIVE {
                MIN_PUSHED_COORDINATE.copysign(direction)
            } else {
                next
            }
        };
        // Each value in each lane, the other two lanes moving other ways (up, down, or kept by a
        // zero or NaN direction), so that a lane mixed up with another would show.
        let push_in = |lane: usize, value: f32, direction: f32| {
            let mut values = Vec3::new(1.5, -2.5, 0.25);
            let mut directions = Vec3::new(-1.0, 0.0, f32::NAN);
            values[lane] = value;
            directions[lane] = direction;
            let out = push_coordinates(values, directions);
            for other in (0..3).filter(|&other| other != lane) {
                let expected_other = match other {
                    0 => 1.5f32.next_down(),
                    1 => -2.5,
                    _ => 0.25,
                };
                assert_eq!(out[other].to_bits(), expected_other.to_bits(), "lane {other} beside {value:e}");
            }
            out[lane]
        };
        for value in values {
            for lane in 0..3 {
                let up = push_in(lane, value, 1.0);
                assert_eq!(up.to_bits(), expected(value.next_up(), 1.0).to_bits(), "up from {value:e}");
                let down = push_in(lane, value, -2.0);
                assert_eq!(
                    down.to_bits(),
                    expected(value.next_down(), -2.0).to_bits(),
                    "down from {value:e}"
                );
                assert_eq!(push_in(lane, value, 0.0).to_bits(), value.to_bits());
                assert_eq!(push_in(lane, value, -0.0).to_bits(), value.to_bits());
                assert_eq!(push_in(lane, value, f32::NAN).to_bits(), value.to_bits());
            }
        }
    }

    #[test]
    fn point_at_the_world_origin_still_moves() {
        // |p| = 0 gives a zero error bound; the origin still moves to the correct side, by
        // MIN_PUSHED_COORDINATE (a normal float), not by the smallest subnormal.
        let pushed = spawn_origin(Vec3::ZERO, Vec3::Y, -Vec3::Y);
        assert_eq!(pushed.y, -MIN_PUSHED_COORDINATE);
        assert!(pushed.y.is_normal());
        assert_eq!(pushed.x, 0.0);
    }

    #[test]
    fn pushed_coordinates_are_never_subnormal() {
        // Points on the planes x = 0 and y = 0 and at tiny coordinates (zero, subnormal, normal
        // below 2⁻⁴⁰), pushed both ways along each axis and along a slanted normal: every moved
        // coordinate is a normal float (never subnormal, never zero), on the side of the direction.
        let tiny = [0.0, -0.0, f32::from_bits(1), 1e-30, -1e-39, 3e-13];
        let normals = [Vec3::X, Vec3::Y, Vec3::Z, Vec3::new(0.6, 0.8, 0.0)];
        for &a in &tiny {
            for &b in &tiny {
                let point = Vec3::new(a, b, 1.5);
                for normal in normals {
                    for dir in [normal, -normal] {
                        let pushed = spawn_origin(point, normal, dir);
                        for (p, q, n) in [(pushed.x, point.x, normal.x), (pushed.y, point.y, normal.y)] {
                            if n != 0.0 {
                                assert!(p.is_normal(), "{p:e} from {point:?} along {dir:?}");
                                assert!((p - q) * dir.dot(normal).signum() * n.signum() > 0.0);
                            } else {
                                assert_eq!(p, q); // (-0 may become +0: -0 + 0·side)
                            }
                        }
                    }
                }
            }
        }
    }
}

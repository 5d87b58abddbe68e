//! The colour scales of `prisma polviz`, as 8-bit sRGB:
//! - degree of linear polarisation, 0..1: a sequential ramp, dark blue through rose and orange
//!   to pale yellow, lightness rising with the value;
//! - angle of linear polarisation, −90°..90°: a cyclic wheel (−90° and +90°, the same
//!   orientation, get the same colour) of constant lightness, a circle of hue in the OKLab
//!   space (Ottosson 2020) at L = 0.72, chroma 0.12, which stays inside the sRGB gamut at every
//!   hue; 0° (horizontal) is red, +45° yellow-green, ±90° teal, −45° violet;
//! - circular part S3/S0, −1..1: a diverging ramp, blue (−) through near-white (0) to red (+).
//!
//! Two greys mark pixels where a quantity is undefined: [`NO_LIGHT`] (S0 too small) and
//! [`UNPOLARIZED`] (an angle of polarisation where the light is barely polarised).

use prisma::spectrum::color::srgb_encode;

/// An 8-bit sRGB colour.
pub type Rgb = [u8; 3];

/// Pixels without light (S0 at or below the floor): every map.
pub const NO_LIGHT: Rgb = [96, 96, 96];
/// Angle-of-polarisation pixels whose degree of linear polarisation is below the threshold.
pub const UNPOLARIZED: Rgb = [185, 185, 185];

/// Anchors of the degree-of-linear-polarisation ramp at 0, ¼, ½, ¾, 1.
const DOLP_ANCHORS: [Rgb; 5] = [[22, 24, 66], [84, 44, 140], [186, 62, 112], [238, 138, 56], [250, 238, 150]];
/// Anchors of the circular ramp at −1, −½, 0, ½, 1.
const CIRCULAR_ANCHORS: [Rgb; 5] =
    [[36, 84, 170], [140, 176, 222], [245, 245, 245], [226, 142, 118], [176, 36, 40]];
/// OKLab lightness and chroma of the angle wheel.
const WHEEL_LIGHTNESS: f32 = 0.72;
const WHEEL_CHROMA: f32 = 0.12;
/// OKLab hue (radians) of AoLP = 0: red.
const WHEEL_HUE_AT_ZERO: f32 = 0.5;

/// The colour of a degree of linear polarisation (clamped to [0, 1]).
pub fn dolp_colour(dolp: f32) -> Rgb {
    ramp(&DOLP_ANCHORS, dolp)
}

/// The colour of an angle of linear polarisation in degrees (any value; period 180°).
pub fn aolp_colour(aolp_deg: f32) -> Rgb {
    let hue = WHEEL_HUE_AT_ZERO + 2.0 * aolp_deg.to_radians();
    let (a, b) = (WHEEL_CHROMA * hue.cos(), WHEEL_CHROMA * hue.sin());
    oklab_to_srgb8(WHEEL_LIGHTNESS, a, b)
}

/// The colour of the circular part S3/S0 (clamped to [−1, 1]).
pub fn circular_colour(s3_over_s0: f32) -> Rgb {
    ramp(&CIRCULAR_ANCHORS, 0.5 * (s3_over_s0 + 1.0))
}

/// A linear value (clamped to [0, 1]) as an sRGB-encoded grey.
pub fn grey(linear: f32) -> Rgb {
    let level = to_byte(srgb_encode(linear.clamp(0.0, 1.0)));
    [level; 3]
}

/// Linear sRGB (clamped to [0, 1]) as 8-bit sRGB.
pub fn srgb8(linear: [f32; 3]) -> Rgb {
    linear.map(|channel| to_byte(srgb_encode(channel.clamp(0.0, 1.0))))
}

/// Piecewise-linear interpolation between evenly spaced `anchors` at `t` in [0, 1] (clamped;
/// NaN takes the first anchor).
fn ramp(anchors: &[Rgb], t: f32) -> Rgb {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let position = t * (anchors.len() - 1) as f32;
    let lower = (position as usize).min(anchors.len() - 2);
    let fraction = position - lower as f32;
    let (from, to) = (anchors[lower], anchors[lower + 1]);
    [0, 1, 2].map(|c| {
        let value = f32::from(from[c]) + fraction * (f32::from(to[c]) - f32::from(from[c]));
        value.round() as u8
    })
}

/// OKLab to 8-bit sRGB.
fn oklab_to_srgb8(lightness: f32, a: f32, b: f32) -> Rgb {
    srgb8(oklab_to_linear_srgb(lightness, a, b))
}

/// OKLab to linear sRGB, through the inverses of the two matrices that define OKLab (Ottosson
/// 2020), unclamped.
fn oklab_to_linear_srgb(lightness: f32, a: f32, b: f32) -> [f32; 3] {
    let l = (lightness + 0.396_337_78 * a + 0.215_803_76 * b).powi(3);
    let m = (lightness - 0.105_561_35 * a - 0.063_854_17 * b).powi(3);
    let s = (lightness - 0.089_484_18 * a - 1.291_485_5 * b).powi(3);
    [
        4.076_741_7 * l - 3.307_711_6 * m + 0.230_969_93 * s,
        -1.268_438 * l + 2.609_757_4 * m - 0.341_319_4 * s,
        -0.004_196_086 * l - 0.703_418_6 * m + 1.707_614_7 * s,
    ]
}

/// A value in [0, 1] as a byte, rounded.
fn to_byte(value: f32) -> u8 {
    (value * 255.0 + 0.5) as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    /// OKLab's white point is sRGB white: L = 1, a = b = 0 must give (255, 255, 255).
    #[test]
    fn oklab_white_is_srgb_white() {
        assert_eq!(oklab_to_srgb8(1.0, 0.0, 0.0), [255, 255, 255]);
    }

    /// The wheel is cyclic with period 180° (an orientation, not a direction), stays inside the
    /// sRGB gamut without clipping, and tells orientations 45° apart clearly apart.
    #[test]
    fn angle_wheel_is_cyclic_in_gamut_and_distinct() {
        assert_eq!(aolp_colour(-90.0), aolp_colour(90.0));
        assert_eq!(aolp_colour(10.0), aolp_colour(190.0));
        for step in 0..360 {
            let hue = WHEEL_HUE_AT_ZERO + (step as f32).to_radians();
            let rgb =
                oklab_to_linear_srgb(WHEEL_LIGHTNESS, WHEEL_CHROMA * hue.cos(), WHEEL_CHROMA * hue.sin());
            assert!(rgb.iter().all(|c| (0.0..=1.0).contains(c)), "hue {step}°: {rgb:?}");
        }
        let distance =
            |p: Rgb, q: Rgb| (0..3).map(|c| (i32::from(p[c]) - i32::from(q[c])).abs()).sum::<i32>();
        for angle in [-90.0, -45.0, 0.0, 45.0] {
            assert!(distance(aolp_colour(angle), aolp_colour(angle + 45.0)) > 80, "{angle}°");
        }
        let red = aolp_colour(0.0);
        assert!(red[0] > red[1] && red[0] > red[2], "0° is red: {red:?}");
    }

    /// The ramps hit their anchors, clamp outside their range, and the DoLP ramp gets lighter
    /// as the value rises (its anchors' sums increase), so "more polarised" reads "brighter".
    #[test]
    fn ramps_hit_their_anchors_and_clamp() {
        assert_eq!(dolp_colour(0.0), DOLP_ANCHORS[0]);
        assert_eq!(dolp_colour(0.5), DOLP_ANCHORS[2]);
        assert_eq!(dolp_colour(1.0), DOLP_ANCHORS[4]);
        assert_eq!(dolp_colour(1.3), DOLP_ANCHORS[4]);
        assert_eq!(circular_colour(-1.0), CIRCULAR_ANCHORS[0]);
        assert_eq!(circular_colour(0.0), CIRCULAR_ANCHORS[2]);
        assert_eq!(circular_colour(2.0), CIRCULAR_ANCHORS[4]);
        let sums: Vec<u32> = DOLP_ANCHORS.iter().map(|c| c.iter().map(|&v| u32::from(v)).sum()).collect();
        assert!(sums.windows(2).all(|w| w[0] < w[1]), "{sums:?}");
        assert_eq!(grey(1.0), [255; 3]);
        assert_eq!(grey(0.0), [0; 3]);
    }
}

//! [`FixedSum`]: an exact sum of floating-point contributions, in 192-bit two's-complement fixed
//! point with a quantum of 2⁻⁶⁴.
//!
//! Why: a render split into parts (sample ranges, pixel windows, an interrupted run and its
//! resumption) must merge into the very bits of the single render. Floating-point addition is
//! not associative, so sums of the same samples in another grouping differ in their last bits.
//! Integer addition is: each contribution is rounded **once**, on its own, to a multiple of the
//! quantum, and from then on every sum is exact, whatever the order and grouping. The image is
//! the sum divided by the sample count, a function of the two alone.
//!
//! The format is fixed, not chosen per scene: the range, |sum| < 2¹²⁷ ≈ 1.7·10³⁸, is f32's, so
//! every contribution f32 can carry up to 2¹²⁶ ≈ 8.5·10³⁷ is accepted; the quantum 2⁻⁶⁴ ≈
//! 5.4·10⁻²⁰ keeps a relative precision finer than f32's (6·10⁻⁸) for every contribution above
//! 10⁻¹², and eight significant digits at 10⁻¹². (A quantum of 2⁻⁹⁶ was tried first: its sums
//! needed a fourth 32-bit word per value in the part files, and writing and reading those cost
//! more than the 10 % a split render may add; docs/farm.md.) A contribution that is not finite
//! or not below 2¹²⁶ in magnitude, and a sum that would leave the range, are refused
//! ([`FixedSum::add`] says so), and the render fails as for a non-finite pixel. All contributions of S0 (XYZ and bands) are ≥ 0, so their partial sums grow
//! monotonically to the total: whether a sum overflows does not depend on the grouping either.
//! Those of S1–S3 are bounded by S0's (|Sₖ| ≤ S0 per wavelength, and the colour-matching
//! functions are ≥ 0), so they stay in range whenever S0 does.

/// Fraction bits: the quantum is 2^-FRACTION_BITS.
pub const FRACTION_BITS: i32 = 64;
/// Largest magnitude (exclusive) of one contribution, as a power of two.
const MAX_CONTRIBUTION_LOG2: i32 = 126;

/// An exact sum: 192-bit two's complement, `lo` the low 128 bits (as two 64-bit halves, low
/// first), `hi` the high 64 (signed), in units of 2⁻⁶⁴. Halves rather than a `u128`, whose
/// 16-byte alignment padded every sum to 32 bytes: a render holds one sum per value per pixel,
/// and 24 bytes is a quarter less memory for the same arithmetic.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FixedSum {
    lo: [u64; 2],
    hi: i64,
}

impl FixedSum {
    /// Zero.
    pub const ZERO: Self = Self { lo: [0, 0], hi: 0 };

    /// `value` rounded to the nearest multiple of the quantum (halves away from zero), or
    /// `None` when it is not finite or its magnitude is 2¹²⁶ or more.
    #[inline]
    pub fn from_f64(value: f64) -> Option<Self> {
        if value == 0.0 {
            return Some(Self::ZERO);
        }
        if !value.is_finite() || value.abs() >= (MAX_CONTRIBUTION_LOG2 as f64).exp2() {
            return None;
        }
        let bits = value.to_bits();
        let negative = bits >> 63 == 1;
        let exponent_bits = ((bits >> 52) & 0x7ff) as i32;
        let fraction = bits & ((1 << 52) - 1);
        // value = mantissa · 2^(exponent), mantissa an integer below 2^53.
        let (mantissa, exponent) =
            if exponent_bits == 0 { (fraction, -1074) } else { (fraction | (1 << 52), exponent_bits - 1075) };
        let shift = exponent + FRACTION_BITS;
        let magnitude: u128 = if shift >= 0 {
            // mantissa < 2^53 and the value < 2^126, so mantissa << shift < 2^190 fits in 192
            // bits, but not in 128 when shift > 75: those go through the wide path below.
            if shift > 75 {
                return Some(Self::wide(mantissa, shift as u32, negative));
            }
            u128::from(mantissa) << shift
        } else {
            let right = (-shift) as u32;
            if right > 54 {
                0
            } else {
                (u128::from(mantissa) + (1u128 << (right - 1))) >> right
            }
        };
        let sum = Self::from_parts(magnitude, 0);
        Some(if negative { sum.negated() } else { sum })
    }

    /// `mantissa << shift` (shift in 76..=137) as a sum, negated when `negative`.
    fn wide(mantissa: u64, shift: u32, negative: bool) -> Self {
        let shifted = u128::from(mantissa) << (shift - 64);
        // shifted holds bits 64.. of the value: its low 64 bits are the value's bits 64..128.
        let lo = (shifted as u64 as u128) << 64;
        let hi = (shifted >> 64) as i64;
        let sum = Self::from_parts(lo, hi);
        if negative {
            sum.negated()
        } else {
            sum
        }
    }

    /// The two's-complement negation.
    #[inline]
    fn negated(self) -> Self {
        let (lo, borrow) = 0u128.overflowing_sub(self.low());
        Self::from_parts(lo, self.hi.wrapping_neg().wrapping_sub(i64::from(borrow)))
    }

    /// Adds `other`; false (leaving `self` unchanged) when the sum would leave the range.
    #[inline]
    #[must_use]
    pub fn add(&mut self, other: Self) -> bool {
        let (lo, carry) = self.low().overflowing_add(other.low());
        let hi = self.hi.checked_add(other.hi).and_then(|h| h.checked_add(i64::from(carry)));
        match hi {
            Some(hi) => {
                *self = Self::from_parts(lo, hi);
                true
            }
            None => false,
        }
    }

    /// Adds the contribution `value` (see [`Self::from_f64`]); false when it cannot be
    /// represented or the sum would leave the range.
    #[inline]
    #[must_use]
    pub fn add_f64(&mut self, value: f64) -> bool {
        match Self::from_f64(value) {
            Some(fixed) => self.add(fixed),
            None => false,
        }
    }

    /// Adds the f32 contribution `value`: the same as `add_f64(f64::from(value))`, bit for bit,
    /// with a short path for the common case, a positive normal value from 2⁻⁴¹ to below 2⁶⁴
    /// (an exact multiple of the quantum, below 2¹²⁸ quanta), which every camera sample and
    /// every light path's splat takes three times (XYZ).
    #[inline]
    #[must_use]
    pub fn add_f32(&mut self, value: f32) -> bool {
        let bits = value.to_bits();
        // value = m·2^(e − 150) for a normal f32 with biased exponent e, so value·2^64 =
        // m·2^(e − 86): an integer from e = 86, below 2^(e − 62) ≤ 2^128 up to e = 190.
        // With the sign bit on top: a negative value gives 256 or more and takes the general path.
        let exponent_bits = bits >> 23;
        if (86..=190).contains(&exponent_bits) {
            let mantissa = (bits & 0x7f_ffff) | 0x80_0000;
            let magnitude = u128::from(mantissa) << (exponent_bits - 86);
            let (lo, carry) = self.low().overflowing_add(magnitude);
            return match self.hi.checked_add(i64::from(carry)) {
                Some(hi) => {
                    *self = Self::from_parts(lo, hi);
                    true
                }
                None => false,
            };
        }
        self.add_f64(f64::from(value))
    }

    /// True when zero.
    #[inline]
    pub fn is_zero(&self) -> bool {
        self.lo == [0, 0] && self.hi == 0
    }

    /// The sum as the nearest f64 (up to the rounding of a two-step conversion: deterministic,
    /// which is what matters, and within 2⁻⁵² relative).
    pub fn to_f64(&self) -> f64 {
        let scale = (-FRACTION_BITS as f64).exp2();
        // Fits in an i128: one correctly rounded conversion.
        let lo = self.low();
        let fits = (self.hi == 0 && lo >> 127 == 0) || (self.hi == -1 && lo >> 127 == 1);
        if fits {
            return (lo as i128) as f64 * scale;
        }
        // hi·2^128 + lo, hi signed, lo unsigned: both parts are converted and added.
        (self.hi as f64 * 2f64.powi(128) + lo as f64) * scale
    }

    /// The sum divided by `count`, as f64 (the mean of `count` contributions).
    pub fn mean(&self, count: f64) -> f64 {
        self.to_f64() / count
    }

    /// The six 32-bit words of the sum, least significant first (for the part files).
    pub fn to_words(&self) -> [u32; 6] {
        let hi = self.hi as u64;
        [
            self.lo[0] as u32,
            (self.lo[0] >> 32) as u32,
            self.lo[1] as u32,
            (self.lo[1] >> 32) as u32,
            hi as u32,
            (hi >> 32) as u32,
        ]
    }

    /// The sum of the six words of [`Self::to_words`].
    pub fn from_words(words: [u32; 6]) -> Self {
        let lo = words[..4].iter().rev().fold(0u128, |acc, &w| (acc << 32) | u128::from(w));
        let hi = ((u64::from(words[5]) << 32) | u64::from(words[4])) as i64;
        Self::from_parts(lo, hi)
    }

    /// The low 128 bits.
    #[inline]
    fn low(&self) -> u128 {
        (u128::from(self.lo[1]) << 64) | u128::from(self.lo[0])
    }

    /// The sum of low 128 bits `lo` and high 64 bits `hi`.
    #[inline]
    fn from_parts(lo: u128, hi: i64) -> Self {
        Self { lo: [lo as u64, (lo >> 64) as u64], hi }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn value(x: f64) -> FixedSum {
        FixedSum::from_f64(x).expect("representable")
    }

    /// Dyadic values are exact, and come back as they went in.
    #[test]
    fn dyadic_values_round_trip() {
        for x in [0.0, 1.0, -1.0, 0.5, 3.25, -1e-3, 12345.678, 2e20, -7e27, 3e37, 1e-25] {
            let back = value(x).to_f64();
            let tolerance = 2f64.powi(-FRACTION_BITS) + x.abs() * 1e-15;
            assert!((back - x).abs() <= tolerance, "{x} came back as {back}");
        }
        assert_eq!(value(0.75).to_f64(), 0.75);
        assert_eq!(value(-3.0e30).to_f64(), -3.0e30, "a value using the high word");
    }

    /// The point of the type: any grouping and order of the same contributions gives the same
    /// bits, where f64 addition does not.
    #[test]
    fn sums_do_not_depend_on_grouping_or_order() {
        let contributions: Vec<f64> = (0..1000)
            .map(|i| {
                let x = ((i * 7919) % 1013) as f64 / 97.0;
                let sign = if i % 3 == 0 { -1.0 } else { 1.0 };
                sign * x * 10f64.powi(i % 13 - 6)
            })
            .collect();
        let sum = |values: &[f64]| {
            let mut s = FixedSum::ZERO;
            for &v in values {
                assert!(s.add_f64(v));
            }
            s
        };
        let forward = sum(&contributions);
        let mut reversed = contributions.clone();
        reversed.reverse();
        assert_eq!(sum(&reversed), forward);
        // In three parts, merged in another order.
        let (a, rest) = contributions.split_at(333);
        let (b, c) = rest.split_at(400);
        let mut merged = sum(c);
        assert!(merged.add(sum(a)));
        assert!(merged.add(sum(b)));
        assert_eq!(merged, forward);
        // f64 is not associative on these (the reason for this type).
        let f_forward: f64 = contributions.iter().sum();
        let f_reversed: f64 = reversed.iter().sum();
        assert_ne!(f_forward.to_bits(), f_reversed.to_bits());
    }

    /// add_f32 is add_f64 of the same value, bit for bit, on both sides of its short path's
    /// bounds (exponents 86 and 190), on subnormals, negatives, zeros and non-finite values,
    /// and when the sum carries into the high word or leaves the range.
    #[test]
    fn add_f32_is_add_f64_of_the_same_value() {
        let mut values =
            vec![0.0f32, -0.0, 1.0, 0.75, 3.1e-3, 123.456, -2.5, f32::MIN_POSITIVE, 1e-45, f32::MAX];
        values.extend([f32::NAN, f32::INFINITY, f32::NEG_INFINITY]);
        for exponent in [85u32, 86, 87, 189, 190, 191] {
            for mantissa in [0u32, 1, 0x40_0000, 0x7f_ffff] {
                values.push(f32::from_bits(exponent << 23 | mantissa));
                values.push(-f32::from_bits(exponent << 23 | mantissa));
            }
        }
        let starts = [
            FixedSum::ZERO,
            value(1.0),
            value(-1.0),
            FixedSum::from_parts(u128::MAX, 0),
            FixedSum::from_parts(u128::MAX, i64::MAX),
            value(-3.0e30),
        ];
        for start in starts {
            for &v in &values {
                let (mut a, mut b) = (start, start);
                assert_eq!(a.add_f32(v), b.add_f64(f64::from(v)), "{start:?} + {v:e}");
                assert_eq!(a, b, "{start:?} + {v:e}");
            }
        }
    }

    #[test]
    fn words_round_trip() {
        for x in [0.0, 1.5, -1.5, 1e25, -1e35, 3e-15] {
            let fixed = value(x);
            assert_eq!(FixedSum::from_words(fixed.to_words()), fixed, "{x}");
        }
    }

    /// Non-finite and too-large contributions, and sums that leave the range, are refused.
    #[test]
    fn overflow_is_refused() {
        assert!(FixedSum::from_f64(f64::NAN).is_none());
        assert!(FixedSum::from_f64(f64::INFINITY).is_none());
        assert!(FixedSum::from_f64(2f64.powi(126)).is_none());
        let big = value(2f64.powi(126) * 0.75);
        let mut sum = big;
        assert!(sum.add(big), "1.5 · 2^126 is within the range, |sum| < 2^127");
        let before = sum;
        assert!(!sum.add(big), "2.25 · 2^126 is past it");
        assert_eq!(sum, before, "unchanged");
        // Values below the quantum's half round to zero; the smallest kept one is exact.
        assert!(value(2f64.powi(-66)).is_zero());
        assert_eq!(value(2f64.powi(-64)).to_f64(), 2f64.powi(-64));
    }
}

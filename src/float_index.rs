//! [`floor_index`]: a float to a table or bin index in one conversion instruction.
//!
//! Rust's `as` from f32 to an integer saturates and maps NaN to 0, which x86-64 does in several
//! instructions (compare, convert, select) and which keeps loops over lanes from vectorising.
//! Table lookups (the spectral tables, the wavelength sampling table) and the BVH build's binning
//! only need ⌊x⌋ clamped to the table, so they clamp first, NaN included, and convert unchecked.

/// ⌊`x`⌋ clamped to 0..=`max` (NaN gives 0), with one conversion instruction. `max` must be exact
/// in f32 (below 2²⁴).
#[inline(always)]
pub(crate) fn floor_index(x: f32, max: u32) -> u32 {
    debug_assert!(max < 1 << 24, "{max} is not exact in f32");
    // `max` first: it maps NaN to 0.
    let clamped = x.max(0.0).min(max as f32);
    // SAFETY: `clamped` is a finite value in [0, max], inside i32's range, so the truncation is
    // defined.
    unsafe { clamped.to_int_unchecked::<i32>() as u32 }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against the saturating cast it replaces: equal on in-range values, ends and NaN.
    #[test]
    fn agrees_with_the_saturating_cast() {
        for x in [
            -1e30f32,
            -3.5,
            -0.0,
            0.0,
            0.25,
            1.0,
            2.999_999_8,
            3.0,
            7.5,
            15.0,
            15.9,
            16.0,
            1e9,
            f32::INFINITY,
        ] {
            assert_eq!(floor_index(x, 15), (x as u32).min(15), "x = {x}");
        }
        assert_eq!(floor_index(f32::NAN, 15), 0);
        assert_eq!(floor_index(f32::NEG_INFINITY, 15), 0);
    }
}

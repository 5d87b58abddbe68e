//! [`PixelRng`]: the sample values of one camera sample, an Owen-scrambled Sobol sequence
//! derived from (seed, pixel, sample index) alone, so images do not depend on tiling or thread
//! count.
//!
//! The samples of a pixel are successive points of one Sobol sequence, scrambled per pixel with
//! Burley's hash-based Owen scrambling (B. Burley, "Practical Hash-based Owen Scrambling", JCGT
//! 9(4), 2020; the `sobol_burley` crate). Every dimension of a pixel's samples is therefore
//! stratified across its samples, and the pixel-position pair (the first two dimensions) is
//! stratified jointly in 2D, so pixel edges and spectra converge faster than with independent
//! random numbers while each pixel's estimate stays an unbiased random variable whose error is
//! independent between pixels and seeds.
//!
//! Dimensions are handed out in order by [`PixelRng::uniform`]: the renderer takes the pixel
//! position (dimensions 0 and 1) and the wavelength ([`WAVELENGTH_DIMENSION`], 2); the
//! integrator takes the rest (light sample shifts, Russian roulette) in the order it needs them,
//! one at a time, or a fresh padded group's first two or all four ([`PixelRng::uniform_2d`],
//! [`PixelRng::uniform_4d`]) where values must be stratified jointly (the path tracer's
//! directions).
//! The first four dimensions are the sequence in its own order, Owen-scrambled, except the
//! wavelength's, which is **digitally shifted** instead (one random XOR mask per pixel): the
//! first 2^m values of an unscrambled Sobol dimension are the multiples of 2^−m, and the mask
//! moves them all by the same amount, so a pixel's 2^m samples take their wavelength offsets on
//! an exactly evenly spaced grid, and with the lanes of each sample (spaced evenly within it,
//! [`crate::spectrum::SampledWavelengths::sample_visible`]) its 2^m·count wavelengths lie on one
//! evenly spaced grid of the spectrum. An evenly spaced grid integrates a smooth spectrum (which
//! fades out at both ends of the visible range) far better than a jittered one, which is what
//! Owen scrambling gives: four lanes at 2 spp left 11× less colour noise on the Newton prism's
//! directly lit screen than with the scrambled offsets (validation/bench/RESULTS.md, "Wavelengths
//! on an evenly spaced grid"). Both randomisations keep the three dimensions one Sobol net, so
//! the wavelength stays stratified jointly with the position, which matters where dispersion
//! makes colour depend on both. Past the first four, dimensions are "padded" as Burley
//! recommends: each further group of four is the same 4D Sobol sequence under an independent
//! scramble and index shuffle, so a group is stratified within itself and randomly associated
//! with the others. The sequence holds 2¹⁶ points; sample indices beyond continue on
//! independently scrambled sequences of 2¹⁶ points each.
//!
//! Light paths draw from [`LightPathSequence`] instead: one Owen-scrambled Sobol sequence over
//! all the light paths of a render, indexed by the path's number in the render.

/// Dimensions per padded group: one call of [`sobol_burley::sample_4d`].
const GROUP: usize = 4;
/// Points in one Sobol sequence of `sobol_burley`.
const SEQUENCE_POINTS: u32 = 1 << 16;

/// The sample values of camera sample `sample` of one pixel, handed out one dimension at a time.
pub struct PixelRng {
    /// Index of this sample in its pixel's Sobol sequence (< 2¹⁶).
    index: u32,
    /// Scramble seed of the pixel's sequence (seed, pixel and the index's high bits).
    sequence_seed: u32,
    /// Padded groups handed out so far.
    group: u32,
    /// The current group's values.
    values: [f32; GROUP],
    /// How many of `values` are handed out.
    used: usize,
    /// Groups from this one on are independent hashed numbers instead of the scrambled
    /// sequence's ([`Self::sobol_groups`]); `u32::MAX` unless an integrator asks.
    sobol_groups: u32,
}

/// What the samples of one pixel under one seed share: the key their scrambles derive from,
/// and the scramble seed and wavelength shift of the pixel's first Sobol sequence (samples 0 to
/// 2¹⁶ − 1), so that a render hashes once per pixel rather than once per sample.
#[derive(Clone, Copy, Debug)]
pub struct PixelKey {
    key: u64,
    first_sequence_seed: u32,
    first_wavelength_shift: u32,
}

impl PixelKey {
    /// The key of pixel (`x`, `y`) under `seed`.
    pub fn new(seed: u64, x: u32, y: u32) -> Self {
        let pixel = (u64::from(y) << 32) | u64::from(x);
        let key = mix64(mix64(seed ^ 0x51_7cc1_b727_220a) ^ pixel);
        let first_sequence_seed = Self::sequence_seed(key, 0);
        Self { key, first_sequence_seed, first_wavelength_shift: wavelength_shift(first_sequence_seed) }
    }

    /// The scramble seed of the pixel's sequence number `sequence` (samples from
    /// `sequence`·2¹⁶ on).
    fn sequence_seed(key: u64, sequence: u32) -> u32 {
        (mix64(key ^ u64::from(sequence)) >> 32) as u32
    }
}

impl PixelRng {
    /// The values of sample `sample` of pixel (`x`, `y`) under `seed`.
    pub fn new(seed: u64, x: u32, y: u32, sample: u32) -> Self {
        Self::for_sample(PixelKey::new(seed, x, y), sample)
    }

    /// The values of sample `sample` of the pixel of `key`: the same as [`Self::new`] for that
    /// pixel and seed.
    #[inline]
    pub fn for_sample(key: PixelKey, sample: u32) -> Self {
        let sequence = sample / SEQUENCE_POINTS;
        let (sequence_seed, shift) = if sequence == 0 {
            (key.first_sequence_seed, key.first_wavelength_shift)
        } else {
            let sequence_seed = PixelKey::sequence_seed(key.key, sequence);
            (sequence_seed, wavelength_shift(sequence_seed))
        };
        let index = sample % SEQUENCE_POINTS;
        Self {
            index,
            sequence_seed,
            group: 0,
            values: first_group(index, sequence_seed, shift),
            used: 0,
            sobol_groups: u32::MAX,
        }
    }

    /// The next dimension's value, uniform in [0, 1).
    #[inline]
    pub fn uniform(&mut self) -> f32 {
        if self.used == GROUP {
            self.next_group();
        }
        let value = self.values[self.used];
        self.used += 1;
        debug_assert!((0.0..1.0).contains(&value), "sample value {value} outside [0, 1)");
        value
    }
}

impl PixelRng {
    /// A pair of values stratified jointly in 2D over the pixel's samples: the first two
    /// dimensions of a fresh padded group (a (0, 2)-sequence under the group's own scramble and
    /// index shuffle), whatever is left of the current group skipped. [`Self::uniform`] after it
    /// continues with the group's third dimension. A pair from [`Self::uniform`] alone would
    /// straddle two groups wherever the dimensions before it are not a multiple of four, and be
    /// stratified in each dimension only, not jointly.
    #[inline]
    pub fn uniform_2d(&mut self) -> (f32, f32) {
        self.next_group();
        self.used = 2;
        (self.values[0], self.values[1])
    }

    /// The four dimensions of a fresh padded group (jointly a 4D Sobol net under the group's own
    /// scramble and index shuffle; the first two a (0, 2)-sequence), whatever is left of the
    /// current group skipped.
    #[inline]
    pub fn uniform_4d(&mut self) -> [f32; GROUP] {
        self.next_group();
        self.used = GROUP;
        self.values
    }

    /// From now on, only the first `groups` padded groups of this sample (the first, of the pixel
    /// position and wavelength, counting as one) come from the scrambled Sobol sequence; later
    /// ones are independent uniform numbers hashed from the sample's sequence seed, index and
    /// group ([`hashed_4d`]): a group of the sequence costs a scrambled index shuffle and four
    /// Owen scrambles, and deep in a path, where many random choices have already decorrelated
    /// the pixel's samples, its stratification buys little. Each sample's values stay uniform and
    /// independent, so estimates stay unbiased; only how they are stratified over a pixel's
    /// samples changes. Groups already handed out are not affected.
    #[inline]
    pub fn sobol_groups(&mut self, groups: u32) {
        self.sobol_groups = groups;
    }

    /// Moves to the next padded group of four dimensions.
    #[inline]
    fn next_group(&mut self) {
        self.group += 1;
        self.values = if self.group < self.sobol_groups {
            let group_seed = self.sequence_seed ^ (mix64(u64::from(self.group)) as u32);
            sample_4d(self.index, group_seed)
        } else {
            hashed_4d(self.sequence_seed, self.index, self.group)
        };
        self.used = 0;
    }
}

/// Four independent uniform numbers in [0, 1) (multiples of 2⁻²⁴, exact in f32) for padded group
/// `group` of the sample of index `index` in the sequence of scramble seed `sequence_seed`: two
/// rounds of SplitMix64's finaliser ([`mix64`]) over the three, each giving two 24-bit values.
#[inline(always)]
fn hashed_4d(sequence_seed: u32, index: u32, group: u32) -> [f32; GROUP] {
    const SCALE: f32 = 1.0 / (1u32 << 24) as f32;
    let sample = (u64::from(sequence_seed) << 32) | u64::from(index);
    let first = mix64(sample ^ u64::from(group).wrapping_mul(0xd1b5_4a32_d192_ed03));
    let second = mix64(first ^ 0x2545_f491_4f6c_dd1d);
    let bits = |word: u64, shift: u32| ((word >> shift) & 0xff_ffff) as u32 as f32 * SCALE;
    [bits(first, 40), bits(first, 8), bits(second, 40), bits(second, 8)]
}

/// Dimensions 0–3 of the unscrambled Sobol point of index `index` (its low 16 bits, as
/// `sobol_burley` takes them), bit-reversed: what [`sobol_burley::parts::sobol_int4_rev`] gives
/// for `index.reverse_bits()` and dimension set 0, from four lookups in [`SOBOL4_NIBBLES`]
/// instead of one XOR per set bit (a loop of up to 16 rounds that was a tenth of a path-traced
/// sample's time).
#[inline(always)]
fn sobol4_rev(index: u32) -> sobol_burley::parts::Int4 {
    let nibble =
        |k: usize| sobol_burley::parts::Int4::from(SOBOL4_NIBBLES[k][(index >> (4 * k)) as usize & 15]);
    nibble(0) ^ nibble(1) ^ nibble(2) ^ nibble(3)
}

/// `sobol_burley::sample_4d(index, 0, seed)`, bit for bit (tested), with the Sobol point taken
/// from [`sobol4_rev`].
#[inline(always)]
fn sample_4d(index: u32, seed: u32) -> [f32; GROUP] {
    use sobol_burley::parts::{hash, hash_int4, owen_scramble_int4_rev, owen_scramble_rev, Int4};
    let shuffled_rev = owen_scramble_rev(index.reverse_bits(), hash(seed ^ 0x79c6_8e4a));
    let sobol = sobol4_rev(shuffled_rev.reverse_bits());
    let seed: Int4 = [seed.wrapping_mul(0x9c8f_2d3b); GROUP].into();
    let scramble = seed ^ [0x912f_69ba, 0x174f_18ab, 0x691e_72ca, 0xb40c_c1b8].into();
    owen_scramble_int4_rev(sobol, hash_int4(scramble)).reverse_bits().to_f32_norm()
}

/// Entry `[k][n]`: the XOR of [`SOBOL_REV`]'s entries `4k + b` (dimensions 0–3) over the bits b
/// of the nibble n, i.e. what index bits 4k to 4k + 3 equal to n contribute to the Sobol point.
const SOBOL4_NIBBLES: [[[u32; GROUP]; 16]; 4] = {
    let mut table = [[[0u32; GROUP]; 16]; 4];
    let mut k = 0;
    while k < 4 {
        let mut n = 0;
        while n < 16 {
            let mut b = 0;
            while b < 4 {
                if (n >> b) & 1 == 1 {
                    let mut dim = 0;
                    while dim < GROUP {
                        table[k][n][dim] ^= SOBOL_REV[4 * k + b][dim];
                        dim += 1;
                    }
                }
                b += 1;
            }
            n += 1;
        }
        k += 1;
    }
    table
};

/// The dimension that [`crate::render`] takes for the wavelengths of a camera sample.
pub const WAVELENGTH_DIMENSION: usize = 2;

/// The random XOR mask of the wavelength dimension of the pixel sequence under `sequence_seed`.
fn wavelength_shift(sequence_seed: u32) -> u32 {
    sobol_burley::parts::hash(sequence_seed ^ 0x5bd1_e995)
}

/// Dimensions 0–3 of point `index` of a pixel's Sobol sequence under `sequence_seed`: the
/// sequence in its own order (not shuffled), dimensions 0, 1 and 3 Owen-scrambled as
/// `sobol_burley` scrambles them, and the wavelength dimension digitally shifted by `shift`
/// ([`wavelength_shift`] of the seed: one random XOR mask per pixel) instead, so that the first 2^m samples of a pixel take it on an exactly
/// evenly spaced grid (the unscrambled dimension's values are the multiples of 2^−m, and the
/// mask moves them all by the same amount below 2^−m), while the three stay one Sobol net, the
/// wavelength stratified jointly with the position. See the module notes.
fn first_group(index: u32, sequence_seed: u32, shift: u32) -> [f32; GROUP] {
    use sobol_burley::parts::{hash_int4, owen_scramble_int4_rev, Int4};
    let sobol = sobol4_rev(index);
    // The scrambles `sobol_burley::sample_4d` derives for dimensions 0–3 of this seed.
    let seed: Int4 = [sequence_seed.wrapping_mul(0x9c8f_2d3b); GROUP].into();
    let scramble = seed ^ [0x912f_69ba, 0x174f_18ab, 0x691e_72ca, 0xb40c_c1b8].into();
    let mut values = owen_scramble_int4_rev(sobol, hash_int4(scramble)).reverse_bits().to_f32_norm();
    let wavelength = SOBOL4_NIBBLES
        .iter()
        .enumerate()
        .fold(0, |sum, (k, nibbles)| sum ^ nibbles[(index >> (4 * k)) as usize & 15][WAVELENGTH_DIMENSION]);
    values[WAVELENGTH_DIMENSION] = sobol_burley::parts::u32_to_f32_norm(wavelength.reverse_bits() ^ shift);
    values
}

/// Dimensions of a light path drawn from the render-wide Sobol sequence ([`LightPathRng`]).
pub const LIGHT_PATH_SOBOL_DIMENSIONS: usize = 8;

/// Sobol direction numbers of the first [`LIGHT_PATH_SOBOL_DIMENSIONS`] dimensions for 32-bit
/// indices, bit-reversed: entry `j` is what bit `j` of the index XORs in. Dimension 0 is van der
/// Corput's, the others Joe and Kuo's (`new-joe-kuo-6`, the table `sobol_burley` uses for its
/// 16-bit indices, so that the two agree there: tested).
const SOBOL_REV: [[u32; LIGHT_PATH_SOBOL_DIMENSIONS]; 32] = sobol_rev_vectors();

/// Entry `t`: the XOR of [`SOBOL_REV`]'s entries 0 to `t`, what going from index n to n + 1
/// flips when n ends in `t` one bits (bits 0 to `t` change).
const SOBOL_REV_PREFIX: [[u32; LIGHT_PATH_SOBOL_DIMENSIONS]; 32] = {
    let mut prefix = [[0u32; LIGHT_PATH_SOBOL_DIMENSIONS]; 32];
    let mut t = 0;
    while t < 32 {
        let mut dim = 0;
        while dim < LIGHT_PATH_SOBOL_DIMENSIONS {
            prefix[t][dim] = SOBOL_REV[t][dim] ^ if t > 0 { prefix[t - 1][dim] } else { 0 };
            dim += 1;
        }
        t += 1;
    }
    prefix
};

/// Builds [`SOBOL_REV`] with Joe and Kuo's recurrence (S. Joe, F. Y. Kuo, "Constructing Sobol
/// sequences with better two-dimensional projections", SIAM J. Sci. Comput. 30, 2008).
const fn sobol_rev_vectors() -> [[u32; LIGHT_PATH_SOBOL_DIMENSIONS]; 32] {
    // Degree s, coefficients a and initial m_1..m_s of dimensions 1–7 (the file's d = 2..8).
    const PARAMETERS: [(usize, u32, [u32; 5]); LIGHT_PATH_SOBOL_DIMENSIONS - 1] = [
        (1, 0, [1, 0, 0, 0, 0]),
        (2, 1, [1, 3, 0, 0, 0]),
        (3, 1, [1, 3, 1, 0, 0]),
        (3, 2, [1, 1, 1, 0, 0]),
        (4, 1, [1, 1, 3, 3, 0]),
        (4, 4, [1, 3, 5, 13, 0]),
        (5, 2, [1, 1, 5, 5, 17]),
    ];
    let mut vectors = [[0u32; LIGHT_PATH_SOBOL_DIMENSIONS]; 32];
    let mut bit = 0;
    while bit < 32 {
        vectors[bit][0] = (1u32 << (31 - bit)).reverse_bits();
        bit += 1;
    }
    let mut dim = 1;
    while dim < LIGHT_PATH_SOBOL_DIMENSIONS {
        let (degree, coefficients, initial) = PARAMETERS[dim - 1];
        let mut v = [0u32; 32];
        let mut i = 0;
        while i < 32 {
            v[i] = if i < degree {
                initial[i] << (31 - i)
            } else {
                let mut value = v[i - degree] ^ (v[i - degree] >> degree);
                let mut k = 1;
                while k < degree {
                    if (coefficients >> (degree - 1 - k)) & 1 == 1 {
                        value ^= v[i - k];
                    }
                    k += 1;
                }
                value
            };
            vectors[i][dim] = v[i].reverse_bits();
            i += 1;
        }
        dim += 1;
    }
    vectors
}

/// The sample sequence of the light paths of a render: **one** Owen-scrambled Sobol sequence over
/// all of them (32-bit indices; each further 2³² paths an independent scramble), keyed by the
/// seed alone.
///
/// Light path `n` of the render takes point `n`, whichever block or thread traces it, so the
/// render's light paths are stratified together: their directions (dimensions 0 and 1, a
/// (0, 2)-sequence) over all of them, where per-block sequences had stratified each block's
/// 4096 paths only among themselves (on the ball-lens caustic the relMSE of 64 passes fell
/// 1.75×), and the first [`LIGHT_PATH_SOBOL_DIMENSIONS`] dimensions jointly. Dimensions past
/// those are independent uniform numbers (a counter-based hash of seed, path and dimension).
#[derive(Clone, Copy, Debug)]
pub struct LightPathSequence {
    key: u64,
    /// The Owen scrambles of the first 2³² paths, per dimension.
    scrambles: [u32; LIGHT_PATH_SOBOL_DIMENSIONS],
}

impl LightPathSequence {
    /// The sequence of `seed`.
    pub fn new(seed: u64) -> Self {
        let key = mix64(seed ^ 0x2f9a_61c3_d0b7_4e85);
        Self { key, scrambles: Self::scrambles_of(key, 0) }
    }

    /// The scrambles of paths `chunk`·2³² to (`chunk` + 1)·2³² − 1.
    fn scrambles_of(key: u64, chunk: u32) -> [u32; LIGHT_PATH_SOBOL_DIMENSIONS] {
        std::array::from_fn(|d| (mix64(key ^ (u64::from(chunk) << 8) ^ d as u64) >> 32) as u32)
    }

    /// The sample values of light path `path` (counted over the whole render from 0).
    #[inline]
    pub fn path(&self, path: u64) -> LightPathRng {
        self.path_at(path, sobol_rev_point(path as u32))
    }

    /// The sample values of the light paths `paths`, in order: the same as [`Self::path`] for
    /// each, with each Sobol point found from the one before by a single XOR (path n + 1 differs
    /// from path n in the trailing ones of n and the bit above them), instead of one XOR per set
    /// bit of the index.
    pub fn paths(&self, paths: std::ops::Range<u64>) -> impl Iterator<Item = LightPathRng> + '_ {
        let mut sobol = sobol_rev_point(paths.start as u32);
        paths.map(move |path| {
            let rng = self.path_at(path, sobol);
            let flipped = SOBOL_REV_PREFIX[((path as u32).trailing_ones() as usize).min(31)];
            for (value, vector) in sobol.iter_mut().zip(flipped) {
                *value ^= vector;
            }
            rng
        })
    }

    /// [`Self::path`] with the path's unscrambled Sobol point `sobol` already found.
    #[inline]
    fn path_at(&self, path: u64, sobol: [u32; LIGHT_PATH_SOBOL_DIMENSIONS]) -> LightPathRng {
        let chunk = (path >> 32) as u32;
        let scrambles = if chunk == 0 { self.scrambles } else { Self::scrambles_of(self.key, chunk) };
        let mut first = [0.0; LIGHT_PATH_SOBOL_DIMENSIONS];
        for ((out, value), scramble) in first.iter_mut().zip(sobol).zip(scrambles) {
            let scrambled = owen_scramble_rev(value, scramble).reverse_bits();
            // The top 24 bits, as a float in [0, 1).
            *out = (scrambled >> 8) as f32 * (1.0 / (1u32 << 24) as f32);
        }
        LightPathRng { first, used: 0, key: mix64(self.key ^ path.wrapping_mul(0x9E37_79B9_7F4A_7C15)) }
    }
}

/// Point `index` of the unscrambled Sobol sequence in its first [`LIGHT_PATH_SOBOL_DIMENSIONS`]
/// dimensions, each bit-reversed.
#[inline]
fn sobol_rev_point(index: u32) -> [u32; LIGHT_PATH_SOBOL_DIMENSIONS] {
    let mut sobol = [0u32; LIGHT_PATH_SOBOL_DIMENSIONS];
    let mut bits = index;
    while bits != 0 {
        let bit = bits.trailing_zeros() as usize;
        for (value, vector) in sobol.iter_mut().zip(SOBOL_REV[bit]) {
            *value ^= vector;
        }
        bits &= bits - 1;
    }
    sobol
}

/// Burley's hash-based Owen scramble of a bit-reversed 32-bit integer (the `sobol_burley` crate's
/// `owen_scramble_rev`, with its scramble value hashed here): each bit is flipped by a hash of
/// the bits above it in the unreversed value, so nets stay nets.
#[inline(always)]
fn owen_scramble_rev(mut n_rev: u32, scramble: u32) -> u32 {
    n_rev ^= n_rev.wrapping_mul(0x3d20_adea);
    n_rev = n_rev.wrapping_add(scramble);
    n_rev = n_rev.wrapping_mul((scramble >> 16) | 1);
    n_rev ^= n_rev.wrapping_mul(0x0552_6c56);
    n_rev ^= n_rev.wrapping_mul(0x53a2_2864);
    n_rev
}

/// The sample values of one light path ([`LightPathSequence::path`]), handed out one dimension
/// at a time.
pub struct LightPathRng {
    first: [f32; LIGHT_PATH_SOBOL_DIMENSIONS],
    used: usize,
    /// Key of the independent values past the Sobol dimensions.
    key: u64,
}

impl LightPathRng {
    /// The next dimension's value, uniform in [0, 1).
    #[inline]
    pub fn uniform(&mut self) -> f32 {
        let value = match self.first.get(self.used) {
            Some(&value) => value,
            None => (mix64(self.key ^ self.used as u64) >> 40) as f32 * (1.0 / (1u32 << 24) as f32),
        };
        self.used += 1;
        debug_assert!((0.0..1.0).contains(&value), "sample value {value} outside [0, 1)");
        value
    }
}

/// A 64-bit finaliser with full avalanche (the `splitmix64` output function of Steele, Lea and
/// Flood, "Fast splittable pseudorandom number generators", OOPSLA 2014).
fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `paths` hands out the very values `path` gives each path, from any start, across the
    /// 2³² boundary where the scrambles change, and past many trailing ones.
    #[test]
    fn paths_in_order_are_the_paths_one_by_one() {
        let sequence = LightPathSequence::new(99);
        let ranges =
            [0..300u64, 12_345..12_600, (1 << 20) - 7..(1 << 20) + 9, (1 << 32) - 70..(1 << 32) + 70];
        for range in ranges {
            for (path, mut streamed) in range.clone().zip(sequence.paths(range.clone())) {
                let mut single = sequence.path(path);
                for dimension in 0..12 {
                    let (a, b) = (streamed.uniform(), single.uniform());
                    assert_eq!(a.to_bits(), b.to_bits(), "path {path}, dimension {dimension}");
                }
            }
        }
    }

    /// The first `dims` values of samples 0..n of one pixel.
    fn points(seed: u64, x: u32, y: u32, n: u32, dims: usize) -> Vec<Vec<f32>> {
        (0..n)
            .map(|k| {
                let mut rng = PixelRng::new(seed, x, y, k);
                (0..dims).map(|_| rng.uniform()).collect()
            })
            .collect()
    }

    #[test]
    fn values_repeat_for_equal_keys_and_differ_between_pixels_samples_and_seeds() {
        let first = |s: u64, x, y, k| PixelRng::new(s, x, y, k).uniform();
        assert_eq!(first(1, 2, 3, 4), first(1, 2, 3, 4));
        assert_ne!(first(1, 2, 3, 4), first(1, 3, 3, 4));
        assert_ne!(first(1, 2, 3, 4), first(1, 2, 4, 4));
        assert_ne!(first(1, 2, 3, 4), first(1, 2, 3, 5));
        assert_ne!(first(1, 2, 3, 4), first(2, 2, 3, 4));
        // Past the first sequence of 2¹⁶ points.
        assert_ne!(first(1, 2, 3, 4), first(1, 2, 3, 4 + SEQUENCE_POINTS));
    }

    #[test]
    fn every_dimension_is_stratified_over_a_power_of_two_of_samples() {
        // A (0, m, 1)-net in each dimension: 64 samples put exactly one value in each interval
        // [i/64, (i+1)/64), for the padded groups as well as the first.
        let pts = points(7, 10, 20, 64, 12);
        for dim in 0..12 {
            let mut cells = [0u32; 64];
            for p in &pts {
                cells[(p[dim] * 64.0) as usize] += 1;
            }
            assert!(cells.iter().all(|&c| c == 1), "dimension {dim}: {cells:?}");
        }
    }

    #[test]
    fn pairs_of_fresh_groups_are_stratified_jointly_in_2d() {
        // After any number of single dimensions, a pair from `uniform_2d` and the pairs of a
        // `uniform_4d` group put one of 64 samples in each 8 × 8 cell (and `uniform_2d`'s pair
        // in each 2 × 32 and 32 × 2 cell too: a (0, 2)-sequence); pairs from `uniform` alone
        // that straddle two groups do not (checked: dimensions 3 and 4, as the path tracer once
        // took them).
        for skipped in [3, 4, 5, 6] {
            let pairs: Vec<[f32; 6]> = (0..64)
                .map(|k| {
                    let mut rng = PixelRng::new(5, 17, 4, k);
                    (0..skipped).for_each(|_| {
                        rng.uniform();
                    });
                    let (a, b) = rng.uniform_2d();
                    let [c, d, e, f] = rng.uniform_4d();
                    [a, b, c, d, e, f]
                })
                .collect();
            for (first, (nx, ny)) in [(0, (8, 8)), (0, (2, 32)), (0, (32, 2)), (2, (8, 8)), (4, (8, 8))] {
                let mut cells = vec![0u32; 64];
                for p in &pairs {
                    let (i, j) = ((p[first] * nx as f32) as usize, (p[first + 1] * ny as f32) as usize);
                    cells[i * ny + j] += 1;
                }
                assert!(
                    cells.iter().all(|&c| c == 1),
                    "after {skipped}: pair {first}, {nx} × {ny}: {cells:?}"
                );
            }
        }
        let straddling: Vec<(f32, f32)> = (0..64)
            .map(|k| {
                let mut rng = PixelRng::new(5, 17, 4, k);
                (0..3).for_each(|_| {
                    rng.uniform();
                });
                (rng.uniform(), rng.uniform())
            })
            .collect();
        let mut cells = vec![0u32; 64];
        for (u, v) in &straddling {
            cells[(u * 8.0) as usize * 8 + (v * 8.0) as usize] += 1;
        }
        assert!(cells.iter().any(|&c| c != 1), "dimensions 3 and 4 happen to be stratified jointly");
    }

    #[test]
    fn wavelength_offsets_of_a_pixel_lie_on_an_evenly_spaced_grid() {
        // The first 2^m samples' wavelength values are j/2^m + c for one c < 2^-m: exactly evenly
        // spaced (an Owen-scrambled dimension would jitter each inside its 1/2^m), for every
        // pixel and for the second sequence of 2^16 points too.
        for (x, y, first) in [(3, 4, 0), (700, 2, 0), (5, 9, SEQUENCE_POINTS)] {
            for n in [2u32, 8, 64, 1024] {
                let mut values: Vec<f32> = (first..first + n)
                    .map(|k| {
                        let mut rng = PixelRng::new(11, x, y, k);
                        (0..=WAVELENGTH_DIMENSION).map(|_| rng.uniform()).last().unwrap()
                    })
                    .collect();
                values.sort_by(f32::total_cmp);
                let offset = values[0];
                assert!(offset < 1.0 / n as f32, "pixel ({x}, {y}), {n} samples: first value {offset}");
                for (j, value) in values.iter().enumerate() {
                    assert_eq!(
                        *value,
                        offset + j as f32 / n as f32,
                        "pixel ({x}, {y}), {n} samples, value {j}"
                    );
                }
            }
        }
    }

    #[test]
    fn wavelength_is_stratified_jointly_with_the_position() {
        // 64 samples: one in each (1/8 × 1/8) cell of (x, wavelength) and of (y, wavelength).
        let pts = points(7, 10, 20, 64, 3);
        for position in [0, 1] {
            let mut cells = [0u32; 64];
            for p in &pts {
                cells[(p[position] * 8.0) as usize * 8 + (p[WAVELENGTH_DIMENSION] * 8.0) as usize] += 1;
            }
            assert!(cells.iter().all(|&c| c == 1), "dimension {position} with the wavelength: {cells:?}");
        }
    }

    #[test]
    fn pixel_position_is_stratified_jointly_in_2d() {
        // Sobol dimensions 0 and 1 form a (0, 2)-sequence: 256 points put one point in each of
        // the 16 × 16 cells (and in every 2^a × 2^b elementary interval with a + b = 8).
        let pts = points(3, 5, 9, 256, 2);
        for (a, b) in [(4, 4), (2, 6), (8, 0)] {
            let mut cells = vec![0u32; 256];
            for p in &pts {
                let (i, j) = ((p[0] * (1 << a) as f32) as usize, (p[1] * (1 << b) as f32) as usize);
                cells[i * (1 << b) + j] += 1;
            }
            assert!(cells.iter().all(|&c| c == 1), "{a}×{b} intervals");
        }
    }

    #[test]
    fn mean_is_one_half_and_pixels_are_independent() {
        // Over many pixels with 4 samples each, every dimension has mean 1/2 (standard error
        // 1/sqrt(12·N) ≈ 0.0009 at most for independent pixels), and the first values of
        // neighbouring pixels are uncorrelated (|r| < 4/sqrt(N) ≈ 0.018).
        let pixels = 12_000u32;
        let mut sums = [0f64; 8];
        let (mut sxy, mut sx, mut sy, mut sxx, mut syy) = (0f64, 0f64, 0f64, 0f64, 0f64);
        for p in 0..pixels {
            for k in 0..4 {
                let mut rng = PixelRng::new(11, p, 0, k);
                for s in &mut sums {
                    *s += f64::from(rng.uniform());
                }
            }
            let a = f64::from(PixelRng::new(11, p, 0, 0).uniform());
            let b = f64::from(PixelRng::new(11, p + 1, 0, 0).uniform());
            (sxy, sx, sy, sxx, syy) = (sxy + a * b, sx + a, sy + b, sxx + a * a, syy + b * b);
        }
        let n = f64::from(pixels);
        for (dim, s) in sums.iter().enumerate() {
            let mean = s / (4.0 * n);
            assert!((mean - 0.5).abs() < 0.004, "dimension {dim}: mean {mean}");
        }
        let cov = sxy / n - (sx / n) * (sy / n);
        let r = cov / ((sxx / n - (sx / n).powi(2)) * (syy / n - (sy / n).powi(2))).sqrt();
        assert!(r.abs() < 4.0 / n.sqrt(), "correlation between neighbouring pixels: {r}");
    }

    /// `sobol_groups(n)` keeps groups 0 to n − 1 as they were and replaces the later ones only,
    /// whenever it is called.
    #[test]
    fn sobol_groups_changes_only_the_groups_past_the_limit() {
        for sample in [0, 5, 77, SEQUENCE_POINTS + 3] {
            let mut plain = PixelRng::new(3, 4, 5, sample);
            let mut limited = PixelRng::new(3, 4, 5, sample);
            limited.sobol_groups(3);
            for group in 0..8 {
                let (a, b) = (plain.values, limited.values);
                if group < 3 {
                    assert_eq!(a.map(f32::to_bits), b.map(f32::to_bits), "sample {sample}, group {group}");
                } else {
                    assert!(a.iter().zip(&b).all(|(x, y)| x != y), "sample {sample}, group {group}: {a:?}");
                }
                plain.uniform_4d();
                limited.uniform_4d();
            }
        }
    }

    /// The hashed groups are uniform and independent: over 40,000 (pixel, sample) pairs, each of
    /// dimensions 0–3 of groups 1–3 past the limit fills 16 equal bins, and each pair of them
    /// (within a group and across groups) the 16 × 16 cells of the square, as independent
    /// uniform numbers would: χ² below its 99.9 % quantile, 37.7 for 15 degrees of freedom and
    /// 330.5 for 255 (the seed is fixed, so the test is deterministic; over its 78 χ² tests a
    /// sound hash would fail one at another seed with probability about 8 %, a biased or
    /// correlated one fails by far). They are deterministic for a pixel, sample and seed and
    /// differ between neighbouring pixels.
    #[test]
    fn hashed_groups_are_uniform_and_independent() {
        let count = 40_000u32;
        let values: Vec<Vec<f32>> = (0..count)
            .map(|k| {
                let mut rng = PixelRng::new(21, k % 200, k / 200 % 50, k / 10_000);
                rng.sobol_groups(1);
                (0..3).flat_map(|_| rng.uniform_4d()).collect()
            })
            .collect();
        let dims = values[0].len();
        let chi2 = |cells: &[u32]| {
            let expected = f64::from(count) / cells.len() as f64;
            cells.iter().map(|&c| (f64::from(c) - expected).powi(2) / expected).sum::<f64>()
        };
        let bin = |v: f32| ((v * 16.0) as usize).min(15);
        for dim in 0..dims {
            let mut cells = [0u32; 16];
            values.iter().for_each(|v| cells[bin(v[dim])] += 1);
            assert!(chi2(&cells) < 37.7, "dimension {dim}: {cells:?}");
            for other in dim + 1..dims {
                let mut cells = [0u32; 256];
                values.iter().for_each(|v| cells[16 * bin(v[dim]) + bin(v[other])] += 1);
                assert!(chi2(&cells) < 330.5, "dimensions {dim} and {other}: χ² {}", chi2(&cells));
            }
        }
        let tail = |x: u32| {
            let mut rng = PixelRng::new(21, x, 0, 9);
            rng.sobol_groups(1);
            rng.uniform_4d()
        };
        assert_eq!(tail(1).map(f32::to_bits), tail(1).map(f32::to_bits));
        assert_ne!(tail(1), tail(2));
    }

    /// The table-driven groups are `sobol_burley`'s own, bit for bit: every index of a sequence
    /// (2¹⁶) under a few seeds, and the first group's unshuffled dimensions likewise.
    #[test]
    fn table_driven_groups_are_sobol_burleys_bit_for_bit() {
        use sobol_burley::parts::{sobol_int4_rev, sobol_rev, Int4};
        let bits = |v: [f32; GROUP]| v.map(f32::to_bits);
        for seed in [0u32, 1, 0x9e37_79b9, 0xdead_beef, u32::MAX] {
            for index in 0..SEQUENCE_POINTS {
                let seed = seed ^ index.wrapping_mul(0x85eb_ca6b) & 0xff00_0000;
                assert_eq!(
                    bits(sample_4d(index, seed)),
                    bits(sobol_burley::sample_4d(index, 0, seed)),
                    "index {index} seed {seed}"
                );
            }
        }
        for index in 0..SEQUENCE_POINTS {
            let ours = sobol4_rev(index) ^ Int4::from([0; GROUP]);
            let theirs = sobol_int4_rev(index.reverse_bits(), 0);
            // to_f32_norm keeps the top 24 bits: compare both ends of the words.
            assert_eq!(bits(ours.to_f32_norm()), bits(theirs.to_f32_norm()), "index {index}");
            assert_eq!(bits(ours.reverse_bits().to_f32_norm()), bits(theirs.reverse_bits().to_f32_norm()));
            let wavelength = sobol_rev(index.reverse_bits(), WAVELENGTH_DIMENSION as u32);
            let shift = 0x1234_5678;
            let value = first_group(index, 7, shift)[WAVELENGTH_DIMENSION];
            assert_eq!(value, sobol_burley::parts::u32_to_f32_norm(wavelength.reverse_bits() ^ shift));
        }
    }

    #[test]
    fn light_path_sobol_agrees_with_sobol_burley_below_two_to_the_sixteen() {
        // The same Joe–Kuo table: the unscrambled points must be the crate's, bit for bit.
        for index in (0..1u32 << 16).step_by(7) {
            let ours = sobol_rev_point(index);
            for (dimension, value) in ours.iter().enumerate() {
                let theirs = sobol_burley::parts::sobol_rev(index.reverse_bits(), dimension as u32);
                assert_eq!(*value, theirs, "index {index}, dimension {dimension}");
            }
        }
    }

    #[test]
    fn light_paths_are_stratified_across_the_whole_render() {
        // Any aligned run of 2^m light paths is a (0, m, 2)-net in the direction dimensions,
        // wherever it starts (here beyond 2^16, where per-block sequences used to restart, and
        // beyond 2^32, where the scramble changes): 256 paths, one in each of 16 × 16 cells.
        let sequence = LightPathSequence::new(7);
        for start in [0u64, 256 * 300, 1 << 20, (1 << 32) + 512] {
            let mut cells = [0u32; 256];
            for path in start..start + 256 {
                let mut rng = sequence.path(path);
                let (u, v) = (rng.uniform(), rng.uniform());
                cells[(u * 16.0) as usize * 16 + (v * 16.0) as usize] += 1;
            }
            assert!(cells.iter().all(|&c| c == 1), "paths from {start}: {cells:?}");
        }
        // Every further Sobol dimension is stratified in 1D over the same runs.
        for dimension in 2..LIGHT_PATH_SOBOL_DIMENSIONS {
            let mut cells = [0u32; 64];
            for path in 4096..4096 + 64 {
                let mut rng = sequence.path(path);
                let value = (0..=dimension).map(|_| rng.uniform()).last().unwrap_or(0.0);
                cells[(value * 64.0) as usize] += 1;
            }
            assert!(cells.iter().all(|&c| c == 1), "dimension {dimension}: {cells:?}");
        }
    }

    #[test]
    fn light_path_values_differ_between_seeds_and_continue_past_the_sobol_dimensions() {
        let values = |seed: u64, path: u64| {
            let mut rng = LightPathSequence::new(seed).path(path);
            (0..12).map(|_| rng.uniform()).collect::<Vec<f32>>()
        };
        assert_eq!(values(1, 5), values(1, 5));
        assert_ne!(values(1, 5), values(2, 5));
        assert_ne!(values(1, 5)[LIGHT_PATH_SOBOL_DIMENSIONS..], values(1, 6)[LIGHT_PATH_SOBOL_DIMENSIONS..]);
        assert!(values(3, 9).iter().all(|v| (0.0..1.0).contains(v)));
    }

    #[test]
    fn stratification_beats_independent_sampling_on_a_smooth_integrand() {
        // ∫∫∫ x·y·z over the unit cube is 1/8. Averaged over 200 pixels, the squared error of a
        // 64-sample estimate must be far below the independent-sampling value Var/64, where
        // Var(xyz) = 1/27 − 1/64 ≈ 0.0214 (a scrambled net converges as O(N^-3 log² N)).
        let exact = 0.125f64;
        let mut squared_error = 0.0;
        for pixel in 0..200 {
            let estimate: f64 = points(5, pixel, 0, 64, 3)
                .iter()
                .map(|p| f64::from(p[0]) * f64::from(p[1]) * f64::from(p[2]))
                .sum::<f64>()
                / 64.0;
            squared_error += (estimate - exact).powi(2) / 200.0;
        }
        let independent = (1.0 / 27.0 - 1.0 / 64.0) / 64.0;
        assert!(squared_error < independent / 20.0, "MSE {squared_error:.3e} vs {independent:.3e}");
    }
}

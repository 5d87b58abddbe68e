//! Guided emission: where the light tracer starts its light paths, learned from the render's
//! own first light paths.
//!
//! A light path's first two sample dimensions (u₀, u₁) choose its direction (or a beam's
//! position) through the light's emission mapping ([`super::emission`]). Uniform over the unit
//! square, they send as many paths to every part of a glass ball: the centre's paths pile up in
//! a bright focus where each pixel gets hundreds, while the few from the rim spread thin over
//! the whole floor, a dim glow made of rare photons, where the image is noisiest relative to
//! its brightness.
//!
//! [`EmissionGuide`] warps (u₀, u₁) through a piecewise-constant density over the square
//! (`GUIDE_BINS` × `GUIDE_BINS` cells) and divides each path's flux by that density: unbiased
//! for any density that is positive everywhere, and every cell keeps at least
//! `DEFENSIVE_FRACTION` of the uniform density.
//!
//! # Learning
//! The render's first [`learning_paths`] light paths (2 to 16 per cell) start uniformly, as
//! without a guide, and count in the image like any other; [`Record`] keeps the cell each
//! started in, the rays it cost, and the pixel and luminance Y of each of its splats. [`learn`] makes from them a
//! rough light image m (per path, blurred; in blocks of pixels beyond `LEARNING_IMAGE_SIZE`) and,
//! per cell c, the mean over its paths of Σ Y² / (m² + `DISPLAY_FLOOR`) over their splats, M_c: the
//! second moment of a path's contribution to the relMSE of validation's benches (errors below a
//! tenth of display white, pixel value 1, counting absolutely), for paths that each reach few
//! pixels. With C_c the cell's cost per path (its rays, plus `PATH_COST_RAYS` for the rest of a
//! path's work), the density proportional to √(M_c / C_c) minimises variance × cost, the time to a
//! given error; the guide takes M_c blurred over neighbouring cells, each cell's estimate resting
//! on its 16 paths (about 140 with its neighbours).
//!
//! The same sums predict the gain: variance × cost with the uniform density over that with the
//! guide's (variance = second moment − Σ m² / (m² + floor)). Below `MIN_PREDICTED_GAIN` the
//! guide stays uniform: where a light's paths are all worth about the same (a beam aimed
//! at a prism), guiding would only add the warp's cost. The prediction is for independent
//! samples; the light paths are Sobol-stratified, which helps the uniform density most, so the
//! gain measured is smaller (on the caustic bench's ball predicted 2.0, measured 1.4–1.7× less
//! error at equal spp and 1.0–1.25× less time at equal error; validation/bench/RESULTS.md).
//!
//! Why so few, whatever the size of a pass: a path that starts uniformly is worth about half a
//! guided one where the guide helps, and a guide learned from 4,096 paths was as good as one
//! learned from 262,144 (the cells are coarse and their moments blurred). The render's first
//! pass used to teach it: learning from 4,096 paths instead left 16–20 % less error at 2–4 spp
//! and 8 % at 16 spp on `glass_sphere_spot` (262,144 learning paths before, relMSE against a
//! 96-spp render, two seeds), 3–5 % on `tp6_mirror_glass_caustics` at 2, 4 and 16 spp, and 6–8 %
//! on the caustic bench's ball at 2, 4 and 8 spp (6,144 before, six seeds). Fewer still (1,024 or
//! 2,048, by a lower floor) helped the ball a little more at 2 spp but not `glass_sphere_spot`,
//! and made the predicted gain noisier (1.42 for `tp6_mirror_glass_caustics` where 4,096 paths
//! and more predict 1.35, below 1 for the Newton prism): 16 paths per cell stays the number
//! for passes of `MAX_LEARNING_PATHS` × 32 paths and more (every shipped scene's: there the
//! learning paths are 1 % of a pass or less, and only the guide's quality counts).
//!
//! A smaller pass learns from a thirty-second of itself, at least `MIN_LEARNING_PATHS` (2 per
//! cell): there the learning paths are a large share of the first pass, and a one-pass preview
//! is better off with more guided paths and a rougher guide. On the caustic bench's ball (one
//! pass, 24 seeds, relMSE against Mitsuba's references, with the weights below) learning from
//! 1,024 paths instead of 4,096 left 21 % less error at 8,192 paths, 9 % at 16,384 and 5 % at
//! 24,576, and 512 paths 6 %, 6 % and 3 % less again at 12,288, 16,384 and 24,576; the guide was
//! as good (four passes of 24,576 paths: 1.057e-4 from 4,096 paths, 1.070e-4 from 1,024,
//! 1.076e-4 from 768, 12 seeds). Small renders of the other scenes did not mind either
//! (`glass_sphere_spot` at 200×113, 22,600 paths a pass, learning from 512 paths against
//! 4,096: relMSE 3.21e-3 against 3.33e-3 at 1 spp, 2.48e-4 against 2.57e-4 at 4 spp, 10 seeds;
//! `tp6_mirror_glass_caustics` at 150×100, 60,000 paths a pass, 1,792 against 4,096: the same
//! error at 1 and 4 spp, predicted gains 1.40 and 1.39).
//!
//! The learning paths are the render's paths 0..n, whatever part of the render is running: a
//! part that does not hold them all traces them for learning only (their splats are dropped),
//! so every part of a split render learns the same guide and the image stays the same bits
//! whatever the threads or the split. (So does a render with fewer light paths in all than its
//! learning paths: at most 512 paths' work there, about 0.25 ms on the caustic bench's ball.)
//!
//! # Weighing the learning paths
//! In the pass that holds both the last learning paths and the first guided ones (the first
//! pass, when a pass has more paths than the learning), each is an unbiased estimate of the
//! pass, but a learning path's is the noisier: counting all alike wastes guided paths on a
//! pass whose learning paths are a large share (a quick one-pass preview). [`PathWeights`]
//! gives the n learning paths of such a pass [`LEARNING_PATH_WORTH`] of a guided path's weight,
//! the weights of its N paths adding up to N (guided w = N / (n·worth + N − n), learning
//! worth·w): a fixed combination of unbiased estimates, so the pass stays unbiased whatever the
//! guide learned. Every other pass, all learning or all guided, weighs its paths 1 (the same
//! bits as before). On the caustic bench's ball (one pass, 16 seeds, relMSE against Mitsuba's
//! references, edge refinement 4, learning then from 4,096 paths) it left 14 % less error at 16,384 paths (1.25e-3 → 1.08e-3),
//! 11 % at 24,576 and 13 % at 8,192; worth 0.35 did as well, 0.25 and 0.15 worse, 0.7 half as
//! well. Where the guide turns out uniform (below `MIN_PREDICTED_GAIN`) its "guided" paths are
//! as noisy as the learning ones and the weights cost a little variance in that pass (about
//! 1 % with passes of 12,288 to 24,576 paths, which learn from 512 to 768, 0.3 % with passes of
//! 360,000, which learn from 4,096): the weights may not depend on what the guide learned, or
//! the image would depend on the learning paths twice.

/// Cells of the guide along each of (u₀, u₁).
pub const GUIDE_BINS: usize = 16;
/// The most light paths the guide learns from: 16 per cell (Sobol points fill every cell
/// equally), for passes of 32 times as many paths and more (module docs, "Learning").
pub const MAX_LEARNING_PATHS: u64 = 4096;
/// The fewest light paths the guide learns from: 2 per cell, for passes of 24,575 paths and
/// fewer.
pub const MIN_LEARNING_PATHS: u64 = 512;

/// The light paths the guide learns from, the render's first, for passes of `per_pass` light
/// paths: a thirty-second of a pass in whole multiples of the cells (so that Sobol points fill
/// every cell equally), from [`MIN_LEARNING_PATHS`] to [`MAX_LEARNING_PATHS`] (module docs,
/// "Learning").
pub fn learning_paths(per_pass: u64) -> u64 {
    let cells = (GUIDE_BINS * GUIDE_BINS) as u64;
    (per_pass / 32 / cells * cells).clamp(MIN_LEARNING_PATHS, MAX_LEARNING_PATHS)
}
/// The share of the uniform density every cell keeps (defensive sampling: a cell the learning
/// paths under-rated still gets paths, with a bounded weight of at most 1/`DEFENSIVE_FRACTION`).
pub const DEFENSIVE_FRACTION: f32 = 0.1;
/// Below about the square root of this pixel value (a tenth of display white) the guide
/// weighs errors absolutely rather than relative to the pixel: relMSE's floor.
pub const DISPLAY_FLOOR: f64 = 0.01;
/// The work of a light path besides its rays (emission, sample values, splats), in rays.
pub const PATH_COST_RAYS: f64 = 1.0;
/// Least predicted gain (variance × cost, uniform over guided) for the guide to be used.
pub const MIN_PREDICTED_GAIN: f64 = 1.1;
/// Largest width and height of the learning paths' light image: a larger display is binned in
/// square blocks of pixels (so that learning a guide for a 16k render takes a few MB, not GB).
const LEARNING_IMAGE_SIZE: u32 = 512;
/// Passes of a 3×3 box blur over the learning paths' light image before it divides scores.
const BLUR_PASSES: usize = 2;
/// Passes of a 3×3 box blur over the cells' moments before they shape the density: one left
/// 3–7 % less error than none on the caustic bench's ball (6 seeds, 4 and 16 spp), two no more.
const MOMENT_BLUR_PASSES: usize = 1;

/// What a learning path counts for against a guided one in a pass that holds both (module
/// docs, "Weighing the learning paths"): about half, as a path that starts uniformly is worth
/// about half a guided one where the guide helps.
pub const LEARNING_PATH_WORTH: f64 = 0.5;

/// The weight of each light path's splats: 1, except in the one pass that holds both learning
/// and guided paths, where the learning paths count [`LEARNING_PATH_WORTH`] of a guided one and
/// the pass's weights still add up to its paths (so it stays an unbiased pass). Made once per
/// render, so that a path's weight is two comparisons.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathWeights {
    /// The paths of the mixed pass, `mixed_start..mixed_end` (empty when there is none).
    mixed_start: u64,
    mixed_end: u64,
    /// The end of the learning paths (they are the render's first).
    learning_end: u64,
    /// The weights of the mixed pass's learning and guided paths.
    learning: f32,
    guided: f32,
}

impl PathWeights {
    /// The weights of a render of `per_pass` light paths a pass whose first `learning_paths`
    /// start uniformly (0 without a guide).
    pub fn new(per_pass: u64, learning_paths: u64) -> Self {
        let in_mixed = learning_paths.checked_rem(per_pass).unwrap_or(0);
        let mixed_start = learning_paths - in_mixed;
        let guided = if in_mixed == 0 {
            1.0 // no mixed pass
        } else {
            per_pass as f64 / (in_mixed as f64 * LEARNING_PATH_WORTH + (per_pass - in_mixed) as f64)
        };
        Self {
            mixed_start,
            mixed_end: if in_mixed == 0 { mixed_start } else { mixed_start + per_pass },
            learning_end: learning_paths,
            learning: (guided * LEARNING_PATH_WORTH) as f32,
            guided: guided as f32,
        }
    }

    /// The weight of light path `path` (numbered over the whole render).
    #[inline]
    pub fn weight(&self, path: u64) -> f32 {
        if !(self.mixed_start..self.mixed_end).contains(&path) {
            1.0
        } else if path < self.learning_end {
            self.learning
        } else {
            self.guided
        }
    }
}

/// A piecewise-constant density over the unit square of a light path's first two sample
/// dimensions, with the warp that samples it.
#[derive(Debug, Clone, PartialEq)]
pub struct EmissionGuide {
    /// Density per cell, row `i` (u₀) major, mean 1; empty when uniform.
    density: Vec<f32>,
    /// Cumulative mass of the rows, `GUIDE_BINS` + 1 values from 0 to 1.
    row_cdf: Vec<f32>,
    /// Per row, the cumulative mass of its cells, `GUIDE_BINS` + 1 values from 0 to 1.
    cell_cdf: Vec<f32>,
}

impl Default for EmissionGuide {
    fn default() -> Self {
        Self::uniform()
    }
}

impl EmissionGuide {
    /// The uniform density: paths start as without a guide, with weight 1.
    pub fn uniform() -> Self {
        Self { density: Vec::new(), row_cdf: Vec::new(), cell_cdf: Vec::new() }
    }

    /// True for the uniform guide.
    pub fn is_uniform(&self) -> bool {
        self.density.is_empty()
    }

    /// The guide whose density in each cell is proportional to `shape` (one value per cell,
    /// row-major, u₀ the row), mixed with the uniform density (`DEFENSIVE_FRACTION`). Uniform
    /// when the values are all zero or not all finite and non-negative.
    pub fn proportional_to(shape: &[f64]) -> Self {
        assert_eq!(shape.len(), GUIDE_BINS * GUIDE_BINS, "one value per cell");
        if shape.iter().any(|s| !s.is_finite() || *s < 0.0) {
            return Self::uniform();
        }
        let mean = shape.iter().sum::<f64>() / shape.len() as f64;
        if !(mean > 0.0 && mean.is_finite()) {
            return Self::uniform();
        }
        let keep = f64::from(DEFENSIVE_FRACTION);
        let density: Vec<f32> = shape.iter().map(|r| ((1.0 - keep) * r / mean + keep) as f32).collect();
        // The warp's tables, from the f32 densities (so that they and the weights agree).
        let n = GUIDE_BINS;
        let rows: Vec<Vec<f64>> =
            density.chunks_exact(n).map(|row| row.iter().map(|&d| f64::from(d)).collect()).collect();
        let mut row_cdf = Vec::with_capacity(n + 1);
        push_cdf(&mut row_cdf, &rows.iter().map(|row| row.iter().sum()).collect::<Vec<f64>>());
        let mut cell_cdf = Vec::with_capacity(n * (n + 1));
        for row in &rows {
            push_cdf(&mut cell_cdf, row);
        }
        // Renormalise the densities to the tables' masses, which are what the warp samples.
        let density = (0..n * n)
            .map(|c| {
                let (i, j) = (c / n, c % n);
                let row = row_cdf[i + 1] - row_cdf[i];
                let cell = cell_cdf[i * (n + 1) + j + 1] - cell_cdf[i * (n + 1) + j];
                row * cell * (n * n) as f32
            })
            .collect();
        Self { density, row_cdf, cell_cdf }
    }

    /// The density of cell (`row`, `column`) (mean 1 over the cells).
    pub fn density(&self, row: usize, column: usize) -> f32 {
        if self.is_uniform() {
            1.0
        } else {
            self.density[row * GUIDE_BINS + column]
        }
    }

    /// The cell (row-major index) the point `u` of the unit square lies in.
    pub fn cell_of(u: (f32, f32)) -> usize {
        let n = GUIDE_BINS as f32;
        let i = ((u.0 * n) as usize).min(GUIDE_BINS - 1);
        let j = ((u.1 * n) as usize).min(GUIDE_BINS - 1);
        i * GUIDE_BINS + j
    }

    /// Maps a uniform point `u` of the unit square to one distributed with this density, and
    /// returns it with its weight, 1/density (the identity and 1 when uniform). Monotone in
    /// each coordinate within a row, so stratified points stay stratified.
    #[inline]
    pub fn warp(&self, u: (f32, f32)) -> ((f32, f32), f32) {
        if self.is_uniform() {
            return (u, 1.0);
        }
        let n = GUIDE_BINS;
        let (i, x) = invert(&self.row_cdf, u.0);
        let (j, y) = invert(&self.cell_cdf[i * (n + 1)..(i + 1) * (n + 1)], u.1);
        let scale = n as f32;
        let warped = (((i as f32 + x) / scale).min(ONE_BELOW), ((j as f32 + y) / scale).min(ONE_BELOW));
        (warped, 1.0 / self.density[i * n + j])
    }
}

/// Appends to `table` the cumulative table of `masses` (non-negative, not all zero): its
/// `masses.len()` + 1 values from 0 to exactly 1.
fn push_cdf(table: &mut Vec<f32>, masses: &[f64]) {
    let total: f64 = masses.iter().sum();
    let mut sum = 0.0;
    table.push(0.0);
    for mass in masses {
        sum += mass;
        table.push((sum / total) as f32);
    }
    if let Some(last) = table.last_mut() {
        *last = 1.0;
    }
}

/// The largest f32 below 1.
const ONE_BELOW: f32 = 1.0 - f32::EPSILON / 2.0;

/// The interval `k` of the cumulative table `cdf` (increasing, 0 to 1) that holds `u`, and
/// where in it `u` lies, in [0, 1).
#[inline]
fn invert(cdf: &[f32], u: f32) -> (usize, f32) {
    let last = cdf.len() - 2;
    // The last k with cdf[k] <= u, among intervals of positive width: the values at or below
    // `u` counted (the table is non-decreasing), without branches. A binary search's branches
    // go either way at random (u is a sample), and their mispredictions made the warp 6 % of
    // a light path's time on the caustic bench's ball.
    let k = cdf[1..=last].iter().map(|&c| usize::from(c <= u)).sum::<usize>();
    let (lo, hi) = (cdf[k], cdf[k + 1]);
    let t = if hi > lo { (u - lo) / (hi - lo) } else { 0.0 };
    (k, t.clamp(0.0, ONE_BELOW))
}

/// What the learning paths left: per cell, their number and rays; per splat (in path order),
/// the cell its path started in, its pixel and its luminance.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    paths: Vec<u64>,
    rays: Vec<u64>,
    landings: Vec<Landing>,
}

/// One splat of a learning path.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Landing {
    cell: u16,
    pixel: u32,
    luminance: f32,
}

impl Default for Record {
    fn default() -> Self {
        let cells = GUIDE_BINS * GUIDE_BINS;
        Self { paths: vec![0; cells], rays: vec![0; cells], landings: Vec::new() }
    }
}

impl Record {
    /// Records a light path that started (unwarped) at `u`, cast `rays` rays and made the
    /// splats `landings` (pixel, luminance Y).
    pub fn add_path(&mut self, u: (f32, f32), rays: u64, landings: impl Iterator<Item = (u32, f32)>) {
        let cell = EmissionGuide::cell_of(u);
        self.paths[cell] += 1;
        self.rays[cell] += rays;
        let cell = cell as u16;
        self.landings.extend(landings.map(|(pixel, luminance)| Landing { cell, pixel, luminance }));
    }

    /// Appends the paths of `later` (traced after these).
    pub fn append(&mut self, later: Record) {
        for (total, n) in self.paths.iter_mut().zip(&later.paths) {
            *total += n;
        }
        for (total, n) in self.rays.iter_mut().zip(&later.rays) {
            *total += n;
        }
        self.landings.extend(later.landings);
    }

    /// Light paths recorded.
    pub fn paths(&self) -> u64 {
        self.paths.iter().sum()
    }
}

/// A learned guide and the gain it was predicted to bring.
#[derive(Debug, Clone, PartialEq)]
pub struct Learned {
    /// The guide: uniform when the gain was predicted below `MIN_PREDICTED_GAIN`.
    pub guide: EmissionGuide,
    /// Variance × cost with uniform paths over that with the density learned (module docs);
    /// `None` when nothing was learned (no splat, or too few paths).
    pub predicted_gain: Option<f64>,
}

/// Learns a guide from the learning paths' `record`, whose splats fall on a `display` of
/// (width, height) pixels. Deterministic: sums in the record's order.
pub fn learn(record: &Record, display: (u32, u32)) -> Learned {
    let nothing = Learned { guide: EmissionGuide::uniform(), predicted_gain: None };
    let paths = record.paths();
    if paths < MIN_LEARNING_PATHS || record.landings.is_empty() {
        return nothing;
    }
    // The light image per display pixel, on a grid of `step` × `step` blocks of pixels at most
    // `LEARNING_IMAGE_SIZE` wide and high (pixel by pixel for small images).
    let (display_width, display_height) = (display.0.max(1), display.1.max(1));
    let step = display_width.max(display_height).div_ceil(LEARNING_IMAGE_SIZE).max(1);
    let (width, height) = (display_width.div_ceil(step) as usize, display_height.div_ceil(step) as usize);
    let display_pixels = display_width as usize * display_height as usize;
    let block_of = |pixel: u32| {
        if step == 1 {
            // Pixel by pixel: the block is the pixel (without the two integer divisions per
            // landing below, which took a fifth of the learning's time on the caustic bench).
            return ((pixel as usize) < display_pixels).then_some(pixel as usize);
        }
        let (x, y) = (pixel % display_width, pixel / display_width);
        (y < display_height).then(|| (y / step) as usize * width + (x / step) as usize)
    };
    let pixels_per_block = f64::from(step).powi(2);
    let mut image = vec![0.0f64; width * height];
    for landing in &record.landings {
        if let Some(block) = block_of(landing.pixel) {
            image[block] += f64::from(landing.luminance) / (paths as f64 * pixels_per_block);
        }
    }
    for _ in 0..BLUR_PASSES {
        image = box_blur(&image, width, height);
    }
    let denominator = |pixel: u32| block_of(pixel).map(|block| image[block] * image[block] + DISPLAY_FLOOR);
    let cells = GUIDE_BINS * GUIDE_BINS;
    // Per cell, the mean over its paths of Σ Y²/(m² + floor), and the cost of a path.
    let mut moments = vec![0.0f64; cells];
    for landing in &record.landings {
        if let Some(den) = denominator(landing.pixel) {
            let y = f64::from(landing.luminance);
            moments[usize::from(landing.cell)] += y * y / den;
        }
    }
    let mean_cost = record.rays.iter().sum::<u64>() as f64 / paths as f64 + PATH_COST_RAYS;
    let mut costs = vec![mean_cost; cells];
    for c in 0..cells {
        if record.paths[c] > 0 {
            moments[c] /= record.paths[c] as f64;
            costs[c] = record.rays[c] as f64 / record.paths[c] as f64 + PATH_COST_RAYS;
        }
    }
    // The square of the mean image, which every density's variance subtracts alike.
    let squared_mean: f64 =
        image.iter().map(|m| m * m / (m * m + DISPLAY_FLOOR)).sum::<f64>() * pixels_per_block;
    // The density follows the moments blurred over neighbouring cells (each cell's estimate
    // rests on a few dozen paths); the prediction below uses the cells' own.
    let mut smoothed = moments.clone();
    for _ in 0..MOMENT_BLUR_PASSES {
        smoothed = box_blur(&smoothed, GUIDE_BINS, GUIDE_BINS);
    }
    let shape: Vec<f64> = smoothed.iter().zip(&costs).map(|(m, c)| (m / c).sqrt()).collect();
    let guide = EmissionGuide::proportional_to(&shape);
    if guide.is_uniform() {
        return nothing;
    }
    let mean = |f: &dyn Fn(usize) -> f64| (0..cells).map(f).sum::<f64>() / cells as f64;
    let density = |c: usize| f64::from(guide.density(c / GUIDE_BINS, c % GUIDE_BINS));
    let uniform = (mean(&|c| moments[c]) - squared_mean) * mean(&|c| costs[c]);
    let guided = (mean(&|c| moments[c] / density(c)) - squared_mean) * mean(&|c| costs[c] * density(c));
    let gain = uniform / guided;
    if !(gain.is_finite() && gain > 0.0) {
        return nothing;
    }
    let guide = if gain >= MIN_PREDICTED_GAIN { guide } else { EmissionGuide::uniform() };
    Learned { guide, predicted_gain: Some(gain) }
}

/// One pass of a 3×3 box blur over a `width`×`height` image (row-major), the edges clamped.
/// Each pixel sums its nine neighbours row by row, left to right; the pixels off the edges,
/// nearly all of them, from three rows without clamping (the same sums, fewer instructions).
fn box_blur(image: &[f64], width: usize, height: usize) -> Vec<f64> {
    let clamped = |x: usize, y: usize| {
        let mut sum = 0.0;
        for dy in -1..=1 {
            for dx in -1..=1 {
                let xx = (x as isize + dx).clamp(0, width as isize - 1) as usize;
                let yy = (y as isize + dy).clamp(0, height as isize - 1) as usize;
                sum += image[yy * width + xx];
            }
        }
        sum / 9.0
    };
    let mut out = vec![0.0; image.len()];
    for (y, out_row) in out.chunks_exact_mut(width).enumerate() {
        if y == 0 || y + 1 == height || width < 3 {
            for (x, value) in out_row.iter_mut().enumerate() {
                *value = clamped(x, y);
            }
            continue;
        }
        let row = |r: usize| &image[r * width..(r + 1) * width];
        let (up, middle, down) = (row(y - 1), row(y), row(y + 1));
        for (x, value) in out_row.iter_mut().enumerate().take(width - 1).skip(1) {
            let (a, b, c) = (&up[x - 1..x + 2], &middle[x - 1..x + 2], &down[x - 1..x + 2]);
            // The clamped sum's terms in its order, from 0.
            let sum = 0.0 + a[0] + a[1] + a[2] + b[0] + b[1] + b[2] + c[0] + c[1] + c[2];
            *value = sum / 9.0;
        }
        out_row[0] = clamped(0, y);
        out_row[width - 1] = clamped(width - 1, y);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A lopsided density: cell c weighs √((c mod 7)² + (c / 40)⁴).
    fn lopsided() -> EmissionGuide {
        let shape: Vec<f64> = (0..GUIDE_BINS * GUIDE_BINS)
            .map(|c| (((c % 7) as f64).powi(2) + ((c / 40) as f64).powi(4)).sqrt())
            .collect();
        EmissionGuide::proportional_to(&shape)
    }

    /// Every pass's weights add up to its paths; only the pass that mixes learning and guided
    /// paths departs from 1, its learning paths worth `LEARNING_PATH_WORTH` of a guided one.
    #[test]
    fn a_mixed_pass_weighs_its_paths_to_their_number() {
        for (per_pass, mixed_pass) in [(6144, 0), (24_576, 0), (1000, 4), (4096, usize::MAX), (3, 1365)] {
            let weights = PathWeights::new(per_pass, MAX_LEARNING_PATHS);
            for pass in 0..6.max(mixed_pass.saturating_add(2)).min(1400) as u64 {
                let paths = pass * per_pass..(pass + 1) * per_pass;
                let sum: f64 = paths.clone().map(|p| f64::from(weights.weight(p))).sum();
                assert!(
                    (sum - per_pass as f64).abs() < 1e-5 * per_pass as f64,
                    "pass {pass} of {per_pass}: {sum}"
                );
                // Learning paths come first in a pass: equal weights lie together.
                let mut distinct: Vec<f32> = paths.map(|p| weights.weight(p)).collect();
                distinct.dedup();
                if pass as usize == mixed_pass {
                    let (learning, guided) = (distinct[0], distinct[1]);
                    assert_eq!(distinct.len(), 2, "pass {pass} of {per_pass}");
                    assert!((f64::from(learning / guided) - LEARNING_PATH_WORTH).abs() < 1e-6);
                } else {
                    assert_eq!(distinct, [1.0], "pass {pass} of {per_pass}");
                }
            }
        }
        // Without a guide, or without light paths, every path weighs 1.
        assert_eq!(PathWeights::new(6144, 0).weight(17), 1.0);
        assert_eq!(PathWeights::new(0, MAX_LEARNING_PATHS).weight(17), 1.0);
    }

    #[test]
    fn small_passes_learn_from_a_thirty_second() {
        assert_eq!(learning_paths(1), MIN_LEARNING_PATHS);
        assert_eq!(learning_paths(16_384), 512);
        assert_eq!(learning_paths(24_576), 768);
        assert_eq!(learning_paths(60_000), 1792); // 1,875 down to a multiple of 256
        assert_eq!(learning_paths(131_072), MAX_LEARNING_PATHS);
        assert_eq!(learning_paths(360_000), MAX_LEARNING_PATHS);
    }

    #[test]
    fn uniform_guide_is_the_identity() {
        let guide = EmissionGuide::uniform();
        assert_eq!(guide.warp((0.25, 0.75)), ((0.25, 0.75), 1.0));
        assert_eq!(EmissionGuide::proportional_to(&[0.0; GUIDE_BINS * GUIDE_BINS]), guide);
        let mut bad = [1.0; GUIDE_BINS * GUIDE_BINS];
        bad[3] = f64::NAN;
        assert!(EmissionGuide::proportional_to(&bad).is_uniform());
    }

    #[test]
    fn density_has_mean_one_and_a_defensive_floor() {
        let guide = lopsided();
        let n = GUIDE_BINS;
        let mean: f64 =
            (0..n * n).map(|c| f64::from(guide.density(c / n, c % n))).sum::<f64>() / (n * n) as f64;
        assert!((mean - 1.0).abs() < 1e-5, "mean density {mean}");
        let least = (0..n * n).map(|c| guide.density(c / n, c % n)).fold(f32::INFINITY, f32::min);
        assert!(least >= DEFENSIVE_FRACTION * 0.999, "least density {least}");
        // Cells 0, 7, 14... weigh zero: only the floor. Cell 255 weighs most.
        assert!(guide.density(0, 0) < 0.11 && guide.density(n - 1, n - 1) > 2.0);
    }

    /// The warped points of a fine grid fall in each cell in proportion to its density, and the
    /// weighted mean of a function over them is its integral over the square (the estimator
    /// stays unbiased): checked on x² + y·eˣ, whose integral is 1/3 + (e − 1)/2.
    #[test]
    fn warp_samples_the_density_and_weights_integrate() {
        let guide = lopsided();
        let n = GUIDE_BINS;
        let k = 2048;
        let mut counts = vec![0u32; n * n];
        let mut integral = 0.0f64;
        for a in 0..k {
            for b in 0..k {
                let u = ((a as f32 + 0.5) / k as f32, (b as f32 + 0.5) / k as f32);
                let ((x, y), weight) = guide.warp(u);
                assert!((0.0..1.0).contains(&x) && (0.0..1.0).contains(&y), "{u:?} -> {x}, {y}");
                let cell = EmissionGuide::cell_of((x, y));
                assert_eq!(weight, 1.0 / guide.density(cell / n, cell % n));
                counts[cell] += 1;
                let (x, y) = (f64::from(x), f64::from(y));
                integral += (x * x + y * x.exp()) * f64::from(weight);
            }
        }
        let points = (k * k) as f64;
        for (cell, &count) in counts.iter().enumerate() {
            let expected = f64::from(guide.density(cell / n, cell % n)) * points / (n * n) as f64;
            assert!(
                (f64::from(count) - expected).abs() <= 0.02 * expected + 64.0,
                "cell {cell}: {count}, {expected}"
            );
        }
        // The grid's quadrature error (its points do not line up with the cells' edges) falls
        // with k: relative 9e-4 at k = 512, −3.6e-4 at 1024, −1.0e-4 at 2048, −1e-6 at 4096.
        let exact = 1.0 / 3.0 + (std::f64::consts::E - 1.0) / 2.0;
        assert!((integral / points - exact).abs() < 2e-4 * exact, "{} vs {exact}", integral / points);
    }

    #[test]
    fn warp_is_monotone_along_each_coordinate() {
        let guide = lopsided();
        let mut last = -1.0;
        for a in 0..4096 {
            let ((x, _), _) = guide.warp(((a as f32 + 0.5) / 4096.0, 0.3));
            assert!(x >= last);
            last = x;
        }
        let mut last = -1.0;
        for b in 0..4096 {
            let ((_, y), _) = guide.warp((0.6, (b as f32 + 0.5) / 4096.0));
            assert!(y >= last);
            last = y;
        }
    }

    /// A record of `per_cell` paths in every cell of a 1×1 display (where the blur keeps the
    /// image), path k of cell c casting `rays(c)` rays and splatting `luminance(c, k)` (none
    /// when zero).
    fn record(
        per_cell: usize,
        rays: impl Fn(usize) -> u64,
        luminance: impl Fn(usize, usize) -> f32,
    ) -> Record {
        let n = GUIDE_BINS;
        let mut record = Record::default();
        for k in 0..per_cell {
            for c in 0..n * n {
                let u = (
                    ((c / n) as f32 + 0.5) / n as f32,
                    ((c % n) as f32 + (k as f32 + 0.5) / per_cell as f32) / n as f32,
                );
                let y = luminance(c, k);
                record.add_path(u, rays(c), (y > 0.0).then_some((0, y)).into_iter());
            }
        }
        record
    }

    #[test]
    fn too_few_paths_or_no_splat_learn_nothing() {
        let few = record(MIN_LEARNING_PATHS as usize / (GUIDE_BINS * GUIDE_BINS) - 1, |_| 2, |c, _| c as f32);
        assert_eq!(learn(&few, (1, 1)), Learned { guide: EmissionGuide::uniform(), predicted_gain: None });
        let dark = record(32, |_| 2, |_, _| 0.0);
        assert_eq!(learn(&dark, (1, 1)).predicted_gain, None);
    }

    #[test]
    fn paths_all_worth_the_same_keep_the_uniform_density() {
        let flat = record(16, |_| 3, |_, k| if k.is_multiple_of(4) { 2.8 } else { 0.0 });
        let learned = learn(&flat, (1, 1));
        assert!(learned.guide.is_uniform());
        let gain = learned.predicted_gain.expect("learned");
        assert!((gain - 1.0).abs() < 1e-6, "{gain}");
    }

    #[test]
    fn dearer_cells_get_fewer_paths() {
        // Equal contributions (one path in 8 of every cell brings 8); the upper half of the rows
        // costs 24 + 1 = 25 path units, the lower 0 + 1 = 1: densities before the defensive mix
        // in the ratio √25.
        let n = GUIDE_BINS;
        let dear_upper = |c: usize| if c / n >= n / 2 { 24 } else { 0 };
        let learned =
            learn(&record(16, dear_upper, |_, k| if k.is_multiple_of(8) { 8.0 } else { 0.0 }), (1, 1));
        let (cheap, dear) = (learned.guide.density(0, 0), learned.guide.density(n - 1, 0));
        let keep = DEFENSIVE_FRACTION;
        let ratio = (cheap - keep) / (dear - keep);
        assert!((ratio - 5.0).abs() < 1e-3, "{ratio}");
    }

    /// The predicted gain is the ratio of variances (equal costs) that sampling with the guide
    /// shows: paths drawn uniformly and through the guide's warp, each estimating the pixel
    /// (one pixel, the cells' luminances lopsided), their sample variances compared.
    #[test]
    fn predicted_gain_is_the_variance_ratio_sampling_shows() {
        let n = GUIDE_BINS;
        let luminance = |c: usize, _: usize| {
            if c.is_multiple_of(5) {
                4.0 + (c / n) as f32
            } else {
                0.05 * (c % 3) as f32
            }
        };
        let learned = learn(&record(16, |_| 3, luminance), (1, 1));
        let gain = learned.predicted_gain.expect("learned");
        assert!(!learned.guide.is_uniform() && gain > 1.5, "{gain}");
        // A pixel far above the display floor: relative variance, the same for both.
        let variance = |guide: &EmissionGuide| {
            let k = 2048;
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for a in 0..k {
                for b in 0..k {
                    let ((x, y), weight) =
                        guide.warp(((a as f32 + 0.5) / k as f32, (b as f32 + 0.5) / k as f32));
                    let value = f64::from(luminance(EmissionGuide::cell_of((x, y)), 0) * weight);
                    sum += value;
                    sum2 += value * value;
                }
            }
            let count = (k * k) as f64;
            (sum / count, sum2 / count - (sum / count).powi(2))
        };
        let (uniform_mean, uniform_variance) = variance(&EmissionGuide::uniform());
        let (guided_mean, guided_variance) = variance(&learned.guide);
        assert!((guided_mean / uniform_mean - 1.0).abs() < 1e-3, "{guided_mean} vs {uniform_mean}");
        let shown = uniform_variance / guided_variance;
        // The floor cancels from the ratio (one pixel); the grid's quadrature over the warped
        // cells leaves 0.16 %.
        assert!((shown / gain - 1.0).abs() < 0.01, "predicted {gain}, shown {shown}");
    }

    /// A display of 40,000 × 40,000 pixels (an f64 per pixel would be 12.8 GB) learns on a
    /// binned image: the same landings in one pixel give a guide, quickly.
    #[test]
    fn a_huge_display_learns_on_a_binned_image() {
        let n = GUIDE_BINS;
        let luminance = |c: usize, _: usize| if c.is_multiple_of(5) { 4.0 + (c / n) as f32 } else { 0.0 };
        let learned = learn(&record(16, |_| 3, luminance), (40_000, 40_000));
        assert!(learned.predicted_gain.is_some_and(|g| g.is_finite() && g > 1.5), "{learned:?}");
        assert!(!learned.guide.is_uniform());
    }

    #[test]
    fn blur_keeps_a_constant_image_and_spreads_a_point() {
        let flat = vec![2.0; 12];
        assert_eq!(box_blur(&flat, 4, 3), flat);
        let mut point = vec![0.0; 25];
        point[12] = 9.0;
        let blurred = box_blur(&point, 5, 5);
        assert_eq!(blurred[12], 1.0);
        assert_eq!(blurred[6], 1.0);
        assert_eq!(blurred[0], 0.0);
    }

    /// The blur's unclamped interior adds the same terms in the same order as the clamped
    /// definition: the same bits, edges and corners included (1- and 2-pixel-wide images too).
    #[test]
    fn blur_interior_gives_the_bits_of_the_clamped_definition() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        for (width, height) in [(7, 5), (1, 4), (2, 2), (16, 16), (3, 1)] {
            let image: Vec<f64> = (0..width * height)
                .map(|_| {
                    state =
                        state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
                    (state >> 11) as f64 / (1u64 << 53) as f64 * 1e3
                })
                .collect();
            let clamped: Vec<f64> = (0..width * height)
                .map(|i| {
                    let (x, y) = ((i % width) as isize, (i / width) as isize);
                    let mut sum = 0.0;
                    for dy in -1..=1 {
                        for dx in -1..=1 {
                            let xx = (x + dx).clamp(0, width as isize - 1) as usize;
                            let yy = (y + dy).clamp(0, height as isize - 1) as usize;
                            sum += image[yy * width + xx];
                        }
                    }
                    sum / 9.0
                })
                .collect();
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&box_blur(&image, width, height)), bits(&clamped), "{width}×{height}");
        }
    }
}

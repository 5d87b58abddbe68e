//! Edge refinement: more camera samples per pass where the image has a sharp edge.
//!
//! One camera sample per pixel and pass leaves most of a low-sample render's camera-side error
//! on a few pixels that an edge crosses (a shadow's border, a spot light's cutoff, a silhouette):
//! a pixel half lit, half dark gets 0 or full light from each sample. On the caustic bench's
//! ball (validation/bench) 1 % of the pixels held 89 % of the camera side's relMSE at 1 spp.
//! With `edge_samples` = m > 1 (the scene's `[render]`, `--edge-samples`), a render spends its
//! samples there: such pixels take m camera samples in every pass, averaged into the pass's one
//! value, so that the pass counts as one sample for the film, the exact sums and the merges of
//! parts alike. Off (m = 1) by default: where edge pixels are many and see glass, refining them
//! costs more than it gives (the showcase at 32 spp: a fifth of its pixels, 2.6× the time);
//! at a few passes with sharp shadows or light edges on cheap surfaces, as in a caustic preview,
//! it pays several times over (the caustic bench, validation/bench/RESULTS.md).
//!
//! **Which pixels**: after the first pass, a pixel is an edge pixel when the first-pass camera
//! luminance of its (up to 8) neighbours spans more than [`EDGE_CONTRAST`] times their level
//! (the mid-range, with [`LEVEL_FLOOR`] below it, as the validation's relMSE weighs errors).
//! The pixel's **own** samples take no part in the choice, and the samples of different pixels
//! are independent ([`crate::sampler`]), so which pixels get more samples is independent of
//! their values: every pass of every pixel stays an unbiased estimate, and so does the image.
//! (A choice that looked at the pixel's own first sample would favour pixels whose first sample
//! was unusual and bias them.) Only the camera side is refined; the light tracer's splats do
//! not enter the choice.
//!
//! **Which sample values**: sub-sample j of pass k of a pixel of m samples per pass is point
//! k·m + j of its Sobol sequence: after any number of passes a pixel has used a prefix of its
//! sequence, stratified as well as m times the passes of plain sampling. The first pass's first
//! sample (point 0) is taken before the map exists; an edge pixel keeps it, weighed 1/m, and
//! completes the pass with points 1..m right after the map is made. A pixel with m = 1 draws
//! point k in pass k, exactly as without refinement.
//!
//! The choice is a function of the first pass's values alone (the same bits whatever the
//! threads), and a part of a split render that does not hold the first pass, or whose window
//! has neighbours outside it, renders those first-pass values for the choice only.

use crate::part::PixelWindow;

/// Contrast of the neighbours' first-pass luminance (range over level) above which a pixel is
/// refined. On the caustic bench's ball at 1 spp, 0.5 marks 7.6 % of the pixels, and giving those
/// 4 samples left the camera side's relMSE where giving every pixel 4 samples does (2.1e-4,
/// from 2.1e-3); 1.0 marked 3.5 % and left 8.8e-4.
pub const EDGE_CONTRAST: f64 = 0.5;
/// Squared luminance below which contrasts count absolutely rather than relative to the level:
/// the floor of the validation's relMSE (a tenth of display white, squared).
pub const LEVEL_FLOOR: f64 = 0.01;
/// Largest `edge_samples` a scene may ask for.
pub const MAX_EDGE_SAMPLES: u32 = 64;

/// Camera samples per pass of each pixel of a window, chosen after the first pass.
#[derive(Debug, Clone, PartialEq)]
pub struct EdgeMap {
    window: PixelWindow,
    /// Per pixel of the window, row-major: camera samples in each pass.
    per_pass: Vec<u8>,
}

impl EdgeMap {
    /// One sample per pass everywhere: no refinement.
    pub fn uniform(window: PixelWindow) -> Self {
        Self { window, per_pass: vec![1; window.pixels()] }
    }

    /// The map of `window` from the first-pass luminance `luminance(x, y)` of the pixels of
    /// `area` (the window grown by a pixel on each side, within the image: [`surrounding`]):
    /// `edge_samples` samples per pass where the neighbours' contrast exceeds
    /// [`EDGE_CONTRAST`], else 1.
    pub fn find(
        window: PixelWindow,
        area: PixelWindow,
        luminance: impl Fn(u32, u32) -> f64,
        edge_samples: u32,
    ) -> Self {
        debug_assert!(area.contains_window(&window));
        let edge_samples = u8::try_from(edge_samples.min(MAX_EDGE_SAMPLES)).unwrap_or(u8::MAX);
        let (width, height) = (area.width() as usize, area.height() as usize);
        let values: Vec<f32> = (area.y0..area.y1)
            .flat_map(|y| (area.x0..area.x1).map(move |x| (x, y)))
            .map(|(x, y)| luminance(x, y) as f32)
            .collect();
        let mut per_pass = Vec::with_capacity(window.pixels());
        for y in (window.y0 - area.y0) as usize..(window.y1 - area.y0) as usize {
            let rows = y.saturating_sub(1)..(y + 2).min(height);
            for x in (window.x0 - area.x0) as usize..(window.x1 - area.x0) as usize {
                let columns = x.saturating_sub(1)..(x + 2).min(width);
                let (mut low, mut high) = (f32::INFINITY, f32::NEG_INFINITY);
                for ny in rows.clone() {
                    let row = &values[ny * width..(ny + 1) * width];
                    for nx in columns.clone() {
                        // The pixel's own value takes no part (module docs).
                        if (nx, ny) != (x, y) {
                            low = if row[nx] < low { row[nx] } else { low };
                            high = if row[nx] > high { row[nx] } else { high };
                        }
                    }
                }
                per_pass.push(if is_edge(low, high) { edge_samples } else { 1 });
            }
        }
        Self { window, per_pass }
    }

    /// Camera samples per pass of pixel (`x`, `y`) (inside the window).
    #[inline]
    pub fn samples(&self, x: u32, y: u32) -> u32 {
        let index =
            (y - self.window.y0) as usize * self.window.width() as usize + (x - self.window.x0) as usize;
        u32::from(self.per_pass[index])
    }

    /// Pixels with more than one sample per pass.
    pub fn edge_pixels(&self) -> usize {
        self.per_pass.iter().filter(|&&m| m > 1).count()
    }
}

/// True when neighbours spanning `low..=high` in luminance mark an edge: a span above
/// [`EDGE_CONTRAST`] times √(level² + [`LEVEL_FLOOR`]), the level their mid-range.
fn is_edge(low: f32, high: f32) -> bool {
    if low > high {
        return false; // no neighbours (a 1×1 image)
    }
    let (low, high) = (f64::from(low), f64::from(high));
    let level = 0.5 * (low + high);
    let span = high - low;
    span * span > EDGE_CONTRAST * EDGE_CONTRAST * (level * level + LEVEL_FLOOR)
}

/// `window` grown by one pixel on each side, within a `width`×`height` image: the pixels whose
/// first pass decides the window's map.
pub fn surrounding(window: PixelWindow, width: u32, height: u32) -> PixelWindow {
    PixelWindow {
        x0: window.x0.saturating_sub(1),
        y0: window.y0.saturating_sub(1),
        x1: (window.x1 + 1).min(width),
        y1: (window.y1 + 1).min(height),
    }
}

/// The point of a pixel's sample sequence that sub-sample `sub` of pass `pass` draws, for a
/// pixel of `per_pass` samples per pass (module docs): `pass` itself when `per_pass` is 1.
#[inline]
pub fn sample_index(pass: u32, per_pass: u32, sub: u32) -> u32 {
    pass * per_pass + sub
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Pixel (x, y)'s value of a row-major image of `area`.
    fn at(image: &[f64], area: PixelWindow) -> impl Fn(u32, u32) -> f64 + '_ {
        move |x, y| image[((y - area.y0) * area.width() + x - area.x0) as usize]
    }

    /// A 6×4 image dark on the left three columns, lit (1.0) on the right three.
    fn step() -> (PixelWindow, Vec<f64>) {
        let window = PixelWindow::full(6, 4);
        let luminance = (0..4).flat_map(|_| (0..6).map(|x| if x < 3 { 0.0 } else { 1.0 })).collect();
        (window, luminance)
    }

    #[test]
    fn an_edge_refines_the_columns_beside_it_and_nothing_else() {
        let (window, luminance) = step();
        let map = EdgeMap::find(window, window, at(&luminance, window), 4);
        for y in 0..4 {
            for x in 0..6 {
                let expected = if x == 2 || x == 3 { 4 } else { 1 };
                assert_eq!(map.samples(x, y), expected, "pixel ({x}, {y})");
            }
        }
        assert_eq!(map.edge_pixels(), 8);
    }

    #[test]
    fn a_pixels_own_value_does_not_choose_its_samples() {
        // Unbiasedness rests on this: a lone outlier (a firefly, or a pixel whose first sample
        // happened to hit a small bright thing) is not refined for its own value, while its
        // neighbours, which see it, are.
        let window = PixelWindow::full(5, 5);
        let mut luminance = vec![0.5; 25];
        luminance[12] = 100.0;
        let map = EdgeMap::find(window, window, at(&luminance, window), 3);
        assert_eq!(map.samples(2, 2), 1);
        assert_eq!(map.samples(1, 1), 3);
        assert_eq!(map.edge_pixels(), 8);
    }

    #[test]
    fn contrast_is_relative_to_the_level_above_the_floor() {
        // 10 % around 0.5: smooth shading; 2 against 1: an edge; 0.02 against 0: below the floor.
        assert!(!is_edge(0.475, 0.525));
        assert!(is_edge(1.0, 2.0));
        assert!(!is_edge(0.0, 0.02));
        assert!(is_edge(0.0, 0.1));
    }

    #[test]
    fn a_crop_is_decided_by_the_pixels_around_it() {
        // The same step, seen through the window of columns 3..6 with its surrounding column 2.
        let (full, luminance) = step();
        let window = PixelWindow { x0: 3, y0: 1, x1: 6, y1: 3 };
        let area = surrounding(window, 6, 4);
        assert_eq!(area, PixelWindow { x0: 2, y0: 0, x1: 6, y1: 4 });
        let cropped: Vec<f64> = (area.y0..area.y1)
            .flat_map(|y| (area.x0..area.x1).map(move |x| (x, y)))
            .map(|(x, y)| luminance[(y * full.width() + x) as usize])
            .collect();
        let whole = EdgeMap::find(full, full, at(&luminance, full), 4);
        let part = EdgeMap::find(window, area, at(&cropped, area), 4);
        for y in window.y0..window.y1 {
            for x in window.x0..window.x1 {
                assert_eq!(part.samples(x, y), whole.samples(x, y), "pixel ({x}, {y})");
            }
        }
    }

    #[test]
    fn passes_use_a_prefix_of_each_pixels_sequence() {
        for per_pass in [1, 2, 4] {
            let mut used: Vec<u32> = (0..5)
                .flat_map(|pass| (0..per_pass).map(move |sub| sample_index(pass, per_pass, sub)))
                .collect();
            used.sort_unstable();
            let expected: Vec<u32> = (0..used.len() as u32).collect();
            assert_eq!(used, expected, "{per_pass} per pass");
        }
        assert_eq!(sample_index(7, 1, 0), 7);
    }
}

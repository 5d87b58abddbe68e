//! [`Film`]: the rendered image: per-pixel mean CIE XYZ of the radiance (in monochromatic mode,
//! the mean spectral radiance at one wavelength), and, as the [`FilmLayout`] asks, the XYZ of
//! the Stokes components S1–S3 and the mean spectral radiance in wavelength bands.
//!
//! [`add_sample`] adds one camera sample to a pixel's exact sums ([`WindowSums`], of
//! [`FixedSum`]s); the division by the wavelength pdf happens there and in
//! [`crate::spectrum::cie::to_xyz`], nowhere else. [`WindowSums::film`] divides the sums by the
//! sample count.

pub mod window;

use glam::Vec3;

use crate::fixed::FixedSum;
use crate::geometry::huge_pages::filled_on_huge_pages;
use crate::polarization::Beam;
use crate::spectrum::color::xyz_to_linear_srgb;
use crate::spectrum::{cie, SampledWavelengths};

pub use window::PixelWindow;

/// `count` wavelength bands of equal width over [`min_nm`, `max_nm`), for spectral output.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpectralBands {
    /// Number of bands (≥ 1).
    pub count: usize,
    /// Short end of the first band, nm.
    pub min_nm: f32,
    /// Long end of the last band, nm.
    pub max_nm: f32,
}

impl SpectralBands {
    /// Width of each band, nm.
    pub fn width_nm(&self) -> f32 {
        (self.max_nm - self.min_nm) / self.count as f32
    }
    /// Centre of band `band`, nm.
    pub fn center_nm(&self, band: usize) -> f32 {
        self.min_nm + (band as f32 + 0.5) * self.width_nm()
    }
    /// The band holding `lambda_nm`, if any (bands are closed below, open above; the last one
    /// also holds `max_nm`).
    #[inline]
    pub fn band_of(&self, lambda_nm: f32) -> Option<usize> {
        if !(self.min_nm..=self.max_nm).contains(&lambda_nm) {
            return None;
        }
        let band = ((lambda_nm - self.min_nm) / self.width_nm()) as usize;
        Some(band.min(self.count - 1))
    }
}

/// What every pixel of a film holds.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FilmLayout {
    /// S1–S3 beside S0 (a polarised render).
    pub stokes: bool,
    /// Mean spectral radiance per band (per Stokes component), for spectral output.
    pub bands: Option<SpectralBands>,
    /// The wavelength (nm) of a monochromatic render, whose "XYZ" is (L, L, L).
    pub monochromatic_nm: Option<f32>,
}

impl FilmLayout {
    /// Stokes components held: 4 when polarised, else 1.
    pub fn components(&self) -> usize {
        if self.stokes {
            4
        } else {
            1
        }
    }
    /// Band values per pixel (bands × components).
    pub fn band_values(&self) -> usize {
        self.bands.map_or(0, |bands| bands.count * self.components())
    }
    /// The colour values summed per Stokes component, as indices into XYZ: X, Y and Z, or for a
    /// monochromatic render, whose XYZ is (L, L, L), Y = L alone.
    pub fn colour_axes(&self) -> &'static [usize] {
        if self.monochromatic_nm.is_some() {
            &[1]
        } else {
            &[0, 1, 2]
        }
    }
    /// Colour values summed per Stokes component (3, or 1 when monochromatic).
    pub fn colour_values(&self) -> usize {
        self.colour_axes().len()
    }
    /// Values summed per pixel: the colour values of each Stokes component, then the band
    /// values.
    pub fn values_per_pixel(&self) -> usize {
        self.colour_values() * self.components() + self.band_values()
    }
    /// The same layout without S1–S3: what the light tracer's sums hold when its splats
    /// cannot be polarised ([`WindowSums::with_light_layout`]).
    pub fn unpolarized(&self) -> FilmLayout {
        FilmLayout { stokes: false, ..*self }
    }
    /// Where the luminance (CIE Y of S0) sits among a pixel's values: the place of the Y axis
    /// among [`Self::colour_axes`], which always hold it.
    pub fn luminance_index(&self) -> usize {
        self.colour_axes().iter().position(|&axis| axis == 1).unwrap_or(0)
    }
}

/// Adds one camera sample's light `beam` at `wavelengths` to one pixel's sums `sums` (the
/// [`FilmLayout::values_per_pixel`] values of [`WindowSums`]): XYZ per Stokes component, then
/// the band estimates. False when a value cannot be summed (not finite, or past the range of
/// [`FixedSum`]): the render then fails, as for a non-finite pixel.
#[inline]
#[must_use]
pub fn add_sample<B: Beam>(
    sums: &mut [FixedSum],
    beam: &B,
    wavelengths: &SampledWavelengths,
    layout: &FilmLayout,
) -> bool {
    add_weighted_sample(sums, beam, wavelengths, layout, 1.0)
}

/// [`add_sample`] with every value times `weight` (1/m for each of a pass's m samples of an
/// edge pixel, [`crate::edges`]). A weight of 1 adds the same bits as [`add_sample`].
#[inline]
#[must_use]
pub fn add_weighted_sample<B: Beam>(
    sums: &mut [FixedSum],
    beam: &B,
    wavelengths: &SampledWavelengths,
    layout: &FilmLayout,
    weight: f32,
) -> bool {
    let mut ok = true;
    for (k, component) in beam.components().iter().enumerate() {
        // Most samples see unpolarised light (diffuse surfaces, the background): S1–S3 are
        // then exactly zero and add nothing.
        if k > 0 && component.is_zero() {
            continue;
        }
        let xyz = cie::to_xyz(component, wavelengths).to_array();
        let axes = layout.colour_axes();
        let colour = axes.len() * k..axes.len() * (k + 1);
        for (sum, &axis) in sums[colour].iter_mut().zip(axes) {
            ok &= sum.add_f32(weight * xyz[axis]);
        }
    }
    let Some(bands) = &layout.bands else { return ok };
    // Band mean of L: (1/Δλ)·∫_band L dλ, estimated like `to_xyz` with an indicator for the
    // colour-matching function: Σ_active L(λ_i)/p(λ_i) / active over the lanes in the band.
    let offset = layout.colour_values() * layout.components();
    let active = wavelengths.active();
    let scale = f64::from(weight) / (active as f64 * f64::from(bands.width_nm()));
    for lane in 0..active {
        let lambda_nm = wavelengths.lambda_nm(lane);
        let Some(band) = bands.band_of(lambda_nm) else { continue };
        let inverse_pdf = if wavelengths.is_monochromatic() {
            // One fixed wavelength: the band holding it gets the radiance itself.
            f64::from(bands.width_nm())
        } else {
            1.0 / f64::from(wavelengths.pdf_per_nm(lane))
        };
        for (k, component) in beam.components().iter().enumerate() {
            let value = f64::from(component[lane]) * inverse_pdf * scale;
            if value != 0.0 {
                ok &= sums[offset + k * bands.count + band].add_f64(value);
            }
        }
    }
    ok
}

/// A pixel whose value is not a finite number: radiance overflowed f32 somewhere in its samples.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "pixel ({x}, {y}) is not finite (XYZ = {xyz}): the scene's radiance overflows 32-bit floats there \
     (see the limits in scenes/README.md)"
)]
pub struct NonFinitePixel {
    /// Column, from the left.
    pub x: u32,
    /// Row, from the top.
    pub y: u32,
    /// Its value.
    pub xyz: Vec3,
}

/// The light tracer's contributions of one block of light paths, in the order they were made:
/// per splat, the pixel and the same values a camera sample adds with [`add_sample`] (XYZ per
/// Stokes component, then band estimates), each an estimate for one light path (not yet divided
/// by the number of paths).
#[derive(Debug, Clone, Default)]
pub struct Splats {
    pixels: Vec<u32>,
    values: Vec<f32>,
}

impl Splats {
    /// Number of splats held.
    pub fn len(&self) -> usize {
        self.pixels.len()
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.pixels.is_empty()
    }

    /// Splat `k`: its pixel and its luminance (CIE Y of its intensity, the first Stokes
    /// component), in a film of `layout`.
    pub fn luminance(&self, k: usize, layout: &FilmLayout) -> (u32, f32) {
        (self.pixels[k], self.values[k * layout.values_per_pixel() + layout.luminance_index()])
    }

    /// Scales the values of splats `first..` (in a film of `layout`) by `weight`.
    pub fn scale_from(&mut self, first: usize, weight: f32, layout: &FilmLayout) {
        for value in &mut self.values[first * layout.values_per_pixel()..] {
            *value *= weight;
        }
    }

    /// Adds the light `beam` (radiance at the camera, per lane) that lands in pixel `pixel`, as
    /// `layout` holds it: the Stokes components beyond [`FilmLayout::components`] must be zero
    /// (S0 alone for the light sums of [`WindowSums::with_light_layout`]).
    pub fn add<B: Beam>(
        &mut self,
        pixel: u32,
        beam: &B,
        wavelengths: &SampledWavelengths,
        layout: &FilmLayout,
    ) {
        self.pixels.push(pixel);
        debug_assert!(
            beam.components()[layout.components()..].iter().all(|c| c.is_zero()),
            "a polarised splat in a film without S1–S3"
        );
        for component in &beam.components()[..layout.components()] {
            let xyz = cie::to_xyz(component, wavelengths).to_array();
            self.values.extend(layout.colour_axes().iter().map(|&axis| xyz[axis]));
        }
        let Some(bands) = &layout.bands else { return };
        let start = self.values.len();
        self.values.resize(start + layout.band_values(), 0.0);
        let active = wavelengths.active();
        let scale = 1.0 / (active as f32 * bands.width_nm());
        for lane in 0..active {
            let Some(band) = bands.band_of(wavelengths.lambda_nm(lane)) else { continue };
            let inverse_pdf = if wavelengths.is_monochromatic() {
                bands.width_nm()
            } else {
                1.0 / wavelengths.pdf_per_nm(lane)
            };
            for (k, component) in beam.components()[..layout.components()].iter().enumerate() {
                self.values[start + k * bands.count + band] += component[lane] * inverse_pdf * scale;
            }
        }
    }
}

/// The exact per-pixel sums of a render or a part over one [`PixelWindow`]: for every pixel,
/// the [`FilmLayout::values_per_pixel`] sums of its camera samples (row-major), and, with
/// caustics, the sums of the light tracer's splats: as many, or in a polarised render whose
/// splats cannot be polarised (no sheets between receiver and camera), those of S0 alone
/// ([`Self::with_light_layout`]; S1–S3 of the light are then zero). These, with the sample count, are
/// what a part file keeps and what merging adds: sums of [`FixedSum`]s do not depend on the
/// order or grouping of their terms, so any split of a render adds up to the same bits.
///
/// Two sums are equal when they hold the same values, whether their light sums keep S1–S3 or
/// not (a value left out is zero).
#[derive(Debug, Clone)]
pub struct WindowSums {
    window: PixelWindow,
    layout: FilmLayout,
    camera: Vec<FixedSum>,
    light_layout: FilmLayout,
    light: Vec<FixedSum>,
}

impl PartialEq for WindowSums {
    fn eq(&self, other: &Self) -> bool {
        if self.window != other.window
            || self.layout != other.layout
            || self.camera != other.camera
            || self.has_light() != other.has_light()
        {
            return false;
        }
        if self.light_layout == other.light_layout || !self.has_light() {
            return self.light == other.light;
        }
        // Value `index` of light sums `sums` at `pixel`, zero where they leave it out.
        let slots =
            |sums: &WindowSums| (0..sums.stride()).map(|index| sums.light_slot(index)).collect::<Vec<_>>();
        let (own_slots, other_slots) = (slots(self), slots(other));
        let value = |sums: &WindowSums, slots: &[Option<usize>], pixel: usize, index: usize| {
            slots[index].map_or(FixedSum::ZERO, |slot| sums.light[pixel * sums.light_stride() + slot])
        };
        (0..self.window.pixels()).all(|pixel| {
            (0..self.stride()).all(|index| {
                value(self, &own_slots, pixel, index) == value(other, &other_slots, pixel, index)
            })
        })
    }
}

/// A sum that left the range of [`FixedSum`] while merging parts.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("the sums of pixel ({x}, {y}) overflow: the radiance there is too large to sum exactly")]
pub struct SumOverflow {
    /// Column.
    pub x: u32,
    /// Row.
    pub y: u32,
}

impl WindowSums {
    /// Zero sums over `window` for `layout`, with light-tracer sums of the same layout when
    /// `light`.
    pub fn new(window: PixelWindow, layout: FilmLayout, light: bool) -> Self {
        Self::build(window, layout, layout, light)
    }

    /// Zero sums over `window` for `layout`, with light-tracer sums for `light_layout`: `layout`
    /// itself, or [`FilmLayout::unpolarized`] of it when the light tracer's splats carry S0
    /// alone (a third or a quarter of the memory in a polarised render).
    ///
    /// # Panics
    /// If `light_layout` is neither.
    pub fn with_light_layout(window: PixelWindow, layout: FilmLayout, light_layout: FilmLayout) -> Self {
        assert!(
            light_layout == layout || light_layout == layout.unpolarized(),
            "light sums of another layout"
        );
        Self::build(window, layout, light_layout, true)
    }

    fn build(window: PixelWindow, layout: FilmLayout, light_layout: FilmLayout, light: bool) -> Self {
        let values = window.pixels() * layout.values_per_pixel();
        let light_values = window.pixels() * light_layout.values_per_pixel();
        Self {
            window,
            layout,
            camera: filled_on_huge_pages(FixedSum::ZERO, values),
            light_layout,
            light: if light { filled_on_huge_pages(FixedSum::ZERO, light_values) } else { Vec::new() },
        }
    }

    /// The window.
    pub fn window(&self) -> PixelWindow {
        self.window
    }
    /// What each pixel holds.
    pub fn layout(&self) -> &FilmLayout {
        &self.layout
    }
    /// Values per pixel.
    pub fn stride(&self) -> usize {
        self.layout.values_per_pixel()
    }
    /// The camera samples' sums, row-major, [`Self::stride`] per pixel.
    pub fn camera(&self) -> &[FixedSum] {
        &self.camera
    }
    /// The camera samples' sums, to add to.
    pub fn camera_mut(&mut self) -> &mut [FixedSum] {
        &mut self.camera
    }
    /// The light tracer's sums (empty without caustics), [`Self::light_stride`] per pixel.
    pub fn light(&self) -> &[FixedSum] {
        &self.light
    }
    /// What the light tracer's sums hold per pixel.
    pub fn light_layout(&self) -> &FilmLayout {
        &self.light_layout
    }
    /// Light-tracer values per pixel.
    pub fn light_stride(&self) -> usize {
        self.light_layout.values_per_pixel()
    }
    /// The index among a pixel's values (of [`Self::layout`]) of its light-tracer value `slot`.
    pub fn light_value_index(&self, slot: usize) -> usize {
        if self.light_layout == self.layout {
            return slot;
        }
        // S0 alone: S0's colour values, then S0's bands (after every component's colour values).
        let colour = self.layout.colour_values();
        if slot < colour {
            slot
        } else {
            colour * self.layout.components() + (slot - colour)
        }
    }
    /// The light-tracer slot of value `index` (of [`Self::layout`]), or `None` for a value the
    /// light sums leave out (S1–S3 when they hold S0 alone: zero): the inverse of
    /// [`Self::light_value_index`], which alone knows the numbering.
    pub fn light_slot(&self, index: usize) -> Option<usize> {
        (0..self.light_stride()).find(|&slot| self.light_value_index(slot) == index)
    }
    /// True when the sums hold light-tracer splats.
    pub fn has_light(&self) -> bool {
        !self.light.is_empty()
    }

    /// Adds one block's splats (pixels numbered row-major over the whole `display_width`-wide
    /// image); splats outside the window are dropped. Returns the first pixel whose sums could
    /// not take a value, if any.
    pub fn add_splats(&mut self, splats: &Splats, display_width: u32) -> Option<(u32, u32)> {
        let stride = self.light_stride();
        let mut failed = None;
        for (pixel, values) in splats.pixels.iter().zip(splats.values.chunks_exact(stride)) {
            let (x, y) = (pixel % display_width, pixel / display_width);
            if !self.window.contains(x, y) {
                continue;
            }
            let index =
                (y - self.window.y0) as usize * self.window.width() as usize + (x - self.window.x0) as usize;
            let start = index * stride;
            for (sum, value) in self.light[start..start + stride].iter_mut().zip(values) {
                if *value != 0.0 && !sum.add_f32(*value) {
                    failed.get_or_insert((x, y));
                }
            }
        }
        failed
    }

    /// Zero light sums as long as these (empty without caustics): where a render keeps the
    /// light sums of its finished passes while it traces the next ones
    /// ([`Self::swap_light`]).
    pub fn zero_light(&self) -> Vec<FixedSum> {
        filled_on_huge_pages(FixedSum::ZERO, self.light.len())
    }

    /// Exchanges the light sums with `other` (as long: [`Self::zero_light`]). A render sets the
    /// sums of its finished passes aside this way while the light paths of the next ones are
    /// added, so that a pass abandoned halfway (Ctrl-C) leaves no trace in what it writes
    /// ([`crate::render`]).
    ///
    /// # Panics
    /// If `other` is not as long as the light sums.
    pub fn swap_light(&mut self, other: &mut Vec<FixedSum>) {
        assert_eq!(self.light.len(), other.len(), "light sums of another size");
        std::mem::swap(&mut self.light, other);
    }

    /// Adds `light`, sums of these light sums' window and layout (set aside by
    /// [`Self::swap_light`]), to the light sums. Errors name the first pixel whose sum
    /// overflows.
    ///
    /// # Panics
    /// If `light` is not as long as the light sums.
    pub fn add_light(&mut self, light: &[FixedSum]) -> Result<(), SumOverflow> {
        assert_eq!(self.light.len(), light.len(), "light sums of another size");
        let stride = self.light_stride();
        self.add_with(self.window, true, |pixel, slot| light[pixel * stride + slot])
    }

    /// Adds `other`, whose window must lie inside this one and whose layout and light sums
    /// must match (checked by the caller: parts of one render), except that light sums of S0
    /// alone add to full ones. Errors name the first pixel whose sum overflows.
    pub fn add(&mut self, other: &WindowSums) -> Result<(), SumOverflow> {
        assert_eq!(self.layout, other.layout, "parts of different layouts");
        assert!(self.light_stride() >= other.light_stride(), "adding full light sums to S0 alone");
        let stride = self.stride();
        self.add_with(other.window, false, |pixel, value| other.camera[pixel * stride + value])?;
        if other.has_light() {
            let light_stride = other.light_stride();
            let from: Vec<Option<usize>> =
                (0..self.light_stride()).map(|slot| other.light_slot(self.light_value_index(slot))).collect();
            self.add_with(other.window, true, |pixel, slot| {
                from[slot].map_or(FixedSum::ZERO, |k| other.light[pixel * light_stride + k])
            })?;
        }
        Ok(())
    }

    /// Adds to the camera sums (or the light sums, when `light`) of the pixels of `window`,
    /// which must lie inside this one, the values `value_of(pixel, value)`, pixels numbered
    /// row-major in `window`, values as the sums number them (light values by their slot,
    /// [`Self::light_value_index`]). Errors name the first pixel whose sum overflows.
    pub fn add_with(
        &mut self,
        window: PixelWindow,
        light: bool,
        value_of: impl Fn(usize, usize) -> FixedSum,
    ) -> Result<(), SumOverflow> {
        assert!(self.window.contains_window(&window), "a part outside the merged window");
        let stride = if light { self.light_stride() } else { self.stride() };
        let width = window.width() as usize;
        let target = if light { &mut self.light } else { &mut self.camera };
        for (row, y) in (window.y0..window.y1).enumerate() {
            let to = ((y - self.window.y0) as usize * self.window.width() as usize
                + (window.x0 - self.window.x0) as usize)
                * stride;
            for (column, pixel_sums) in target[to..to + width * stride].chunks_exact_mut(stride).enumerate() {
                let pixel = row * width + column;
                for (value, sum) in pixel_sums.iter_mut().enumerate() {
                    if !sum.add(value_of(pixel, value)) {
                        return Err(SumOverflow { x: window.x0 + column as u32, y });
                    }
                }
            }
        }
        Ok(())
    }

    /// The image these sums make with `samples` samples per pixel and `light_paths_per_pass`
    /// light paths per sample (pass), placed in a `display` = (width, height) image: per value,
    /// the camera sum over `samples`, plus, where any splat landed, the light sum over all the
    /// light paths. A function of the sums and counts alone, so the same sums give the same bits.
    pub fn film(&self, samples: u64, light_paths_per_pass: u64, display: (u32, u32)) -> Film {
        let stride = self.stride();
        let light_stride = self.light_stride();
        let light_slots: Vec<Option<usize>> = (0..stride).map(|index| self.light_slot(index)).collect();
        let components = self.layout.components();
        let colour = self.layout.colour_values();
        let n = samples as f64;
        let paths = samples as f64 * light_paths_per_pass as f64;
        let pixels = (0..self.window.pixels())
            .map(|index| {
                let camera = &self.camera[index * stride..(index + 1) * stride];
                let light = self.light.get(index * light_stride..(index + 1) * light_stride);
                let value = |i: usize| {
                    let mut mean = camera[i].mean(n) as f32;
                    if let (Some(light), Some(slot)) = (light, light_slots[i]) {
                        if !light[slot].is_zero() {
                            mean += light[slot].mean(paths) as f32;
                        }
                    }
                    mean
                };
                let xyz = |k: usize| match colour {
                    1 => Vec3::splat(value(k)),
                    _ => Vec3::new(value(3 * k), value(3 * k + 1), value(3 * k + 2)),
                };
                let stokes = |k: usize| if k < components { xyz(k) } else { Vec3::ZERO };
                PixelMeans {
                    xyz: xyz(0),
                    stokes_xyz: [stokes(1), stokes(2), stokes(3)],
                    bands: (colour * components..stride).map(value).collect(),
                }
            })
            .collect();
        Film::assemble(self.window.width(), self.window.height(), self.layout, pixels)
            .placed(self.window, display)
    }
}

/// A finished image: row-major, top row first.
#[derive(Debug, Clone, PartialEq)]
pub struct Film {
    width: u32,
    height: u32,
    /// Where the film's top-left pixel lies in the whole image (a crop's offset).
    origin: (u32, u32),
    /// Size of the whole image the film is a window of.
    display: (u32, u32),
    layout: FilmLayout,
    xyz: Vec<Vec3>,
    stokes_xyz: Vec<[Vec3; 3]>,
    bands: Vec<f32>,
}

/// One pixel's means, as [`Film::assemble`] takes them.
#[derive(Debug, Clone, Default)]
pub struct PixelMeans {
    /// Mean XYZ of S0.
    pub xyz: Vec3,
    /// Mean XYZ of S1, S2, S3 (zero when unpolarised).
    pub stokes_xyz: [Vec3; 3],
    /// Band means, component-major.
    pub bands: Vec<f32>,
}

impl Film {
    /// A film from per-pixel S0 XYZ values (or radiance in all three channels when
    /// `monochromatic_nm` is set), unpolarised, without bands. Panics if `xyz.len() !=
    /// width·height`.
    pub fn new(width: u32, height: u32, xyz: Vec<Vec3>, monochromatic_nm: Option<f32>) -> Self {
        assert_eq!(xyz.len(), width as usize * height as usize, "film size mismatch");
        let layout = FilmLayout { monochromatic_nm, ..FilmLayout::default() };
        Self {
            width,
            height,
            origin: (0, 0),
            display: (width, height),
            layout,
            xyz,
            stokes_xyz: Vec::new(),
            bands: Vec::new(),
        }
    }

    /// A film of `layout` from its pixels' means in row-major order. Panics if there are not
    /// `width·height` pixels.
    pub fn assemble(width: u32, height: u32, layout: FilmLayout, pixels: Vec<PixelMeans>) -> Self {
        assert_eq!(pixels.len(), width as usize * height as usize, "film size mismatch");
        let xyz = pixels.iter().map(|p| p.xyz).collect();
        let stokes_xyz =
            if layout.stokes { pixels.iter().map(|p| p.stokes_xyz).collect() } else { Vec::new() };
        let bands = pixels.into_iter().flat_map(|p| p.bands).collect();
        Self { width, height, origin: (0, 0), display: (width, height), layout, xyz, stokes_xyz, bands }
    }

    /// The same film as the `window` of a `display` = (width, height) image (a crop). Panics
    /// if the window's size is not the film's.
    pub fn placed(self, window: PixelWindow, display: (u32, u32)) -> Self {
        assert_eq!((window.width(), window.height()), (self.width, self.height), "window size mismatch");
        Self { origin: (window.x0, window.y0), display, ..self }
    }

    /// Where the film's top-left pixel lies in the whole image.
    pub fn origin(&self) -> (u32, u32) {
        self.origin
    }
    /// Size (width, height) of the whole image the film is a window of.
    pub fn display(&self) -> (u32, u32) {
        self.display
    }

    /// The first pixel (row-major) that is not finite in any value it holds (XYZ of S0–S3, band
    /// means) or in linear sRGB (the conversion can overflow a finite XYZ near f32's limit), if
    /// any. Checked in every build: a NaN would otherwise be silently black in the PNG preview.
    pub fn check_finite(&self) -> Result<(), NonFinitePixel> {
        let per_pixel = self.layout.band_values();
        let displayable = |xyz: Vec3| match self.layout.monochromatic_nm {
            Some(_) => xyz.is_finite(),
            None => xyz.is_finite() && xyz_to_linear_srgb(xyz).is_finite(),
        };
        let finite = |index: usize| {
            displayable(self.xyz[index])
                && self.stokes_xyz.get(index).is_none_or(|s| s.iter().all(|&v| displayable(v)))
                && (per_pixel == 0
                    || self.bands[index * per_pixel..(index + 1) * per_pixel].iter().all(|v| v.is_finite()))
        };
        match (0..self.xyz.len()).find(|&index| !finite(index)) {
            None => Ok(()),
            Some(index) => Err(NonFinitePixel {
                x: self.origin.0 + (index % self.width as usize) as u32,
                y: self.origin.1 + (index / self.width as usize) as u32,
                xyz: self.xyz[index],
            }),
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }
    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }
    /// What each pixel holds.
    pub fn layout(&self) -> &FilmLayout {
        &self.layout
    }
    /// Per-pixel CIE XYZ of S0 (monochromatic mode: radiance L in every channel).
    pub fn xyz(&self) -> &[Vec3] {
        &self.xyz
    }
    /// The wavelength (nm) of a monochromatic render.
    pub fn monochromatic_nm(&self) -> Option<f32> {
        self.layout.monochromatic_nm
    }
    /// Per-pixel XYZ of Stokes component `k` (0–3); `None` for S1–S3 of an unpolarised film.
    pub fn stokes_xyz(&self, k: usize) -> Option<Vec<Vec3>> {
        match k {
            0 => Some(self.xyz.clone()),
            1..=3 if self.layout.stokes => Some(self.stokes_xyz.iter().map(|s| s[k - 1]).collect()),
            _ => None,
        }
    }
    /// Per-pixel mean spectral radiance of Stokes component `k` in band `band`, if the film has
    /// bands (and that component).
    pub fn band(&self, k: usize, band: usize) -> Option<Vec<f32>> {
        let bands = self.layout.bands?;
        if k >= self.layout.components() || band >= bands.count {
            return None;
        }
        let per_pixel = self.layout.band_values();
        let offset = k * bands.count + band;
        Some(self.bands.chunks_exact(per_pixel).map(|values| values[offset]).collect())
    }
    /// Per-pixel linear sRGB (Rec. 709 primaries, D65 white) of S0. In monochromatic mode, the
    /// radiance in all three channels (a grey image).
    pub fn linear_srgb(&self) -> Vec<Vec3> {
        self.to_display(&self.xyz)
    }
    /// Per-pixel linear sRGB of Stokes component `k` (signed for S1–S3: the same linear map).
    pub fn stokes_srgb(&self, k: usize) -> Option<Vec<Vec3>> {
        self.stokes_xyz(k).map(|xyz| self.to_display(&xyz))
    }

    fn to_display(&self, xyz: &[Vec3]) -> Vec<Vec3> {
        match self.layout.monochromatic_nm {
            Some(_) => xyz.to_vec(),
            None => xyz.iter().map(|&v| xyz_to_linear_srgb(v)).collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::polarization::Stokes;
    use crate::spectrum::{SampledSpectrum, N_LAMBDA};

    #[test]
    fn bands_partition_their_range() {
        let bands = SpectralBands { count: 4, min_nm: 400.0, max_nm: 800.0 };
        assert_eq!(bands.band_of(400.0), Some(0));
        assert_eq!(bands.band_of(499.9), Some(0));
        assert_eq!(bands.band_of(500.0), Some(1));
        assert_eq!(bands.band_of(800.0), Some(3));
        assert_eq!(bands.band_of(399.0), None);
        assert_eq!(bands.center_nm(1), 550.0);
    }

    /// An equal-energy radiance of 1 has a band mean of 1 in every band, in expectation: the
    /// average over stratified wavelength samples converges to it.
    #[test]
    fn band_means_of_a_flat_spectrum_are_its_value() {
        let layout = FilmLayout {
            stokes: true,
            bands: Some(SpectralBands { count: 5, min_nm: 380.0, max_nm: 780.0 }),
            monochromatic_nm: None,
        };
        let window = PixelWindow::full(1, 1);
        let mut sums = WindowSums::new(window, layout, false);
        let samples = 4096;
        for i in 0..samples {
            let wavelengths = SampledWavelengths::sample_visible((i as f32 + 0.5) / samples as f32, N_LAMBDA);
            let light = Stokes::unpolarized(SampledSpectrum::splat(1.0));
            assert!(add_sample(sums.camera_mut(), &light, &wavelengths, &layout));
        }
        let film = sums.film(samples, 0, (1, 1));
        for band in 0..5 {
            let (s0, s1) = (film.band(0, band).unwrap()[0], film.band(1, band).unwrap()[0]);
            assert!((s0 - 1.0).abs() < 0.01, "band {band}: {s0}");
            assert_eq!(s1, 0.0, "S1 of unpolarised light");
        }
        let means = PixelMeans { xyz: film.xyz()[0], ..PixelMeans::default() };
        assert!((means.xyz.y - 1.0).abs() < 1e-3, "{}", means.xyz);
    }

    /// A monochromatic film sums its radiance L once per Stokes component (not XYZ = (L, L, L)),
    /// camera samples and splats alike, bands after; its image is (L, L, L) per component.
    #[test]
    fn a_monochromatic_pixel_holds_its_radiance_once_per_component() {
        let bands = SpectralBands { count: 2, min_nm: 500.0, max_nm: 600.0 };
        let layout = FilmLayout { stokes: true, bands: Some(bands), monochromatic_nm: Some(550.0) };
        assert_eq!((layout.values_per_pixel(), layout.luminance_index()), (4 + 8, 0));
        let plain = FilmLayout { monochromatic_nm: None, ..layout };
        assert_eq!((plain.values_per_pixel(), plain.luminance_index()), (12 + 8, 1));
        let wavelengths = SampledWavelengths::monochromatic(550.0);
        let light = Stokes { s: [2.0, 0.5, -0.25, 0.0].map(SampledSpectrum::splat) };
        let mut sums = WindowSums::new(PixelWindow::full(2, 1), layout, true);
        assert!(add_sample(
            &mut sums.camera_mut()[..layout.values_per_pixel()],
            &light,
            &wavelengths,
            &layout
        ));
        let mut splats = Splats::default();
        splats.add(1, &light, &wavelengths, &layout);
        assert_eq!(splats.luminance(0, &layout), (1, 2.0));
        assert_eq!(sums.add_splats(&splats, 2), None);
        // One sample per pixel, one light path: pixel 0 from the camera, pixel 1 from the splat.
        let film = sums.film(1, 1, (2, 1));
        for pixel in 0..2 {
            assert_eq!(film.xyz()[pixel], Vec3::splat(2.0), "pixel {pixel}");
            assert_eq!(film.stokes_xyz(1).unwrap()[pixel], Vec3::splat(0.5));
            assert_eq!(film.stokes_xyz(2).unwrap()[pixel], Vec3::splat(-0.25));
            // 550 nm lies in the second band, which holds the radiance itself.
            assert_eq!((film.band(0, 0).unwrap()[pixel], film.band(0, 1).unwrap()[pixel]), (0.0, 2.0));
            assert_eq!(film.band(1, 1).unwrap()[pixel], 0.5);
        }
    }

    /// Light sums of S0 alone (a polarised render whose splats are unpolarised): the same image
    /// and the same sums as full ones, a third (or with bands, fewer) of the values; added to
    /// full sums (a merge) they land on S0's values; their slots map to and from the full
    /// layout's values, bands included.
    #[test]
    fn light_sums_of_s0_alone_hold_the_same_values() {
        let bands = SpectralBands { count: 3, min_nm: 400.0, max_nm: 700.0 };
        let layout = FilmLayout { stokes: true, bands: Some(bands), monochromatic_nm: None };
        let window = PixelWindow::full(3, 2);
        let mut full = WindowSums::new(window, layout, true);
        let mut compact = WindowSums::with_light_layout(window, layout, layout.unpolarized());
        assert_eq!((full.light_stride(), compact.light_stride()), (12 + 12, 3 + 3));
        assert_eq!(compact.light().len(), 6 * 6);
        // Slots 0–2 are S0's XYZ (values 0–2), slots 3–5 S0's bands (values 12–14).
        assert_eq!(
            (0..6).map(|slot| compact.light_value_index(slot)).collect::<Vec<_>>(),
            [0, 1, 2, 12, 13, 14]
        );
        for index in 0..24 {
            let expected = match index {
                0..=2 => Some(index),
                12..=14 => Some(index - 9),
                _ => None,
            };
            assert_eq!(compact.light_slot(index), expected, "value {index}");
        }
        let wavelengths = SampledWavelengths::sample_visible(0.3, N_LAMBDA);
        let unpolarized =
            Stokes::unpolarized(SampledSpectrum { values: std::array::from_fn(|i| 1.0 + i as f32) });
        let (mut into_full, mut into_compact) = (Splats::default(), Splats::default());
        for pixel in [0, 4, 4, 5] {
            into_full.add(pixel, &unpolarized, &wavelengths, &layout);
            into_compact.add(pixel, &unpolarized, &wavelengths, &compact.light_layout);
        }
        assert_eq!(into_compact.values.len(), 4 * 6);
        assert_eq!(full.add_splats(&into_full, 3), None);
        assert_eq!(compact.add_splats(&into_compact, 3), None);
        assert!(compact == full, "S0 alone against full");
        assert!(full == compact, "full against S0 alone");
        let bits = |film: &Film| {
            let mut bits: Vec<u32> = film.xyz().iter().flat_map(|v| v.to_array().map(f32::to_bits)).collect();
            for k in 0..4 {
                bits.extend(film.stokes_xyz(k).unwrap().iter().flat_map(|v| v.to_array().map(f32::to_bits)));
                for band in 0..3 {
                    bits.extend(film.band(k, band).unwrap().iter().map(|v| v.to_bits()));
                }
            }
            bits
        };
        assert_eq!(bits(&compact.film(1, 4, (3, 2))), bits(&full.film(1, 4, (3, 2))));
        // A merge: S0-alone sums added to full ones.
        let mut merged = WindowSums::new(window, layout, true);
        merged.add(&compact).unwrap();
        assert!(merged == full);
        assert_eq!(merged.light(), full.light());
        // A different value is seen as one.
        let mut other = compact.clone();
        other.add_splats(&into_compact, 3);
        assert!(other != full);
    }

    /// A NaN or infinite pixel is an error naming its column and row (row-major, top first);
    /// it used to be written, and showed as black in the PNG.
    #[test]
    fn nan_pixels_are_named() {
        let mut xyz = vec![Vec3::splat(0.5); 6];
        let film = Film::new(3, 2, xyz.clone(), None);
        assert_eq!(film.check_finite(), Ok(()));
        xyz[4] = Vec3::new(0.1, f32::NAN, 0.2);
        let error = Film::new(3, 2, xyz.clone(), None).check_finite().expect_err("NaN");
        assert_eq!((error.x, error.y), (1, 1));
        assert!(error.to_string().contains("pixel (1, 1)"), "{error}");
        // A finite XYZ near f32's limit whose sRGB overflows is caught too.
        xyz[4] = Vec3::new(3e38, 0.0, 0.0);
        assert!(Film::new(3, 2, xyz, None).check_finite().is_err());
        // S1–S3 are checked as well as S0.
        let layout = FilmLayout { stokes: true, ..FilmLayout::default() };
        let mut pixels = vec![PixelMeans::default(); 6];
        pixels[5].stokes_xyz[2] = Vec3::new(0.0, f32::INFINITY, 0.0);
        let error = Film::assemble(3, 2, layout, pixels).check_finite().expect_err("S3");
        assert_eq!((error.x, error.y), (2, 1));
    }
}

//! The `polviz` figure: four panels (S0 preview, DoLP, AoLP, S3/S0) with titles, colour bars,
//! ticks, swatches for undefined pixels and a footer stating the source and the frame. The maps
//! and bars are written pixel by pixel into an RGB buffer; plotters draws the text and the
//! orientation glyphs on top of it with the embedded DejaVu Sans.

use anyhow::anyhow;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::colour::{self, Rgb, NO_LIGHT, UNPOLARIZED};
use crate::cli::plot::{register_font, FONT};

/// The Stokes components of one channel, per pixel, row-major, top row first.
pub struct StokesImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// S0, S1, S2, S3 of every pixel.
    pub components: [Vec<f32>; 4],
    /// Linear sRGB of each pixel for the preview panel (grey for a single wavelength).
    pub preview: Vec<[f32; 3]>,
    /// Title of the preview panel.
    pub preview_title: String,
    /// What the components are and where they come from (the first footer line).
    pub description: String,
}

/// How the figure is drawn.
pub struct Options {
    /// Below this degree of linear polarisation the angle is shown as [`UNPOLARIZED`].
    pub min_dolp: f32,
    /// Panels per row (1–4).
    pub columns: usize,
    /// Exposure of the preview, in stops.
    pub exposure_ev: f32,
}

/// The polarisation of one pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Polarisation {
    /// Degree of linear polarisation √(S1² + S2²)/S0.
    pub dolp: f32,
    /// Angle of linear polarisation ½·atan2(S2, S1), degrees in [−90, 90], counter-clockwise
    /// from the frame's x axis (image right).
    pub aolp_deg: f32,
    /// Circular part S3/S0 (> 0: the field turns clockwise for the viewer).
    pub circular: f32,
}

/// The polarisation of Stokes components `s`, or `None` where there is no light to speak of
/// (S0 not above `s0_floor`, or a component not finite).
pub fn polarisation(s: [f32; 4], s0_floor: f32) -> Option<Polarisation> {
    if !(s.iter().all(|v| v.is_finite()) && s[0] > s0_floor && s[0] > 0.0) {
        return None;
    }
    Some(Polarisation {
        dolp: s[1].hypot(s[2]) / s[0],
        aolp_deg: 0.5 * s[2].atan2(s[1]).to_degrees(),
        circular: s[3] / s[0],
    })
}

/// Pixels whose S0 is at most this are "no light": 10⁻⁴ of the brightest finite S0, below
/// which the ratios are rounding and noise.
pub fn s0_floor(s0: &[f32]) -> f32 {
    let brightest = s0.iter().copied().filter(|v| v.is_finite()).fold(0.0f32, f32::max);
    1e-4 * brightest
}

/// Labelled ticks of a colour bar: (value, label).
type Ticks = &'static [(f32, &'static str)];

/// Which map a panel shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Map {
    /// The S0 preview.
    Preview,
    /// Degree of linear polarisation.
    Dolp,
    /// Angle of linear polarisation.
    Aolp,
    /// Circular part.
    Circular,
}

impl Map {
    const ALL: [Map; 4] = [Map::Preview, Map::Dolp, Map::Aolp, Map::Circular];

    /// The colour bar's range and labelled ticks.
    fn scale(self) -> Option<(f32, f32, Ticks)> {
        match self {
            Map::Preview => None,
            Map::Dolp => {
                Some((0.0, 1.0, &[(0.0, "0"), (0.25, "0.25"), (0.5, "0.5"), (0.75, "0.75"), (1.0, "1")]))
            }
            Map::Aolp => Some((
                -90.0,
                90.0,
                &[(-90.0, "−90°"), (-45.0, "−45°"), (0.0, "0°"), (45.0, "45°"), (90.0, "90°")],
            )),
            Map::Circular => {
                Some((-1.0, 1.0, &[(-1.0, "−1"), (-0.5, "−0.5"), (0.0, "0"), (0.5, "+0.5"), (1.0, "+1")]))
            }
        }
    }

    /// The colour of a value on this map's scale.
    fn colour(self, value: f32) -> Rgb {
        match self {
            Map::Preview => colour::grey(value),
            Map::Dolp => colour::dolp_colour(value),
            Map::Aolp => colour::aolp_colour(value),
            Map::Circular => colour::circular_colour(value),
        }
    }

    /// The colour of a pixel of `image` on this map.
    fn pixel(self, image: &StokesImage, index: usize, floor: f32, options: &Options) -> Rgb {
        if self == Map::Preview {
            let scale = options.exposure_ev.exp2();
            return colour::srgb8(image.preview[index].map(|v| v * scale));
        }
        let s = [0, 1, 2, 3].map(|k| image.components[k][index]);
        match (self, polarisation(s, floor)) {
            (_, None) => NO_LIGHT,
            (Map::Aolp, Some(p)) if p.dolp < options.min_dolp => UNPOLARIZED,
            (Map::Dolp, Some(p)) => colour::dolp_colour(p.dolp),
            (Map::Aolp, Some(p)) => colour::aolp_colour(p.aolp_deg),
            (_, Some(p)) => colour::circular_colour(p.circular),
        }
    }
}

/// A rectangle in canvas pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rect {
    /// Left column.
    pub x: u32,
    /// Top row.
    pub y: u32,
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
}

/// Where one panel's parts are.
#[derive(Debug, Clone)]
pub struct PanelLayout {
    /// The map.
    pub map: Map,
    /// The top-left corner of the panel.
    pub origin: (u32, u32),
    /// The map image.
    pub image: Rect,
    /// The colour bar, if the map has one.
    pub bar: Option<Rect>,
    /// Swatches of the undefined-pixel greys, with their labels.
    pub swatches: Vec<(Rect, Rgb, String)>,
}

impl PanelLayout {
    /// The bar column that shows `value`.
    pub fn bar_column(&self, value: f32) -> Option<u32> {
        let (bar, (min, max, _)) = (self.bar?, self.map.scale()?);
        let t = ((value - min) / (max - min)).clamp(0.0, 1.0);
        Some(bar.x + ((t * bar.width as f32) as u32).min(bar.width - 1))
    }

    /// The value shown by bar column `column` (its centre).
    fn column_value(&self, column: u32) -> f32 {
        let (Some(bar), Some((min, max, _))) = (self.bar, self.map.scale()) else { return 0.0 };
        min + (max - min) * ((column - bar.x) as f32 + 0.5) / bar.width as f32
    }
}

/// A drawn figure: RGB bytes, row-major.
pub struct Canvas {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// 3 bytes per pixel.
    pub pixels: Vec<u8>,
    /// Where each panel's parts are.
    pub panels: Vec<PanelLayout>,
}

impl Canvas {
    /// The colour at (x, y).
    #[cfg(test)]
    pub fn at(&self, x: u32, y: u32) -> Rgb {
        let i = 3 * (y as usize * self.width as usize + x as usize);
        [self.pixels[i], self.pixels[i + 1], self.pixels[i + 2]]
    }

    fn set(&mut self, x: u32, y: u32, colour: Rgb) {
        let i = 3 * (y as usize * self.width as usize + x as usize);
        self.pixels[i..i + 3].copy_from_slice(&colour);
    }

    fn fill(&mut self, rect: Rect, colour: Rgb) {
        for y in rect.y..rect.y + rect.height {
            for x in rect.x..rect.x + rect.width {
                self.set(x, y, colour);
            }
        }
    }
}

const MARGIN: u32 = 18;
const TITLE_HEIGHT: u32 = 30;
const LEGEND_HEIGHT: u32 = 112;
const FOOTER_HEIGHT: u32 = 44;
const BAR_HEIGHT: u32 = 14;
/// Maps narrower than this are magnified by a whole factor, so that the legends fit.
const MIN_IMAGE_WIDTH: u32 = 320;
const TEXT: RGBColor = RGBColor(30, 30, 30);

/// Draws the figure of `image`.
pub fn draw(image: &StokesImage, options: &Options) -> anyhow::Result<Canvas> {
    let scale = MIN_IMAGE_WIDTH.div_ceil(image.width).max(1);
    let (image_width, image_height) = (image.width * scale, image.height * scale);
    let columns = options.columns.clamp(1, Map::ALL.len()) as u32;
    let rows = (Map::ALL.len() as u32).div_ceil(columns);
    let panel_width = image_width + 2 * MARGIN;
    let panel_height = TITLE_HEIGHT + image_height + LEGEND_HEIGHT;
    let (width, height) = (columns * panel_width, rows * panel_height + FOOTER_HEIGHT);
    if u64::from(width) * u64::from(height) > 200_000_000 {
        return Err(anyhow!("the figure would be {width}×{height} pixels; render a smaller image"));
    }
    let mut canvas =
        Canvas { width, height, pixels: vec![255; 3 * width as usize * height as usize], panels: Vec::new() };
    let floor = s0_floor(&image.components[0]);
    for (index, map) in Map::ALL.into_iter().enumerate() {
        let origin = ((index as u32 % columns) * panel_width, (index as u32 / columns) * panel_height);
        let layout = panel_layout(map, origin, (image_width, image_height), options);
        for y in 0..image_height {
            for x in 0..image_width {
                let source = (y / scale) as usize * image.width as usize + (x / scale) as usize;
                canvas.set(layout.image.x + x, layout.image.y + y, map.pixel(image, source, floor, options));
            }
        }
        if let Some(bar) = layout.bar {
            for column in bar.x..bar.x + bar.width {
                let colour = map.colour(layout.column_value(column));
                canvas.fill(Rect { x: column, y: bar.y, width: 1, height: bar.height }, colour);
            }
        }
        for (rect, colour, _) in &layout.swatches {
            canvas.fill(*rect, *colour);
        }
        canvas.panels.push(layout);
    }
    draw_text(&mut canvas, image, options).map_err(|e| anyhow!("drawing the legends: {e}"))?;
    Ok(canvas)
}

fn panel_layout(map: Map, origin: (u32, u32), image_size: (u32, u32), options: &Options) -> PanelLayout {
    let image =
        Rect { x: origin.0 + MARGIN, y: origin.1 + TITLE_HEIGHT, width: image_size.0, height: image_size.1 };
    let legend_top = image.y + image.height + 10;
    let bar = map.scale().map(|_| Rect { x: image.x, y: legend_top, width: image.width, height: BAR_HEIGHT });
    let swatch =
        |slot: u32| Rect { x: image.x + slot * (image.width / 2), y: legend_top + 80, width: 12, height: 12 };
    let swatches = match map {
        Map::Preview => Vec::new(),
        Map::Aolp => vec![
            (swatch(0), UNPOLARIZED, format!("DoLP < {}", options.min_dolp)),
            (swatch(1), NO_LIGHT, "no light".into()),
        ],
        Map::Dolp | Map::Circular => vec![(swatch(0), NO_LIGHT, "no light (S0 ≈ 0)".into())],
    };
    PanelLayout { map, origin, image, bar, swatches }
}

/// Titles, tick marks and labels, captions, swatch labels, AoLP glyphs and the footer.
fn draw_text(canvas: &mut Canvas, image: &StokesImage, options: &Options) -> Result<(), String> {
    register_font().map_err(|e| e.to_string())?;
    let (width, height) = (canvas.width, canvas.height);
    let panels = canvas.panels.clone();
    let root = BitMapBackend::with_buffer(&mut canvas.pixels, (width, height)).into_drawing_area();
    let error = |e: DrawingAreaErrorKind<_>| e.to_string();
    let text = |size: u32| (FONT, size).into_font().color(&TEXT);
    let centred = |size: u32| text(size).pos(Pos::new(HPos::Center, VPos::Top));
    for panel in &panels {
        let (title, caption) = match panel.map {
            Map::Preview => (
                image.preview_title.clone(),
                format!("as the render's preview, exposure {:+} EV", options.exposure_ev),
            ),
            Map::Dolp => {
                ("DoLP = √(S1² + S2²) / S0".into(), "0 unpolarised … 1 fully linearly polarised".into())
            }
            Map::Aolp => (
                "AoLP = ½·atan2(S2, S1)".into(),
                "field orientation, counter-clockwise from image right".into(),
            ),
            Map::Circular => {
                ("circular part S3 / S0".into(), "+ : field turns clockwise for the viewer".into())
            }
        };
        root.draw_text(&title, &text(17), (panel.image.x as i32, panel.origin.1 as i32 + 7))
            .map_err(error)?;
        let legend_top = (panel.image.y + panel.image.height + 10) as i32;
        root.draw_text(&caption, &text(13), (panel.image.x as i32, legend_top + 59)).map_err(error)?;
        for (rect, _, label) in &panel.swatches {
            root.draw_text(label, &text(13), ((rect.x + rect.width + 5) as i32, rect.y as i32 - 1))
                .map_err(error)?;
        }
        let (Some(bar), Some((_, _, ticks))) = (panel.bar, panel.map.scale()) else { continue };
        for &(value, label) in ticks {
            let column = panel.bar_column(value).unwrap_or(bar.x) as i32;
            let below = (bar.y + bar.height) as i32;
            root.draw(&PathElement::new([(column, below), (column, below + 5)], TEXT.stroke_width(1)))
                .map_err(error)?;
            root.draw_text(label, &centred(13), (column, below + 7)).map_err(error)?;
            if panel.map == Map::Aolp {
                // A short stroke along the field orientation (image y points down).
                let (dx, dy) = (8.0 * value.to_radians().cos(), -8.0 * value.to_radians().sin());
                let centre = (column, below + 31);
                let ends = [
                    (centre.0 - dx.round() as i32, centre.1 - dy.round() as i32),
                    (centre.0 + dx.round() as i32, centre.1 + dy.round() as i32),
                ];
                root.draw(&PathElement::new(ends, TEXT.stroke_width(2))).map_err(error)?;
            }
        }
    }
    let footer = (height - FOOTER_HEIGHT) as i32;
    root.draw_text(&image.description, &text(13), (MARGIN as i32, footer + 4)).map_err(error)?;
    root.draw_text(
        "Stokes frame: x = image right, y = image up, seen by the viewer (the camera); AoLP counter-clockwise from x",
        &text(13),
        (MARGIN as i32, footer + 22),
    )
    .map_err(error)?;
    root.present().map_err(error)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four pixels of known polarisation: (S0, S1, S2, S3) =
    /// (1, 1, 0, 0): DoLP 1, AoLP 0°, S3/S0 0;
    /// (2, 0, 1, 0): DoLP 0.5, AoLP 45°, S3/S0 0;
    /// (1, 0, 0, −0.5): DoLP 0 (AoLP undefined), S3/S0 −0.5;
    /// (0, 0, 0, 0): no light.
    fn synthetic() -> StokesImage {
        StokesImage {
            width: 4,
            height: 1,
            components: [
                vec![1.0, 2.0, 1.0, 0.0],
                vec![1.0, 0.0, 0.0, 0.0],
                vec![0.0, 1.0, 0.0, 0.0],
                vec![0.0, 0.0, -0.5, 0.0],
            ],
            preview: vec![[1.0; 3], [0.5; 3], [0.2; 3], [0.0; 3]],
            preview_title: "S0".into(),
            description: "synthetic".into(),
        }
    }

    #[test]
    fn polarisation_of_known_stokes_vectors() {
        let p = polarisation([2.0, 0.0, 1.0, 0.0], 0.0).unwrap();
        assert_eq!((p.dolp, p.aolp_deg, p.circular), (0.5, 45.0, 0.0));
        let p = polarisation([1.0, -1.0, 0.0, 0.0], 0.0).unwrap();
        assert_eq!(p.aolp_deg, 90.0, "S1 = −S0: polarised along image up");
        let p = polarisation([1.0, 0.0, -0.6, 0.8], 0.0).unwrap();
        assert!((p.aolp_deg + 45.0).abs() < 1e-5 && (p.circular - 0.8).abs() < 1e-6);
        assert_eq!(polarisation([0.0, 0.0, 0.0, 0.0], 0.0), None);
        assert_eq!(polarisation([1e-6, 0.0, 0.0, 0.0], 1e-5), None, "below the floor");
        assert_eq!(polarisation([1.0, f32::NAN, 0.0, 0.0], 0.0), None);
    }

    /// Every known pixel value is drawn in the colour that the legend's bar shows at that value
    /// (within the bar's one-column quantisation), and undefined pixels in their swatch's grey.
    #[test]
    fn known_pixels_map_to_the_legends_colours() {
        let options = Options { min_dolp: 0.02, columns: 4, exposure_ev: 0.0 };
        let canvas = draw(&synthetic(), &options).unwrap();
        let panel = |map: Map| canvas.panels.iter().find(|p| p.map == map).unwrap();
        let scale = panel(Map::Dolp).image.width / 4;
        assert_eq!(scale, 80, "a 4-pixel-wide image is magnified to 320 pixels");
        // The centre of source pixel `i` in a panel's map.
        let map_colour = |map: Map, i: u32| {
            let p = panel(map);
            canvas.at(p.image.x + i * scale + scale / 2, p.image.y + scale / 2)
        };
        let bar_colour = |map: Map, value: f32| {
            let p = panel(map);
            let bar = p.bar.unwrap();
            canvas.at(p.bar_column(value).unwrap(), bar.y + bar.height / 2)
        };
        let close = |a: Rgb, b: Rgb| (0..3).all(|c| (i32::from(a[c]) - i32::from(b[c])).abs() <= 2);
        let swatch_colour = |map: Map, label: &str| {
            let (rect, _, _) = panel(map).swatches.iter().find(|(_, _, l)| l.starts_with(label)).unwrap();
            canvas.at(rect.x + rect.width / 2, rect.y + rect.height / 2)
        };
        let expected = [
            (Map::Dolp, 0, 1.0),
            (Map::Dolp, 1, 0.5),
            (Map::Dolp, 2, 0.0),
            (Map::Aolp, 0, 0.0),
            (Map::Aolp, 1, 45.0),
            (Map::Circular, 0, 0.0),
            (Map::Circular, 2, -0.5),
        ];
        for (map, pixel, value) in expected {
            let drawn = map_colour(map, pixel);
            assert_eq!(drawn, map.colour(value), "{map:?} pixel {pixel}");
            assert!(
                close(drawn, bar_colour(map, value)),
                "{map:?} {value}: {drawn:?} vs bar {:?}",
                bar_colour(map, value)
            );
        }
        assert_eq!(map_colour(Map::Dolp, 0), [250, 238, 150], "DoLP 1: the ramp's pale-yellow end");
        assert_eq!(map_colour(Map::Aolp, 2), swatch_colour(Map::Aolp, "DoLP <"), "AoLP of unpolarised light");
        for map in [Map::Dolp, Map::Aolp, Map::Circular] {
            assert_eq!(map_colour(map, 3), swatch_colour(map, "no light"), "{map:?}");
            assert_eq!(map_colour(map, 3), NO_LIGHT);
        }
        assert_eq!(map_colour(Map::Preview, 0), [255; 3]);
        assert_eq!(map_colour(Map::Preview, 3), [0; 3]);
    }

    /// Two columns put the four panels in a 2 × 2 grid.
    #[test]
    fn columns_make_a_grid() {
        let options = Options { min_dolp: 0.02, columns: 2, exposure_ev: 0.0 };
        let canvas = draw(&synthetic(), &options).unwrap();
        let origins: Vec<(u32, u32)> = canvas.panels.iter().map(|p| p.origin).collect();
        let (w, h) = (origins[1].0, origins[2].1);
        assert_eq!(origins, vec![(0, 0), (w, 0), (0, h), (w, h)]);
    }
}

//! Line charts for the `fresnel` and `glass` commands, through plotters: SVG or PNG by the file
//! extension, panels side by side or in a grid, a grid and labelled vertical markers. Nothing is
//! written over the curves: the legend sits above or right of the plot area (its swatches drawn
//! in the style of their curves), marker labels in rows above it.
//! Text uses the DejaVu Sans font embedded by the `dejavu` crate, so no system font is needed
//! (`polviz` draws its labels with it too).

use std::ops::Range;
use std::path::Path;
use std::sync::Once;

use anyhow::anyhow;
use plotters::coord::ranged1d::{KeyPointHint, NoDefaultFormatting, Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor;
use plotters::style::{FontDesc, FontStyle};

use super::CliError;
use prisma::output::file::{check_destination, text_into, Destination, Sink};
use prisma::output::OutputError;

/// How a series is drawn; its legend swatch is drawn the same way.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// A solid line.
    Line,
    /// A dashed line ([`DASH`] pixels on, [`GAP`] off).
    Dashed,
    /// Small circles at the data points (reference data).
    Points,
}

/// Length in pixels of a dash of [`Style::Dashed`], in the plot and in its legend swatch.
pub const DASH: u32 = 8;
/// Length in pixels of the gap between two dashes of [`Style::Dashed`].
pub const GAP: u32 = 5;
/// Radius in pixels of the circles of [`Style::Points`].
const POINT_RADIUS: u32 = 2;
/// Length in pixels of a legend swatch: three dashes and two gaps, so that a dashed swatch
/// reads as dashed.
const SWATCH: u32 = 3 * DASH + 2 * GAP;
/// Height in pixels of a legend line.
const LEGEND_LINE: u32 = 18;

/// One curve.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend text; empty: the series has no legend entry of its own (see [`Panel::key`]).
    pub label: String,
    /// (x, y) points; a non-finite y breaks the line there.
    pub points: Vec<(f64, f64)>,
    /// Colour.
    pub color: RGBColor,
    /// Drawing style.
    pub style: Style,
}

/// A labelled vertical line.
#[derive(Debug, Clone)]
pub struct Marker {
    /// Where on the x axis.
    pub x: f64,
    /// Its label, written above the plot area so that it never covers a curve.
    pub label: String,
}

/// Where a panel's legend goes: outside the plot area, so that it covers no curve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LegendPlace {
    /// Rows between the title and the plot area (a few short entries).
    Above,
    /// A column right of the plot area, as wide as its longest line (many entries).
    Right,
}

/// A legend line that is not a series of its own: a swatch and its text, or a heading.
#[derive(Debug, Clone, PartialEq)]
pub struct LegendEntry {
    /// Text.
    pub label: String,
    /// The swatch's colour.
    pub color: RGBColor,
    /// The swatch, drawn as a series of this style would be; none for a heading.
    pub style: Option<Style>,
}

/// One chart.
#[derive(Debug, Clone)]
pub struct Panel {
    /// Title above the chart.
    pub title: String,
    /// A smaller line under the title (conventions, sources); none when empty.
    pub subtitle: String,
    /// x axis label, with units.
    pub x_label: String,
    /// y axis label, with units.
    pub y_label: String,
    /// x range.
    pub x_range: (f64, f64),
    /// y range.
    pub y_range: (f64, f64),
    /// Labelled y ticks (e.g. every 45° on a phase axis); plotters' own choice when empty.
    pub y_ticks: Vec<f64>,
    /// Curves.
    pub series: Vec<Series>,
    /// Vertical markers.
    pub markers: Vec<Marker>,
    /// Where the legend goes.
    pub legend: LegendPlace,
    /// Legend lines after those of the labelled series (a key of colours and styles shared by
    /// several series).
    pub key: Vec<LegendEntry>,
}

/// Paul Tol's "muted" qualitative scheme (<https://personal.sron.nl/~pault/>): nine colours that
/// stay distinct from each other on white and for the common colour-vision deficiencies,
/// ordered so that neighbours differ in hue and lightness.
const QUALITATIVE: [RGBColor; 9] = [
    RGBColor(0x33, 0x22, 0x88), // indigo
    RGBColor(0xCC, 0x66, 0x77), // rose
    RGBColor(0x11, 0x77, 0x33), // green
    RGBColor(0x88, 0xCC, 0xEE), // cyan
    RGBColor(0x88, 0x22, 0x55), // wine
    RGBColor(0xDD, 0xCC, 0x77), // sand
    RGBColor(0x44, 0xAA, 0x99), // teal
    RGBColor(0xAA, 0x44, 0x99), // purple
    RGBColor(0x99, 0x99, 0x33), // olive
];

/// `count` distinct colours, one per curve or group: [`QUALITATIVE`] when it has enough, else
/// `count` hues evenly spaced around the colour wheel, alternately dark and light, so that no
/// two curves ever share a colour.
pub fn palette(count: usize) -> Vec<RGBColor> {
    if count <= QUALITATIVE.len() {
        return QUALITATIVE[..count].to_vec();
    }
    (0..count)
        .map(|index| {
            let hue = index as f64 / count as f64;
            let lightness = if index % 2 == 0 { 0.38 } else { 0.55 };
            let (r, g, b) = HSLColor(hue, 0.75, lightness).rgb();
            RGBColor(r, g, b)
        })
        .collect()
}

/// The family name under which the embedded DejaVu Sans is registered.
pub const FONT: &str = "sans-serif";

/// Registers the embedded DejaVu Sans as [`FONT`] (once per process); every text drawn by
/// plotters in prisma uses it.
pub fn register_font() -> anyhow::Result<()> {
    static REGISTER: Once = Once::new();
    let mut result = Ok(());
    REGISTER.call_once(|| {
        result = plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular())
            .map_err(|_| anyhow!("the embedded DejaVu Sans font cannot be loaded"));
    });
    result
}

/// The file format of a plot, from its name.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlotFormat {
    /// Scalable vector graphics.
    Svg,
    /// A PNG bitmap.
    Png,
}

/// Checks a plot path before any work: a usable destination named `.svg` or `.png` (bad
/// input, exit code 2, otherwise). A special file (/dev/null) gets SVG.
pub fn check_plot_path(path: &Path) -> Result<PlotFormat, CliError> {
    let destination = check_destination(path).map_err(|e| CliError::Input(e.into()))?;
    let extension = path.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
    match (extension.as_str(), destination) {
        ("svg", _) | (_, Destination::Special(_)) => Ok(PlotFormat::Svg),
        ("png", _) => Ok(PlotFormat::Png),
        _ => Err(CliError::Input(anyhow!("{}: the plot file must end in .svg or .png", path.display()))),
    }
}

/// Draws `panels` side by side, each `panel_size` pixels, as `format` into `sink` (errors name
/// `path`).
pub fn encode_chart(
    sink: &mut Sink,
    path: &Path,
    format: PlotFormat,
    panels: &[Panel],
    panel_size: (u32, u32),
) -> Result<(), OutputError> {
    encode_chart_grid(sink, path, format, panels, panels.len(), panel_size)
}

/// Draws `panels` row by row, `columns` to a row, each `panel_size` pixels, as `format` into
/// `sink` (errors name `path`). The drawing is made in memory first, then written.
pub fn encode_chart_grid(
    sink: &mut Sink,
    path: &Path,
    format: PlotFormat,
    panels: &[Panel],
    columns: usize,
    panel_size: (u32, u32),
) -> Result<(), OutputError> {
    let columns = columns.clamp(1, panels.len().max(1));
    let rows = panels.len().div_ceil(columns).max(1);
    let size = (panel_size.0 * columns as u32, panel_size.1 * rows as u32);
    encode_figure(sink, path, format, size, Figure::Grid { panels, columns })
}

/// What a figure file holds: a grid of chart panels, or a colour strip over its panel.
enum Figure<'a> {
    /// Panels row by row, `columns` to a row.
    Grid { panels: &'a [Panel], columns: usize },
    /// A [`ColorStrip`].
    Strip(&'a ColorStrip),
}

impl Figure<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        match self {
            Figure::Grid { panels, columns } => draw(root, panels, *columns),
            Figure::Strip(strip) => draw_strip(root, strip),
        }
    }
}

/// Draws `figure` at `size` pixels as `format` into `sink` (errors name `path`): in memory
/// first, then written.
fn encode_figure(
    sink: &mut Sink,
    path: &Path,
    format: PlotFormat,
    size: (u32, u32),
    figure: Figure,
) -> Result<(), OutputError> {
    let codec = |message: String| OutputError::Codec { path: path.display().to_string(), message };
    register_font().map_err(|e| codec(e.to_string()))?;
    match format {
        PlotFormat::Svg => {
            let mut svg = String::new();
            {
                let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
                figure.draw(&root).and_then(|()| root.present().map_err(|e| e.to_string())).map_err(codec)?;
            }
            text_into(sink, path, &svg)
        }
        PlotFormat::Png => {
            let mut pixels = vec![0u8; size.0 as usize * size.1 as usize * 3];
            {
                let root = BitMapBackend::with_buffer(&mut pixels, size).into_drawing_area();
                figure.draw(&root).and_then(|()| root.present().map_err(|e| e.to_string())).map_err(codec)?;
            }
            encode_png_compact(sink, path, &pixels, size)
        }
    }
}

/// Encodes 8-bit RGB `pixels` of `size` as a PNG into `sink` (errors name `path`), compressed
/// hard: figures are written once and read many times, and their flat areas compress well (a
/// 2 × 2 Fresnel plot: 79 KB instead of 374 KB with the fast setting).
pub fn encode_png_compact(
    sink: &mut Sink,
    path: &Path,
    pixels: &[u8],
    size: (u32, u32),
) -> Result<(), OutputError> {
    use image::codecs::png::{CompressionType, FilterType, PngEncoder};
    use image::ImageEncoder as _;
    PngEncoder::new_with_quality(sink, CompressionType::Best, FilterType::Adaptive)
        .write_image(pixels, size.0, size.1, image::ExtendedColorType::Rgb8)
        .map_err(|e| match e {
            image::ImageError::IoError(source) => {
                OutputError::Io { path: path.display().to_string(), source }
            }
            e => OutputError::Codec { path: path.display().to_string(), message: e.to_string() },
        })
}

/// A strip of colours against x (an interference colour chart): each cell runs from its x to
/// the next cell's (the last to the end of `x_range`), drawn above `panel`, whose plot area it
/// shares in x, so that a colour lines up with the curve under it.
#[derive(Debug, Clone)]
pub struct ColorStrip {
    /// Title above the strip.
    pub title: String,
    /// A smaller line under the title; none when empty.
    pub subtitle: String,
    /// (x where the cell starts, its colour), in increasing x.
    pub cells: Vec<(f64, RGBColor)>,
    /// The chart drawn under the strip, over the same x range.
    pub panel: Panel,
}

/// Height in pixels of the title, subtitle and strip of a [`ColorStrip`] figure.
const STRIP_HEIGHT: u32 = 230;

/// Draws `strip` (the colours on top, its panel under them), `width` pixels wide and
/// `panel_height` more for the panel, as `format` into `sink` (errors name `path`).
pub fn encode_color_strip(
    sink: &mut Sink,
    path: &Path,
    format: PlotFormat,
    strip: &ColorStrip,
    width: u32,
    panel_height: u32,
) -> Result<(), OutputError> {
    let size = (width, STRIP_HEIGHT + panel_height);
    encode_figure(sink, path, format, size, Figure::Strip(strip))
}

fn draw_strip<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, strip: &ColorStrip) -> Result<(), String> {
    let failed = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(failed)?;
    let (top, bottom) = root.split_vertically(STRIP_HEIGHT);
    let titled = top.margin(8, 0, 0, 0).titled(&strip.title, (FONT, 20)).map_err(failed)?;
    let area = if strip.subtitle.is_empty() {
        titled
    } else {
        titled.titled(&strip.subtitle, (FONT, 13).into_font().color(&RGBColor(70, 70, 70))).map_err(failed)?
    };
    let (x_start, x_end) = strip.panel.x_range;
    // The same margins and label areas as a panel's, so that the strip's x matches the plot's.
    let mut chart = ChartBuilder::on(&area)
        .margin(CHART_MARGIN)
        .margin_top(6)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(x_start..x_end, 0.0..1.0)
        .map_err(failed)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .disable_y_axis()
        .x_desc(&strip.panel.x_label)
        .x_label_formatter(&|value: &f64| format!("{value:.0}"))
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 15))
        .draw()
        .map_err(failed)?;
    let ends = strip.cells.iter().skip(1).map(|&(x, _)| x).chain(std::iter::once(x_end));
    chart
        .draw_series(
            strip
                .cells
                .iter()
                .zip(ends)
                .map(|(&(x, color), end)| Rectangle::new([(x, 0.0), (end, 1.0)], color.filled())),
        )
        .map_err(failed)?;
    draw_panel(&bottom, &strip.panel).map_err(failed)
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    panels: &[Panel],
    columns: usize,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let areas = root.split_evenly((panels.len().div_ceil(columns).max(1), columns));
    for (area, panel) in areas.iter().zip(panels) {
        draw_panel(area, panel).map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// Space in pixels around a chart, and the widths of its axis label areas.
const CHART_MARGIN: u32 = 14;
const Y_LABEL_AREA: u32 = 60;
const X_LABEL_AREA: u32 = 44;
/// Height in pixels of a row of marker labels above the plot area.
const MARKER_ROW: u32 = 16;

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let titled = area.margin(8, 0, 0, 0).titled(&panel.title, (FONT, 20))?;
    let area = if panel.subtitle.is_empty() {
        titled
    } else {
        titled.titled(&panel.subtitle, (FONT, 13).into_font().color(&RGBColor(70, 70, 70)))?
    };
    let entries = legend_entries(panel);
    let label_font = (FONT, 13).into_font();
    let (area, legend_area) = match panel.legend {
        LegendPlace::Above => {
            let rows = legend_rows(&area, &entries, &label_font)?;
            let height = rows.len() as u32 * LEGEND_LINE + 4;
            let (legend, chart) = area.split_vertically(height);
            (chart, legend)
        }
        LegendPlace::Right => {
            let mut width = 0;
            for entry in &entries {
                width = width.max(legend_entry_width(&area, entry, &label_font)?);
            }
            let (chart, legend) = area.split_horizontally(area.dim_in_pixel().0.saturating_sub(width + 24));
            (chart, legend)
        }
    };

    // Marker labels go in rows above the plot area, so that they never cover a curve.
    let marker_font = (FONT, 13).into_font().color(&RGBColor(90, 90, 90));
    let plot_left = CHART_MARGIN + Y_LABEL_AREA;
    let plot_width = area.dim_in_pixel().0.saturating_sub(plot_left + CHART_MARGIN).max(1);
    let span = panel.x_range.1 - panel.x_range.0;
    let to_pixel = |x: f64| plot_left as i32 + ((x - panel.x_range.0) / span * f64::from(plot_width)) as i32;
    let mut labels = Vec::new();
    for marker in &panel.markers {
        labels.push((to_pixel(marker.x), area.estimate_text_size(&marker.label, &marker_font)?.0 as i32));
    }
    let placed = place_labels(&labels, area.dim_in_pixel().0 as i32);
    let marker_rows = placed.iter().map(|&(row, _)| row as u32 + 1).max().unwrap_or(0);

    let y_axis = YAxis { inner: (panel.y_range.0..panel.y_range.1).into(), ticks: panel.y_ticks.clone() };
    let mut chart = ChartBuilder::on(&area)
        .margin(CHART_MARGIN)
        .margin_top(6 + marker_rows * MARKER_ROW)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(panel.x_range.0..panel.x_range.1, y_axis)?;
    let whole_numbers = |value: &f64| format!("{value:.0}");
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(&panel.x_label)
        .y_desc(&panel.y_label)
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 15))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(200, 200, 200));
    if !panel.y_ticks.is_empty() {
        mesh.y_label_formatter(&whole_numbers);
    }
    // Wavelengths and thicknesses in nm read better without a ".0" on every tick.
    if panel.x_range.1 - panel.x_range.0 >= 100.0 {
        mesh.x_label_formatter(&whole_numbers);
    }
    mesh.draw()?;
    let grey = RGBColor(90, 90, 90);
    let (_, plot_y) = chart.plotting_area().get_pixel_range();
    // Label positions come from the layout estimated above; plotters' may differ by a pixel.
    let area_y = area.get_base_pixel().1;
    for (marker, &(row, left)) in panel.markers.iter().zip(&placed) {
        chart.draw_series(DashedLineSeries::new(
            [(marker.x, panel.y_range.0), (marker.x, panel.y_range.1)],
            6,
            4,
            grey.stroke_width(1),
        ))?;
        let bottom = plot_y.start - area_y - 3 - ((marker_rows - 1 - row as u32) * MARKER_ROW) as i32;
        let style = marker_font
            .clone()
            .pos(text_anchor::Pos::new(text_anchor::HPos::Left, text_anchor::VPos::Bottom));
        area.draw_text(&marker.label, &style, (left, bottom))?;
    }
    for series in &panel.series {
        let color = series.color;
        // A non-finite y breaks the line: each run between breaks is drawn on its own.
        for run in series.points.split(|point| !point.1.is_finite()).filter(|run| !run.is_empty()) {
            let points = run.iter().copied();
            match series.style {
                Style::Line => {
                    chart.draw_series(LineSeries::new(points, color.stroke_width(2)))?;
                }
                Style::Dashed => {
                    chart.draw_series(DashedLineSeries::new(points, DASH, GAP, color.stroke_width(2)))?;
                }
                Style::Points => {
                    chart.draw_series(
                        points.map(|point| Circle::new(point, POINT_RADIUS, color.stroke_width(1))),
                    )?;
                }
            }
        }
    }
    match panel.legend {
        LegendPlace::Above => {
            let rows = legend_rows(&legend_area, &entries, &label_font)?;
            for (index, row) in rows.iter().enumerate() {
                let y = (index as u32 * LEGEND_LINE + LEGEND_LINE / 2) as i32;
                for &(x, entry) in row {
                    draw_legend_entry(&legend_area, entry, (plot_left as i32 + x, y), &label_font)?;
                }
            }
        }
        LegendPlace::Right => {
            let top = plot_y.start - legend_area.get_base_pixel().1;
            for (index, entry) in entries.iter().enumerate() {
                let y = top + (index as u32 * LEGEND_LINE + LEGEND_LINE / 2) as i32;
                draw_legend_entry(&legend_area, entry, (8, y), &label_font)?;
            }
        }
    }
    Ok(())
}

/// Places labels of the given (centre, width) in pixels in rows, none overlapping another and
/// all within `0..area_width`: each in the lowest row where it fits centred on its marker, or
/// ending at it (first, when the next marker is too close to centre on), or starting at it.
/// Returns (row, left edge) per label.
fn place_labels(labels: &[(i32, i32)], area_width: i32) -> Vec<(usize, i32)> {
    const SPACE: i32 = 8;
    let mut placed: Vec<(usize, i32, i32)> = Vec::new();
    for (index, &(centre, width)) in labels.iter().enumerate() {
        let crowded = labels
            .iter()
            .enumerate()
            .any(|(other, &(x, _))| other != index && x > centre && x - centre < width / 2 + SPACE);
        let centred = centre - width / 2;
        let before = centre - SPACE / 2 - width;
        let after = centre + SPACE / 2;
        let candidates = if crowded { [before, centred, after] } else { [centred, after, before] };
        let fits = |row: usize, left: i32| {
            left >= 0
                && left + width <= area_width
                && placed
                    .iter()
                    .all(|&(r, l, rr)| r != row || left + width + SPACE <= l || rr + SPACE <= left)
        };
        let (row, left) = (0..=labels.len())
            .find_map(|row| candidates.iter().find(|&&left| fits(row, left)).map(|&left| (row, left)))
            .unwrap_or((placed.len(), centred.clamp(0, (area_width - width).max(0))));
        placed.push((row, left, left + width));
    }
    placed.into_iter().map(|(row, left, _)| (row, left)).collect()
}

/// The legend lines of a panel: its labelled series, then its key.
fn legend_entries(panel: &Panel) -> Vec<LegendEntry> {
    panel
        .series
        .iter()
        .filter(|series| !series.label.is_empty())
        .map(|series| LegendEntry {
            label: series.label.clone(),
            color: series.color,
            style: Some(series.style),
        })
        .chain(panel.key.iter().cloned())
        .collect()
}

/// One row of a legend above a plot: (x offset from the plot area's left edge, entry).
type LegendRow<'a> = Vec<(i32, &'a LegendEntry)>;

/// Lays `entries` out in rows across `area`, starting under the plot area's left edge: each
/// row lists (x offset from that edge, entry).
fn legend_rows<'a, DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &'a [LegendEntry],
    font: &FontDesc,
) -> Result<Vec<LegendRow<'a>>, DrawingAreaErrorKind<DB::ErrorType>> {
    let available = area.dim_in_pixel().0.saturating_sub(CHART_MARGIN * 2 + Y_LABEL_AREA) as i32;
    let mut rows: Vec<LegendRow> = vec![Vec::new()];
    let mut x = 0;
    for entry in entries {
        let width = legend_entry_width(area, entry, font)? as i32;
        if x > 0 && x + width > available {
            rows.push(Vec::new());
            x = 0;
        }
        rows.last_mut().expect("one row at least").push((x, entry));
        x += width + 24;
    }
    Ok(rows)
}

/// The width in pixels of one legend line: its swatch, a space and its text.
fn legend_entry_width<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entry: &LegendEntry,
    font: &FontDesc,
) -> Result<u32, DrawingAreaErrorKind<DB::ErrorType>> {
    let text = area.estimate_text_size(&entry.label, &TextStyle::from(font.clone()))?.0;
    Ok(if entry.style.is_some() { SWATCH + 6 + text } else { text })
}

/// Draws one legend line with its left end at `at` (y: the line's middle): the swatch as its
/// series is drawn, then the text; a heading is text alone, in grey.
fn draw_legend_entry<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entry: &LegendEntry,
    at: (i32, i32),
    font: &FontDesc,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let (x, y) = at;
    let text_style = |color: RGBColor| {
        font.clone()
            .color(&color)
            .pos(text_anchor::Pos::new(text_anchor::HPos::Left, text_anchor::VPos::Center))
    };
    let Some(style) = entry.style else {
        if entry.label.is_empty() {
            return Ok(());
        }
        return area.draw_text(&entry.label, &text_style(RGBColor(70, 70, 70)), (x, y));
    };
    for segment in swatch_segments(style) {
        match segment {
            SwatchPart::Line(from, to) => {
                area.draw(&PathElement::new([(x + from, y), (x + to, y)], entry.color.stroke_width(2)))?
            }
            SwatchPart::Circle(centre) => {
                area.draw(&Circle::new((x + centre, y), POINT_RADIUS, entry.color.stroke_width(1)))?
            }
        }
    }
    area.draw_text(&entry.label, &text_style(BLACK), (x + (SWATCH + 6) as i32, y))
}

/// A piece of a legend swatch, in pixels from the swatch's left end.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum SwatchPart {
    /// A horizontal stroke from one x to another.
    Line(i32, i32),
    /// A circle of [`POINT_RADIUS`] at this x.
    Circle(i32),
}

/// The swatch of a style, drawn as its series are: one stroke; dashes of [`DASH`] with gaps of
/// [`GAP`], as `DashedLineSeries` draws them; or three circles.
fn swatch_segments(style: Style) -> Vec<SwatchPart> {
    let length = SWATCH as i32;
    match style {
        Style::Line => vec![SwatchPart::Line(0, length)],
        Style::Dashed => (0..)
            .map(|k| k * (DASH + GAP) as i32)
            .take_while(|&start| start < length)
            .map(|start| SwatchPart::Line(start, (start + DASH as i32).min(length)))
            .collect(),
        Style::Points => [1, 3, 5].iter().map(|&sixth| SwatchPart::Circle(length * sixth / 6)).collect(),
    }
}

/// A y axis that places its ticks where plotters would, or at the given values.
struct YAxis {
    inner: RangedCoordf64,
    /// Bold, labelled ticks; empty: plotters' own ticks and light lines.
    ticks: Vec<f64>,
}

impl Ranged for YAxis {
    type FormatOption = NoDefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        self.inner.map(value, limit)
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        match (self.ticks.is_empty(), hint.weight().allow_light_points()) {
            (true, _) => self.inner.key_points(hint),
            (false, true) => Vec::new(),
            (false, false) => self.ticks.clone(),
        }
    }

    fn range(&self) -> Range<f64> {
        self.inner.range()
    }
}

impl ValueFormatter<f64> for YAxis {
    fn format(value: &f64) -> String {
        RangedCoordf64::format(value)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// No two curves share a colour, however many there are (the fixture plots had η = 1.0 and
    /// η = 2.4 both black when eight colours were cycled over sixteen curves).
    #[test]
    fn palette_never_repeats_a_colour() {
        for count in 1..=40 {
            let colors = palette(count);
            assert_eq!(colors.len(), count);
            for (i, a) in colors.iter().enumerate() {
                for b in &colors[i + 1..] {
                    assert_ne!(a, b, "{count} colours");
                }
            }
        }
        assert_eq!(palette(9), QUALITATIVE.to_vec());
    }

    /// A dashed series' legend swatch is dashed like the series (DASH on, GAP off, as plotters'
    /// `DashedLineSeries` draws it), not a solid stroke; a line's swatch is one stroke; points are
    /// circles.
    #[test]
    fn legend_swatches_are_drawn_in_their_series_style() {
        let dashed = swatch_segments(Style::Dashed);
        assert!(dashed.len() >= 2, "{dashed:?}");
        for pair in dashed.windows(2) {
            let (SwatchPart::Line(a0, a1), SwatchPart::Line(b0, _)) = (pair[0], pair[1]) else {
                panic!("{dashed:?}")
            };
            assert_eq!((a1 - a0, b0 - a1), (DASH as i32, GAP as i32));
        }
        assert_eq!(swatch_segments(Style::Line), vec![SwatchPart::Line(0, SWATCH as i32)]);
        assert!(swatch_segments(Style::Points).iter().all(|part| matches!(part, SwatchPart::Circle(_))));
    }

    /// N-BK7 from inside: Brewster's angle 33.4° and the critical angle 41.3° are 48 px apart on
    /// a 550 px axis, closer than their labels are wide. The labels share a row, one ending and one
    /// starting at its line, without overlapping; a label near the edge stays inside the panel.
    #[test]
    fn marker_labels_never_overlap() {
        let labels = [(280, 96), (328, 90)];
        let placed = place_labels(&labels, 640);
        assert_eq!(placed.iter().map(|&(row, _)| row).collect::<Vec<_>>(), [0, 0]);
        assert!(placed[0].1 + labels[0].1 <= labels[0].0, "the first ends left of its line");
        assert!(placed[1].1 >= labels[1].0, "the second starts right of its line");
        assert!(placed[0].1 + labels[0].1 < placed[1].1);
        // Three labels on one spot: three rows.
        let stacked = place_labels(&[(300, 80), (300, 80), (300, 80)], 640);
        assert_eq!(stacked.iter().map(|&(row, _)| row).collect::<Vec<_>>(), [0, 1, 2]);
        let edge = place_labels(&[(630, 160)], 640);
        assert!(edge[0].1 >= 0 && edge[0].1 + 160 <= 640, "{edge:?}");
    }
}

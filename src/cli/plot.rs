//! Line charts for the `fresnel` and `glass` commands, through plotters: SVG or PNG by the file
//! extension, panels side by side or in a grid, a legend, a grid and labelled vertical markers.
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
use plotters::style::FontStyle;

use super::CliError;
use prisma::output::file::{check_destination, text_into, Destination, Sink};
use prisma::output::OutputError;

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// A solid line.
    Line,
    /// A dashed line.
    Dashed,
    /// Small circles at the data points (reference data).
    Points,
}

/// One curve.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend text.
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
    /// Its label.
    pub label: String,
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
    /// Where the legend goes (somewhere the curves leave empty).
    pub legend: SeriesLabelPosition,
}

/// A palette that reads well on white and for common colour-vision deficiencies (Okabe & Ito 2008).
pub const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
    RGBColor(150, 150, 150),
];

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
    let codec = |message: String| OutputError::Codec { path: path.display().to_string(), message };
    register_font().map_err(|e| codec(e.to_string()))?;
    let columns = columns.clamp(1, panels.len().max(1));
    let rows = panels.len().div_ceil(columns).max(1);
    let size = (panel_size.0 * columns as u32, panel_size.1 * rows as u32);
    match format {
        PlotFormat::Svg => {
            let mut svg = String::new();
            {
                let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
                draw(&root, panels, columns)
                    .and_then(|()| root.present().map_err(|e| e.to_string()))
                    .map_err(codec)?;
            }
            text_into(sink, path, &svg)
        }
        PlotFormat::Png => {
            let mut pixels = vec![0u8; size.0 as usize * size.1 as usize * 3];
            {
                let root = BitMapBackend::with_buffer(&mut pixels, size).into_drawing_area();
                draw(&root, panels, columns)
                    .and_then(|()| root.present().map_err(|e| e.to_string()))
                    .map_err(codec)?;
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
    let y_axis = YAxis { inner: (panel.y_range.0..panel.y_range.1).into(), ticks: panel.y_ticks.clone() };
    let mut chart = ChartBuilder::on(&area)
        .margin(14)
        .margin_top(4)
        .x_label_area_size(44)
        .y_label_area_size(60)
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
    mesh.draw()?;
    for (index, marker) in panel.markers.iter().enumerate() {
        let grey = RGBColor(90, 90, 90);
        chart.draw_series(DashedLineSeries::new(
            [(marker.x, panel.y_range.0), (marker.x, panel.y_range.1)],
            6,
            4,
            grey.stroke_width(1),
        ))?;
        // Staggered so that labels of nearby markers do not overlap.
        let y = panel.y_range.0 + (0.97 - 0.06 * index as f64) * (panel.y_range.1 - panel.y_range.0);
        chart.draw_series(std::iter::once(Text::new(
            marker.label.clone(),
            (marker.x, y),
            (FONT, 13).into_font().color(&grey).pos(plotters::style::text_anchor::Pos::new(
                plotters::style::text_anchor::HPos::Right,
                plotters::style::text_anchor::VPos::Top,
            )),
        )))?;
    }
    for series in &panel.series {
        let color = series.color;
        // A non-finite y breaks the line: each run between breaks is drawn on its own, and
        // the first carries the legend entry.
        let mut labelled = false;
        for run in series.points.split(|point| !point.1.is_finite()).filter(|run| !run.is_empty()) {
            let points = run.iter().copied();
            let drawn = match series.style {
                Style::Line => chart.draw_series(LineSeries::new(points, color.stroke_width(2)))?,
                Style::Dashed => {
                    chart.draw_series(DashedLineSeries::new(points, 8, 5, color.stroke_width(2)))?
                }
                Style::Points => {
                    chart.draw_series(points.map(|point| Circle::new(point, 2, color.stroke_width(1))))?
                }
            };
            if !labelled {
                labelled = true;
                drawn
                    .label(&series.label)
                    .legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], color.stroke_width(2)));
            }
        }
    }
    chart
        .configure_series_labels()
        .position(panel.legend.clone())
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(180, 180, 180))
        .label_font((FONT, 13))
        .draw()?;
    Ok(())
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

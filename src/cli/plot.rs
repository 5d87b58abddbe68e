//! Line charts for the `fresnel` and `glass` commands, through plotters: SVG or PNG by the file
//! extension, side-by-side panels, a legend, a grid and labelled vertical markers. Text uses the
//! DejaVu Sans font embedded by the `dejavu` crate, so no system font is needed.

use std::path::Path;
use std::sync::Once;

use anyhow::anyhow;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;

use super::CliError;
use prisma::output::file::{check_destination, text_into, Destination, Sink};
use prisma::output::png::encode_png_bytes;
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
    /// (x, y) points.
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
    /// x axis label, with units.
    pub x_label: String,
    /// y axis label, with units.
    pub y_label: String,
    /// x range.
    pub x_range: (f64, f64),
    /// y range.
    pub y_range: (f64, f64),
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

const FONT: &str = "sans-serif";

fn register_font() -> anyhow::Result<()> {
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
/// `path`). The drawing is made in memory first, then written.
pub fn encode_chart(
    sink: &mut Sink,
    path: &Path,
    format: PlotFormat,
    panels: &[Panel],
    panel_size: (u32, u32),
) -> Result<(), OutputError> {
    let codec = |message: String| OutputError::Codec { path: path.display().to_string(), message };
    register_font().map_err(|e| codec(e.to_string()))?;
    let size = (panel_size.0 * panels.len().max(1) as u32, panel_size.1);
    match format {
        PlotFormat::Svg => {
            let mut svg = String::new();
            {
                let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
                draw(&root, panels)
                    .and_then(|()| root.present().map_err(|e| e.to_string()))
                    .map_err(codec)?;
            }
            text_into(sink, path, &svg)
        }
        PlotFormat::Png => {
            let mut pixels = vec![0u8; size.0 as usize * size.1 as usize * 3];
            {
                let root = BitMapBackend::with_buffer(&mut pixels, size).into_drawing_area();
                draw(&root, panels)
                    .and_then(|()| root.present().map_err(|e| e.to_string()))
                    .map_err(codec)?;
            }
            encode_png_bytes(sink, path, size.0, size.1, &pixels)
        }
    }
}

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, panels: &[Panel]) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let areas = root.split_evenly((1, panels.len().max(1)));
    for (area, panel) in areas.iter().zip(panels) {
        draw_panel(area, panel).map_err(|e| e.to_string())?;
    }
    Ok(())
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, (FONT, 20))
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(60)
        .build_cartesian_2d(panel.x_range.0..panel.x_range.1, panel.y_range.0..panel.y_range.1)?;
    chart
        .configure_mesh()
        .x_desc(&panel.x_label)
        .y_desc(&panel.y_label)
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 15))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(200, 200, 200))
        .draw()?;
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
        let drawn =
            match series.style {
                Style::Line => chart
                    .draw_series(LineSeries::new(series.points.iter().copied(), color.stroke_width(2)))?,
                Style::Dashed => chart.draw_series(DashedLineSeries::new(
                    series.points.iter().copied(),
                    8,
                    5,
                    color.stroke_width(2),
                ))?,
                Style::Points => chart
                    .draw_series(series.points.iter().map(|&p| Circle::new(p, 2, color.stroke_width(1))))?,
            };
        drawn
            .label(&series.label)
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 18, y)], color.stroke_width(2)));
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

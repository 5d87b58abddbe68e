//! `prisma fresnel`: Fresnel reflectance curves (Rs, Rp, R against the angle of incidence, from
//! outside and from inside) and the phases of r_s and r_p with their difference δ, as CSV and
//! plots, and plots of Mitsuba fixtures with prisma's curves overlaid; the curves of a coated
//! interface (`--coating`, [`coating`]) and the interference colour chart of a free-standing
//! film (`--film-colours`, [`film`]), both by the transfer-matrix method of
//! [`prisma::optics::thin_film`] (issue 41).

mod coating;
mod curves;
mod film;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Context};
use clap::Args;
use num_complex::Complex32;

use plotters::style::RGBColor;

use super::plot::{
    check_plot_path, encode_chart, encode_chart_grid, encode_color_strip, palette, LegendEntry, LegendPlace,
    Marker, Panel, PlotFormat, Series, Style,
};
use super::{output_error, say, CliError};
use coating::Against;
use curves::Reflection;
use prisma::optics::catalogue;
use prisma::optics::conductor::fresnel_conductor;
use prisma::optics::fresnel::fresnel_dielectric_amplitudes;
use prisma::optics::{fresnel_dielectric, metals, Ior};
use prisma::output::file::{check_destination, check_not_inputs, text_into, Outputs, Sink};
use prisma::output::OutputError;

/// The phase convention, as the plots' subtitles and the CSV header state it.
const PHASE_CONVENTION: &str =
    "fields E·exp(+iωt) as in Mitsuba; Hecht's signs (r_p = −r_s at 0°); δ > 0: p leads s";

/// Arguments of `prisma fresnel`.
#[derive(Debug, Args)]
pub struct FresnelArgs {
    /// The interface: a number (1.5), a named glass (N-BK7), `cauchy:A,B,C` (λ in µm),
    /// `sellmeier:B1,B2,B3,C1,C2,C3` (C in µm²), a metal (Ag, Al, Au, Cu) or a complex index
    /// `n+ki` (e.g. 0.05+4.2i).
    #[arg(
        long,
        value_name = "SPEC",
        required_unless_present = "fixture",
        conflicts_with = "fixture",
        allow_negative_numbers = true
    )]
    ior: Option<String>,
    /// Wavelength in nm at which a dispersive IOR or a metal is evaluated: 200–2000, and for a
    /// metal within its tabulated data (about 290–1000 nm).
    #[arg(long, value_name = "NM", default_value_t = 587.56, allow_negative_numbers = true)]
    wavelength: f32,
    /// Write the curves as CSV: angle in degrees; Rs, Rp, R from outside and (dielectrics) from
    /// inside; then the phases arg r_s, arg r_p and δ = arg r_p − arg r_s in degrees, in
    /// (−180, 180] (a negative real coefficient reads 180), from each side; then the
    /// interface's index, wavelength and name in every row (no comment lines, so pandas and
    /// spreadsheets read the file as it is). Phase convention: see `--plot`.
    #[arg(short, long, value_name = "curves.csv")]
    output: Option<PathBuf>,
    /// Plot the curves (.svg or .png): the reflectances, and under them the phases arg r_s,
    /// arg r_p and δ = arg r_p − arg r_s in degrees (the phase jump of r_p at Brewster's angle,
    /// the phases of total internal reflection from inside, a metal's principal angle where
    /// δ = 90°). Phase convention: fields E·e^{+iωt} as in Mitsuba 3 (an absorbing medium has
    /// index n − ik, and a positive phase leads), amplitudes with Hecht's signs (r_p = −r_s at
    /// normal incidence, so δ = 180° there).
    #[arg(long, value_name = "curves.svg|png")]
    plot: Option<PathBuf>,
    /// Plot a Mitsuba fixture from tests/fixtures/ with prisma's curves overlaid, and print the
    /// largest difference.
    #[arg(long, value_name = "FILE.csv")]
    fixture: Option<PathBuf>,
    /// Coat the `--ior` interface with coherent layers, listed from the incident (vacuum) side,
    /// comma-separated, each INDEX:THICKNESS_NM (thickness 0–10000 nm, at most 64 layers).
    /// INDEX is a number, n+ki, a glass or a metal, as `--ior` takes them, evaluated at each
    /// wavelength: "1.38:99.64" is a quarter-wave MgF₂ layer at 550 nm. The plot shows Rs, Rp,
    /// R (and the uncoated R), Ts, Tp, T and the phases of r_s, r_p; the CSV has the angle or
    /// wavelength, rs, rp, r, ts, tp, t, phase_rs_deg, phase_rp_deg, psi_deg, delta_deg
    /// (ellipsometric ψ and Δ = arg r_p − arg r_s, same phase convention) and r_bare.
    #[arg(long, value_name = "INDEX:NM,...", conflicts_with = "fixture", allow_hyphen_values = true)]
    coating: Option<String>,
    /// What a coating's curves are drawn against: `angle` (0–90° in 0.25° steps, at
    /// `--wavelength`) or `wavelength` (360–830 nm in 1 nm steps, at `--angle`).
    #[arg(long, value_enum, value_name = "AXIS", default_value_t = Against::Angle)]
    against: Against,
    /// Angle of incidence in degrees (0–90) for `--against wavelength` and `--film-colours`.
    #[arg(long, value_name = "DEG", default_value_t = 0.0, allow_negative_numbers = true)]
    angle: f64,
    /// The interference colour chart of a free-standing film of the `--ior` index in vacuum
    /// (a soap film: `--ior 1.333`), seen in reflection at `--angle` under D65: a strip of the
    /// reflected colour against thickness 0–1500 nm, over R at 450, 550 and 650 nm and the
    /// luminous reflectance Y. The CSV has thickness_nm, X, Y, Z and linear sRGB R, G, B (a
    /// perfect white reflector has Y = 1); the strip is shown brighter (its factor is in the
    /// subtitle), clipped to the sRGB gamut.
    #[arg(long, conflicts_with_all = ["coating", "fixture"])]
    film_colours: bool,
}

/// The interface whose curves are drawn.
enum Interface {
    /// A dielectric of relative index n (to vacuum).
    Dielectric { n: f32, label: String },
    /// A conductor of complex index n + ik.
    Conductor { eta: Complex32, label: String },
}

/// The curves of one interface on a grid of angles of incidence.
struct Table {
    angles_deg: Vec<f64>,
    /// Light from the exterior (vacuum).
    outside: Vec<Reflection>,
    /// Light from the interior of a dielectric; empty for a conductor.
    inside: Vec<Reflection>,
}

impl Table {
    fn new(interface: &Interface) -> Self {
        let angles_deg: Vec<f64> = (0..=360).map(|i| f64::from(i) * 0.25).collect();
        let (outside, inside) = match interface {
            Interface::Dielectric { n, .. } => (
                angles_deg.iter().map(|&a| curves::dielectric(a, *n, false)).collect(),
                angles_deg.iter().map(|&a| curves::dielectric(a, *n, true)).collect(),
            ),
            Interface::Conductor { eta, .. } => {
                (angles_deg.iter().map(|&a| curves::conductor(a, *eta)).collect(), Vec::new())
            }
        };
        Self { angles_deg, outside, inside }
    }

    /// The table as CSV: one header line, then a row per angle ending in the interface's index,
    /// the wavelength and its name (metadata in columns, not `#` lines, so that pandas and
    /// spreadsheets read the file as it is). The phase convention is in `--help` and the plot.
    fn csv(&self, interface: &Interface, wavelength_nm: f32) -> String {
        let mut csv = String::new();
        let reflectances =
            |row: &Reflection| format!("{},{},{}", row.reflectance_s, row.reflectance_p, row.reflectance);
        let phases = |row: &Reflection| format!("{},{},{}", row.phase_s_deg, row.phase_p_deg, row.delta_deg);
        match interface {
            Interface::Dielectric { n, label } => {
                let metadata = format!("{n},{wavelength_nm},{}", csv_field(label));
                let _ = writeln!(
                    csv,
                    "angle_deg,rs_outside,rp_outside,r_outside,rs_inside,rp_inside,r_inside,\
                     phase_s_outside_deg,phase_p_outside_deg,delta_outside_deg,\
                     phase_s_inside_deg,phase_p_inside_deg,delta_inside_deg,n,wavelength_nm,interface"
                );
                for ((angle, out), inn) in self.angles_deg.iter().zip(&self.outside).zip(&self.inside) {
                    let _ = writeln!(
                        csv,
                        "{angle},{},{},{},{},{metadata}",
                        reflectances(out),
                        reflectances(inn),
                        phases(out),
                        phases(inn)
                    );
                }
            }
            Interface::Conductor { eta, label } => {
                let metadata = format!("{},{},{wavelength_nm},{}", eta.re, eta.im, csv_field(label));
                let _ = writeln!(
                    csv,
                    "angle_deg,rs_outside,rp_outside,r_outside,phase_s_deg,phase_p_deg,delta_deg,n,k,wavelength_nm,interface"
                );
                for (angle, row) in self.angles_deg.iter().zip(&self.outside) {
                    let _ = writeln!(csv, "{angle},{},{},{metadata}", reflectances(row), phases(row));
                }
            }
        }
        csv
    }
}

/// Runs `prisma fresnel`.
pub fn run(args: &FresnelArgs) -> Result<(), CliError> {
    // Every output is checked before any work.
    let plot_format = args.plot.as_deref().map(check_plot_path).transpose()?;
    if let Some(path) = &args.output {
        check_destination(path).map_err(|e| CliError::Input(e.into()))?;
    }
    if let Some(fixture) = &args.fixture {
        let outputs = [("-o", args.output.as_deref()), ("--plot", args.plot.as_deref())];
        let outputs = outputs.into_iter().filter_map(|(flag, path)| Some((flag, path?)));
        check_not_inputs(outputs, &[(fixture.as_path(), "the fixture being plotted")])
            .map_err(|e| CliError::Input(e.into()))?;
        return run_fixture(fixture, args.plot.as_deref());
    }
    let spec = args.ior.as_deref().unwrap_or_default();
    if !(args.wavelength.is_finite() && (200.0..=2000.0).contains(&args.wavelength)) {
        return Err(CliError::Input(anyhow!("--wavelength must be in 200–2000 nm, got {}", args.wavelength)));
    }
    if !(args.angle.is_finite() && (0.0..=90.0).contains(&args.angle)) {
        return Err(CliError::Input(anyhow!("--angle must be in 0–90 degrees, got {}", args.angle)));
    }
    if args.coating.is_none() && args.against != Against::Angle {
        return Err(CliError::Input(anyhow!("--against wavelength draws a coating: add --coating")));
    }
    if args.film_colours {
        return run_film(args, spec, plot_format);
    }
    if let Some(coating) = &args.coating {
        return run_coating(args, spec, coating, plot_format);
    }
    let interface = parse_spec(spec, args.wavelength, "--ior").map_err(CliError::Input)?;
    let table = Table::new(&interface);
    let csv = table.csv(&interface, args.wavelength);
    write_outputs(args, &csv, plot_format, |sink, path, format| {
        let panels = curve_panels(&interface, &table, args.wavelength);
        // Reflectances on the first row, phases under them.
        let columns = panels.len() / 2;
        encode_chart_grid(sink, path, format, &panels, columns, (640, 480))
    })
}

/// Writes `csv` to `-o` (or prints it when there is neither `-o` nor `--plot`) and the plot
/// `draw` makes to `--plot`, both or neither.
fn write_outputs(
    args: &FresnelArgs,
    csv: &str,
    plot_format: Option<PlotFormat>,
    draw: impl FnOnce(&mut Sink, &Path, PlotFormat) -> Result<(), OutputError>,
) -> Result<(), CliError> {
    if args.output.is_none() && args.plot.is_none() {
        say!("{}", csv.trim_end());
    }
    let mut outputs = Outputs::new();
    if let Some(path) = &args.output {
        outputs
            .stage(path, |sink| text_into(sink, path, csv))
            .map_err(|e| output_error(e, "writing the CSV"))?;
    }
    if let (Some(path), Some(format)) = (&args.plot, plot_format) {
        outputs
            .stage(path, |sink| draw(sink, path, format))
            .map_err(|e| output_error(e, "writing the plot"))?;
    }
    outputs.commit().map_err(|e| output_error(e, "writing the outputs"))?;
    for path in args.output.iter().chain(&args.plot) {
        say!("wrote {}", path.display());
    }
    Ok(())
}

/// `prisma fresnel --coating`: the stack's curves against angle or wavelength.
fn run_coating(
    args: &FresnelArgs,
    substrate: &str,
    coating: &str,
    plot_format: Option<PlotFormat>,
) -> Result<(), CliError> {
    let layers = coating::parse_coating(coating).map_err(CliError::Input)?;
    // Every index is resolved, at every wavelength, before anything is written.
    let rows = coating::table(substrate, &layers, args.against, f64::from(args.wavelength), args.angle)
        .map_err(CliError::Input)?;
    let csv = coating::csv(&rows, args.against);
    write_outputs(args, &csv, plot_format, |sink, path, format| {
        let place = match args.against {
            Against::Angle => format!("at {} nm", args.wavelength),
            Against::Wavelength => format!("at θi = {}°", args.angle),
        };
        let title = format!("vacuum → layers {coating} (index:nm) → {substrate}, {place}");
        let panels = coating::panels(&rows, args.against, &title);
        encode_chart_grid(sink, path, format, &panels, panels.len(), (640, 520))
    })
}

/// `prisma fresnel --film-colours`: the interference colour chart of a free-standing film.
fn run_film(args: &FresnelArgs, spec: &str, plot_format: Option<PlotFormat>) -> Result<(), CliError> {
    let index_per_nm = (360..=830)
        .map(|lambda| coating::index_at(spec, f64::from(lambda), "--ior"))
        .collect::<anyhow::Result<Vec<_>>>()
        .map_err(CliError::Input)?;
    let cos_theta_i = args.angle.to_radians().cos().clamp(0.0, 1.0);
    let colours = film::chart(&index_per_nm, cos_theta_i);
    let csv = film::csv(&colours);
    write_outputs(args, &csv, plot_format, |sink, path, format| {
        let strip = film::strip(&colours, &index_per_nm, spec, args.angle, cos_theta_i);
        encode_color_strip(sink, path, format, &strip, 1400, 420)
    })
}

/// `text` as one CSV field: quoted when it holds a comma or a quote.
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_owned()
    }
}

/// The reflectance panels (outside, and inside for a dielectric), then the phase panels in the
/// same order.
fn curve_panels(interface: &Interface, table: &Table, wavelength_nm: f32) -> Vec<Panel> {
    let angles = &table.angles_deg;
    let colors = palette(3);
    let reflectance_series = |rows: &[Reflection]| -> Vec<Series> {
        let curve =
            |value: fn(&Reflection) -> f64| angles.iter().copied().zip(rows.iter().map(value)).collect();
        vec![
            Series {
                label: "Rs (s, TE)".into(),
                points: curve(|row| row.reflectance_s),
                color: colors[0],
                style: Style::Dashed,
            },
            Series {
                label: "Rp (p, TM)".into(),
                points: curve(|row| row.reflectance_p),
                color: colors[1],
                style: Style::Dashed,
            },
            Series {
                label: "R unpolarised".into(),
                points: curve(|row| row.reflectance),
                color: colors[2],
                style: Style::Line,
            },
        ]
    };
    let phase_series = |rows: &[Reflection]| -> Vec<Series> {
        let curve = |value: fn(&Reflection) -> f64| curves::phase_points(angles, rows.iter().map(value));
        vec![
            Series {
                label: "arg r_s".into(),
                points: curve(|row| row.phase_s_deg),
                color: colors[0],
                style: Style::Dashed,
            },
            Series {
                label: "arg r_p".into(),
                points: curve(|row| row.phase_p_deg),
                color: colors[1],
                style: Style::Dashed,
            },
            Series {
                label: "δ = arg r_p − arg r_s".into(),
                points: curve(|row| row.delta_deg),
                color: colors[2],
                style: Style::Line,
            },
        ]
    };
    let reflectance_panel = |title: String, series: Vec<Series>, markers: Vec<Marker>| Panel {
        title,
        subtitle: String::new(),
        x_label: "angle of incidence θi (degrees)".into(),
        y_label: "reflectance".into(),
        x_range: (0.0, 90.0),
        y_range: (0.0, 1.0),
        y_ticks: Vec::new(),
        series,
        markers,
        legend: LegendPlace::Above,
        key: Vec::new(),
    };
    let phase_panel = |title: String, series: Vec<Series>, markers: Vec<Marker>| Panel {
        title,
        subtitle: PHASE_CONVENTION.into(),
        x_label: "angle of incidence θi (degrees)".into(),
        y_label: "phase (degrees)".into(),
        x_range: (0.0, 90.0),
        y_range: (-190.0, 190.0),
        y_ticks: (-4..=4).map(|k| f64::from(k) * 45.0).collect(),
        series,
        markers,
        legend: LegendPlace::Above,
        key: Vec::new(),
    };
    match interface {
        Interface::Dielectric { n, label } => {
            let n = f64::from(*n);
            let brewster_out = n.atan().to_degrees();
            let brewster_in = (1.0 / n).atan().to_degrees();
            let mut markers_in =
                vec![Marker { x: brewster_in, label: format!("Brewster {brewster_in:.2}°") }];
            if n > 1.0 {
                let critical = (1.0 / n).asin().to_degrees();
                markers_in.push(Marker { x: critical, label: format!("critical {critical:.2}°") });
            }
            let mut markers_out =
                vec![Marker { x: brewster_out, label: format!("Brewster {brewster_out:.2}°") }];
            if n < 1.0 {
                let critical = n.asin().to_degrees();
                markers_out.push(Marker { x: critical, label: format!("critical {critical:.2}°") });
            }
            vec![
                reflectance_panel(
                    format!("vacuum → {label} (n = {n:.4} at {wavelength_nm} nm)"),
                    reflectance_series(&table.outside),
                    markers_out.clone(),
                ),
                reflectance_panel(
                    format!("{label} → vacuum (from inside)"),
                    reflectance_series(&table.inside),
                    markers_in.clone(),
                ),
                phase_panel(
                    format!("phases of r, vacuum → {label}"),
                    phase_series(&table.outside),
                    markers_out,
                ),
                phase_panel(
                    format!("phases of r, {label} → vacuum (TIR past critical)"),
                    phase_series(&table.inside),
                    markers_in,
                ),
            ]
        }
        Interface::Conductor { eta, label } => {
            let markers: Vec<Marker> = curves::principal_angle(angles, &table.outside)
                .map(|angle| Marker { x: angle, label: format!("principal {angle:.2}° (δ = 90°)") })
                .into_iter()
                .collect();
            vec![
                reflectance_panel(
                    format!(
                        "vacuum → {label} (n + ik = {:.3} + {:.3}i at {wavelength_nm} nm)",
                        eta.re, eta.im
                    ),
                    reflectance_series(&table.outside),
                    markers.clone(),
                ),
                phase_panel(format!("phases of r, vacuum → {label}"), phase_series(&table.outside), markers),
            ]
        }
    }
}

/// Parses an interface SPEC at `wavelength_nm`; errors name `flag`, the option that gave it
/// (`--ior`, or "the index" of a `--coating` layer, whose error names the layer around it).
fn parse_spec(spec: &str, wavelength_nm: f32, flag: &str) -> anyhow::Result<Interface> {
    let spec = spec.trim();
    let numbers = |list: &str, count: usize, what: &str| -> anyhow::Result<Vec<f32>> {
        let values: Result<Vec<f32>, _> = list.split(',').map(|v| v.trim().parse::<f32>()).collect();
        match values {
            Ok(v) if v.len() == count && v.iter().all(|x| x.is_finite()) => Ok(v),
            _ => bail!("{flag} {what}: expected {count} comma-separated finite numbers, got \"{list}\""),
        }
    };
    let dielectric = |ior: Ior, label: String| -> anyhow::Result<Interface> {
        ior.validate().map_err(|e| anyhow!("{flag} {spec}: {e}"))?;
        Ok(Interface::Dielectric { n: ior.eval(wavelength_nm), label })
    };
    if let Ok(n) = spec.parse::<f32>() {
        if !(n.is_finite() && n > 0.0) {
            bail!("{flag} must be finite and > 0, got {spec}");
        }
        return dielectric(Ior::Constant(n), "dielectric".into());
    }
    if let Some(list) = spec.strip_prefix("cauchy:") {
        let v = numbers(list, 3, "cauchy:A,B,C")?;
        return dielectric(Ior::Cauchy { a: v[0], b_um2: v[1], c_um4: v[2] }, "Cauchy glass".into());
    }
    if let Some(list) = spec.strip_prefix("sellmeier:") {
        let v = numbers(list, 6, "sellmeier:B1,B2,B3,C1,C2,C3")?;
        return dielectric(
            Ior::Sellmeier { b: [v[0], v[1], v[2]], c_um2: [v[3], v[4], v[5]] },
            "Sellmeier glass".into(),
        );
    }
    if let Some(glass) = catalogue::glass(spec) {
        return dielectric(glass.ior().clone(), glass.name().to_owned());
    }
    if let Some(metal) = metals::metal(spec) {
        // Beyond its table a metal's index is held at the end value, which is no measurement.
        let (first, last) = metal.wavelength_range_nm();
        if !(first..=last).contains(&wavelength_nm) {
            bail!(
                "--wavelength {wavelength_nm} nm is outside the tabulated data of {} ({first}–{last} nm)",
                metal.name()
            );
        }
        return Ok(Interface::Conductor { eta: metal.eta(wavelength_nm), label: metal.name().to_owned() });
    }
    if let Some(complex) = spec.strip_suffix('i') {
        if let Some(split) = complex.rfind(['+', '-']).filter(|&i| i > 0) {
            let (re, im) =
                (complex[..split].parse::<f32>(), complex[split..].trim_start_matches('+').parse::<f32>());
            if let (Ok(re), Ok(im)) = (re, im) {
                if re.is_finite() && im.is_finite() && (re != 0.0 || im != 0.0) {
                    return Ok(Interface::Conductor {
                        eta: Complex32::new(re, im),
                        label: "conductor".into(),
                    });
                }
            }
        }
    }
    bail!(
        "{flag} \"{spec}\" is not a number, cauchy:A,B,C, sellmeier:B1,B2,B3,C1,C2,C3, n+ki, a glass ({}) or a metal ({})",
        catalogue::glass_names().join(", "),
        metals::metal_names().join(", ")
    )
}

/// A fixture file: its column names and numeric rows.
struct Fixture {
    columns: Vec<String>,
    rows: Vec<Vec<f64>>,
}

fn read_fixture(path: &Path) -> anyhow::Result<Fixture> {
    let text = std::fs::read_to_string(path).with_context(|| format!("{}: cannot read", path.display()))?;
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.starts_with('#') && !l.trim().is_empty());
    let (_, header) = lines.next().ok_or_else(|| anyhow!("{}: no header line", path.display()))?;
    let columns: Vec<String> = header.split(',').map(|c| c.trim().to_owned()).collect();
    let mut rows = Vec::new();
    for (index, line) in lines {
        let row: Result<Vec<f64>, _> = line.split(',').map(|v| v.trim().parse::<f64>()).collect();
        match row {
            Ok(row) if row.len() == columns.len() => rows.push(row),
            _ => bail!("{}:{}: expected {} numbers", path.display(), index + 1, columns.len()),
        }
    }
    Ok(Fixture { columns, rows })
}

/// The rows of a fixture that share one relative index and one quantity (R, or Rs and Rp of the
/// polarised fixture): Mitsuba's and prisma's (cos θi, value).
struct FixtureCurve {
    key: Vec<f64>,
    quantity: &'static str,
    mitsuba: Vec<(f64, f64)>,
    prisma: Vec<(f64, f64)>,
}

/// Plots a Mitsuba fixture with prisma's values overlaid and prints the largest difference.
fn run_fixture(path: &Path, plot: Option<&Path>) -> Result<(), CliError> {
    let mut outputs = Outputs::new();
    fixture_overlay(path, plot, &mut outputs)?;
    outputs.commit().map_err(|e| output_error(e, "writing the plot"))?;
    if let Some(plot) = plot {
        say!("wrote {}", plot.display());
    }
    Ok(())
}

/// Compares a Mitsuba fixture with prisma, prints the largest difference, stages the overlay
/// plot in `outputs` when `plot` is given, and returns the largest difference. The polarised
/// fixture is drawn as Rs = |a_s|² and Rp = |a_p|², the others as the unpolarised R.
pub fn fixture_overlay(path: &Path, plot: Option<&Path>, outputs: &mut Outputs) -> Result<f64, CliError> {
    let format = plot.map(check_plot_path).transpose()?;
    let fixture = read_fixture(path).map_err(CliError::Input)?;
    let col = |name: &str| fixture.columns.iter().position(|c| c == name);
    let (cos_col, key_cols, value_col): (usize, Vec<usize>, usize) =
        match (col("cos_theta_i"), col("eta"), col("eta_re"), col("reflectance"), col("a_s_re")) {
            (Some(c), Some(e), None, Some(r), None) => (c, vec![e], r),
            (Some(c), Some(e), None, None, Some(_)) => (c, vec![e], usize::MAX),
            (Some(c), None, Some(re), Some(r), None) => (c, vec![re, re + 1], r),
            _ => {
                return Err(CliError::Input(anyhow!(
                    "{}: not a prisma Fresnel fixture (columns: {})",
                    path.display(),
                    fixture.columns.join(",")
                )))
            }
        };
    let polarized = value_col == usize::MAX;
    let (a_s, a_p) = (col("a_s_re"), col("a_p_re"));
    let mut groups: Vec<FixtureCurve> = Vec::new();
    let mut largest = 0f64;
    for row in &fixture.rows {
        let key: Vec<f64> = key_cols.iter().map(|&k| row[k]).collect();
        let cos = row[cos_col] as f32;
        let values: Vec<(&'static str, f64, f64)> = if polarized {
            let squared =
                |column: Option<usize>| column.map_or(f64::NAN, |c| row[c].powi(2) + row[c + 1].powi(2));
            let amplitudes = fresnel_dielectric_amplitudes(cos, key[0] as f32);
            vec![
                ("Rs", squared(a_s), f64::from(amplitudes.reflectance_s)),
                ("Rp", squared(a_p), f64::from(amplitudes.reflectance_p)),
            ]
        } else if key.len() == 1 {
            vec![("R", row[value_col], f64::from(fresnel_dielectric(cos, key[0] as f32).reflectance))]
        } else {
            let eta = Complex32::new(key[0] as f32, key[1] as f32);
            vec![("R", row[value_col], f64::from(fresnel_conductor(cos, eta).reflectance))]
        };
        let x = f64::from(cos);
        for (quantity, mitsuba, prisma) in values {
            largest = largest.max((mitsuba - prisma).abs());
            match groups.iter_mut().find(|g| g.key == key && g.quantity == quantity) {
                Some(group) => {
                    group.mitsuba.push((x, mitsuba));
                    group.prisma.push((x, prisma));
                }
                None => groups.push(FixtureCurve {
                    key: key.clone(),
                    quantity,
                    mitsuba: vec![(x, mitsuba)],
                    prisma: vec![(x, prisma)],
                }),
            }
        }
    }
    say!(
        "{}: {} rows, {} curves; largest |prisma − Mitsuba| in reflectance = {largest:.3e}",
        path.display(),
        fixture.rows.len(),
        groups.len()
    );
    if let (Some(plot), Some(format)) = (plot, format) {
        let file_name = path.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        let panel = fixture_panel(&file_name, groups, polarized, largest);
        outputs
            .stage(plot, |sink| encode_chart(sink, plot, format, &[panel], (1200, 640)))
            .map_err(|e| output_error(e, "writing the plot"))?;
    }
    Ok(largest)
}

/// The overlay of a fixture: one colour per relative index η (in increasing order, none
/// repeated), the line style for the quantity (prisma's R or Rs solid, Rp dashed) and circles
/// for Mitsuba's values; a key right of the plot lists the colours, then the styles.
fn fixture_panel(file_name: &str, groups: Vec<FixtureCurve>, polarized: bool, largest: f64) -> Panel {
    let mut keys: Vec<Vec<f64>> = Vec::new();
    for group in &groups {
        if !keys.contains(&group.key) {
            keys.push(group.key.clone());
        }
    }
    keys.sort_by(|a, b| {
        a.iter().zip(b).map(|(x, y)| x.total_cmp(y)).find(|o| o.is_ne()).unwrap_or(std::cmp::Ordering::Equal)
    });
    let colors = palette(keys.len());
    let color_of = |key: &[f64]| colors[keys.iter().position(|k| k == key).unwrap_or(0)];
    let conductor = keys.first().is_some_and(|key| key.len() == 2);
    let mut series = Vec::new();
    for FixtureCurve { key, quantity, mitsuba, prisma } in groups {
        let color = color_of(&key);
        series.push(Series { label: String::new(), points: mitsuba, color, style: Style::Points });
        series.push(Series {
            label: String::new(),
            points: prisma,
            color,
            style: if quantity == "Rp" { Style::Dashed } else { Style::Line },
        });
    }
    // prisma's lines over Mitsuba's circles, which stay visible around them.
    series.sort_by_key(|s| s.style != Style::Points);
    let heading = |label: &str| LegendEntry { label: label.into(), color: RGBColor(0, 0, 0), style: None };
    let style_entry = |label: &str, style: Style| LegendEntry {
        label: label.into(),
        color: RGBColor(60, 60, 60),
        style: Some(style),
    };
    let mut key = vec![heading(if conductor { "η = n + ik" } else { "relative index η" })];
    for (index, eta) in keys.iter().enumerate() {
        key.push(LegendEntry { label: eta_label(eta), color: colors[index], style: Some(Style::Line) });
    }
    key.push(heading(""));
    key.push(heading("drawn as"));
    if polarized {
        key.push(style_entry("prisma Rs = |r_s|²", Style::Line));
        key.push(style_entry("prisma Rp = |r_p|²", Style::Dashed));
    } else {
        key.push(style_entry("prisma R", Style::Line));
    }
    key.push(style_entry("Mitsuba 3", Style::Points));
    Panel {
        subtitle: String::new(),
        y_ticks: Vec::new(),
        title: format!("{file_name}: Mitsuba 3 (circles) vs prisma (lines), max |Δ| = {largest:.1e}"),
        x_label: if conductor {
            "cos θi".into()
        } else {
            "cos θi (negative: light from the interior)".into()
        },
        y_label: if polarized {
            "reflectance Rs = |a_s|², Rp = |a_p|² (s and p polarised)".into()
        } else {
            "unpolarised reflectance".into()
        },
        x_range: (if conductor { 0.0 } else { -1.0 }, 1.0),
        y_range: (0.0, 1.0),
        series,
        markers: Vec::new(),
        legend: LegendPlace::Right,
        key,
    }
}

/// A relative index for a legend: at most four decimals, no trailing zeros (1.0001, 1.33,
/// 0.6667); a complex one as `n + ki`.
fn eta_label(eta: &[f64]) -> String {
    let short = |value: f64| {
        let text = format!("{value:.4}");
        let text = text.trim_end_matches('0').trim_end_matches('.');
        if text == "-0" {
            "0".to_owned()
        } else {
            text.to_owned()
        }
    };
    match eta {
        [re, im] => format!("{} + {}i", short(*re), short(*im)),
        [value] => short(*value),
        _ => String::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve(eta: f64, quantity: &'static str) -> FixtureCurve {
        FixtureCurve { key: vec![eta], quantity, mitsuba: vec![(0.5, 0.1)], prisma: vec![(0.5, 0.1)] }
    }

    /// The polarised fixture's sixteen (η, quantity) curves: one colour per η and a different one
    /// for every η, Rp dashed and Rs solid, Mitsuba's values as circles, and a key right of the
    /// plot with one line per η (in increasing order) and one per style instead of one per curve.
    #[test]
    fn fixture_plot_has_one_colour_per_index_and_a_compact_key() {
        let etas = [0.5, 0.75, 0.6666667, 1.0, 1.0001, 1.33, 1.5, 2.4];
        let groups = etas.iter().flat_map(|&eta| [curve(eta, "Rs"), curve(eta, "Rp")]).collect();
        let panel = fixture_panel("fresnel_polarized.csv", groups, true, 1e-7);
        assert_eq!(panel.legend, LegendPlace::Right);
        assert!(panel.series.iter().all(|s| s.label.is_empty()), "no legend line per curve");
        let colours: Vec<RGBColor> = panel
            .key
            .iter()
            .filter(|e| e.style == Some(Style::Line) && e.color != RGBColor(60, 60, 60))
            .map(|e| e.color)
            .collect();
        let labels: Vec<&str> = panel.key.iter().map(|e| e.label.as_str()).collect();
        assert_eq!(colours, palette(8));
        for (index, eta) in ["0.5", "0.6667", "0.75", "1", "1.0001", "1.33", "1.5", "2.4"].iter().enumerate()
        {
            assert_eq!(labels[1 + index], *eta);
        }
        for style in [Style::Line, Style::Dashed, Style::Points] {
            assert_eq!(
                panel
                    .key
                    .iter()
                    .filter(|e| e.color == RGBColor(60, 60, 60) && e.style == Some(style))
                    .count(),
                1
            );
        }
        // Every series of an η in that η's colour; prisma's Rp dashed, Rs solid.
        assert_eq!(panel.series.len(), 32);
        let mut by_colour = std::collections::HashMap::new();
        for series in &panel.series {
            *by_colour.entry((series.color.0, series.color.1, series.color.2)).or_insert(0) += 1;
        }
        assert_eq!(by_colour.len(), 8);
        assert!(by_colour.values().all(|&n| n == 4), "{by_colour:?}");
        assert_eq!(panel.series.iter().filter(|s| s.style == Style::Dashed).count(), 8);
        assert_eq!(panel.series.iter().filter(|s| s.style == Style::Points).count(), 16);
    }

    #[test]
    fn indices_are_labelled_briefly() {
        assert_eq!(eta_label(&[0.6666667]), "0.6667");
        assert_eq!(eta_label(&[1.0]), "1");
        assert_eq!(eta_label(&[1.0001]), "1.0001");
        assert_eq!(eta_label(&[0.17, 3.15]), "0.17 + 3.15i");
    }
}

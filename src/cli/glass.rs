//! `prisma glass`: the glass catalogue (n_d, V_d, source), n(λ) of named glasses, and a plot of
//! n(λ) over the rendered range.

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::anyhow;
use clap::Args;

use super::plot::{check_plot_path, encode_chart, palette, LegendPlace, Marker, Panel, Series, Style};
use super::{output_error, say, CliError};
use prisma::optics::catalogue::{self, GlassEntry};
use prisma::optics::dispersion::{LAMBDA_C_NM, LAMBDA_D_NM, LAMBDA_F_NM};
use prisma::output::file::write_file;
use prisma::spectrum::{LAMBDA_MAX_NM, LAMBDA_MIN_NM};

/// Arguments of `prisma glass`.
#[derive(Debug, Args)]
pub struct GlassArgs {
    /// Glasses to print n(λ) of (all of the catalogue when plotting without names).
    names: Vec<String>,
    /// Plot n(λ) over 360–830 nm (.svg or .png).
    #[arg(long, value_name = "n.svg|png")]
    plot: Option<PathBuf>,
    /// Wavelength step of the printed table, in nm.
    #[arg(long, value_name = "NM", default_value_t = 10.0, allow_negative_numbers = true)]
    step_nm: f32,
}

/// Runs `prisma glass`.
pub fn run(args: &GlassArgs) -> Result<(), CliError> {
    if !(args.step_nm.is_finite() && (0.1..=100.0).contains(&args.step_nm)) {
        return Err(CliError::Input(anyhow!("--step-nm must be in [0.1, 100], got {}", args.step_nm)));
    }
    // Checked before the table is printed: a bad plot name fails at once.
    let plot_format = args.plot.as_deref().map(check_plot_path).transpose()?;
    let selected: Vec<&GlassEntry> = args
        .names
        .iter()
        .map(|name| {
            catalogue::glass(name).ok_or_else(|| {
                CliError::Input(anyhow!(
                    "unknown glass \"{name}\"; known glasses: {}",
                    catalogue::glass_names().join(", ")
                ))
            })
        })
        .collect::<Result<_, _>>()?;

    if selected.is_empty() {
        say!("{:<14} {:>8} {:>7}  {:<22} source", "glass", "n_d", "V_d", "Cauchy fit max error");
        for glass in catalogue::glasses() {
            say!(
                "{:<14} {:>8.5} {:>7.2}  {:<22.1e} {}",
                glass.name(),
                glass.n_d(),
                glass.abbe_vd(),
                glass.cauchy_fit().max_abs_error,
                glass.source()
            );
        }
    } else {
        let mut table = String::new();
        let _ = write!(table, "lambda_nm");
        for glass in &selected {
            let _ = write!(table, ",{}", glass.name());
        }
        let _ = writeln!(table);
        let steps = ((LAMBDA_MAX_NM - LAMBDA_MIN_NM) / args.step_nm).floor() as usize;
        for i in 0..=steps {
            let nm = LAMBDA_MIN_NM + i as f32 * args.step_nm;
            let _ = write!(table, "{nm}");
            for glass in &selected {
                let _ = write!(table, ",{:.6}", glass.ior().eval(nm));
            }
            let _ = writeln!(table);
        }
        say!("{}", table.trim_end());
    }

    if let (Some(path), Some(format)) = (&args.plot, plot_format) {
        let glasses: Vec<&GlassEntry> =
            if selected.is_empty() { catalogue::glasses().iter().collect() } else { selected };
        let mut y_range = (f64::INFINITY, f64::NEG_INFINITY);
        let colors = palette(glasses.len());
        let series: Vec<Series> = glasses
            .iter()
            .enumerate()
            .map(|(k, glass)| {
                let points: Vec<(f64, f64)> = (0..=470)
                    .map(|i| {
                        let nm = LAMBDA_MIN_NM + i as f32;
                        (f64::from(nm), f64::from(glass.ior().eval(nm)))
                    })
                    .collect();
                for &(_, n) in &points {
                    y_range = (y_range.0.min(n), y_range.1.max(n));
                }
                Series {
                    label: format!("{} (n_d {:.4}, V_d {:.1})", glass.name(), glass.n_d(), glass.abbe_vd()),
                    points,
                    color: colors[k],
                    style: Style::Line,
                }
            })
            .collect();
        let pad = 0.05 * (y_range.1 - y_range.0).max(0.01);
        let panel = Panel {
            title: "Index of refraction n(λ)".into(),
            subtitle: String::new(),
            x_label: "wavelength λ (nm)".into(),
            y_label: "n".into(),
            x_range: (f64::from(LAMBDA_MIN_NM), f64::from(LAMBDA_MAX_NM)),
            y_range: (y_range.0 - pad, y_range.1 + pad),
            y_ticks: Vec::new(),
            series,
            markers: vec![
                Marker { x: LAMBDA_F_NM, label: "F 486.1".into() },
                Marker { x: LAMBDA_D_NM, label: "d 587.6".into() },
                Marker { x: LAMBDA_C_NM, label: "C 656.3".into() },
            ],
            legend: LegendPlace::Right,
            key: Vec::new(),
        };
        write_file(path, |sink| encode_chart(sink, path, format, &[panel], (1160, 600)))
            .map_err(|e| output_error(e, "writing the plot"))?;
        say!("wrote {}", path.display());
    }
    Ok(())
}

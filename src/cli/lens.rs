//! `prisma lens FILE`: what an optical engineer checks first of a lens prescription (pbrt-v4
//! lens file or Zemax `.zmx`): the surface table, effective and back focal lengths, f-number,
//! pupils, the paraxial focus at the F, d and C lines and the longitudinal chromatic focal
//! shift, the transmission on axis (against Π(1 − R)) and across the field, RMS spot radii; and
//! with `--plot`, spot diagrams per wavelength at 0, 0.7 and 1.0 of the field, the focal shift
//! against wavelength and the relative illumination against field, with a CSV of every curve.
//! Definitions in [`prisma::lens::analysis`].

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::anyhow;
use clap::Args;

use super::plot::{check_plot_path, encode_chart_grid, palette, LegendPlace, Marker, Panel, Series, Style};
use super::{output_error, say, CliError};
use prisma::lens::analysis::{
    coated_normal_incidence_transmission, normal_incidence_transmission, Analysis, Illumination, Spot,
    FRAUNHOFER_FDC_NM,
};
use prisma::lens::{read_lens_file, LensSystem, LAMBDA_D_NM};
use prisma::output::file::{text_into, write_file};

/// Arguments of `prisma lens`.
#[derive(Debug, Args)]
pub struct LensArgs {
    /// The prescription: a pbrt-v4 lens file (optionally with a glass column) or a Zemax .zmx.
    file: PathBuf,
    /// The full field angle in degrees (default: the half-diagonal of a 36 × 24 mm sensor,
    /// 21.63 mm, at the d-line focal length).
    #[arg(long, value_name = "DEG", allow_negative_numbers = true)]
    field_deg: Option<f64>,
    /// Plot spot diagrams, focal shift and relative illumination (.svg or .png); a CSV of every
    /// curve is written beside it (same name, `.csv`).
    #[arg(long, value_name = "lens.png|svg")]
    plot: Option<PathBuf>,
}

/// Half-diagonal of a 36 × 24 mm ("full frame") sensor, in mm.
const FULL_FRAME_HALF_DIAGONAL_MM: f64 = 21.633_307_652_783_937;

/// Field fractions of the spot diagrams and the printed tables.
const FIELD_FRACTIONS: [f64; 3] = [0.0, 0.7, 1.0];

/// Runs `prisma lens`.
pub fn run(args: &LensArgs) -> Result<(), CliError> {
    let plot_format = args.plot.as_deref().map(check_plot_path).transpose()?;
    let mut system = read_lens_file(&args.file).map_err(|e| CliError::Input(e.into()))?;
    let input = |e: prisma::lens::LensError| CliError::Input(e.into());
    let d = system.paraxial(LAMBDA_D_NM).map_err(input)?;
    let last = system.surfaces.len() - 1;
    let refocused = system.surfaces[last].thickness_mm == 0.0;
    if refocused {
        // A pbrt lens file leaves the film at 0: pbrt focuses the lens itself. So does this.
        system.surfaces[last].thickness_mm = d.bfl_mm;
    }
    let max_field_deg = match args.field_deg {
        Some(f) if f.is_finite() && f > 0.0 && f < 90.0 => f,
        Some(f) => return Err(CliError::Input(anyhow!("--field-deg must be in (0, 90), got {f}"))),
        None => (FULL_FRAME_HALF_DIAGONAL_MM / d.efl_mm.abs()).atan().to_degrees(),
    };

    print_surfaces(&system);
    say!("\nparaxial, d line ({LAMBDA_D_NM} nm), object at infinity:");
    say!("  effective focal length  {:>12.6} mm", d.efl_mm);
    say!("  back focal length       {:>12.6} mm (last vertex to focus)", d.bfl_mm);
    say!("  front focal length      {:>12.6} mm (front focus to first vertex)", d.ffl_mm);
    say!("  f-number                {:>12.4}", d.f_number);
    say!(
        "  entrance pupil          {:>12.6} mm from the first vertex, diameter {:.6} mm",
        d.entrance_pupil_z_mm,
        d.entrance_pupil_diameter_mm
    );
    say!(
        "  exit pupil              {:>12.6} mm from the last vertex, diameter {:.6} mm",
        d.exit_pupil_z_mm,
        d.exit_pupil_diameter_mm
    );
    if refocused {
        say!("  image plane             the file's last thickness is 0: set to the d-line focus");
    } else {
        say!(
            "  image plane             {:>12.6} mm behind the last vertex (the file's)",
            system.surfaces[last].thickness_mm
        );
    }
    say!("\nfocus per line (paraxial, object at infinity):");
    say!("  line   λ (nm)    EFL (mm)       focus (mm from last vertex)   shift from d (mm)");
    let mut focus = Vec::new();
    for (name, lambda_nm) in FRAUNHOFER_FDC_NM {
        let p = system.paraxial(lambda_nm).map_err(input)?;
        focus.push(p.bfl_mm);
        say!(
            "  {name}    {lambda_nm:>9.4}  {:>12.6}   {:>12.6}                  {:>+12.6}",
            p.efl_mm,
            p.bfl_mm,
            p.bfl_mm - d.bfl_mm
        );
    }
    say!("  longitudinal chromatic focal shift F − C: {:+.6} mm", focus[0] - focus[2]);

    let analysis = Analysis::new(&system).map_err(input)?;
    let fields: Vec<f64> = FIELD_FRACTIONS.iter().map(|f| f * max_field_deg).collect();
    let illumination_fields: Vec<f64> = (0..=10).map(|i| 0.1 * i as f64 * max_field_deg).collect();
    let illumination = analysis.illumination(&illumination_fields);
    let bare = normal_incidence_transmission(&system, LAMBDA_D_NM);
    if system.surfaces.iter().any(|s| s.coating.is_some()) {
        say!("\ntransmission, with the coatings, no ghosts, d line:");
        say!(
            "  on axis {:.6} (traced over the pupil); Π(1 − R) at normal incidence {:.6} with the coatings \
             (R of each stack), {bare:.6} uncoated",
            illumination[0].transmission,
            coated_normal_incidence_transmission(&system, LAMBDA_D_NM)
        );
    } else {
        say!("\ntransmission, uncoated, no ghosts, d line:");
        say!(
            "  on axis {:.6} (traced over the pupil); Π(1 − R) at normal incidence {bare:.6}",
            illumination[0].transmission
        );
    }
    say!("  field (deg)  image height (mm)  relative illumination  with Fresnel  transmission");
    for row in &illumination {
        say!(
            "  {:>10.3}  {:>17.4}  {:>21.4}  {:>12.4}  {:>12.4}",
            row.field_deg,
            row.image_height_mm,
            row.relative,
            row.relative_with_fresnel,
            row.transmission
        );
    }

    let mut spots = Vec::new();
    say!(
        "\nRMS spot radius (µm, about the centroid; rays passing of {} in the pupil):",
        analysis.spot(0.0, LAMBDA_D_NM).rays_in_pupil
    );
    say!("  field (deg)   {}", FRAUNHOFER_FDC_NM.map(|(n, l)| format!("{n} {l:.1} nm         ")).join(""));
    for &field in &fields {
        let row: Vec<Spot> =
            FRAUNHOFER_FDC_NM.iter().map(|&(_, lambda)| analysis.spot(field, lambda)).collect();
        say!(
            "  {:>10.3}   {}",
            field,
            row.iter()
                .map(|s| format!("{:>9.3} ({:>3})     ", 1e3 * s.rms_radius_mm, s.points.len()))
                .collect::<String>()
        );
        spots.push(row);
    }

    if let (Some(path), Some(format)) = (&args.plot, plot_format) {
        let panels = panels(&system, &spots, &illumination, max_field_deg).map_err(input)?;
        write_file(path, |sink| encode_chart_grid(sink, path, format, &panels, 3, (560, 520)))
            .map_err(|e| output_error(e, "writing the plot"))?;
        let csv_path = path.with_extension("csv");
        let csv = csv_text(&system, &spots, &illumination).map_err(input)?;
        write_file(&csv_path, |sink| text_into(sink, &csv_path, &csv))
            .map_err(|e| output_error(e, "writing the CSV"))?;
        say!("\nwrote {} and {}", path.display(), csv_path.display());
    }
    Ok(())
}

fn print_surfaces(system: &LensSystem) {
    say!("{}: {} surfaces, object side first (mm)", system.source.display(), system.surfaces.len());
    say!("  #   radius        thickness    medium behind        n_d        semi-diameter  stop  coating (air side first as written)");
    for (i, s) in system.surfaces.iter().enumerate() {
        let radius = if s.radius_mm == 0.0 { "flat".to_string() } else { format!("{:.4}", s.radius_mm) };
        let coating = s.coating.as_ref().map_or(String::new(), |coating| {
            let n1 = system.medium_before(i).n_at_nm(LAMBDA_D_NM);
            let r = coating.normal_reflectance(n1, s.medium.n_at_nm(LAMBDA_D_NM), LAMBDA_D_NM);
            format!("{} (R {:.3} % at normal incidence, d line)", coating.name, 100.0 * r)
        });
        say!(
            "  {:<3} {:>12} {:>12.4}    {:<18} {:>9.6}  {:>10.4}     {:<4}  {}",
            i + 1,
            radius,
            s.thickness_mm,
            s.medium.name(),
            s.medium.n_at_nm(LAMBDA_D_NM),
            s.semi_diameter_mm,
            if s.is_stop { "stop" } else { "" },
            coating
        );
    }
}

/// Wavelengths (nm) of the focal-shift curve: 400–700 nm every 5 nm.
fn focal_shift_wavelengths() -> impl Iterator<Item = f64> {
    (0..=60).map(|i| 400.0 + 5.0 * i as f64)
}

fn panels(
    system: &LensSystem,
    spots: &[Vec<Spot>],
    illumination: &[Illumination],
    max_field_deg: f64,
) -> Result<Vec<Panel>, prisma::lens::LensError> {
    let colors = [
        plotters::style::RGBColor(0x33, 0x66, 0xCC),
        plotters::style::RGBColor(0x22, 0x88, 0x33),
        plotters::style::RGBColor(0xCC, 0x33, 0x33),
    ];
    let mut panels = Vec::new();
    // One scale for the three spot diagrams, about the d-line chief ray of each field.
    let mut half = 1e-3f64;
    for row in spots {
        let reference = row[1].chief_mm.unwrap_or(row[1].centroid_mm);
        for spot in row {
            for p in &spot.points {
                half = half.max((p[0] - reference[0]).abs()).max((p[1] - reference[1]).abs());
            }
        }
    }
    let half_um = 1e3 * half * 1.05;
    for row in spots {
        let reference = row[1].chief_mm.unwrap_or(row[1].centroid_mm);
        let series = row
            .iter()
            .zip(FRAUNHOFER_FDC_NM)
            .zip(colors)
            .map(|((spot, (name, lambda)), color)| Series {
                label: format!("{name} {lambda:.1} nm: RMS {:.2} µm", 1e3 * spot.rms_radius_mm),
                points: spot
                    .points
                    .iter()
                    .map(|p| (1e3 * (p[0] - reference[0]), 1e3 * (p[1] - reference[1])))
                    .collect(),
                color,
                style: Style::Points,
            })
            .collect();
        panels.push(Panel {
            title: format!("Spot diagram, field {:.2}°", row[0].field_deg),
            subtitle: "about the d-line chief ray".into(),
            x_label: "x (µm)".into(),
            y_label: "y (µm)".into(),
            x_range: (-half_um, half_um),
            y_range: (-half_um, half_um),
            y_ticks: Vec::new(),
            series,
            markers: Vec::new(),
            legend: LegendPlace::Above,
            key: Vec::new(),
        });
    }
    let reference = system.paraxial(LAMBDA_D_NM)?.bfl_mm;
    let mut shift = Vec::new();
    for lambda in focal_shift_wavelengths() {
        shift.push((lambda, 1e3 * (system.paraxial(lambda)?.bfl_mm - reference)));
    }
    let (low, high) = shift.iter().fold((0.0f64, 0.0f64), |(a, b), &(_, s)| (a.min(s), b.max(s)));
    let pad = 0.05 * (high - low).max(1.0);
    panels.push(Panel {
        title: "Longitudinal chromatic focal shift".into(),
        subtitle: "paraxial focus minus the d line's, object at infinity".into(),
        x_label: "wavelength λ (nm)".into(),
        y_label: "focal shift (µm)".into(),
        x_range: (400.0, 700.0),
        y_range: (low - pad, high + pad),
        y_ticks: Vec::new(),
        series: vec![Series {
            label: String::new(),
            points: shift,
            color: palette(1)[0],
            style: Style::Line,
        }],
        markers: FRAUNHOFER_FDC_NM.iter().map(|&(name, x)| Marker { x, label: format!("{name}") }).collect(),
        legend: LegendPlace::Above,
        key: Vec::new(),
    });
    let colors = palette(3);
    panels.push(Panel {
        title: "Relative illumination and transmission".into(),
        subtitle: "d line, uniform radiance at infinity, no ghosts".into(),
        x_label: "field angle (°)".into(),
        y_label: "relative to the lossless axis".into(),
        x_range: (0.0, max_field_deg),
        y_range: (0.0, 1.05),
        y_ticks: Vec::new(),
        series: vec![
            Series {
                label: "relative illumination (lossless)".into(),
                points: illumination.iter().map(|r| (r.field_deg, r.relative)).collect(),
                color: colors[0],
                style: Style::Line,
            },
            Series {
                label: "with Fresnel losses".into(),
                points: illumination.iter().map(|r| (r.field_deg, r.relative_with_fresnel)).collect(),
                color: colors[1],
                style: Style::Dashed,
            },
            Series {
                label: "Fresnel transmission".into(),
                points: illumination.iter().map(|r| (r.field_deg, r.transmission)).collect(),
                color: colors[2],
                style: Style::Points,
            },
        ],
        markers: Vec::new(),
        legend: LegendPlace::Above,
        key: Vec::new(),
    });
    Ok(panels)
}

/// Every plotted value, one table with a `curve` column.
fn csv_text(
    system: &LensSystem,
    spots: &[Vec<Spot>],
    illumination: &[Illumination],
) -> Result<String, prisma::lens::LensError> {
    let mut text = String::from("curve,field_deg,wavelength_nm,x,y\n");
    for row in spots {
        for spot in row {
            for p in &spot.points {
                let _ = writeln!(text, "spot_mm,{},{},{},{}", spot.field_deg, spot.lambda_nm, p[0], p[1]);
            }
        }
    }
    let reference = system.paraxial(LAMBDA_D_NM)?.bfl_mm;
    for lambda in focal_shift_wavelengths() {
        let _ = writeln!(
            text,
            "focal_shift_mm,0,{lambda},{lambda},{}",
            system.paraxial(lambda)?.bfl_mm - reference
        );
    }
    for r in illumination {
        let _ = writeln!(
            text,
            "relative_illumination,{},{LAMBDA_D_NM},{},{}",
            r.field_deg, r.field_deg, r.relative
        );
        let _ = writeln!(
            text,
            "relative_illumination_fresnel,{},{LAMBDA_D_NM},{},{}",
            r.field_deg, r.field_deg, r.relative_with_fresnel
        );
        let _ =
            writeln!(text, "transmission,{},{LAMBDA_D_NM},{},{}", r.field_deg, r.field_deg, r.transmission);
    }
    Ok(text)
}

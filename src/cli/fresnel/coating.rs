//! `prisma fresnel --coating`: what a stack of coherent layers on the `--ior` interface
//! reflects and transmits, for s and p, with the phases of r_s and r_p and the ellipsometric
//! ψ and Δ, against the angle of incidence or the wavelength, by the transfer-matrix method of
//! [`prisma::optics::thin_film`] (Macleod, *Thin-Film Optical Filters*, §2.2–2.4).
//!
//! A coating is written from the incident side, layers separated by commas, each
//! `INDEX:THICKNESS_NM`: `--coating "1.38:99.64"` is a quarter-wave MgF₂ layer at 550 nm. INDEX
//! is what `--ior` takes that holds no comma: a number, a complex `n+ki`, a catalogue glass or a
//! metal, evaluated at each wavelength. Light arrives from vacuum.

use anyhow::{anyhow, bail};
use num_complex::Complex64;

use plotters::style::RGBColor;

use super::curves::{self, phase_deg_f64 as phase_deg};
use super::{parse_spec, Interface};
use crate::cli::plot::{palette, LegendPlace, Panel, Series, Style};
use prisma::optics::{thin_film_amplitudes, Layer, ThinFilmAmplitudes};

/// Most layers a coating may have: far more than any real design (a 4-layer AR stack, a
/// 20–40-layer dichroic), few enough that a pasted typo is caught.
pub const MAX_LAYERS: usize = 64;

/// Thickest layer accepted, in nm: 10 µm, beyond the coherence length of daylight (a few µm),
/// where the model of coherent layers stops describing what is seen, and well below the
/// thickness where an absorbing layer overflows f64 (some 20 µm of gold).
pub const MAX_THICKNESS_NM: f64 = 10_000.0;

/// One layer as written: its index spec (re-evaluated at each wavelength) and thickness in nm.
#[derive(Clone, Debug, PartialEq)]
pub struct LayerSpec {
    /// The index, as `--ior` takes it.
    pub index: String,
    /// Physical thickness in nm, in [0, [`MAX_THICKNESS_NM`]].
    pub thickness_nm: f64,
}

/// Parses `--coating`'s list (see the module documentation); the error is one line naming
/// `--coating` and the offending item.
pub fn parse_coating(spec: &str) -> anyhow::Result<Vec<LayerSpec>> {
    let items: Vec<&str> = spec.split(',').map(str::trim).collect();
    if items.len() > MAX_LAYERS {
        bail!("--coating has {} layers; at most {MAX_LAYERS} are accepted", items.len());
    }
    items
        .iter()
        .enumerate()
        .map(|(position, item)| {
            let number = position + 1;
            let (index, thickness) = item.rsplit_once(':').ok_or_else(|| {
                anyhow!("--coating layer {number} \"{item}\": expected INDEX:THICKNESS_NM, e.g. 1.38:99.64")
            })?;
            let thickness_nm: f64 = thickness.trim().parse().map_err(|_| {
                anyhow!("--coating layer {number} \"{item}\": the thickness \"{thickness}\" is not a number of nm")
            })?;
            if !(thickness_nm.is_finite() && (0.0..=MAX_THICKNESS_NM).contains(&thickness_nm)) {
                bail!(
                    "--coating layer {number} \"{item}\": the thickness must be in 0–{MAX_THICKNESS_NM} nm, got {thickness}"
                );
            }
            let index = index.trim();
            if index.is_empty() {
                bail!("--coating layer {number} \"{item}\": no index before the ':'");
            }
            Ok(LayerSpec { index: index.to_owned(), thickness_nm })
        })
        .collect()
}

/// The complex index n + ik of an `--ior`-style spec at `wavelength_nm`; errors name `flag`.
pub fn index_at(spec: &str, wavelength_nm: f64, flag: &str) -> anyhow::Result<Complex64> {
    Ok(match parse_spec(spec, wavelength_nm as f32, flag)? {
        Interface::Dielectric { n, .. } => Complex64::new(f64::from(n), 0.0),
        Interface::Conductor { eta, .. } => Complex64::new(f64::from(eta.re), f64::from(eta.im)),
    })
}

/// The layers of `coating` at `wavelength_nm`; an index that does not resolve is an error
/// naming `--coating` and the layer.
pub fn layers_at(coating: &[LayerSpec], wavelength_nm: f64) -> anyhow::Result<Vec<Layer>> {
    coating
        .iter()
        .enumerate()
        .map(|(position, layer)| {
            let index = index_at(&layer.index, wavelength_nm, "the index").map_err(|e| {
                anyhow!("--coating layer {} \"{}:{}\": {e}", position + 1, layer.index, layer.thickness_nm)
            })?;
            Ok(Layer { index, thickness_nm: layer.thickness_nm })
        })
        .collect()
}

/// What the curves are drawn against.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Against {
    /// The angle of incidence, 0–90° in steps of 0.25°, at `--wavelength`.
    Angle,
    /// The wavelength, 360–830 nm in steps of 1 nm, at `--angle`.
    Wavelength,
}

/// One row of the table: the abscissa (degrees or nm), the coated interface's amplitudes and
/// the bare substrate's unpolarised reflectance for comparison.
pub struct Row {
    /// Angle of incidence in degrees, or wavelength in nm.
    pub x: f64,
    /// The stack's amplitudes.
    pub coated: ThinFilmAmplitudes,
    /// Unpolarised reflectance of the uncoated substrate.
    pub bare_reflectance: f64,
}

/// The rows of `coating` on `substrate` against `against`: angles at `wavelength_nm`, or
/// wavelengths at `angle_deg`. Every index is resolved before the first row is returned.
pub fn table(
    substrate: &str,
    coating: &[LayerSpec],
    against: Against,
    wavelength_nm: f64,
    angle_deg: f64,
) -> anyhow::Result<Vec<Row>> {
    let row = |x: f64, lambda_nm: f64, theta_deg: f64| -> anyhow::Result<Row> {
        let n_substrate = index_at(substrate, lambda_nm, "--ior")?;
        let layers = layers_at(coating, lambda_nm)?;
        let cos_theta_i = theta_deg.to_radians().cos().clamp(0.0, 1.0);
        let coated = thin_film_amplitudes(1.0, &layers, n_substrate, lambda_nm, cos_theta_i);
        let bare = thin_film_amplitudes(1.0, &[], n_substrate, lambda_nm, cos_theta_i);
        Ok(Row { x, coated, bare_reflectance: 0.5 * (bare.reflectance_s + bare.reflectance_p) })
    };
    match against {
        Against::Angle => (0..=360)
            .map(|step| {
                let angle = f64::from(step) * 0.25;
                row(angle, wavelength_nm, angle)
            })
            .collect(),
        Against::Wavelength => (360..=830)
            .map(|lambda| {
                let lambda = f64::from(lambda);
                row(lambda, lambda, angle_deg)
            })
            .collect(),
    }
}

/// The table as CSV: one header line, a row per angle or wavelength, every quantity in its own
/// column (phases, ψ and Δ in degrees).
pub fn csv(rows: &[Row], against: Against) -> String {
    use std::fmt::Write as _;
    let mut csv = String::new();
    let x = match against {
        Against::Angle => "angle_deg",
        Against::Wavelength => "wavelength_nm",
    };
    let _ = writeln!(csv, "{x},rs,rp,r,ts,tp,t,phase_rs_deg,phase_rp_deg,psi_deg,delta_deg,r_bare");
    for row in rows {
        let a = &row.coated;
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{},{},{}",
            row.x,
            a.reflectance_s,
            a.reflectance_p,
            0.5 * (a.reflectance_s + a.reflectance_p),
            a.transmittance_s,
            a.transmittance_p,
            0.5 * (a.transmittance_s + a.transmittance_p),
            phase_deg(a.r_s),
            phase_deg(a.r_p),
            a.psi().to_degrees(),
            phase_deg(a.r_p * a.r_s.conj()),
            row.bare_reflectance,
        );
    }
    csv
}

/// The smallest of 1, 2 and 5 × 10^k above `value` (a reflectance axis that shows a 1 % AR
/// coating and a 100 % mirror alike), at most 1.
fn axis_ceiling(value: f64) -> f64 {
    [0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0].into_iter().find(|&top| top >= value).unwrap_or(1.0)
}

/// The plots of `rows`: reflectances (with the bare substrate's in grey), transmittances,
/// the unpolarised curves first so that the dashed s and p curves stay visible over them,
/// and the phases of r_s, r_p with Δ = arg r_p − arg r_s. `title` names the stack and where it
/// is evaluated.
pub fn panels(rows: &[Row], against: Against, title: &str) -> Vec<Panel> {
    let colors = palette(3);
    let x_label = match against {
        Against::Angle => "angle of incidence θi (degrees)",
        Against::Wavelength => "wavelength λ (nm)",
    };
    let x_range = match against {
        Against::Angle => (0.0, 90.0),
        Against::Wavelength => (360.0, 830.0),
    };
    let xs: Vec<f64> = rows.iter().map(|row| row.x).collect();
    let curve = |value: &dyn Fn(&Row) -> f64| -> Vec<(f64, f64)> {
        rows.iter().map(|row| (row.x, value(row))).collect()
    };
    let series = |label: &str, points: Vec<(f64, f64)>, color: RGBColor, style: Style| Series {
        label: label.into(),
        points,
        color,
        style,
    };
    let unpolarised = |s: f64, p: f64| 0.5 * (s + p);
    let highest_r = rows
        .iter()
        .map(|row| row.coated.reflectance_s.max(row.coated.reflectance_p).max(row.bare_reflectance))
        .fold(0.0, f64::max);
    let lowest_t =
        rows.iter().map(|row| row.coated.transmittance_s.min(row.coated.transmittance_p)).fold(1.0, f64::min);
    let panel = |title: String, subtitle: String, y_label: &str, y_range, y_ticks, series| Panel {
        title,
        subtitle,
        x_label: x_label.into(),
        y_label: y_label.into(),
        x_range,
        y_range,
        y_ticks,
        series,
        markers: Vec::new(),
        legend: LegendPlace::Above,
        key: Vec::new(),
    };
    let phase = |value: &dyn Fn(&Row) -> f64| curves::phase_points(&xs, rows.iter().map(value));
    vec![
        panel(
            format!("reflectance, {title}"),
            String::new(),
            "reflectance",
            (0.0, axis_ceiling(highest_r * 1.05)),
            Vec::new(),
            vec![
                series(
                    "R unpolarised",
                    curve(&|row| unpolarised(row.coated.reflectance_s, row.coated.reflectance_p)),
                    colors[2],
                    Style::Line,
                ),
                series("Rs", curve(&|row| row.coated.reflectance_s), colors[0], Style::Dashed),
                series("Rp", curve(&|row| row.coated.reflectance_p), colors[1], Style::Dashed),
                series(
                    "R uncoated",
                    curve(&|row| row.bare_reflectance),
                    RGBColor(150, 150, 150),
                    Style::Line,
                ),
            ],
        ),
        panel(
            "transmittance into the substrate".into(),
            String::new(),
            "transmittance",
            (1.0 - axis_ceiling((1.0 - lowest_t) * 1.05), 1.0),
            Vec::new(),
            vec![
                series(
                    "T unpolarised",
                    curve(&|row| unpolarised(row.coated.transmittance_s, row.coated.transmittance_p)),
                    colors[2],
                    Style::Line,
                ),
                series("Ts", curve(&|row| row.coated.transmittance_s), colors[0], Style::Dashed),
                series("Tp", curve(&|row| row.coated.transmittance_p), colors[1], Style::Dashed),
            ],
        ),
        panel(
            "phases of r_s and r_p".into(),
            super::PHASE_CONVENTION.into(),
            "phase (degrees)",
            (-190.0, 190.0),
            (-4..=4).map(|k| f64::from(k) * 45.0).collect(),
            vec![
                series("arg r_s", phase(&|row| phase_deg(row.coated.r_s)), colors[0], Style::Dashed),
                series("arg r_p", phase(&|row| phase_deg(row.coated.r_p)), colors[1], Style::Dashed),
                series(
                    "Δ = arg r_p − arg r_s",
                    phase(&|row| phase_deg(row.coated.r_p * row.coated.r_s.conj())),
                    colors[2],
                    Style::Line,
                ),
            ],
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_coating_lists_its_layers_from_the_incident_side() {
        let layers = parse_coating("1.38:99.64, N-BK7:10,0.05+4.2i:0").unwrap();
        let indices: Vec<&str> = layers.iter().map(|l| l.index.as_str()).collect();
        assert_eq!(indices, ["1.38", "N-BK7", "0.05+4.2i"]);
        assert_eq!(layers[0].thickness_nm, 99.64);
        assert_eq!(layers[2].thickness_nm, 0.0);
    }

    /// Each bad coating is refused in one line that names `--coating` and the item at fault.
    #[test]
    fn bad_coatings_name_the_flag_and_the_item() {
        for (spec, item) in [
            ("1.38:-5", "1.38:-5"),
            ("1.38:1e6", "1.38:1e6"),
            ("1.38:nan", "1.38:nan"),
            ("1.38", "1.38"),
            ("1.38:99,:5", ":5"),
            ("1.38:abc", "1.38:abc"),
        ] {
            let message = parse_coating(spec).unwrap_err().to_string();
            assert!(message.starts_with("--coating"), "{spec}: {message}");
            assert!(message.contains(item), "{spec}: {message}");
            assert_eq!(message.lines().count(), 1, "{spec}: {message}");
        }
        let many = vec!["1.38:10"; MAX_LAYERS + 1].join(",");
        assert!(parse_coating(&many).unwrap_err().to_string().contains("65 layers"));
        assert!(parse_coating(&vec!["1.38:10"; MAX_LAYERS].join(",")).is_ok());
        let unknown = parse_coating("unobtainium:10").unwrap();
        let message = layers_at(&unknown, 550.0).unwrap_err().to_string();
        assert!(message.starts_with("--coating layer 1 \"unobtainium:10\""), "{message}");
        assert_eq!(message.lines().count(), 1, "{message}");
    }

    /// A quarter-wave layer of n₁ = 1.38 on a substrate of n_s = 1.52 at normal incidence
    /// reflects ((n₀n_s − n₁²)/(n₀n_s + n₁²))² (Macleod §3.2: the layer turns the substrate's
    /// admittance into n₁²/n_s), 1.26 %, against ((n_s − 1)/(n_s + 1))² = 4.26 % bare.
    #[test]
    fn a_quarter_wave_layer_reflects_the_closed_form() {
        let coating = parse_coating(&format!("1.38:{}", 550.0 / (4.0 * 1.38))).unwrap();
        let rows = table("1.52", &coating, Against::Wavelength, 550.0, 0.0).unwrap();
        let design = rows.iter().find(|row| row.x == 550.0).unwrap();
        let expected = ((1.52 - 1.38f64 * 1.38) / (1.52 + 1.38 * 1.38)).powi(2);
        assert!((design.coated.reflectance_s - expected).abs() < 1e-6, "{}", design.coated.reflectance_s);
        assert!((design.bare_reflectance - (0.52f64 / 2.52).powi(2)).abs() < 1e-6);
        // Lossless: T = 1 − R.
        assert!((design.coated.transmittance_s + design.coated.reflectance_s - 1.0).abs() < 1e-9);
    }

    #[test]
    fn the_csv_has_every_column_and_a_row_per_angle() {
        let coating = parse_coating("1.38:99.64").unwrap();
        let rows = table("N-BK7", &coating, Against::Angle, 550.0, 0.0).unwrap();
        let text = csv(&rows, Against::Angle);
        let mut lines = text.lines();
        assert_eq!(
            lines.next().unwrap(),
            "angle_deg,rs,rp,r,ts,tp,t,phase_rs_deg,phase_rp_deg,psi_deg,delta_deg,r_bare"
        );
        assert_eq!(lines.count(), 361);
    }
}

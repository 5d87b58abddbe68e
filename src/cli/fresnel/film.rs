//! `prisma fresnel --film-colours`: the interference colour chart of a free-standing film (a
//! soap film) of the `--ior` index in air (n = 1), seen in reflection under D65: for each
//! thickness, the unpolarised reflectance R(λ) = (R_s + R_p)/2 of the one-layer stack
//! ([`prisma::optics::thin_film`]) times the D65 illuminant, integrated with the CIE 1931
//! observer into XYZ ([`prisma::spectrum::cie::xyz_by_quadrature`], 1 nm over 360–830 nm) and
//! converted to linear sRGB. D65 is normalised to Y = 1, so a perfect white reflector has
//! Y = 1 and the film's Y is its luminous reflectance.
//!
//! Physics to read the chart by (Born & Wolf §7.5; Isenberg, *The Science of Soap Films and
//! Soap Bubbles*, ch. 3): the two faces reflect with opposite signs, so a film much thinner
//! than λ/(4n) reflects nothing (the "black film" of a bubble about to burst); at λ/(4n) the
//! two reflections add, R = ((n² − 1)/(n² + 1))²; thicker films give Newton's series of
//! colours (first-order white and yellow near 100–150 nm of water, then the purples, blues,
//! greens of the higher orders) that fade towards white above about 1 µm, where the many
//! maxima within the visible average out.

use glam::Vec3;
use num_complex::Complex64;
use plotters::style::RGBColor;

use crate::cli::plot::{ColorStrip, LegendPlace, Panel, Series, Style};

use prisma::optics::{thin_film_amplitudes, Layer};
use prisma::spectrum::cie::xyz_by_quadrature;
use prisma::spectrum::color::{srgb_encode, xyz_to_linear_srgb};
use prisma::spectrum::{Spectrum, LAMBDA_MAX_NM, LAMBDA_MIN_NM};

/// The thickest film of the chart, in nm: past 1.5 µm of water the colours are pale pinks and
/// greens that fade to white.
pub const MAX_THICKNESS_NM: u32 = 1500;

/// The colour of one thickness of film.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilmColour {
    /// Film thickness in nm.
    pub thickness_nm: f64,
    /// CIE 1931 XYZ of the reflected D65 light; a perfect white reflector has Y = 1.
    pub xyz: Vec3,
    /// The same colour in linear sRGB (may leave [0, 1]: saturated colours are out of gamut).
    pub linear_rgb: Vec3,
}

/// Unpolarised reflectance of a free-standing film of complex index `index` (n + ik) and
/// `thickness_nm` in vacuum, at vacuum wavelength `lambda_nm` and `cos_theta_i`.
pub fn film_reflectance(index: Complex64, thickness_nm: f64, lambda_nm: f64, cos_theta_i: f64) -> f64 {
    let film = [Layer { index, thickness_nm }];
    let amplitudes = thin_film_amplitudes(1.0, &film, Complex64::new(1.0, 0.0), lambda_nm, cos_theta_i);
    0.5 * (amplitudes.reflectance_s + amplitudes.reflectance_p)
}

/// The chart, one entry per nm of thickness over 0–[`MAX_THICKNESS_NM`]. `index_per_nm[i]` is the
/// film's index at 360 + i nm (471 values, one per nm of the CIE table).
///
/// # Panics
/// If `index_per_nm` does not hold one index per nm over 360–830 nm.
pub fn chart(index_per_nm: &[Complex64], cos_theta_i: f64) -> Vec<FilmColour> {
    assert_eq!(index_per_nm.len(), (LAMBDA_MAX_NM - LAMBDA_MIN_NM) as usize + 1, "one index per nm");
    // Both names are known to the spectrum module; a failure here is a bug, not bad input.
    let d65 = Spectrum::named_illuminant("D65").expect("D65 is a named illuminant");
    (0..=MAX_THICKNESS_NM)
        .map(|thickness| {
            let thickness_nm = f64::from(thickness);
            // The quadrature evaluates at whole nanometres, the grid of `index_per_nm`.
            let xyz = xyz_by_quadrature(|lambda_nm| {
                let index = index_per_nm[(lambda_nm - LAMBDA_MIN_NM).round() as usize];
                let reflectance = film_reflectance(index, thickness_nm, f64::from(lambda_nm), cos_theta_i);
                reflectance as f32 * d65.eval(lambda_nm)
            });
            FilmColour { thickness_nm, xyz, linear_rgb: xyz_to_linear_srgb(xyz) }
        })
        .collect()
}

/// The chart as CSV: thickness_nm, X, Y, Z and linear sRGB, one row per thickness.
pub fn csv(colours: &[FilmColour]) -> String {
    use std::fmt::Write as _;
    let mut csv = String::from("thickness_nm,X,Y,Z,R,G,B\n");
    for colour in colours {
        let (xyz, rgb) = (colour.xyz, colour.linear_rgb);
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{}",
            colour.thickness_nm, xyz.x, xyz.y, xyz.z, rgb.x, rgb.y, rgb.z
        );
    }
    csv
}

/// The figure of the chart: the colour strip, shown `exposure` times brighter so that the
/// brightest thickness reaches Y = 1 (a film reflects at most some 8 %), clipped to [0, 1] and
/// sRGB-encoded; under it R against thickness at 450, 550 and 650 nm and the luminous
/// reflectance Y. `spec` names the film, `angle_deg` the angle of incidence.
pub fn strip(
    colours: &[FilmColour],
    index_per_nm: &[Complex64],
    spec: &str,
    angle_deg: f64,
    cos_theta_i: f64,
) -> ColorStrip {
    let brightest = colours.iter().map(|colour| colour.xyz.y).fold(0.0f32, f32::max);
    let exposure = if brightest > 0.0 { 1.0 / brightest } else { 1.0 };
    let encode = |linear: f32| (srgb_encode((linear * exposure).clamp(0.0, 1.0)) * 255.0).round() as u8;
    let cells = colours
        .iter()
        .map(|colour| {
            let rgb = colour.linear_rgb;
            (colour.thickness_nm, RGBColor(encode(rgb.x), encode(rgb.y), encode(rgb.z)))
        })
        .collect();
    let thicknesses = || colours.iter().map(|colour| colour.thickness_nm);
    let mut series: Vec<Series> =
        [(450.0, RGBColor(40, 80, 220)), (550.0, RGBColor(30, 150, 60)), (650.0, RGBColor(210, 50, 40))]
            .into_iter()
            .map(|(lambda_nm, color)| {
                let index = index_per_nm[(lambda_nm - f64::from(LAMBDA_MIN_NM)) as usize];
                Series {
                    label: format!("R at {lambda_nm} nm"),
                    points: thicknesses()
                        .map(|thickness| {
                            (thickness, film_reflectance(index, thickness, lambda_nm, cos_theta_i))
                        })
                        .collect(),
                    color,
                    style: Style::Dashed,
                }
            })
            .collect();
    series.push(Series {
        label: "Y (luminous reflectance under D65)".into(),
        points: colours.iter().map(|colour| (colour.thickness_nm, f64::from(colour.xyz.y))).collect(),
        color: RGBColor(0, 0, 0),
        style: Style::Line,
    });
    let highest = series.iter().flat_map(|s| s.points.iter().map(|point| point.1)).fold(0.0, f64::max);
    let n_550 = index_per_nm[(550.0 - LAMBDA_MIN_NM) as usize];
    let index = if n_550.im == 0.0 {
        format!("{:.4}", n_550.re)
    } else {
        format!("{:.3} + {:.3}i", n_550.re, n_550.im)
    };
    ColorStrip {
        title: format!(
            "interference colours of a free-standing film of {spec} (n = {index} at 550 nm) in vacuum, reflected at θi = {angle_deg}° under D65"
        ),
        subtitle: format!(
            "CIE 1931 2° → linear sRGB, shown ×{exposure:.1} (the brightest thickness at Y = 1), clipped to the gamut; CSV values unscaled"
        ),
        cells,
        panel: Panel {
            title: String::new(),
            subtitle: String::new(),
            x_label: "film thickness d (nm)".into(),
            y_label: "reflectance".into(),
            x_range: (0.0, f64::from(MAX_THICKNESS_NM)),
            y_range: (0.0, (highest * 1.1).max(1e-3)),
            y_ticks: Vec::new(),
            series,
            markers: Vec::new(),
            legend: LegendPlace::Above,
            key: Vec::new(),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const WATER: f64 = 1.333;

    /// As d → 0 the film's two reflections, r at the front and −r at the back (Stokes), cancel:
    /// R → 0, and goes as d² (the amplitude is linear in the phase thickness).
    #[test]
    fn a_vanishing_film_reflects_nothing() {
        let water = Complex64::new(WATER, 0.0);
        for lambda_nm in [400.0, 550.0, 700.0] {
            assert_eq!(film_reflectance(water, 0.0, lambda_nm, 1.0), 0.0);
            let thin = film_reflectance(water, 1.0, lambda_nm, 1.0);
            let thinner = film_reflectance(water, 0.1, lambda_nm, 1.0);
            assert!(thin < 1e-3, "{thin} at 1 nm, {lambda_nm} nm");
            assert!((thin / thinner - 100.0).abs() < 0.1, "R ∝ d²: {thin} / {thinner}");
        }
    }

    /// At normal incidence the front face reflects −r and the back face +r, with
    /// r = (n − 1)/(n + 1); Airy's sum is r_film = (−r + r·e^{−2iβ}) / (1 − r²·e^{−2iβ}). A
    /// quarter-wave film (n d = λ/4, β = π/2, e^{−2iβ} = −1) gives r_film = −2r / (1 + r²), so
    /// R = (2r / (1 + r²))² = ((n² − 1)/(n² + 1))², 7.8 % for water: the brightest it gets.
    #[test]
    fn a_quarter_wave_film_reflects_the_closed_form() {
        let r = (WATER - 1.0) / (WATER + 1.0);
        let expected = (2.0 * r / (1.0 + r * r)).powi(2);
        let closed = ((WATER * WATER - 1.0) / (WATER * WATER + 1.0)).powi(2);
        assert!((expected - closed).abs() < 1e-15);
        for lambda_nm in [400.0, 550.0, 700.0] {
            let quarter_wave = lambda_nm / (4.0 * WATER);
            let reflectance = film_reflectance(Complex64::new(WATER, 0.0), quarter_wave, lambda_nm, 1.0);
            assert!((reflectance - expected).abs() < 1e-12, "{reflectance} vs {expected} at {lambda_nm} nm");
        }
    }

    fn water_chart() -> Vec<FilmColour> {
        chart(&vec![Complex64::new(WATER, 0.0); 471], 1.0)
    }

    /// The chart against what soap films show. The two reflections differ in path by 2nd and
    /// in sign, so R(λ) peaks where 2nd = (m + ½)λ and vanishes where 2nd = mλ: black below
    /// ~20 nm, the first-order white near 100–130 nm at the brightest Y of the chart, a
    /// magenta-purple at 200 nm (2nd = 533 nm: green missing, 1066 and 355 nm peaks), then
    /// the second-order green at 300 nm (2nd = 800 nm: a peak at 533 nm).
    #[test]
    fn the_chart_shows_the_colours_of_a_soap_film() {
        let colours = water_chart();
        assert_eq!(colours.len(), 1501);
        for colour in &colours[..=20] {
            assert!(colour.xyz.y < 0.01, "not black at {} nm: Y = {}", colour.thickness_nm, colour.xyz.y);
        }
        let brightest = colours.iter().max_by(|a, b| a.xyz.y.total_cmp(&b.xyz.y)).unwrap();
        assert!((90.0..=130.0).contains(&brightest.thickness_nm), "{brightest:?}");
        let first_order = colours[120].linear_rgb;
        assert!(first_order.min_element() > 0.3 * first_order.max_element(), "whitish: {first_order}");
        let purple = colours[200].linear_rgb;
        assert!(purple.y < 0.1 * purple.x.min(purple.z), "no green at 200 nm: {purple}");
        let green = colours[300].linear_rgb;
        assert!(green.y > green.x && green.y > green.z, "green at 300 nm: {green}");
    }

    /// The normalisation: D65 itself, reflected by a perfect white, has Y = 1 and sRGB ≈ (1, 1, 1).
    #[test]
    fn a_perfect_white_reflector_has_unit_luminance() {
        let d65 = Spectrum::named_illuminant("D65").unwrap();
        let xyz = xyz_by_quadrature(|lambda_nm| d65.eval(lambda_nm));
        assert!((xyz.y - 1.0).abs() < 1e-4, "{xyz}");
        let rgb = xyz_to_linear_srgb(xyz);
        assert!((rgb - Vec3::ONE).abs().max_element() < 0.01, "{rgb}");
    }
}

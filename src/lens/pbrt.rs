//! pbrt-v4 lens files (`RealisticCamera`'s `lensfile`), read as pbrt-v4 reads them, plus an
//! optional fifth column naming each element's glass.
//!
//! One surface per line, object side first, four numbers in mm:
//! `curvature_radius thickness eta aperture_diameter`; `#` starts a comment, blank lines are
//! skipped. As in pbrt-v4 (`src/pbrt/cameras.cpp`, `RealisticCamera::Create` and the
//! constructor): a radius of 0 marks the aperture stop (a flat surface); `eta` is the index of
//! the medium behind the surface, where pbrt's `TraceLensesFromFilm` takes an `eta` of 0 as air
//! (n = 1), as its files write for the stop; the aperture diameter is the full clear diameter
//! (the semi-diameter is half of it). pbrt-v4 ignores the last line's thickness and places the
//! film by focusing; here the last thickness is the distance from the last vertex to the image
//! plane, and a last thickness of exactly 0 (pbrt's own files write 0) is replaced by the paraxial
//! back focal distance at the d line, 587.5618 nm (focus at infinity), so those files read as they
//! are.
//!
//! The fifth column, when present, is the glass behind the surface
//! ([`parse_glass_spec`]: a catalogue name, `sellmeier:B1,B2,B3,C1,C2,C3`, `abbe:nd,vd` or
//! `air`), so its index depends on wavelength; the fourth-column `eta` must then agree with the
//! glass's n_d within 0.01 (else the glass is probably not the designer's). Without it the medium
//! has the constant index `eta` ([`Medium::constant`]), or is air for `eta` 0 or 1.
//!
//! A `coat=SPEC` token after the numbers (and the glass) coats the surface
//! ([`super::coating`]: `coat=AR`, or layers `MATERIAL@THICKNESS_NM` separated by `/`, air side
//! first). pbrt-v4 does not read it; a line without it reads exactly as before.
//!
//! ```text
//! # radius  thickness  eta    aperture  glass
//! 51.68     5.0        1.517  25.0      N-BK7  coat=AR
//! -51.68    2.0        1      25.0             coat=MgF2@qw550
//! 0         45.0       0      20.0
//! ```

use std::path::Path;

use super::coating::{orient_file_coatings, parse_coating_spec, Coating};
use super::glass_spec::parse_glass_spec;
use super::{LensError, LensSystem, Medium, Surface};
use crate::optics::dispersion::LAMBDA_D_NM;

/// How far (absolute) a glass's n_d may differ from the file's `eta` column: pbrt's files give
/// indices to 3 decimals, and a designer's glass matched to them lies within ~0.005; a different
/// glass family lies farther.
pub const ETA_GLASS_TOLERANCE: f64 = 0.01;

/// The names of the columns, for error messages.
const COLUMNS: [&str; 5] = ["radius", "thickness", "eta", "aperture diameter", "glass"];

/// Parses and [validates](LensSystem::validate) the text of a pbrt-v4 lens file read from
/// `source` (named in errors).
///
/// # Errors
/// [`LensError::Line`] for a line that is wrong on its own (a missing or extra column, a field
/// that is not a finite number, a negative thickness, an aperture ≤ 0, an `eta` between 0 and 1,
/// an unknown glass, a glass whose n_d disagrees with `eta`); [`LensError::System`] for the lens
/// as a whole.
pub fn parse_pbrt(text: &str, source: &Path) -> Result<LensSystem, LensError> {
    let file = source.display().to_string();
    let mut surfaces = Vec::new();
    for (index, raw_line) in text.lines().enumerate() {
        let line = index + 1;
        let content = raw_line.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        let line_error = |message: String| LensError::Line { file: file.clone(), line, message };
        surfaces.push(parse_surface(content, line).map_err(line_error)?);
    }
    let mut system = LensSystem { surfaces, source: source.to_path_buf() };
    orient_file_coatings(&mut system);
    let Some(last) = system.surfaces.len().checked_sub(1) else { return system.validate().map(|()| system) };
    if system.surfaces[last].thickness_mm != 0.0 {
        return system.validate().map(|()| system);
    }
    // Check everything else first, with a placeholder image distance.
    system.surfaces[last].thickness_mm = 1.0;
    system.validate()?;
    match paraxial_back_focal_distance_mm(&system, LAMBDA_D_NM) {
        Some(distance) if distance > 0.0 && distance.is_finite() => {
            system.surfaces[last].thickness_mm = distance;
            Ok(system)
        }
        distance => Err(LensError::System {
            file,
            message: format!(
                "a sensor behind nothing: the last thickness (line {}) is 0, so the image plane is \
                 put at the paraxial focus for infinity at {LAMBDA_D_NM} nm, but the lens does not \
                 form a real image there (back focal distance {:?} mm); give the image distance",
                system.surfaces[last].line, distance
            ),
        }),
    }
}

/// One line's surface, or the message naming the column that is wrong.
fn parse_surface(content: &str, line: usize) -> Result<Surface, String> {
    let mut fields: Vec<&str> = content.split_whitespace().collect();
    let coating = match fields.iter().position(|field| is_coat_token(field)) {
        None => None,
        Some(position) => {
            let token = fields.remove(position);
            if position < 4 {
                return Err(format!(
                    "field {} (coat): \"{token}\" must follow the four numbers (and the glass)",
                    position + 1
                ));
            }
            if let Some(second) = fields.iter().find(|field| is_coat_token(field)) {
                return Err(format!("a second coat= token \"{second}\": give one coating per surface"));
            }
            Some(coating_column(token, position + 1)?)
        }
    };
    if fields.len() < 4 {
        return Err(format!(
            "{} columns, expected 4 (radius thickness eta aperture_diameter, mm) and an optional glass: \
             column {} ({}) is missing",
            fields.len(),
            fields.len() + 1,
            COLUMNS[fields.len()]
        ));
    }
    if fields.len() > 5 {
        return Err(format!(
            "{} columns, expected 4 (radius thickness eta aperture_diameter, mm) and an optional glass",
            fields.len()
        ));
    }
    let mut numbers = [0.0_f64; 4];
    for (column, (field, number)) in fields.iter().zip(numbers.iter_mut()).enumerate() {
        *number = match field.parse::<f64>() {
            Ok(value) if value.is_finite() => value,
            _ => {
                return Err(format!(
                    "column {} ({}): \"{field}\" is not a finite number",
                    column + 1,
                    COLUMNS[column]
                ))
            }
        };
    }
    let [radius_mm, thickness_mm, eta, aperture_mm] = numbers;
    if thickness_mm < 0.0 {
        return Err(format!("column 2 (thickness): {thickness_mm} mm is negative"));
    }
    if aperture_mm <= 0.0 {
        return Err(format!("column 4 (aperture diameter): {aperture_mm} mm must be > 0"));
    }
    if eta != 0.0 && eta < 1.0 {
        return Err(format!("column 3 (eta): {eta} must be 0 or 1 for air, or an index ≥ 1"));
    }
    let medium = match fields.get(4) {
        None if eta == 0.0 || eta == 1.0 => Medium::Air,
        None => Medium::constant(eta),
        Some(spec) => {
            let medium = parse_glass_spec(spec).map_err(|message| format!("column 5 (glass): {message}"))?;
            let eta_n = if eta == 0.0 { 1.0 } else { eta };
            let n_d = medium.n_at_nm(LAMBDA_D_NM);
            if n_d.is_nan() || (n_d - eta_n).abs() > ETA_GLASS_TOLERANCE {
                return Err(format!(
                    "column 5 (glass): {} has n_d = {n_d:.5} but column 3 (eta) is {eta}; they must agree \
                     within {ETA_GLASS_TOLERANCE} (a wrong glass?)",
                    medium.name()
                ));
            }
            medium
        }
    };
    Ok(Surface {
        radius_mm,
        conic: 0.0,
        aspheric_mm: Vec::new(),
        thickness_mm,
        medium,
        semi_diameter_mm: aperture_mm / 2.0,
        is_stop: radius_mm == 0.0,
        coating,
        line,
    })
}

/// Whether a field is the `coat=` token.
fn is_coat_token(field: &str) -> bool {
    field.get(..5).is_some_and(|prefix| prefix.eq_ignore_ascii_case("coat="))
}

/// The coating of a `coat=SPEC` token at 1-based field `position`, checked as
/// [`LensSystem::validate`] would.
fn coating_column(token: &str, position: usize) -> Result<Coating, String> {
    let coating = parse_coating_spec(&token[5..])
        .and_then(|coating| coating.check(super::prescription::VALIDATE_RANGE_NM).map(|()| coating))
        .map_err(|message| format!("field {position} (coat): {message}"))?;
    Ok(coating)
}

/// The paraxial back focal distance (mm, from the last vertex) at `lambda_nm` for an object at
/// infinity, by the y–nu trace of a marginal ray entering parallel to the axis (Smith, *Modern
/// Optical Engineering*, §3.3): n′u′ = nu − yφ with φ = (n′ − n)c, and y advancing by t·u′. A
/// conic or asphere refracts paraxially like a sphere of curvature c + 2α₁. `None` when the ray
/// leaves parallel or diverging (no real focus).
fn paraxial_back_focal_distance_mm(system: &LensSystem, lambda_nm: f64) -> Option<f64> {
    let mut height = 1.0;
    let mut slope = 0.0;
    let last = system.surfaces.len().checked_sub(1)?;
    for (index, surface) in system.surfaces.iter().enumerate() {
        let n_before = system.medium_before(index).n_at_nm(lambda_nm);
        let n_after = surface.medium.n_at_nm(lambda_nm);
        let curvature =
            surface.curvature_per_mm() + 2.0 * surface.aspheric_mm.first().copied().unwrap_or(0.0);
        let power = (n_after - n_before) * curvature;
        slope = (n_before * slope - height * power) / n_after;
        if index < last {
            height += surface.thickness_mm * slope;
        }
    }
    (slope < 0.0).then(|| -height / slope)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<LensSystem, LensError> {
        parse_pbrt(text, Path::new("lens.dat"))
    }

    fn line_error(text: &str) -> (usize, String) {
        match parse(text) {
            Err(LensError::Line { line, message, .. }) => (line, message),
            other => panic!("expected a line error, got {other:?}"),
        }
    }

    const SINGLET: &str = "# a biconvex singlet\n\
                           \n\
                           50 5 1.5 20   # front\n\
                           -50 1 1 20\n\
                           0 40 0 10\n";

    #[test]
    fn numbers_are_read_as_written() {
        let system = parse(SINGLET).expect("valid singlet");
        let [front, back, stop] = system.surfaces.as_slice() else { panic!("three surfaces") };
        assert_eq!(
            (front.radius_mm, front.thickness_mm, front.semi_diameter_mm, front.line),
            (50.0, 5.0, 10.0, 3)
        );
        assert_eq!(front.medium, Medium::constant(1.5));
        assert!(!front.is_stop);
        assert_eq!((back.radius_mm, back.medium.clone(), back.line), (-50.0, Medium::Air, 4));
        assert!(stop.is_stop && stop.radius_mm == 0.0 && stop.medium == Medium::Air);
        assert_eq!((stop.thickness_mm, stop.semi_diameter_mm), (40.0, 5.0));
        assert_eq!(system.stop_index(), Some(2));
    }

    #[test]
    fn a_last_thickness_of_zero_focuses_at_infinity() {
        // Thick lens in air (Hecht, Optics, §6.2): 1/f = (n − 1)[1/R1 − 1/R2 + (n − 1)d/(n R1 R2)],
        // back focal distance f (1 − (n − 1)d/(n R1)). Here the stop comes first, 2 mm ahead.
        let (n, r1, r2, d) = (1.5_f64, 50.0_f64, -50.0_f64, 5.0_f64);
        let f = 1.0 / ((n - 1.0) * (1.0 / r1 - 1.0 / r2 + (n - 1.0) * d / (n * r1 * r2)));
        let bfd = f * (1.0 - (n - 1.0) * d / (n * r1));
        let system = parse("0 2 0 10\n50 5 1.5 20\n-50 0 1 20\n").expect("valid");
        let image = system.surfaces[2].thickness_mm;
        // The y–nu trace and the closed form agree to f64 rounding of a few operations.
        assert!((image - bfd).abs() < 1e-12 * bfd, "{image} vs {bfd}");
        // A diverging lens has no real focus behind it.
        match parse("0 2 0 10\n-50 5 1.5 20\n50 0 1 20\n") {
            Err(LensError::System { message, .. }) => {
                assert!(
                    message.starts_with("a sensor behind nothing: the last thickness (line 3) is 0"),
                    "{message}"
                )
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_glass_column_gives_the_dispersion() {
        let system = parse("50 5 1.517 20 N-BK7\n-50 1 1 20 air\n0 40 0 10\n").expect("valid");
        let glass = &system.surfaces[0].medium;
        assert_eq!(glass.name(), "N-BK7");
        // N-BK7 (SCHOTT data sheet): n_F = 1.52238, n_C = 1.51432, to 5 decimals.
        assert!((glass.n_at_nm(486.1327) - 1.52238).abs() < 1e-5);
        assert!((glass.n_at_nm(656.2725) - 1.51432).abs() < 1e-5);
        assert_eq!(system.surfaces[1].medium, Medium::Air);
        let abbe = parse("50 5 1.6 20 abbe:1.6,40\n-50 1 0 20\n0 40 0 10\n").expect("valid");
        assert!((abbe.surfaces[0].medium.n_at_nm(LAMBDA_D_NM) - 1.6).abs() < 1e-14);
    }

    #[test]
    fn bad_lines_name_the_line_and_column() {
        let cases = [
            ("50 5 1.5\n", 1, "3 columns, expected 4 (radius thickness eta aperture_diameter, mm) and an optional glass: column 4 (aperture diameter) is missing"),
            ("# c\n50 5 1.5 20\n-50 x 1 20\n", 3, "column 2 (thickness): \"x\" is not a finite number"),
            ("50 5 NaN 20\n", 1, "column 3 (eta): \"NaN\" is not a finite number"),
            ("50 5 1.5 inf\n", 1, "column 4 (aperture diameter): \"inf\" is not a finite number"),
            ("50 5 1.5 -20\n", 1, "column 4 (aperture diameter): -20 mm must be > 0"),
            ("50 -5 1.5 20\n", 1, "column 2 (thickness): -5 mm is negative"),
            ("50 5 0.5 20\n", 1, "column 3 (eta): 0.5 must be 0 or 1 for air, or an index ≥ 1"),
            ("50 5 1.5 20 N-BK7 extra\n", 1, "6 columns, expected 4 (radius thickness eta aperture_diameter, mm) and an optional glass"),
            ("50 5 1.67 20 N-BK7\n", 1, "column 5 (glass): N-BK7 has n_d = 1.51680 but column 3 (eta) is 1.67; they must agree within 0.01 (a wrong glass?)"),
            ("50 5 0 20 N-BK7\n", 1, "column 5 (glass): N-BK7 has n_d = 1.51680 but column 3 (eta) is 0; they must agree within 0.01 (a wrong glass?)"),
        ];
        for (text, line, message) in cases {
            assert_eq!(line_error(text), (line, message.to_owned()), "{text}");
        }
        let (line, message) = line_error("50 5 1.5 20 unobtainium\n");
        assert_eq!(line, 1);
        assert!(message.starts_with("column 5 (glass): unknown glass \"unobtainium\""), "{message}");
        let display = parse("50 5 1.5 -20\n").expect_err("bad").to_string();
        assert_eq!(display, "lens.dat:1: column 4 (aperture diameter): -20 mm must be > 0");
    }

    #[test]
    fn bad_systems_are_system_errors() {
        let system_error = |text: &str| match parse(text) {
            Err(LensError::System { file, message }) => {
                assert_eq!(file, "lens.dat");
                message
            }
            other => panic!("expected a system error for {text:?}, got {other:?}"),
        };
        assert!(system_error("# nothing\n").starts_with("no surfaces"));
        assert!(system_error("50 5 1.5 20\n-50 40 1 20\n").starts_with("no aperture stop"));
        assert_eq!(
            system_error("0 1 0 10\n50 5 1.5 20\n-50 1 1 20\n0 40 0 10\n"),
            "two aperture stops, surface 1 (line 1) and surface 4 (line 4): mark only one"
        );
        // R = 50 mm, clear semi-diameter 10 mm: each sag is 50 − √(50² − 10²) = 1.0102 mm, so a
        // 1 mm centre thickness makes the two faces cross at the rim.
        let crossing = system_error("50 1 1.5 20\n-50 1 1 20\n0 40 0 10\n");
        assert!(
            crossing.starts_with("surface 1 (line 1) and surface 2 (line 2) cross: at 10 mm"),
            "{crossing}"
        );
        let too_wide = system_error("5 5 1.5 20\n-50 1 1 20\n0 40 0 10\n");
        assert!(
            too_wide.starts_with("surface 1 (line 1): semi-diameter 10 mm is beyond the surface's edge"),
            "{too_wide}"
        );
    }

    #[test]
    fn coat_tokens_coat_the_surface_facing_the_air() {
        use crate::lens::coating::named_ar;
        let system = parse("50 5 1.5 20 coat=AR\n-50 1 1 20 air coat=MgF2@100/2.05@50\n0 40 0 10\n")
            .expect("coated singlet");
        assert_eq!(system.surfaces[0].coating, Some(named_ar()));
        // Glass to air: the layers written air side first are stored object side first, reversed.
        let back = system.surfaces[1].coating.as_ref().expect("coated");
        assert_eq!(back.layers.iter().map(|l| l.thickness_nm).collect::<Vec<_>>(), [50.0, 100.0]);
        assert_eq!(system.surfaces[2].coating, None);
        // Without coat= tokens a line reads as before: the same surfaces, uncoated.
        let bare = parse("50 5 1.5 20\n-50 1 1 20 air\n0 40 0 10\n").expect("bare");
        for (coated, bare) in system.surfaces.iter().zip(&bare.surfaces) {
            assert_eq!(Surface { coating: None, ..coated.clone() }, *bare);
        }
    }

    #[test]
    fn misplaced_or_bad_coat_tokens_name_the_field() {
        assert_eq!(
            line_error("50 5 coat=AR 1.5 20\n"),
            (1, "field 3 (coat): \"coat=AR\" must follow the four numbers (and the glass)".to_owned())
        );
        assert_eq!(
            line_error("50 5 1.5 20 coat=AR coat=AR\n"),
            (1, "a second coat= token \"coat=AR\": give one coating per surface".to_owned())
        );
        assert_eq!(
            line_error("0 40 0 10\n50 5 1.5 20 N-BK7 COAT=MgF2@-1\n"),
            (2, "field 6 (coat): layer 1 \"MgF2@-1\": thickness -1 nm must be > 0".to_owned())
        );
    }
}

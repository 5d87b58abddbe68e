//! Zemax OpticStudio `.zmx` files, the common subset of a rotationally symmetric sequential lens.
//!
//! Read: `UNIT MM` (other units are an error: convert the file to millimetres), `SURF n`
//! (numbered 0, 1, … in order), and in a surface `TYPE STANDARD` or `TYPE EVENASPH`, `CURV`
//! (curvature in 1/mm: radius 1/CURV, 0 flat), `CONI` (conic constant), `PARM 1..8` of an even
//! asphere (the coefficients of r², r⁴, …, r¹⁶), `DISZ` (thickness to the next surface, mm;
//! `INFINITY` on the object surface only), `GLAS` (the medium behind the surface), `DIAM` (the
//! clear semi-diameter, mm) and `STOP`.
//!
//! Surface 0 is the object: it must be at `DISZ INFINITY` (a finite object distance is not
//! supported yet) and in air; it is not a surface of the [`LensSystem`]. The last surface is the
//! image plane (flat): it is not a surface either, and its position is the `DISZ` of the surface
//! before it.
//!
//! `GLAS NAME …` resolves NAME in the catalogue (`data/glasses.toml`); when NAME is not there but
//! the line carries n_d and V_d (its 4th and 5th fields, as Zemax writes every glass and as a
//! model glass `GLAS ___BLANK 1 0 nd vd …` is defined), the glass is modelled from them
//! ([`abbe_formula`], V_d = 0 meaning a constant index) and named `NAME (model n_d …, V_d …)`.
//! A catalogue glass whose n_d on the line differs from the catalogue's by more than 0.01 is an
//! error (a different glass under the same name). `GLAS AIR` is air.
//!
//! Keywords that change the optics in ways not modelled here are errors naming the line and the
//! keyword ([`UNSUPPORTED`], other surface `TYPE`s, `GLAS MIRROR`, a non-zero `PARM` on a
//! `STANDARD` surface, a curved image surface). Bookkeeping keywords ([`IGNORED`]: names, notes,
//! wavelengths, fields, pupil settings, drawing and tolerancing data) are skipped. Any other
//! keyword is an error: prisma cannot tell whether it changes the optics.
//!
//! `COAT NAME` coats the surface with a coating of the names prisma defines ([`read_coat`]):
//! `AR`, one quarter-wave layer of MgF₂ (n = 1.38) at 550 nm ([`super::coating::named_ar`]),
//! oriented as OpticStudio orients a coating (air side first, [`super::coating`]). This is
//! prisma's definition, not a copy of OpticStudio's: its sample coating file `COATING.DAT` also
//! has an `AR`, a single MgF₂ layer, but gives MgF₂ by a table of indices (1.38387 at 0.4 µm to
//! 1.37608 at 0.7 µm) and states layer thicknesses relative to the lens's wavelengths, so the two
//! differ a little (data/lenses/README.md). A `COAT` line without a name is an uncoated surface.
//! Any other name is an error naming the line: its layers are in a coating file prisma does not
//! read, and reading the surface bare would brighten the lens and its ghosts unnoticed.

use std::path::Path;

use super::coating::{named_ar, orient_file_coatings, Coating, NAMED_AR};
use super::glass_spec::{abbe_formula, catalogue_medium, unknown_glass_message};
use super::{LensError, LensSystem, Medium, Surface};
use crate::optics::dispersion::LAMBDA_D_NM;

/// How far (absolute) the n_d written on a `GLAS` line may differ from the catalogue's for the
/// same name: catalogue editions differ by ~1e-5; another glass under the same name by far more.
pub const GLAS_ND_TOLERANCE: f64 = 0.01;

/// Keywords skipped: they do not change the geometry or the media of a sequential, rotationally
/// symmetric lens. They are system data, wavelengths and fields, pupil and ray-aiming settings,
/// optimisation, tolerancing and multi-configuration data, solve, pickup and variable flags (the
/// values they set are stored in the surface data), drawing data such as `MIRR` (the mirror
/// *substrate* drawn, written on every surface; a mirror is `GLAS MIRROR`).
pub const IGNORED: &[&str] = &[
    "VERS", "MODE", "NAME", "NOTE", "PFIL", "LANG", "ENPD", "ENVD", "FNUM", "OBNA", "FLOA", "FTYP", "WAVL",
    "WAVM", "WAVN", "WWGT", "WWGN", "PWAV", "GCAT", "GFAC", "GLRS", "GSTD", "RAIM", "PUPD", "PUSH", "SDMA",
    "ROPD", "PICB", "XFLD", "YFLD", "XFLN", "YFLN", "FWGT", "FWGN", "VDXN", "VDYN", "VCXN", "VCYN", "VANN",
    "ZVDX", "ZVDY", "ZVCX", "ZVCY", "ZVAN", "OPDX", "EFFL", "COFN", "NSCD", "BLNK", "TOL", "TOLE", "MNUM",
    "MOFF", "CONF", "DMFS", "ISNA", "VDSZ", "MNCA", "MNEA", "MNCG", "MNEG", "MXCA", "MXCG", "RGLA", "TRAC",
    "TCMM", "PMAG", "TOTR", "POLS", "TCED", "HIDE", "MIRR", "SLAB", "POPS", "COMM", "FLAP", "MEMA", "FIMP",
    "PZUP", "PKUP", "PPAR", "VPAR", "VCON",
];

/// Keywords that change the optics in ways prisma does not model: decentres and tilts,
/// apertures other than the circular `DIAM`, obscurations, extra surface data. Each is an error
/// naming its line.
pub const UNSUPPORTED: &[&str] = &[
    "DECX", "DECY", "TILT", "SCBD", "CLAP", "OBSC", "OBDC", "SQAP", "SQOB", "ELAP", "ELOB", "UDAP", "USAP",
    "XDAT", "YDAT",
];

/// The even-asphere coefficients read (`PARM 1..8`: r² … r¹⁶).
const EVENASPH_TERMS: usize = 8;

#[derive(Clone, Copy, PartialEq)]
enum SurfaceType {
    Standard,
    EvenAsphere,
}

#[derive(Clone, Copy, PartialEq)]
enum Thickness {
    Finite(f64),
    Infinity,
}

/// One `SURF` block as written.
struct RawSurface {
    line: usize,
    surface_type: SurfaceType,
    curvature: f64,
    conic: f64,
    /// (index, value, line) of every non-zero `PARM`.
    parameters: Vec<(i64, f64, usize)>,
    thickness: Option<(Thickness, usize)>,
    medium: Medium,
    semi_diameter_mm: Option<f64>,
    stop_line: Option<usize>,
    glass_line: Option<usize>,
    /// The coating and the line of its `COAT`.
    coating: Option<(Coating, usize)>,
}

/// Parses and [validates](LensSystem::validate) the text of a Zemax `.zmx` file read from
/// `source` (named in errors); see the module header for the subset read.
///
/// # Errors
/// [`LensError::Line`] naming the line and keyword that is wrong or not supported;
/// [`LensError::System`] for the lens as a whole (fewer than three surfaces, no stop, …).
pub fn parse_zmx(text: &str, source: &Path) -> Result<LensSystem, LensError> {
    let file = source.display().to_string();
    let line_error = |line: usize, message: String| LensError::Line { file: file.clone(), line, message };
    let mut raw: Vec<RawSurface> = Vec::new();
    for (index, text_line) in text.lines().enumerate() {
        let line = index + 1;
        let mut fields = text_line.split_whitespace();
        let Some(keyword) = fields.next() else { continue };
        let args: Vec<&str> = fields.collect();
        read_keyword(keyword, &args, line, &mut raw).map_err(|message| line_error(line, message))?;
    }
    let mut system =
        LensSystem { surfaces: assemble(&raw, &line_error, &file)?, source: source.to_path_buf() };
    orient_file_coatings(&mut system);
    system.validate()?;
    Ok(system)
}

/// Applies one line to the surfaces read so far.
fn read_keyword(keyword: &str, args: &[&str], line: usize, raw: &mut Vec<RawSurface>) -> Result<(), String> {
    let number = |position: usize| -> Result<f64, String> {
        let Some(field) = args.get(position) else {
            return Err(format!("{keyword}: field {} is missing", position + 1));
        };
        match field.parse::<f64>() {
            Ok(value) if value.is_finite() => Ok(value),
            _ => Err(format!("{keyword}: field {} \"{field}\" is not a finite number", position + 1)),
        }
    };
    match keyword {
        "UNIT" => match args.first() {
            Some(&"MM") => Ok(()),
            other => Err(format!(
                "UNIT {}: only lenses in millimetres (UNIT MM) are read; convert the file in the design code",
                other.unwrap_or(&"(none)")
            )),
        },
        "SURF" => {
            let expected = raw.len();
            if args.first().and_then(|n| n.parse::<usize>().ok()) != Some(expected) {
                return Err(format!("SURF: expected surface number {expected} (surfaces are numbered 0, 1, … in order)"));
            }
            raw.push(RawSurface {
                line,
                surface_type: SurfaceType::Standard,
                curvature: 0.0,
                conic: 0.0,
                parameters: Vec::new(),
                thickness: None,
                medium: Medium::Air,
                semi_diameter_mm: None,
                stop_line: None,
                glass_line: None,
                coating: None,
            });
            Ok(())
        }
        "TYPE" | "CURV" | "CONI" | "PARM" | "DISZ" | "GLAS" | "DIAM" | "STOP" | "COAT" => {
            let surface_number = raw.len().checked_sub(1);
            let Some(surface) = raw.last_mut() else {
                return Err(format!("{keyword} before the first SURF"));
            };
            match keyword {
                "TYPE" => {
                    surface.surface_type = match args.first() {
                        Some(&"STANDARD") => SurfaceType::Standard,
                        Some(&"EVENASPH") => SurfaceType::EvenAsphere,
                        other => {
                            return Err(format!(
                                "TYPE {}: not supported (prisma reads TYPE STANDARD and TYPE EVENASPH)",
                                other.unwrap_or(&"(none)")
                            ))
                        }
                    }
                }
                "CURV" => surface.curvature = number(0)?,
                "CONI" => surface.conic = number(0)?,
                "PARM" => {
                    let index = number(0)?;
                    let value = number(1)?;
                    if value != 0.0 {
                        surface.parameters.push((index as i64, value, line));
                    }
                }
                "DISZ" => {
                    let thickness = if args.first() == Some(&"INFINITY") {
                        if surface_number != Some(0) {
                            return Err("DISZ INFINITY: only the object surface (SURF 0) may be at infinity".to_owned());
                        }
                        Thickness::Infinity
                    } else {
                        let value = number(0)?;
                        if value < 0.0 && surface_number != Some(0) {
                            return Err(format!("DISZ: {value} mm is negative (mirrors and folded lenses are not supported)"));
                        }
                        Thickness::Finite(value)
                    };
                    surface.thickness = Some((thickness, line));
                }
                "GLAS" => {
                    surface.medium = glass(args, &number)?;
                    surface.glass_line = Some(line);
                }
                "DIAM" => surface.semi_diameter_mm = Some(number(0)?),
                "COAT" => surface.coating = read_coat(args)?.map(|coating| (coating, line)),
                _ => surface.stop_line = Some(line),
            }
            Ok(())
        }
        _ if IGNORED.contains(&keyword) => Ok(()),
        _ if UNSUPPORTED.contains(&keyword) => {
            Err(format!("{keyword}: not supported (it changes the optics; prisma reads rotationally symmetric, centred lenses)"))
        }
        _ => Err(format!(
            "unknown keyword {keyword}: prisma reads the .zmx subset listed in scenes/README.md and cannot tell \
             whether {keyword} changes the optics"
        )),
    }
}

/// The coating of a `COAT` line: `None` without a name, `AR` (module header), else an error.
fn read_coat(args: &[&str]) -> Result<Option<Coating>, String> {
    match args.first() {
        None => Ok(None),
        Some(name) if name.eq_ignore_ascii_case(NAMED_AR) => Ok(Some(named_ar())),
        Some(name) => Err(format!(
            "COAT {name}: unknown coating (prisma defines {NAMED_AR}, a quarter-wave MgF2 layer at 550 nm; \
             other coatings live in a coating file prisma does not read: use {NAMED_AR} or remove the line)"
        )),
    }
}

/// The medium of a `GLAS` line.
fn glass(args: &[&str], number: &dyn Fn(usize) -> Result<f64, String>) -> Result<Medium, String> {
    let Some(&name) = args.first() else {
        return Err("GLAS: field 1 (the glass name) is missing".to_owned());
    };
    if name.eq_ignore_ascii_case("MIRROR") {
        return Err("GLAS MIRROR: mirrors are not supported (prisma reads refracting lenses)".to_owned());
    }
    if name.eq_ignore_ascii_case("AIR") {
        return Ok(Medium::Air);
    }
    // Zemax writes n_d and V_d as the 4th and 5th fields; 0 or absent means "not given".
    let n_d = number(3).ok().filter(|&n_d| n_d != 0.0);
    let v_d = number(4).ok();
    if let Some(medium) = catalogue_medium(name) {
        let catalogue_n_d = medium.n_at_nm(LAMBDA_D_NM);
        if let Some(n_d) = n_d.filter(|n_d| (n_d - catalogue_n_d).abs() > GLAS_ND_TOLERANCE) {
            return Err(format!(
                "GLAS {name}: the line gives n_d = {n_d} but the catalogue's {} has n_d = {catalogue_n_d:.5}; \
                 they must agree within {GLAS_ND_TOLERANCE} (another glass under the same name?)",
                medium.name()
            ));
        }
        return Ok(medium);
    }
    match (n_d, v_d) {
        (Some(n_d), Some(v_d)) => {
            let formula =
                abbe_formula(n_d, v_d).map_err(|message| format!("GLAS {name} (model glass): {message}"))?;
            Ok(Medium::Glass { name: format!("{name} (model n_d {n_d}, V_d {v_d})"), formula })
        }
        _ => Err(format!(
            "GLAS {}; a glass outside it needs n_d and V_d in fields 4 and 5 (GLAS NAME 1 0 nd vd)",
            unknown_glass_message(name)
        )),
    }
}

/// The lens surfaces between the object (surface 0) and the image (the last surface).
fn assemble(
    raw: &[RawSurface],
    line_error: &dyn Fn(usize, String) -> LensError,
    file: &str,
) -> Result<Vec<Surface>, LensError> {
    if raw.len() < 3 {
        return Err(LensError::System {
            file: file.to_owned(),
            message: format!(
                "{} SURF blocks: a lens needs the object (SURF 0), at least one surface and the image",
                raw.len()
            ),
        });
    }
    let object = &raw[0];
    match object.thickness {
        Some((Thickness::Infinity, _)) => {}
        Some((Thickness::Finite(_), line)) => return Err(line_error(
            line,
            "DISZ: the object surface must be at INFINITY (a finite object distance is not supported yet)"
                .to_owned(),
        )),
        None => {
            return Err(line_error(object.line, "SURF 0: the object surface needs DISZ INFINITY".to_owned()))
        }
    }
    if let (Some(line), false) = (object.glass_line, object.medium == Medium::Air) {
        return Err(line_error(line, "GLAS: object space must be air".to_owned()));
    }
    let image = &raw[raw.len() - 1];
    for (surface, role) in [(object, "object"), (image, "image")] {
        if let Some(line) = surface.stop_line {
            return Err(line_error(line, format!("STOP: the {role} surface cannot be the aperture stop")));
        }
        if let Some((_, line)) = surface.coating {
            return Err(line_error(
                line,
                format!("COAT: the {role} surface is not a lens surface and takes no coating"),
            ));
        }
    }
    if image.curvature != 0.0 || image.surface_type != SurfaceType::Standard {
        return Err(line_error(
            image.line,
            "SURF: a curved image surface is not supported (the image is a plane)".to_owned(),
        ));
    }
    let mut surfaces = Vec::with_capacity(raw.len() - 2);
    for (number, surface) in raw.iter().enumerate().take(raw.len() - 1).skip(1) {
        let mut aspheric_mm = vec![0.0; EVENASPH_TERMS];
        for &(index, value, line) in &surface.parameters {
            let in_range = (1..=EVENASPH_TERMS as i64).contains(&index);
            match (surface.surface_type, in_range) {
                (SurfaceType::EvenAsphere, true) => aspheric_mm[index as usize - 1] = value,
                (SurfaceType::EvenAsphere, false) => {
                    return Err(line_error(line, format!("PARM {index}: an even asphere has PARM 1..8")))
                }
                (SurfaceType::Standard, _) => {
                    return Err(line_error(
                        line,
                        format!(
                            "PARM {index} = {value} on a STANDARD surface: not supported (it changes the \
                             surface; prisma reads PARM 1..8 of TYPE EVENASPH)"
                        ),
                    ))
                }
            }
        }
        while aspheric_mm.last() == Some(&0.0) {
            aspheric_mm.pop();
        }
        let thickness_mm = match surface.thickness {
            Some((Thickness::Finite(value), _)) => value,
            _ => {
                return Err(line_error(
                    surface.line,
                    format!("SURF {number}: no DISZ (the thickness to the next surface)"),
                ))
            }
        };
        let Some(semi_diameter_mm) = surface.semi_diameter_mm else {
            return Err(line_error(
                surface.line,
                format!("SURF {number}: no DIAM (the clear semi-diameter)"),
            ));
        };
        surfaces.push(Surface {
            radius_mm: if surface.curvature == 0.0 { 0.0 } else { 1.0 / surface.curvature },
            conic: surface.conic,
            aspheric_mm,
            thickness_mm,
            medium: surface.medium.clone(),
            semi_diameter_mm,
            is_stop: surface.stop_line.is_some(),
            coating: surface.coating.as_ref().map(|(coating, _)| coating.clone()),
            line: surface.line,
        });
    }
    Ok(surfaces)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<LensSystem, LensError> {
        parse_zmx(text, Path::new("lens.zmx"))
    }

    fn line_error(text: &str) -> (usize, String) {
        match parse(text) {
            Err(LensError::Line { line, message, .. }) => (line, message),
            other => panic!("expected a line error, got {other:?}"),
        }
    }

    /// An N-BK7 singlet with the stop in front, as OpticStudio writes one (trimmed).
    const SINGLET: &str = "VERS 190513 80 123457 L123457\n\
        MODE SEQ\n\
        NAME singlet\n\
        UNIT MM X W X CM MR CPMM\n\
        ENPD 20\n\
        SURF 0\n  TYPE STANDARD\n  CURV 0.0 0 0 0 0 \"\"\n  HIDE 0 0 0 0 0 0 0 0 0 0\n  MIRR 2 0\n  DISZ INFINITY\n\
        SURF 1\n  STOP\n  TYPE STANDARD\n  CURV 0.0\n  DISZ 2\n  DIAM 10 1 0 0 1 \"\"\n\
        SURF 2\n  TYPE STANDARD\n  CURV 2.0E-2 0 0 0 0 \"\"\n  DISZ 5\n  GLAS N-BK7 1 0 1.5168 64.17 0 0 0 0 0 0\n  DIAM 12 1 0 0 1 \"\"\n\
        SURF 3\n  TYPE STANDARD\n  CURV -2.0E-2\n  DISZ 47.5\n  DIAM 12\n\
        SURF 4\n  TYPE STANDARD\n  CURV 0\n  DISZ 0\n  DIAM 5\n";

    /// The singlet with the line `find` replaced by `replace`.
    fn singlet_with(find: &str, replace: &str) -> String {
        assert!(SINGLET.contains(find), "{find}");
        SINGLET.replacen(find, replace, 1)
    }

    #[test]
    fn numbers_are_read_as_written() {
        let system = parse(SINGLET).expect("valid singlet");
        let [stop, front, back] = system.surfaces.as_slice() else { panic!("three surfaces") };
        assert!(stop.is_stop && stop.radius_mm == 0.0 && stop.medium == Medium::Air);
        assert_eq!((stop.thickness_mm, stop.semi_diameter_mm, stop.line), (2.0, 10.0, 12));
        assert_eq!((front.radius_mm, front.thickness_mm, front.semi_diameter_mm), (50.0, 5.0, 12.0));
        assert_eq!(front.medium.name(), "N-BK7");
        assert_eq!((back.radius_mm, back.thickness_mm, back.medium.clone()), (-50.0, 47.5, Medium::Air));
        assert!(front.aspheric_mm.is_empty() && front.conic == 0.0);
    }

    #[test]
    fn even_aspheres_and_conics_are_read() {
        let text = singlet_with(
            "  CURV -2.0E-2\n",
            "  TYPE EVENASPH\n  CURV -2.0E-2\n  CONI -0.5\n  PARM 1 0\n  PARM 2 1e-6\n  PARM 3 -2e-9\n  PARM 8 0\n",
        );
        let system = parse(&text).expect("valid asphere");
        let back = &system.surfaces[2];
        assert_eq!((back.conic, back.aspheric_mm.clone()), (-0.5, vec![0.0, 1e-6, -2e-9]));
    }

    #[test]
    fn model_glasses_use_nd_and_vd() {
        let text = singlet_with("GLAS N-BK7 1 0 1.5168 64.17", "GLAS ___BLANK 1 0 1.6 40");
        let system = parse(&text).expect("model glass");
        let medium = &system.surfaces[1].medium;
        assert_eq!(medium.name(), "___BLANK (model n_d 1.6, V_d 40)");
        // abbe_formula reproduces n_d exactly up to f64 rounding.
        assert!((medium.n_at_nm(LAMBDA_D_NM) - 1.6).abs() < 1e-14);
    }

    #[test]
    fn utf16_files_read_like_utf8() {
        let mut bytes = vec![0xFF, 0xFE];
        for unit in SINGLET.replace('\n', "\r\n").encode_utf16() {
            bytes.extend(unit.to_le_bytes());
        }
        let text = super::super::file::decode_text(&bytes).expect("UTF-16LE with a BOM");
        assert_eq!(parse(&text), parse(SINGLET));
    }

    #[test]
    fn unsupported_and_bad_lines_name_the_line_and_keyword() {
        let cases = [
            (singlet_with("UNIT MM", "UNIT IN"), 4, "UNIT IN: only lenses in millimetres (UNIT MM) are read; convert the file in the design code"),
            (singlet_with("  TYPE STANDARD\n  CURV 2.0E-2", "  TYPE COORDBRK\n  CURV 2.0E-2"), 19, "TYPE COORDBRK: not supported (prisma reads TYPE STANDARD and TYPE EVENASPH)"),
            (singlet_with("  TYPE STANDARD\n  CURV 2.0E-2", "  TYPE TOROIDAL\n  CURV 2.0E-2"), 19, "TYPE TOROIDAL: not supported (prisma reads TYPE STANDARD and TYPE EVENASPH)"),
            (singlet_with("  DISZ 5\n", "  DISZ 5\n  DECX 1\n"), 22, "DECX: not supported (it changes the optics; prisma reads rotationally symmetric, centred lenses)"),
            (singlet_with("  DISZ 5\n", "  DISZ 5\n  TILT 1\n"), 22, "TILT: not supported (it changes the optics; prisma reads rotationally symmetric, centred lenses)"),
            (singlet_with("GLAS N-BK7 1 0 1.5168 64.17 0 0 0 0 0 0", "GLAS MIRROR"), 22, "GLAS MIRROR: mirrors are not supported (prisma reads refracting lenses)"),
            (singlet_with("  DISZ 5\n", "  DISZ 5\n  PARM 2 1e-5\n"), 22, "PARM 2 = 0.00001 on a STANDARD surface: not supported (it changes the surface; prisma reads PARM 1..8 of TYPE EVENASPH)"),
            (singlet_with("  DISZ 5\n", "  DISZ 5\n  FROB 1\n"), 22, "unknown keyword FROB: prisma reads the .zmx subset listed in scenes/README.md and cannot tell whether FROB changes the optics"),
            (singlet_with("  DISZ 5\n", "  DISZ abc\n"), 21, "DISZ: field 1 \"abc\" is not a finite number"),
            (singlet_with("  DISZ 5\n", "  DISZ INFINITY\n"), 21, "DISZ INFINITY: only the object surface (SURF 0) may be at infinity"),
            (singlet_with("  DISZ 5\n", "  DISZ -5\n"), 21, "DISZ: -5 mm is negative (mirrors and folded lenses are not supported)"),
            (singlet_with("DISZ INFINITY", "DISZ 1000"), 11, "DISZ: the object surface must be at INFINITY (a finite object distance is not supported yet)"),
            (singlet_with("SURF 3", "SURF 4"), 24, "SURF: expected surface number 3 (surfaces are numbered 0, 1, … in order)"),
            (singlet_with("GLAS N-BK7 1 0 1.5168", "GLAS N-BK7 1 0 1.67"), 22, "GLAS N-BK7: the line gives n_d = 1.67 but the catalogue's N-BK7 has n_d = 1.51680; they must agree within 0.01 (another glass under the same name?)"),
            (singlet_with("  DIAM 12\n", "\n"), 24, "SURF 3: no DIAM (the clear semi-diameter)"),
            (format!("CURV 1\n{SINGLET}"), 1, "CURV before the first SURF"),
        ];
        for (text, line, message) in cases {
            assert_eq!(line_error(&text), (line, message.to_owned()), "{text}");
        }
        let (line, message) =
            line_error(&singlet_with("GLAS N-BK7 1 0 1.5168 64.17 0 0 0 0 0 0", "GLAS UNOBTAINIUM"));
        assert_eq!(line, 22);
        assert!(
            message.starts_with(
                "GLAS unknown glass \"UNOBTAINIUM\": the catalogue (data/glasses.toml) has N-BK7"
            ),
            "{message}"
        );
        assert!(
            message.ends_with("a glass outside it needs n_d and V_d in fields 4 and 5 (GLAS NAME 1 0 nd vd)")
        );
    }

    #[test]
    fn coat_ar_coats_the_surface_facing_the_air() {
        let text = singlet_with("  DISZ 5\n", "  DISZ 5\n  COAT AR\n  COAT\n");
        assert!(parse(&text).expect("bare").surfaces[1].coating.is_none(), "a nameless COAT is bare");
        let text = singlet_with("  DISZ 5\n", "  DISZ 5\n  COAT AR\n");
        let system = parse(&text).expect("AR");
        assert_eq!(system.surfaces[1].coating, Some(named_ar()));
        let (line, message) = line_error(&singlet_with("  DISZ 5\n", "  DISZ 5\n  COAT I.99\n"));
        assert_eq!(line, 22);
        assert!(message.starts_with("COAT I.99: unknown coating"), "{message}");
        let (line, message) = line_error(&singlet_with("SURF 4\n", "SURF 4\n  COAT AR\n"));
        assert_eq!(
            (line, message.as_str()),
            (30, "COAT: the image surface is not a lens surface and takes no coating")
        );
    }

    #[test]
    fn bad_systems_are_system_errors() {
        let system_error = |text: &str| match parse(text) {
            Err(LensError::System { message, .. }) => message,
            other => panic!("expected a system error, got {other:?}"),
        };
        assert_eq!(
            system_error("SURF 0\n  DISZ INFINITY\nSURF 1\n"),
            "2 SURF blocks: a lens needs the object (SURF 0), at least one surface and the image"
        );
        assert!(system_error(&singlet_with("  STOP\n", "")).starts_with("no aperture stop"));
        let behind_nothing = system_error(&singlet_with("DISZ 47.5", "DISZ 0"));
        assert!(behind_nothing.starts_with("a sensor behind nothing"), "{behind_nothing}");
    }
}

//! Coatings on lens surfaces: a stack of coherent thin layers between the media before and
//! after a surface, whose s and p amplitudes (reflection and transmission, with phase) replace
//! the bare Fresnel coefficients in the lens trace. The amplitudes come from the one
//! transfer-matrix method of [`crate::optics::thin_film`] (Macleod, *Thin-Film Optical
//! Filters*, 4th ed., §2.2–2.4), in f64; the ray's direction stays that of the bare interface
//! (the layers are thin and parallel, so n sin θ carries through them).
//!
//! # Orientation
//! A [`Coating`] holds its layers in the order a ray travelling toward the image crosses them
//! (object side first); a ray travelling toward the object crosses them last first, the same
//! stack seen from the other side. Lens files write a coating **air side first**, as
//! OpticStudio reads its coatings (Ansys OpticStudio User Guide, "Specifying Coatings on
//! Surfaces": as written on an air-to-glass boundary, reversed on glass-to-air, as written
//! between two glasses or two airs): [`orient_file_coatings`] turns the files' order into this
//! one.
//!
//! # In a lens file
//! A pbrt lens file line takes a `coat=SPEC` token after its numbers (and glass), a Zemax
//! surface a `COAT NAME` line. SPEC is [`AR`](NAMED_AR) or layers separated by `/`, air side
//! first, each `MATERIAL@THICKNESS`:
//! - MATERIAL: `MgF2` (n = [`MGF2_INDEX`] at every wavelength), a constant index (`1.38`), or a
//!   glass as in the glass column ([`super::glass_spec::parse_glass_spec`]: a catalogue name,
//!   `sellmeier:…`, `abbe:nd,vd`);
//! - THICKNESS: the physical thickness in nm, or `qwL`, a quarter wave at L nm (optical
//!   thickness n(L)·d = L/4).
//!
//! ```text
//! 29.475  3.76  1.67  25.2  N-BAF10  coat=MgF2@qw550
//! 84.83   0.12  1.0   25.2  air      coat=MgF2@99.64/2.05@134.15
//! ```

use num_complex::Complex64;

use super::glass_spec::parse_glass_spec;
use super::{LensSystem, Medium};
use crate::optics::{thin_film_amplitudes, Layer, ThinFilmAmplitudes};

/// Most layers a lens coating may have: the limit of the scenes' coatings
/// ([`crate::material::MAX_COATING_LAYERS`]).
pub const MAX_LAYERS: usize = crate::material::MAX_COATING_LAYERS;

/// Largest layer thickness in nm, 100 µm: the scenes' limit
/// ([`crate::scene::limits::MAX_COATING_THICKNESS_NM`]); a thicker "layer" is a plate, not a
/// coherent film.
pub const MAX_LAYER_THICKNESS_NM: f64 = crate::scene::limits::MAX_COATING_THICKNESS_NM as f64;

/// The index used for magnesium fluoride, `MgF2`: 1.38 at every wavelength, the textbook value
/// of the single-layer anti-reflection coating (Hecht, *Optics*, 5th ed., §9.7.1; Macleod §3.2).
/// The glass catalogue has no MgF₂ dispersion; a thin MgF₂ film's index varies by ~0.01 over the
/// visible, less than deposited films differ from one another.
pub const MGF2_INDEX: f64 = 1.38;

/// The named coating `AR`: one quarter-wave layer of `MgF2` at [`AR_DESIGN_NM`].
pub const NAMED_AR: &str = "AR";

/// The design wavelength of `AR`, in nm: the middle of the visible, where the eye is most
/// sensitive.
pub const AR_DESIGN_NM: f64 = 550.0;

/// Coatings of up to this many layers are evaluated in an array on the stack (longer ones in a
/// `Vec`).
const SHORT_COATING: usize = 8;

/// One coherent layer of a lens coating.
#[derive(Clone, Debug, PartialEq)]
pub struct CoatingLayer {
    /// The layer's material (a real, non-absorbing index n(λ)).
    pub medium: Medium,
    /// Physical thickness in nm, in (0, [`MAX_LAYER_THICKNESS_NM`]].
    pub thickness_nm: f64,
}

/// A coating on one lens surface.
#[derive(Clone, Debug, PartialEq)]
pub struct Coating {
    /// As the file names it (`AR`, `MgF2@qw550`, …), for reports.
    pub name: String,
    /// The layers in the order a ray travelling toward the image crosses them (object side
    /// first); at most [`MAX_LAYERS`].
    pub layers: Vec<CoatingLayer>,
}

impl Coating {
    /// The stack's amplitudes for a ray in index `n_in` meeting the surface at `cos_theta_i` in
    /// [0, 1] and entering index `n_out`, at `lambda_nm` (nm); `toward_image`: the ray travels
    /// toward the image (it crosses the layers as listed), else toward the object (last first).
    pub fn amplitudes(
        &self,
        toward_image: bool,
        n_in: f64,
        n_out: f64,
        lambda_nm: f64,
        cos_theta_i: f64,
    ) -> ThinFilmAmplitudes {
        let count = self.layers.len();
        let layer_at = |slot: usize| {
            let layer = &self.layers[if toward_image { slot } else { count - 1 - slot }];
            Layer::dielectric(layer.medium.n_at_nm(lambda_nm), layer.thickness_nm)
        };
        let substrate = Complex64::new(n_out, 0.0);
        if count <= SHORT_COATING {
            let mut short = [Layer::dielectric(1.0, 0.0); SHORT_COATING];
            for (slot, layer) in short[..count].iter_mut().enumerate() {
                *layer = layer_at(slot);
            }
            thin_film_amplitudes(n_in, &short[..count], substrate, lambda_nm, cos_theta_i)
        } else {
            let long: Vec<Layer> = (0..count).map(layer_at).collect();
            thin_film_amplitudes(n_in, &long, substrate, lambda_nm, cos_theta_i)
        }
    }

    /// The reflectance at normal incidence between indices `n_before` and `n_after` at
    /// `lambda_nm` (nm), the same from either side for these lossless layers.
    pub fn normal_reflectance(&self, n_before: f64, n_after: f64, lambda_nm: f64) -> f64 {
        self.amplitudes(true, n_before, n_after, lambda_nm, 1.0).reflectance_s
    }

    /// Checks the layer count, every thickness and every layer's index (finite and ≥ 1 from
    /// `range_nm.0` to `range_nm.1`, every 1 nm).
    ///
    /// # Errors
    /// A message naming the layer (1-based, as listed) and what is wrong.
    pub fn check(&self, range_nm: (f64, f64)) -> Result<(), String> {
        if self.layers.is_empty() {
            return Err("a coating needs at least one layer".to_owned());
        }
        if self.layers.len() > MAX_LAYERS {
            return Err(format!("{} layers: at most {MAX_LAYERS}", self.layers.len()));
        }
        for (index, layer) in self.layers.iter().enumerate() {
            check_thickness(layer.thickness_nm)
                .map_err(|message| format!("layer {}: {message}", index + 1))?;
            let mut lambda_nm = range_nm.0;
            while lambda_nm <= range_nm.1 {
                let n = layer.medium.n_at_nm(lambda_nm);
                if !(n.is_finite() && n >= 1.0) {
                    return Err(format!(
                        "layer {}: the index of {} is {n} at {lambda_nm} nm; it must be finite and ≥ 1 \
                         from {} to {} nm",
                        index + 1,
                        layer.medium.name(),
                        range_nm.0,
                        range_nm.1
                    ));
                }
                lambda_nm += 1.0;
            }
        }
        Ok(())
    }
}

/// A thickness in nm within (0, [`MAX_LAYER_THICKNESS_NM`]].
fn check_thickness(thickness_nm: f64) -> Result<(), String> {
    if !(thickness_nm.is_finite() && thickness_nm > 0.0) {
        return Err(format!("thickness {thickness_nm} nm must be > 0"));
    }
    if thickness_nm > MAX_LAYER_THICKNESS_NM {
        return Err(format!(
            "thickness {thickness_nm} nm is more than {MAX_LAYER_THICKNESS_NM} nm (100 µm: a coherent \
             coating layer is well under a micrometre; thicker is a plate)"
        ));
    }
    Ok(())
}

/// The `AR` coating: one quarter-wave `MgF2` layer at [`AR_DESIGN_NM`].
pub fn named_ar() -> Coating {
    Coating {
        name: NAMED_AR.to_owned(),
        layers: vec![CoatingLayer { medium: mgf2(), thickness_nm: AR_DESIGN_NM / (4.0 * MGF2_INDEX) }],
    }
}

/// `MgF2` as a medium.
fn mgf2() -> Medium {
    Medium::Glass {
        name: format!("MgF2 (n={MGF2_INDEX})"),
        formula: crate::optics::dispersion::DispersionFormula::Cauchy {
            a: MGF2_INDEX,
            b_um2: 0.0,
            c_um4: 0.0,
        },
    }
}

/// Parses a coating SPEC (module header): `AR`, or `MATERIAL@THICKNESS` layers separated by
/// `/`, in the file's order (air side first; see [`orient_file_coatings`]).
///
/// # Errors
/// A message naming the layer and what is wrong: an unknown material, a thickness that is not a
/// number, ≤ 0 or above [`MAX_LAYER_THICKNESS_NM`], more than [`MAX_LAYERS`] layers.
pub fn parse_coating_spec(spec: &str) -> Result<Coating, String> {
    if spec.eq_ignore_ascii_case(NAMED_AR) {
        return Ok(named_ar());
    }
    if spec.is_empty() {
        return Err(format!("empty: give {NAMED_AR} or layers MATERIAL@THICKNESS_NM separated by /"));
    }
    let count = spec.split('/').count();
    if count > MAX_LAYERS {
        return Err(format!("{count} layers: at most {MAX_LAYERS}"));
    }
    let layers = spec
        .split('/')
        .enumerate()
        .map(|(index, layer)| {
            parse_layer(layer).map_err(|message| format!("layer {} \"{layer}\": {message}", index + 1))
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Coating { name: spec.to_owned(), layers })
}

/// One `MATERIAL@THICKNESS` layer.
fn parse_layer(text: &str) -> Result<CoatingLayer, String> {
    let Some((material, thickness)) = text.rsplit_once('@') else {
        return Err(
            "expected MATERIAL@THICKNESS (thickness in nm, or qwL for a quarter wave at L nm)".to_owned()
        );
    };
    let medium = if material.eq_ignore_ascii_case("mgf2") {
        mgf2()
    } else if let Ok(n) = material.parse::<f64>() {
        if !(n.is_finite() && n >= 1.0) {
            return Err(format!("index {material} must be a finite number ≥ 1"));
        }
        Medium::constant(n)
    } else {
        let medium = parse_glass_spec(material)
            .map_err(|message| format!("material: {message}; or MgF2, or a constant index"))?;
        if medium == Medium::Air {
            return Err("material: a layer of air is no coating".to_owned());
        }
        medium
    };
    let thickness_nm = match thickness.strip_prefix("qw").or_else(|| thickness.strip_prefix("QW")) {
        Some(design) => {
            let design_nm = match design.parse::<f64>() {
                Ok(value) if value.is_finite() && value > 0.0 => value,
                _ => return Err(format!("qw{design}: the design wavelength must be a number > 0 (nm)")),
            };
            design_nm / (4.0 * medium.n_at_nm(design_nm))
        }
        None => thickness
            .parse::<f64>()
            .map_err(|_| format!("thickness \"{thickness}\" is not a number (nm) or qwL"))?,
    };
    check_thickness(thickness_nm)?;
    Ok(CoatingLayer { medium, thickness_nm })
}

/// Turns coatings read from a file (layers air side first) into the runtime order (object
/// side first): a surface from glass to air has its layers reversed; air to glass, glass to
/// glass and air to air keep the file's order (OpticStudio's rule, module header).
pub fn orient_file_coatings(system: &mut LensSystem) {
    for index in 0..system.surfaces.len() {
        let before_is_air = *system.medium_before(index) == Medium::Air;
        let surface = &mut system.surfaces[index];
        if let (Some(coating), false, Medium::Air) = (&mut surface.coating, before_is_air, &surface.medium) {
            coating.layers.reverse();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn specs_parse_into_layers() {
        let ar = parse_coating_spec("ar").expect("AR");
        assert_eq!(ar, named_ar());
        // Quarter wave: n·d = 550/4 nm, d = 99.637… nm.
        assert!((ar.layers[0].thickness_nm * MGF2_INDEX - 137.5).abs() < 1e-12);
        assert_eq!(parse_coating_spec("MgF2@qw550").expect("qw").layers, ar.layers);
        let two = parse_coating_spec("MgF2@99.64/2.05@134.15").expect("two layers");
        assert_eq!(two.layers.len(), 2);
        assert_eq!(two.layers[1], CoatingLayer { medium: Medium::constant(2.05), thickness_nm: 134.15 });
        let glass = parse_coating_spec("N-BK7@qw500").expect("a catalogue glass");
        assert_eq!(glass.layers[0].medium.name(), "N-BK7");
    }

    #[test]
    fn bad_specs_say_why() {
        let error = |spec: &str| parse_coating_spec(spec).expect_err(spec);
        assert!(error("unobtainium@100").contains("layer 1 \"unobtainium@100\": material: unknown glass"));
        assert!(error("MgF2@-5").contains("thickness -5 nm must be > 0"));
        assert!(error("MgF2@0").contains("must be > 0"));
        assert!(error("MgF2@2e5").contains("more than 100000 nm"));
        assert!(error("MgF2@nan").contains("must be > 0"));
        assert!(error("MgF2@x").contains("\"x\" is not a number"));
        assert!(error("MgF2").contains("expected MATERIAL@THICKNESS"));
        assert!(error("0.5@100").contains("≥ 1"));
        assert!(error("air@100").contains("a layer of air"));
        assert!(error("MgF2@qw0").contains("design wavelength"));
        assert!(error(&vec!["MgF2@100"; 65].join("/")).contains("65 layers: at most 64"));
        assert!(error("").contains("empty"));
    }

    #[test]
    fn a_quarter_wave_mgf2_layer_meets_its_closed_form() {
        // At the design wavelength and normal incidence a quarter-wave layer of index n₁ on a
        // substrate n₂ from air reflects R = ((n₂ − n₁²)/(n₂ + n₁²))² (Hecht §9.7.1); on
        // n₂ = 1.5168: ((1.5168 − 1.9044)/(1.5168 + 1.9044))² = 0.012841…; to f64 rounding.
        let n2 = 1.5168;
        let expected = ((n2 - MGF2_INDEX * MGF2_INDEX) / (n2 + MGF2_INDEX * MGF2_INDEX)).powi(2);
        let ar = named_ar();
        assert!((ar.normal_reflectance(1.0, n2, AR_DESIGN_NM) - expected).abs() < 1e-15);
        // The same from the glass side, the layers crossed the other way.
        let from_glass = ar.amplitudes(false, n2, 1.0, AR_DESIGN_NM, 1.0);
        assert!((from_glass.reflectance_s - expected).abs() < 1e-15);
    }

    #[test]
    fn file_coatings_face_the_air() {
        let layers = parse_coating_spec("MgF2@100/2.05@50").expect("two layers");
        let glass = Medium::constant(1.5);
        let mut surfaces = vec![
            super::super::Surface::spherical(10.0, 1.0, glass.clone(), 3.0, true),
            super::super::Surface::spherical(-10.0, 5.0, Medium::Air, 3.0, false),
        ];
        for surface in &mut surfaces {
            surface.coating = Some(layers.clone());
        }
        let mut system = LensSystem { surfaces, source: Default::default() };
        orient_file_coatings(&mut system);
        let thickness =
            |i: usize| system.surfaces[i].coating.as_ref().map(|c| c.layers[0].thickness_nm).unwrap_or(0.0);
        // Air to glass: as written (MgF₂ first, on the air side). Glass to air: reversed, so
        // that MgF₂, last in the object-side-first order, again touches the air.
        assert_eq!((thickness(0), thickness(1)), (100.0, 50.0));
    }
}

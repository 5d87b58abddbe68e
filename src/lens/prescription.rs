//! [`LensSystem`]: a lens prescription, the surfaces from the object side to the image side
//! with their media and clear apertures (conventions in the [module](super) header).

use std::path::PathBuf;

use super::coating::Coating;
use crate::optics::dispersion::DispersionFormula;

/// The medium behind a surface (on its image side).
#[derive(Clone, Debug, PartialEq)]
pub enum Medium {
    /// Air, n = 1 at every wavelength.
    Air,
    /// A glass: its name as the prescription gives it (a catalogue name, or a description of
    /// the numbers it was given) and its dispersion formula (λ in µm, as published).
    Glass {
        /// The name shown in reports and errors, e.g. `"N-BK7"` or `"n=1.67"`.
        name: String,
        /// n(λ).
        formula: DispersionFormula,
    },
}

impl Medium {
    /// The refractive index at `lambda_nm` (nm).
    pub fn n_at_nm(&self, lambda_nm: f64) -> f64 {
        match self {
            Medium::Air => 1.0,
            Medium::Glass { formula, .. } => formula.n_at_nm(lambda_nm),
        }
    }

    /// A glass of index `n` at every wavelength (a pbrt lens file's column as it is).
    pub fn constant(n: f64) -> Self {
        Medium::Glass {
            name: format!("n={n}"),
            formula: DispersionFormula::Cauchy { a: n, b_um2: 0.0, c_um4: 0.0 },
        }
    }

    /// The name shown in reports: `"air"` or the glass's.
    pub fn name(&self) -> &str {
        match self {
            Medium::Air => "air",
            Medium::Glass { name, .. } => name,
        }
    }
}

/// One rotationally symmetric surface of a lens system.
#[derive(Clone, Debug, PartialEq)]
pub struct Surface {
    /// Radius of curvature at the vertex in mm, positive when the centre of curvature lies on
    /// the image side; 0 for a flat surface (and the aperture stop).
    pub radius_mm: f64,
    /// Conic constant k (0: a sphere; −1: a paraboloid), as Zemax's `CONI`.
    pub conic: f64,
    /// Even-asphere coefficients α₁, α₂, … of r², r⁴, … (in mm^(1−2i)), as Zemax's `EVENASPH`
    /// `PARM 1..8`; empty for a conic.
    pub aspheric_mm: Vec<f64>,
    /// Axial distance from this vertex to the next surface's (to the image plane for the last
    /// surface), in mm.
    pub thickness_mm: f64,
    /// The medium behind the surface.
    pub medium: Medium,
    /// Clear semi-diameter (radius of the clear aperture) in mm: rays farther from the axis at
    /// this surface are blocked.
    pub semi_diameter_mm: f64,
    /// Whether this surface is the aperture stop.
    pub is_stop: bool,
    /// The coating between the media before and after the surface, if any
    /// ([`super::coating`]); `None`: the bare interface.
    pub coating: Option<Coating>,
    /// The 1-based line of the prescription file that defines it (0 when built in code), for
    /// error messages.
    pub line: usize,
}

impl Surface {
    /// A spherical surface (flat when `radius_mm` is 0) built in code (line 0), for lenses
    /// made by programs and tests rather than read from a file.
    pub fn spherical(
        radius_mm: f64,
        thickness_mm: f64,
        medium: Medium,
        semi_diameter_mm: f64,
        is_stop: bool,
    ) -> Self {
        Self {
            radius_mm,
            conic: 0.0,
            aspheric_mm: Vec::new(),
            thickness_mm,
            medium,
            semi_diameter_mm,
            is_stop,
            coating: None,
            line: 0,
        }
    }

    /// Curvature 1/R in mm⁻¹ (0 for a flat surface).
    pub fn curvature_per_mm(&self) -> f64 {
        if self.radius_mm == 0.0 {
            0.0
        } else {
            1.0 / self.radius_mm
        }
    }

    /// The sag z(r) in mm at `r_mm` from the axis, measured from the vertex along +z:
    /// c r² / (1 + √(1 − (1 + k) c² r²)) + Σᵢ αᵢ r²ⁱ (Zemax's even asphere; a sphere when k = 0
    /// and there are no αᵢ). `None` beyond the conic's edge, where (1 + k) c² r² > 1 (for a
    /// sphere: r > |R|).
    pub fn sag_mm(&self, r_mm: f64) -> Option<f64> {
        super::surface_geometry::sag(self, r_mm * r_mm)
    }
}

/// Wavelength range (nm) over which [`LensSystem::validate`] requires every index to be ≥ 1
/// and finite: the renderer's spectral range.
pub const VALIDATE_RANGE_NM: (f64, f64) = (360.0, 830.0);

/// How far (mm, relative to the lens's length scale) two surfaces may overlap and still count
/// as touching: elements designed in edge contact compute their sags to f64 rounding, ~1e-15 of
/// the radii; 1e-9 leaves room for files that print 10 significant digits.
const TOUCH_TOLERANCE_RELATIVE: f64 = 1e-9;

/// Radial samples per surface pair in the crossing test: two spheres' sag difference is
/// monotonic in r, so its ends decide; a conic or asphere can turn in between, and 64 samples
/// catch any turn wider than 1/64 of the clear aperture.
const CROSSING_SAMPLES: usize = 64;

/// Why a prescription cannot be used; each names the file and, where there is one, the line.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LensError {
    /// The file's text is wrong at a line (a field that is not a number, a missing column, an
    /// unsupported Zemax keyword, an unknown glass, …).
    #[error("{file}:{line}: {message}")]
    Line {
        /// The prescription file.
        file: String,
        /// The 1-based line.
        line: usize,
        /// What is wrong, naming the field.
        message: String,
    },
    /// The prescription as a whole cannot form an image (no surfaces, no stop, surfaces that
    /// cross, an axial ray that cannot pass, …).
    #[error("{file}: {message}")]
    System {
        /// The prescription file.
        file: String,
        /// What is wrong.
        message: String,
    },
}

/// A lens prescription: surfaces from the object side to the image side.
#[derive(Clone, Debug, PartialEq)]
pub struct LensSystem {
    /// The surfaces, object side first.
    pub surfaces: Vec<Surface>,
    /// The file it was read from (empty when built in code).
    pub source: PathBuf,
}

impl LensSystem {
    /// The index of the aperture stop, if one is marked.
    pub fn stop_index(&self) -> Option<usize> {
        self.surfaces.iter().position(|s| s.is_stop)
    }

    /// Axial position (mm) of each surface's vertex, the first at 0, and of the image plane last.
    pub fn vertex_z_mm(&self) -> Vec<f64> {
        let mut z = Vec::with_capacity(self.surfaces.len() + 1);
        let mut at = 0.0;
        z.push(at);
        for surface in &self.surfaces {
            at += surface.thickness_mm;
            z.push(at);
        }
        z
    }

    /// Checks what can be checked without tracing a ray: at least one surface; exactly one
    /// aperture stop; finite numbers; every clear semi-diameter > 0 and within its surface (for a
    /// sphere, ≤ |R|); no two surfaces crossing within their common clear aperture (each pair's
    /// sags compared at radii up to the smaller semi-diameter, so a thickness too small for the
    /// elements' sags is caught, not only a negative one); the image plane behind the last
    /// vertex; every index finite and ≥ 1 from 360 to 830 nm (sampled every 1 nm), coating
    /// layers' included, and every coating within its limits ([`Coating::check`]).
    ///
    /// # Errors
    /// [`LensError::System`] naming the surfaces by number (1-based, object side first) and the
    /// line of the file that defines them.
    pub fn validate(&self) -> Result<(), LensError> {
        let error = |message: String| LensError::System { file: self.source.display().to_string(), message };
        let describe = |index: usize| {
            let line = self.surfaces[index].line;
            if line == 0 {
                format!("surface {}", index + 1)
            } else {
                format!("surface {} (line {line})", index + 1)
            }
        };
        if self.surfaces.is_empty() {
            return Err(error(
                "no surfaces: a lens needs at least one surface and an aperture stop".to_owned(),
            ));
        }
        let stops: Vec<usize> = (0..self.surfaces.len()).filter(|&i| self.surfaces[i].is_stop).collect();
        match stops.as_slice() {
            [] => return Err(error("no aperture stop: mark one surface as the stop".to_owned())),
            [_] => {}
            [first, second, ..] => {
                return Err(error(format!(
                    "two aperture stops, {} and {}: mark only one",
                    describe(*first),
                    describe(*second)
                )))
            }
        }
        for (index, surface) in self.surfaces.iter().enumerate() {
            let numbers = [surface.radius_mm, surface.conic, surface.thickness_mm, surface.semi_diameter_mm];
            if numbers.iter().chain(&surface.aspheric_mm).any(|x| !x.is_finite()) {
                return Err(error(format!("{}: a number is not finite", describe(index))));
            }
            if surface.semi_diameter_mm <= 0.0 {
                return Err(error(format!(
                    "{}: semi-diameter {} mm must be > 0",
                    describe(index),
                    surface.semi_diameter_mm
                )));
            }
            if surface.sag_mm(surface.semi_diameter_mm).is_none() {
                return Err(error(format!(
                    "{}: semi-diameter {} mm is beyond the surface's edge (radius {} mm, conic {}): \
                     the clear aperture cannot be wider than the sphere",
                    describe(index),
                    surface.semi_diameter_mm,
                    surface.radius_mm,
                    surface.conic
                )));
            }
        }
        let z = self.vertex_z_mm();
        if z.iter().any(|z| !z.is_finite()) {
            return Err(error("the thicknesses add up to more than f64 can hold".to_owned()));
        }
        let scale = z.iter().map(|z| z.abs()).fold(1.0, f64::max);
        for first in 0..self.surfaces.len() {
            for second in first + 1..self.surfaces.len() {
                let (a, b) = (&self.surfaces[first], &self.surfaces[second]);
                let reach = a.semi_diameter_mm.min(b.semi_diameter_mm);
                // The deepest overlap over the common aperture, and where it is.
                let mut worst = (f64::NEG_INFINITY, 0.0);
                for sample in 0..=CROSSING_SAMPLES {
                    let r_mm = reach * sample as f64 / CROSSING_SAMPLES as f64;
                    let (Some(sag_a), Some(sag_b)) = (a.sag_mm(r_mm), b.sag_mm(r_mm)) else { continue };
                    let overlap = (z[first] + sag_a) - (z[second] + sag_b);
                    if overlap > worst.0 {
                        worst = (overlap, r_mm);
                    }
                }
                let (overlap, r_mm) = worst;
                if overlap > TOUCH_TOLERANCE_RELATIVE * scale {
                    return Err(error(format!(
                        "{} and {} cross: at {r_mm} mm from the axis the first lies {overlap:.6} mm \
                         behind the second (thickness too small for the sags)",
                        describe(first),
                        describe(second)
                    )));
                }
            }
        }
        let last = self.surfaces.len() - 1;
        if self.surfaces[last].thickness_mm <= 0.0 {
            return Err(error(format!(
                "a sensor behind nothing: the image plane must lie behind the last vertex, but the \
                 thickness of {} is {} mm",
                describe(last),
                self.surfaces[last].thickness_mm
            )));
        }
        let (first_nm, last_nm) = VALIDATE_RANGE_NM;
        for (index, surface) in self.surfaces.iter().enumerate() {
            let mut lambda_nm = first_nm;
            while lambda_nm <= last_nm {
                let n = surface.medium.n_at_nm(lambda_nm);
                if !(n.is_finite() && n >= 1.0) {
                    return Err(error(format!(
                        "{}: the index of {} is {n} at {lambda_nm} nm; it must be finite and ≥ 1 from \
                         {first_nm} to {last_nm} nm",
                        describe(index),
                        surface.medium.name()
                    )));
                }
                lambda_nm += 1.0;
            }
            if let Some(coating) = &surface.coating {
                coating.check(VALIDATE_RANGE_NM).map_err(|message| {
                    error(format!("{}: coating {}: {message}", describe(index), coating.name))
                })?;
            }
        }
        Ok(())
    }

    /// The medium in front of surface `index` (air for the first).
    pub fn medium_before(&self, index: usize) -> &Medium {
        if index == 0 {
            &Medium::Air
        } else {
            &self.surfaces[index - 1].medium
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn surface(radius_mm: f64, conic: f64, aspheric_mm: Vec<f64>) -> Surface {
        Surface { conic, aspheric_mm, ..Surface::spherical(radius_mm, 1.0, Medium::Air, 1.0, false) }
    }

    #[test]
    fn sags_match_their_closed_forms() {
        // Sphere: z = R − √(R² − r²) (sign of R); R = 50, r = 30: 50 − 40 = 10, to the f64
        // rounding of the c r²/(1 + √…) form (a few ulp of 10).
        let close = |sag: Option<f64>, expected: f64| sag.is_some_and(|z| (z - expected).abs() < 1e-13);
        assert!(close(surface(50.0, 0.0, vec![]).sag_mm(30.0), 10.0));
        assert!(close(surface(-50.0, 0.0, vec![]).sag_mm(30.0), -10.0));
        // Paraboloid (k = −1): z = r²/(2R), to f64 rounding.
        let parabola = surface(50.0, -1.0, vec![]).sag_mm(30.0).expect("a paraboloid has no edge");
        assert!((parabola - 9.0).abs() < 1e-14);
        // Even asphere terms add α₁r² + α₂r⁴ to a flat surface: 4 · 0.01 + 16 · 0.001 = 0.056.
        let asphere = surface(0.0, 0.0, vec![0.01, 0.001]).sag_mm(2.0).expect("flat");
        assert!((asphere - 0.056).abs() < 1e-15);
        // Beyond a sphere's edge there is no surface.
        assert!(close(surface(5.0, 0.0, vec![]).sag_mm(5.0), 5.0));
        assert_eq!(surface(5.0, 0.0, vec![]).sag_mm(5.000001), None);
    }

    #[test]
    fn a_system_built_in_code_is_named_by_surface_number() {
        let mut stop = surface(0.0, 0.0, vec![]);
        stop.is_stop = true;
        stop.thickness_mm = -1.0;
        let system = LensSystem { surfaces: vec![stop], source: PathBuf::new() };
        assert_eq!(
            system.validate().expect_err("behind nothing").to_string(),
            ": a sensor behind nothing: the image plane must lie behind the last vertex, but the \
             thickness of surface 1 is -1 mm"
        );
    }
}

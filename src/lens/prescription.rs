//! [`LensSystem`]: a lens prescription, the surfaces from the object side to the image side
//! with their media and clear apertures (conventions in the [module](super) header).

use std::path::PathBuf;

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
    /// The 1-based line of the prescription file that defines it (0 when built in code), for
    /// error messages.
    pub line: usize,
}

impl Surface {
    /// Curvature 1/R in mm⁻¹ (0 for a flat surface).
    pub fn curvature_per_mm(&self) -> f64 {
        if self.radius_mm == 0.0 {
            0.0
        } else {
            1.0 / self.radius_mm
        }
    }
}

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

    /// The medium in front of surface `index` (air for the first).
    pub fn medium_before(&self, index: usize) -> &Medium {
        if index == 0 {
            &Medium::Air
        } else {
            &self.surfaces[index - 1].medium
        }
    }
}

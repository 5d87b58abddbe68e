//! First-order (paraxial) optics of a [`LensSystem`] at one wavelength: the y–nu trace of
//! Smith, *Modern Optical Engineering* (4th ed., §2.6), written as 2×2 matrices in reduced
//! coordinates (y, n·u) (Gerrard & Burch, *Introduction to Matrix Methods in Optics*, ch. 3):
//! a refraction by a surface of curvature c between indices n and n′ is
//! `[[1, 0], [−(n′ − n)c, 1]]`, a transfer by the thickness t in index n is
//! `[[1, t/n], [0, 1]]`, and every product has determinant 1.
//!
//! Signs: y is the height above the axis, u the slope dy/dz (positive going up toward +z),
//! positions are z coordinates along +z (toward the image). Object space is air (n = 1).

use super::{LensError, LensSystem};

/// The Fraunhofer d line (helium), 587.5618 nm: the reference of n_d, V_d and of the
/// chromatic focal shift.
pub const LAMBDA_D_NM: f64 = 587.5618;

/// A reduced-coordinate ray-transfer matrix [[A, B], [C, D]]: (y′, n′u′) = M (y, n u).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Abcd {
    /// ∂y′/∂y.
    pub a: f64,
    /// ∂y′/∂(n u), mm.
    pub b: f64,
    /// ∂(n′u′)/∂y, mm⁻¹ (minus the power).
    pub c: f64,
    /// ∂(n′u′)/∂(n u).
    pub d: f64,
}

impl Abcd {
    /// The identity.
    pub const IDENTITY: Self = Self { a: 1.0, b: 0.0, c: 0.0, d: 1.0 };

    /// `self` followed by `next` (the matrix product next · self).
    pub fn then(self, next: Abcd) -> Abcd {
        Abcd {
            a: next.a * self.a + next.b * self.c,
            b: next.a * self.b + next.b * self.d,
            c: next.c * self.a + next.d * self.c,
            d: next.c * self.b + next.d * self.d,
        }
    }

    /// Refraction by a surface of curvature `c` (mm⁻¹) from index `n` to `n_after`.
    pub fn refraction(c: f64, n: f64, n_after: f64) -> Abcd {
        Abcd { c: -(n_after - n) * c, ..Abcd::IDENTITY }
    }

    /// Transfer by `thickness_mm` in index `n`.
    pub fn transfer(thickness_mm: f64, n: f64) -> Abcd {
        Abcd { b: thickness_mm / n, ..Abcd::IDENTITY }
    }

    /// (y′, n′u′) of the ray (y, n u).
    pub fn apply(&self, y: f64, nu: f64) -> (f64, f64) {
        (self.a * y + self.b * nu, self.c * y + self.d * nu)
    }
}

/// The first-order properties of a lens system at one wavelength. Positions are in mm along
/// +z; "relative to the last vertex" means z − z_last_vertex.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Paraxial {
    /// The wavelength (nm).
    pub lambda_nm: f64,
    /// Effective focal length f′ = 1/Φ (mm), Φ = −C of the system matrix from just before the
    /// first surface to just after the last: positive for a converging system. With object
    /// and image in air it is the distance from the rear principal plane to the rear focus.
    pub efl_mm: f64,
    /// Back focal length (mm): the paraxial focus of an object at infinity relative to the
    /// last vertex, −n′A/C (positive when the focus lies behind the last surface).
    pub bfl_mm: f64,
    /// Front focal length (mm): the distance from the front focal point to the first vertex,
    /// −D/C (positive when the front focus lies in front of the lens, as for a converging
    /// lens). The front focal point's z is −`ffl_mm`.
    pub ffl_mm: f64,
    /// Entrance pupil: the paraxial image of the stop through the surfaces in front of it, as
    /// seen from object space; its z relative to the first vertex (mm).
    pub entrance_pupil_z_mm: f64,
    /// Entrance pupil diameter (mm): the diameter of the axial collimated beam that fills the
    /// stop, 2·(stop semi-diameter)/|A_stop| with A_stop the A of the matrix from object space
    /// to the stop plane.
    pub entrance_pupil_diameter_mm: f64,
    /// Exit pupil: the paraxial image of the stop through the surfaces behind it, seen from
    /// image space; its z relative to the last vertex (mm).
    pub exit_pupil_z_mm: f64,
    /// Exit pupil diameter (mm): 2·(stop semi-diameter)/|D| of the matrix from the stop plane
    /// to image space.
    pub exit_pupil_diameter_mm: f64,
    /// f-number for an object at infinity: `efl_mm` / `entrance_pupil_diameter_mm`.
    pub f_number: f64,
    /// The index of image space (the last surface's medium).
    pub n_image: f64,
    /// The system matrix from object space (just before surface 1) to image space (just after
    /// the last surface).
    pub system: Abcd,
}

impl Paraxial {
    /// The paraxial image of an object `object_distance_mm` in front of the first vertex
    /// (object at z = −`object_distance_mm`; `f64::INFINITY` for an object at infinity),
    /// relative to the last vertex (mm). `None` when the image is at infinity (the object is
    /// at the front focus).
    pub fn image_distance_mm(&self, object_distance_mm: f64) -> Option<f64> {
        let m = self.system;
        let (y, nu) = if object_distance_mm.is_infinite() {
            (1.0, 0.0)
        } else {
            // A ray from the axial object point with slope 1: at the first vertex y = D.
            (object_distance_mm, 1.0)
        };
        let (y_out, nu_out) = m.apply(y, nu);
        if nu_out == 0.0 {
            return None;
        }
        Some(-y_out * self.n_image / nu_out)
    }

    /// The stop semi-diameter (mm) that gives the f-number `f_number` for an object at
    /// infinity, given the current one `stop_semi_diameter_mm` (the pupil scales with it).
    pub fn stop_semi_diameter_for_f_number(&self, f_number: f64, stop_semi_diameter_mm: f64) -> f64 {
        let wanted_ep_diameter = self.efl_mm / f_number;
        stop_semi_diameter_mm * wanted_ep_diameter / self.entrance_pupil_diameter_mm
    }
}

impl LensSystem {
    /// The paraxial properties at `lambda_nm` (nm). Errors when no stop is marked, or when
    /// the system has no power (an afocal system has no focal length).
    pub fn paraxial(&self, lambda_nm: f64) -> Result<Paraxial, LensError> {
        let file = self.source.display().to_string();
        let error = |message: String| LensError::System { file: file.clone(), message };
        let stop = self.stop_index().ok_or_else(|| error("no aperture stop is marked".into()))?;
        let last = self.surfaces.len().checked_sub(1).ok_or_else(|| error("no surfaces".into()))?;
        // Object space → stop plane (before the stop's own refraction), and stop → image space.
        let mut to_stop = Abcd::IDENTITY;
        let mut from_stop = Abcd::IDENTITY;
        let mut system = Abcd::IDENTITY;
        for (index, surface) in self.surfaces.iter().enumerate() {
            let n = self.medium_before(index).n_at_nm(lambda_nm);
            let n_after = surface.medium.n_at_nm(lambda_nm);
            let refraction = Abcd::refraction(surface.curvature_per_mm(), n, n_after);
            system = system.then(refraction);
            if index >= stop {
                from_stop = from_stop.then(refraction);
            }
            if index < last {
                let transfer = Abcd::transfer(surface.thickness_mm, n_after);
                system = system.then(transfer);
                if index < stop {
                    to_stop = system;
                } else {
                    from_stop = from_stop.then(transfer);
                }
            }
        }
        if stop == 0 {
            to_stop = Abcd::IDENTITY;
        }
        let n_image = self.surfaces[last].medium.n_at_nm(lambda_nm);
        if system.c == 0.0 || !system.c.is_finite() {
            return Err(error(format!("the system has no optical power at {lambda_nm} nm (afocal)")));
        }
        let stop_semi = self.surfaces[stop].semi_diameter_mm;
        let efl_mm = -1.0 / system.c;
        let bfl_mm = -n_image * system.a / system.c;
        // Front focus: the object-space ray (y = −z_F u, n u = u) leaves parallel:
        // C(−z_F) + D = 0, so z_F = D/C.
        let ffl_mm = -system.d / system.c;
        // Entrance pupil: the object-space ray crossing the axis at z_E reaches the stop's
        // centre: A(−z_E) + B = 0.
        let entrance_pupil_z_mm = to_stop.b / to_stop.a;
        let entrance_pupil_diameter_mm = 2.0 * stop_semi / to_stop.a.abs();
        // Exit pupil: the ray from the stop's centre (0, 1) leaves as (B, D) and crosses the
        // axis at −B n′/D behind the last vertex; its magnification is det/D = 1/D.
        let exit_pupil_z_mm = -from_stop.b * n_image / from_stop.d;
        let exit_pupil_diameter_mm = 2.0 * stop_semi / from_stop.d.abs();
        Ok(Paraxial {
            lambda_nm,
            efl_mm,
            bfl_mm,
            ffl_mm,
            entrance_pupil_z_mm,
            entrance_pupil_diameter_mm,
            exit_pupil_z_mm,
            exit_pupil_diameter_mm,
            f_number: efl_mm / entrance_pupil_diameter_mm,
            n_image,
            system,
        })
    }

    /// The longitudinal chromatic focal shift at `lambda_nm` (mm): the paraxial focus at
    /// `lambda_nm` minus the focus at the d line ([`LAMBDA_D_NM`]), for an object
    /// `object_distance_mm` in front of the first vertex (`f64::INFINITY`: the back focal
    /// lengths' difference).
    pub fn chromatic_focal_shift_mm(
        &self,
        lambda_nm: f64,
        object_distance_mm: f64,
    ) -> Result<f64, LensError> {
        let at = self.paraxial_image_distance_mm(lambda_nm, object_distance_mm)?;
        let reference = self.paraxial_image_distance_mm(LAMBDA_D_NM, object_distance_mm)?;
        Ok(at - reference)
    }

    /// The last thickness (last vertex to the image plane, mm) that puts the paraxial image
    /// of an object `object_distance_mm` in front of the first vertex (`f64::INFINITY` for
    /// infinity) on the image plane at `lambda_nm`: how a camera focuses by moving its sensor.
    pub fn focus_thickness_mm(&self, object_distance_mm: f64, lambda_nm: f64) -> Result<f64, LensError> {
        self.paraxial_image_distance_mm(lambda_nm, object_distance_mm)
    }

    fn paraxial_image_distance_mm(&self, lambda_nm: f64, object_distance_mm: f64) -> Result<f64, LensError> {
        self.paraxial(lambda_nm)?.image_distance_mm(object_distance_mm).ok_or_else(|| LensError::System {
            file: self.source.display().to_string(),
            message: format!(
                "an object {object_distance_mm} mm away images at infinity (it is at the front focus)"
            ),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lens::{Medium, Surface};

    fn surface(radius_mm: f64, thickness_mm: f64, medium: Medium, semi: f64, is_stop: bool) -> Surface {
        Surface::spherical(radius_mm, thickness_mm, medium, semi, is_stop)
    }

    /// A thick biconvex singlet of index n with the stop on its first surface.
    fn singlet(r1: f64, r2: f64, d: f64, n: f64) -> LensSystem {
        LensSystem {
            surfaces: vec![
                surface(r1, d, Medium::constant(n), 10.0, true),
                surface(r2, 40.0, Medium::Air, 10.0, false),
            ],
            source: Default::default(),
        }
    }

    #[test]
    fn thick_singlet_matches_the_lensmakers_formulas() {
        // Hecht §6.2: 1/f = (n−1)[1/R1 − 1/R2 + (n−1)d/(n R1 R2)],
        // BFL = f(1 − (n−1)d/(n R1)), FFL = f(1 + (n−1)d/(n R2)).
        let (r1, r2, d, n) = (50.0, -80.0, 6.0, 1.6);
        let p = singlet(r1, r2, d, n).paraxial(LAMBDA_D_NM).unwrap();
        let f = 1.0 / ((n - 1.0) * (1.0 / r1 - 1.0 / r2 + (n - 1.0) * d / (n * r1 * r2)));
        let bfl = f * (1.0 - (n - 1.0) * d / (n * r1));
        let ffl = f * (1.0 + (n - 1.0) * d / (n * r2));
        for (got, want) in [(p.efl_mm, f), (p.bfl_mm, bfl), (p.ffl_mm, ffl)] {
            assert!((got / want - 1.0).abs() < 1e-12, "{got} vs {want}");
        }
        // The stop on the first surface is its own entrance pupil.
        assert_eq!(p.entrance_pupil_z_mm, 0.0);
        assert!((p.entrance_pupil_diameter_mm - 20.0).abs() < 1e-12);
    }

    #[test]
    fn newtons_equation_for_a_finite_object() {
        // Newton: x x′ = −f² (in air), with x the object's distance from the front focus and
        // x′ the image's from the back focus (Hecht §5.2.3).
        let system = singlet(50.0, -80.0, 6.0, 1.6);
        let p = system.paraxial(LAMBDA_D_NM).unwrap();
        for object_distance in [200.0, 500.0, 3000.0] {
            let x = -(object_distance - p.ffl_mm); // object at z = −D, front focus at −FFL
            let image = p.image_distance_mm(object_distance).unwrap();
            let x_prime = image - p.bfl_mm;
            assert!((x * x_prime + p.efl_mm * p.efl_mm).abs() < 1e-9 * p.efl_mm * p.efl_mm);
        }
    }
}

//! [`ThinLens`]: an ideal thin lens, for depth of field (Kolb, Mitchell and Hanrahan, "A
//! realistic camera model for computer graphics", SIGGRAPH 1995, §2; pbrt-v4 §5.2.3; Mitsuba 3's
//! `thinlens` sensor, whose parameters these are).
//!
//! The lens is a disc of radius `aperture_radius` at the pinhole's position, facing the view
//! direction, and the film is the pinhole's: film position (x, y) is conjugate to the point
//! `focus_distance` along the pinhole's ray through (x, y), on the **plane of focus** (depth
//! `focus_distance` along the view direction, as Mitsuba's `focus_distance`). Every ray from
//! that film position leaves a point of the lens toward that conjugate point: points on the
//! plane of focus are sharp, and a point at depth d is spread over a disc on the plane of focus
//! of diameter 2·a·|d − f|/d (the circle of confusion). The field of view is the pinhole's, and
//! the lens has no aberrations, no vignetting and no cos⁴ falloff: a pixel reads the radiance
//! averaged over its area and the lens (ray weight 1, as Mitsuba's `thinlens`), so a scene of
//! constant radiance renders as with the pinhole, and `aperture_radius → 0` is the pinhole.
//!
//! ```toml
//! [camera]
//! position = [0, 1, -6]
//! look_at = [0, 1, 0]
//! fov_y_deg = 40
//! width = 320
//! height = 240
//! aperture_radius = 0.1  # scene units
//! focus_distance = 6     # scene units, along the view direction
//! ```
//!
//! The light tracer connects to it as to the pinhole, from a point of the lens it draws
//! uniformly ([`ThinLens::project`]).

use glam::Vec3;

use super::{CameraError, FilmPoint, Pinhole};
use crate::geometry::Ray;
use crate::material::diffuse::concentric_disk;

/// A thin-lens camera: the pinhole's film and field of view, a lens of radius
/// `aperture_radius` focused at `focus_distance` (scene units).
#[derive(Debug, Clone, PartialEq)]
pub struct ThinLens {
    pinhole: Pinhole,
    aperture_radius: f32,
    focus_distance: f32,
}

impl ThinLens {
    /// The pinhole camera `pinhole` with a lens of radius `aperture_radius` (> 0, finite) focused
    /// on the plane at depth `focus_distance` (> 0, finite) along the view direction, both in
    /// scene units.
    pub fn new(pinhole: Pinhole, aperture_radius: f32, focus_distance: f32) -> Result<Self, CameraError> {
        if !(aperture_radius > 0.0 && aperture_radius.is_finite()) {
            return Err(CameraError::ApertureRadius(aperture_radius));
        }
        if !(focus_distance > 0.0 && focus_distance.is_finite()) {
            return Err(CameraError::FocusDistance(focus_distance));
        }
        Ok(Self { pinhole, aperture_radius, focus_distance })
    }

    /// The same camera with another resolution (the field of view stays vertical).
    pub fn with_resolution(&self, width: u32, height: u32) -> Result<Self, CameraError> {
        Ok(Self { pinhole: self.pinhole.with_resolution(width, height)?, ..*self })
    }

    /// The film, field of view and lens centre, as a pinhole.
    pub fn pinhole(&self) -> &Pinhole {
        &self.pinhole
    }

    /// Radius of the lens (scene units).
    pub fn aperture_radius(&self) -> f32 {
        self.aperture_radius
    }

    /// Depth of the plane of focus along the view direction (scene units).
    pub fn focus_distance(&self) -> f32 {
        self.focus_distance
    }

    /// The point of the lens for the lens sample `u` in [0, 1)², uniform over its area
    /// (Shirley and Chiu's concentric map).
    #[inline]
    pub fn lens_point(&self, u: (f32, f32)) -> Vec3 {
        let (disc_x, disc_y) = concentric_disk(u);
        let (right, up) = self.pinhole.right_and_up();
        self.pinhole.position() + self.aperture_radius * (disc_x * right + disc_y * up)
    }

    /// The ray from film position (`x`, `y`) in pixels through the lens point of `u`
    /// ([`Self::lens_point`]): toward the conjugate point on the plane of focus.
    #[inline]
    pub fn ray(&self, x: f32, y: f32, u: (f32, f32)) -> Ray {
        let lens = self.lens_point(u);
        // The pinhole's direction has unit depth, so this point lies on the plane of focus.
        let conjugate = self.pinhole.position() + self.focus_distance * self.pinhole.film_direction(x, y);
        Ray::new(lens, (conjugate - lens).normalize())
    }

    /// Where the light leaving `point` toward the lens point of `u` lands on the film, if it
    /// does: the film position conjugate to where the line from the lens point through `point`
    /// crosses the plane of focus. The sensitivity is the pinhole's at that lens point,
    /// 1/(d²·A_pixel·cos³θ) with d and θ of the line from the lens point: the film position and
    /// the lens point of a camera ray are uniform over the pixel and the lens, and for a fixed
    /// lens point the rays through a pixel's conjugate patch on the plane of focus (area f²·A_pixel)
    /// span the solid angle A_pixel·cos³θ, as at a pinhole. With the lens point drawn uniformly
    /// its density 1/(π·a²) cancels the lens average: an unbiased estimate of what the camera
    /// paths read.
    pub fn project(&self, point: Vec3, u: (f32, f32)) -> Option<FilmPoint> {
        let lens = self.lens_point(u);
        let offset = point - lens;
        let depth = self.pinhole.depth(offset);
        let distance_sq = offset.length_squared();
        if !(depth > 0.0 && distance_sq.is_finite()) {
            return None;
        }
        // Relative to the lens centre; its depth is the focus distance (the lens point's is 0).
        let on_focus_plane = (lens - self.pinhole.position()) + offset * (self.focus_distance / depth);
        let pixel = self.pinhole.pixel_toward(on_focus_plane, self.focus_distance)?;
        Some(self.pinhole.seen_from(offset, depth, distance_sq, pixel))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lens(aperture_radius: f32, focus_distance: f32) -> ThinLens {
        let pinhole = Pinhole::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 40.0, 64, 48).unwrap();
        ThinLens::new(pinhole, aperture_radius, focus_distance).unwrap()
    }

    /// The lens points lie on the disc of radius a about the pinhole, in the plane facing the
    /// view, and the lens sample's corners reach its rim.
    #[test]
    fn lens_points_fill_the_aperture_disc() {
        let camera = lens(0.25, 5.0);
        for u in [(0.0, 0.0), (0.999, 0.5), (0.5, 0.999), (0.3, 0.7), (0.5, 0.5)] {
            let p = camera.lens_point(u);
            assert!(p.z.abs() < 1e-7, "{p}");
            assert!(p.length() <= 0.25 * (1.0 + 1e-6), "{p}");
        }
        // (0.999, 0.5) maps to radius 0.998 on the +x of the disc: image right, world −x.
        assert!((camera.lens_point((0.999, 0.5)) - Vec3::new(-0.2495, 0.0, 0.0)).length() < 1e-5);
        assert_eq!(camera.lens_point((0.5, 0.5)), Vec3::ZERO);
    }

    /// Every ray from one film position passes through its conjugate point: the point at the
    /// focus distance on the pinhole's ray (the thin-lens equation, 1/s + 1/s' = 1/f'), whatever
    /// the lens point.
    #[test]
    fn rays_from_a_film_point_meet_at_its_conjugate() {
        let camera = lens(0.3, 4.0);
        for (x, y) in [(32.0f32, 24.0f32), (3.5, 40.25), (60.0, 2.0)] {
            let chief = camera.pinhole.ray(x, y);
            let conjugate = chief.at(4.0 / chief.dir.z);
            assert!((conjugate.z - 4.0).abs() < 1e-5);
            for u in [(0.1, 0.2), (0.9, 0.4), (0.5, 0.95), (0.02, 0.98)] {
                let ray = camera.ray(x, y, u);
                let t = (conjugate - ray.origin).dot(ray.dir);
                // f32 rounding of a 4-unit point: ~1e-6 relative.
                assert!((ray.at(t) - conjugate).length() < 4e-6 * 4.0, "{} vs {conjugate}", ray.at(t));
            }
        }
    }

    /// `project` inverts `ray` at any lens point: a point on a camera ray through lens point u
    /// projects, with the same u, into the pixel the ray left from, along the ray, at the
    /// distance from the lens point; its sensitivity is the pinhole's seen from that lens point.
    #[test]
    fn project_inverts_ray_for_every_lens_point() {
        let camera = lens(0.2, 3.0);
        for (x, y, u, t) in [
            (10.5f32, 40.5f32, (0.1f32, 0.9f32), 7.0f32),
            (32.5, 24.5, (0.7, 0.3), 1.5),
            (63.5, 0.5, (0.4, 0.6), 3.2),
        ] {
            let ray = camera.ray(x, y, u);
            let seen = camera.project(ray.at(t), u).unwrap();
            assert_eq!(seen.pixel, x as u32 + (y as u32) * 64);
            assert!((seen.distance - t).abs() < 1e-4);
            assert!((seen.to_camera + ray.dir).length() < 1e-5);
            // A pixel's area on the image plane at unit distance: (2·tan 20°)²·(64/48)/(64·48).
            let pixel_area = (2.0 * 20f32.to_radians().tan()).powi(2) * (64.0 / 48.0) / (64.0 * 48.0);
            let cos_theta = ray.dir.z;
            let expected = 1.0 / (t * t * pixel_area * cos_theta.powi(3));
            assert!((seen.sensitivity / expected - 1.0).abs() < 1e-4, "{} vs {expected}", seen.sensitivity);
        }
        assert!(camera.project(Vec3::new(0.0, 0.0, -1.0), (0.5, 0.5)).is_none(), "behind the lens");
    }

    #[test]
    fn bad_lenses_are_rejected() {
        let pinhole = Pinhole::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 40.0, 4, 3).unwrap();
        for (a, f) in [(-0.1, 1.0), (f32::NAN, 1.0), (0.0, 1.0), (f32::INFINITY, 1.0)] {
            assert!(matches!(ThinLens::new(pinhole.clone(), a, f), Err(CameraError::ApertureRadius(_))));
        }
        for f in [-1.0, 0.0, f32::NAN, f32::INFINITY] {
            assert!(matches!(ThinLens::new(pinhole.clone(), 0.1, f), Err(CameraError::FocusDistance(_))));
        }
    }
}

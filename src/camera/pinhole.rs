//! [`Pinhole`]: a pinhole camera, every ray from one point.
//!
//! Right-handed, as Mitsuba 3's `look_at`: a camera at the origin looking along +z with +y up
//! has +x on the image's left. Pixel (0, 0) is the top-left corner; a sample at film position
//! (x, y) in pixels (continuous, x to the right, y down) maps through the vertical field of view.
//!
//! ```toml
//! [camera]
//! position = [0, 2, -6]
//! look_at = [0, 0, 100]
//! up = [0, 1, 0]
//! fov_y_deg = 60
//! width = 600
//! height = 400
//! ```

use glam::Vec3;

use super::{CameraError, FilmPoint};
use crate::geometry::Ray;

/// A pinhole camera.
#[derive(Debug, Clone, PartialEq)]
pub struct Pinhole {
    position: Vec3,
    forward: Vec3,
    /// Unit vector toward the image's right, scaled by tan(fov_y/2)·aspect.
    right_scaled: Vec3,
    /// Unit vector toward the image's top, scaled by tan(fov_y/2).
    up_scaled: Vec3,
    /// Unit vector toward the image's right.
    right: Vec3,
    /// Unit vector toward the image's top.
    up: Vec3,
    width: u32,
    height: u32,
    /// |`right_scaled`|², |`up_scaled`|² and a pixel's area on the image plane at unit
    /// distance: what [`Self::project`] divides by for every light path that reaches a
    /// diffuse surface, computed once ([`Self::with_projection`]).
    right_sq: f32,
    up_sq: f32,
    pixel_area: f32,
}

impl Pinhole {
    /// A camera at `position` looking at `look_at`, with `up` (any length, not parallel to the
    /// view), vertical field of view `fov_y_deg` degrees, and an image of `width`×`height` pixels.
    pub fn look_at(
        position: Vec3,
        look_at: Vec3,
        up: Vec3,
        fov_y_deg: f32,
        width: u32,
        height: u32,
    ) -> Result<Self, CameraError> {
        let view = look_at - position;
        if view.length_squared() <= 0.0 || !view.is_finite() {
            return Err(CameraError::NoViewDirection);
        }
        let forward = view.normalize();
        let left = up.cross(forward);
        // NaN lengths fail the finiteness test; zero or tiny cross products mean up ∥ view.
        if !left.is_finite() || left.length_squared() <= 1e-12 * up.length_squared().max(1e-30) {
            return Err(CameraError::UpParallel);
        }
        if !(fov_y_deg > 0.0 && fov_y_deg < 180.0) {
            return Err(CameraError::FieldOfView(fov_y_deg));
        }
        if width == 0 || height == 0 {
            return Err(CameraError::Resolution(width, height));
        }
        let left = left.normalize();
        let true_up = forward.cross(left);
        let tan_half = (fov_y_deg.to_radians() * 0.5).tan();
        let aspect = width as f32 / height as f32;
        Ok(Self {
            position,
            forward,
            right_scaled: -left * tan_half * aspect,
            up_scaled: true_up * tan_half,
            right: -left,
            up: true_up,
            width,
            height,
            right_sq: 0.0,
            up_sq: 0.0,
            pixel_area: 0.0,
        }
        .with_projection())
    }

    /// The camera with [`Self::project`]'s constants computed from its axes and resolution.
    fn with_projection(self) -> Self {
        let (right_sq, up_sq) = (self.right_scaled.length_squared(), self.up_scaled.length_squared());
        // A pixel's solid angle at the film centre: its area on the image plane at unit distance.
        let pixel_area = 4.0 * (right_sq * up_sq).sqrt() / (self.width as f32 * self.height as f32);
        Self { right_sq, up_sq, pixel_area, ..self }
    }

    /// The same camera with another resolution (the field of view stays vertical).
    pub fn with_resolution(&self, width: u32, height: u32) -> Result<Self, CameraError> {
        if width == 0 || height == 0 {
            return Err(CameraError::Resolution(width, height));
        }
        let aspect_old = self.width as f32 / self.height as f32;
        let aspect_new = width as f32 / height as f32;
        Ok(Self {
            right_scaled: self.right_scaled * (aspect_new / aspect_old),
            width,
            height,
            ..self.clone()
        }
        .with_projection())
    }

    /// Image width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Image height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The pinhole (scene units).
    pub fn position(&self) -> Vec3 {
        self.position
    }

    /// Unit vectors toward the image's right and top (scene space).
    pub fn right_and_up(&self) -> (Vec3, Vec3) {
        (self.right, self.up)
    }

    /// The direction from the pinhole through film position (`x`, `y`) in pixels, not
    /// normalised: its component along the view direction is 1 (a point of the image plane at
    /// unit distance, relative to the pinhole).
    #[inline]
    pub fn film_direction(&self, x: f32, y: f32) -> Vec3 {
        let ndc_x = 2.0 * x / self.width as f32 - 1.0;
        let ndc_y = 1.0 - 2.0 * y / self.height as f32;
        self.forward + ndc_x * self.right_scaled + ndc_y * self.up_scaled
    }

    /// The primary ray through film position (`x`, `y`) in pixels (x to the right, y down).
    #[inline]
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        Ray::new(self.position, self.film_direction(x, y).normalize())
    }

    /// Where the light leaving `point` toward the camera lands on the film, if it does (the
    /// point lies in front of the camera and projects inside the image); for the light tracer.
    pub fn project(&self, point: Vec3) -> Option<FilmPoint> {
        let offset = point - self.position;
        let depth = offset.dot(self.forward);
        let distance_sq = offset.length_squared();
        if !(depth > 0.0 && distance_sq.is_finite()) {
            return None;
        }
        let pixel = self.pixel_toward(offset, depth)?;
        Some(self.seen_from(offset, depth, distance_sq, pixel))
    }

    /// The depth of `offset` (a vector in scene space) along the view direction.
    #[inline]
    pub(super) fn depth(&self, offset: Vec3) -> f32 {
        offset.dot(self.forward)
    }

    /// The pixel whose film position the pinhole sees along `toward` (from the pinhole, of
    /// positive `depth` along the view), if inside the image: row-major index.
    #[inline]
    pub(super) fn pixel_toward(&self, toward: Vec3, depth: f32) -> Option<u32> {
        let ndc_x = toward.dot(self.right_scaled) / (depth * self.right_sq);
        let ndc_y = toward.dot(self.up_scaled) / (depth * self.up_sq);
        let x = (ndc_x + 1.0) * 0.5 * self.width as f32;
        let y = (1.0 - ndc_y) * 0.5 * self.height as f32;
        if !(x >= 0.0 && x < self.width as f32 && y >= 0.0 && y < self.height as f32) {
            return None;
        }
        Some((x as u32).min(self.width - 1) + (y as u32).min(self.height - 1) * self.width)
    }

    /// The point at `offset` from the eye (of `depth` along the view and squared length
    /// `distance_sq`), landing in `pixel`: its direction, distance and the sensitivity
    /// 1/(d²·A_pixel·cos³θ) ([`FilmPoint::sensitivity`]).
    #[inline]
    pub(super) fn seen_from(&self, offset: Vec3, depth: f32, distance_sq: f32, pixel: u32) -> FilmPoint {
        let distance = distance_sq.sqrt();
        let cos_theta = depth / distance;
        FilmPoint {
            pixel,
            to_camera: -offset / distance,
            distance,
            sensitivity: 1.0 / (distance_sq * self.pixel_area * cos_theta * cos_theta * cos_theta),
        }
    }

    /// The x axis of the Stokes frame in which the light arriving along a camera ray of
    /// direction `dir` is recorded: normalize(dir × up), with `up` the camera's unit up vector.
    /// It is the image's right for the central ray, as in Mitsuba 3's `stokes` integrator, and
    /// tilts with off-axis rays. Light travels along −dir, so y = (−dir) × x points up.
    #[inline]
    pub fn stokes_x(&self, dir: Vec3) -> Vec3 {
        dir.cross(self.up).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plus_x_is_on_the_left_when_looking_down_plus_z() {
        let camera = Pinhole::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 60.0, 200, 100).unwrap();
        let left_edge = camera.ray(0.0, 50.0);
        assert!(left_edge.dir.x > 0.0, "{:?}", left_edge.dir);
        let top_edge = camera.ray(100.0, 0.0);
        assert!(top_edge.dir.y > 0.0);
        let centre = camera.ray(100.0, 50.0);
        assert!((centre.dir - Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn vertical_field_of_view_is_exact() {
        let camera = Pinhole::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 60.0, 300, 100).unwrap();
        let top = camera.ray(150.0, 0.0).dir;
        assert!((top.y.atan2(top.z).to_degrees() - 30.0).abs() < 1e-4);
        // Horizontal half-angle follows the 3:1 aspect ratio: atan(3·tan 30°).
        let left = camera.ray(0.0, 50.0).dir;
        let expected = (3.0 * 30f32.to_radians().tan()).atan().to_degrees();
        assert!((left.x.atan2(left.z).to_degrees() - expected).abs() < 1e-3);
    }

    #[test]
    fn degenerate_cameras_are_rejected() {
        assert_eq!(
            Pinhole::look_at(Vec3::ONE, Vec3::ONE, Vec3::Y, 60.0, 1, 1),
            Err(CameraError::NoViewDirection)
        );
        assert_eq!(Pinhole::look_at(Vec3::ZERO, Vec3::Y, Vec3::Y, 60.0, 1, 1), Err(CameraError::UpParallel));
        assert_eq!(
            Pinhole::look_at(Vec3::ZERO, Vec3::Z, Vec3::ZERO, 60.0, 1, 1),
            Err(CameraError::UpParallel)
        );
        assert_eq!(
            Pinhole::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 180.0, 1, 1),
            Err(CameraError::FieldOfView(180.0))
        );
    }

    /// `project` inverts `ray`, and its sensitivity is what a pixel reads of a small patch:
    /// a patch of area a and radiance L facing the camera has intensity J = L·a; the pixel
    /// that sees it whole reads L·(a/d²)/Ω_pixel, so sensitivity = 1/(d²·Ω_pixel), with the
    /// pixel's solid angle Ω_pixel computed here from its four corner rays.
    #[test]
    fn project_inverts_ray_and_gives_the_pixel_solid_angle() {
        let camera = Pinhole::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 50.0, 64, 48).unwrap();
        for (x, y) in [(10.5f32, 40.5f32), (32.5, 24.5), (63.5, 0.5)] {
            let ray = camera.ray(x, y);
            let point = ray.at(7.0);
            let seen = camera.project(point).unwrap();
            assert_eq!(seen.pixel, x as u32 + (y as u32) * 64);
            assert!((seen.distance - 7.0).abs() < 1e-4);
            assert!((seen.to_camera + ray.dir).length() < 1e-5);
            // The solid angle of the pixel, as two spherical triangles (van Oosterom–Strackee).
            let (px, py) = (x.floor(), y.floor());
            let corners = [(px, py), (px + 1.0, py), (px + 1.0, py + 1.0), (px, py + 1.0)]
                .map(|(a, b)| camera.ray(a, b).dir);
            let triangle = |a: Vec3, b: Vec3, c: Vec3| {
                let numerator = a.dot(b.cross(c)).abs();
                let denominator = 1.0 + a.dot(b) + b.dot(c) + c.dot(a);
                2.0 * numerator.atan2(denominator)
            };
            let omega =
                triangle(corners[0], corners[1], corners[2]) + triangle(corners[0], corners[2], corners[3]);
            let expected = 1.0 / (49.0 * omega);
            assert!((seen.sensitivity / expected - 1.0).abs() < 1e-3, "{} vs {expected}", seen.sensitivity);
        }
        assert!(camera.project(Vec3::new(0.0, 0.0, -1.0)).is_none(), "behind the camera");
        assert!(camera.project(Vec3::new(10.0, 0.0, 1.0)).is_none(), "outside the image");
    }

    #[test]
    fn stokes_frame_is_image_right_and_up_for_the_receiver() {
        let camera = Pinhole::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 60.0, 200, 100).unwrap();
        let centre = camera.ray(100.0, 50.0);
        let x = camera.stokes_x(centre.dir);
        // Image right is world −x here (see the test above); y = (−dir) × x is image up.
        assert!((x - Vec3::NEG_X).length() < 1e-6, "{x}");
        assert!(((-centre.dir).cross(x) - Vec3::Y).length() < 1e-6);
        let off_axis = camera.ray(10.0, 5.0).dir;
        assert!(camera.stokes_x(off_axis).dot(off_axis).abs() < 1e-6);
    }
}

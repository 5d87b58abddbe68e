//! [`Camera`]: a pinhole camera.
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

use crate::geometry::Ray;

/// A pinhole camera.
#[derive(Debug, Clone, PartialEq)]
pub struct Camera {
    position: Vec3,
    forward: Vec3,
    /// Unit vector toward the image's right, scaled by tan(fov_y/2)·aspect.
    right_scaled: Vec3,
    /// Unit vector toward the image's top, scaled by tan(fov_y/2).
    up_scaled: Vec3,
    /// Unit vector toward the image's top.
    up: Vec3,
    width: u32,
    height: u32,
}

/// Why a camera is degenerate.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CameraError {
    /// look_at equals position.
    #[error("look_at equals position: the view direction is undefined")]
    NoViewDirection,
    /// up is zero or parallel to the view direction.
    #[error("up is zero or parallel to the view direction")]
    UpParallel,
    /// The field of view is not in (0, 180) degrees.
    #[error("fov_y_deg must be in (0, 180), got {0}")]
    FieldOfView(f32),
    /// Zero image size.
    #[error("width and height must be ≥ 1, got {0}×{1}")]
    Resolution(u32, u32),
}

impl Camera {
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
            up: true_up,
            width,
            height,
        })
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
        })
    }

    /// Image width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Image height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The primary ray through film position (`x`, `y`) in pixels (x to the right, y down).
    #[inline]
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        let ndc_x = 2.0 * x / self.width as f32 - 1.0;
        let ndc_y = 1.0 - 2.0 * y / self.height as f32;
        let dir = (self.forward + ndc_x * self.right_scaled + ndc_y * self.up_scaled).normalize();
        Ray::new(self.position, dir)
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
        let camera = Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 60.0, 200, 100).unwrap();
        let left_edge = camera.ray(0.0, 50.0);
        assert!(left_edge.dir.x > 0.0, "{:?}", left_edge.dir);
        let top_edge = camera.ray(100.0, 0.0);
        assert!(top_edge.dir.y > 0.0);
        let centre = camera.ray(100.0, 50.0);
        assert!((centre.dir - Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn vertical_field_of_view_is_exact() {
        let camera = Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 60.0, 300, 100).unwrap();
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
            Camera::look_at(Vec3::ONE, Vec3::ONE, Vec3::Y, 60.0, 1, 1),
            Err(CameraError::NoViewDirection)
        );
        assert_eq!(Camera::look_at(Vec3::ZERO, Vec3::Y, Vec3::Y, 60.0, 1, 1), Err(CameraError::UpParallel));
        assert_eq!(
            Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::ZERO, 60.0, 1, 1),
            Err(CameraError::UpParallel)
        );
        assert_eq!(
            Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 180.0, 1, 1),
            Err(CameraError::FieldOfView(180.0))
        );
    }

    #[test]
    fn stokes_frame_is_image_right_and_up_for_the_receiver() {
        let camera = Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 60.0, 200, 100).unwrap();
        let centre = camera.ray(100.0, 50.0);
        let x = camera.stokes_x(centre.dir);
        // Image right is world −x here (see the test above); y = (−dir) × x is image up.
        assert!((x - Vec3::NEG_X).length() < 1e-6, "{x}");
        assert!(((-centre.dir).cross(x) - Vec3::Y).length() < 1e-6);
        let off_axis = camera.ray(10.0, 5.0).dir;
        assert!(camera.stokes_x(off_axis).dot(off_axis).abs() < 1e-6);
    }
}

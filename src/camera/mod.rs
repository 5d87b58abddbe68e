//! [`Camera`]: what turns a film position into a ray (for the camera's estimators) and a point of
//! the scene into a film position (for the light tracer's connections), as a closed set of kinds:
//!
//! - [`Pinhole`]: every ray from one point (`[camera]` without `aperture_radius`);
//! - [`ThinLens`]: an ideal thin lens, for depth of field (`aperture_radius`, `focus_distance`).
//! - [`LensCamera`]: a lens system of real glass traced per wavelength (`lens`,
//!   `sensor_height_mm`; see [`lens_system`]).
//!
//! Both share the pinhole's conventions (Mitsuba 3's `look_at`, pixel (0, 0) top-left, a
//! vertical field of view) and the Stokes frame [`Camera::stokes_x`]. A camera sample draws the
//! film position, then the lens sample, only for a camera with a lens ([`Camera::sample_ray`]),
//! so the pinhole's sample stream is unchanged by the existence of lenses.
//!
//! ```toml
//! [camera]
//! position = [0, 2, -6]
//! look_at = [0, 0, 100]
//! up = [0, 1, 0]
//! fov_y_deg = 60
//! width = 600
//! height = 400
//! aperture_radius = 0.05  # optional: a thin lens (scene units)
//! focus_distance = 6      # with aperture_radius: the plane of focus's depth (scene units)
//! ```

pub mod lens_system;
mod pinhole;
mod thin_lens;

use glam::Vec3;

pub use lens_system::{HeroSample, LanePaths, LensCamera, LensSettings};
pub use pinhole::Pinhole;
pub use thin_lens::ThinLens;

use crate::geometry::Ray;

/// A camera: one of a closed set of kinds.
#[derive(Debug, Clone, PartialEq)]
pub enum Camera {
    /// Every ray from one point.
    Pinhole(Pinhole),
    /// An ideal thin lens: depth of field.
    ThinLens(ThinLens),
    /// A lens system of real glass, traced per wavelength: the renderer draws its rays with
    /// [`LensCamera::sample_ray`] (one per wavelength lane); [`Camera::sample_ray`] gives its
    /// chief-ray approximation and [`Camera::project`] `None` (light paths cannot be connected
    /// through glass; caustics are refused with it).
    Lens(LensCamera),
}

/// A point seen by the camera, as [`Camera::project`] finds it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilmPoint {
    /// Row-major index of the pixel it lands in.
    pub pixel: u32,
    /// Unit direction from the point to the camera (the pinhole, or the lens point drawn).
    pub to_camera: Vec3,
    /// Distance from the point to the camera (the pinhole, or the lens point drawn).
    pub distance: f32,
    /// The radiance that pixel reads (box filter) per unit of radiant intensity (W·sr⁻¹)
    /// leaving the point toward the camera: 1/(d²·A_pixel·cos³θ), with A_pixel a pixel's area
    /// on the image plane at unit distance and θ the angle off the optical axis (a pixel there
    /// spans the solid angle A_pixel·cos³θ). Per unit area (m⁻²·sr⁻¹ per W·sr⁻¹). For a thin
    /// lens, divided by the density of the lens point drawn (uniform over the lens).
    pub sensitivity: f32,
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
    /// A thin lens's radius is not positive and finite.
    #[error("aperture_radius must be positive and finite, got {0}")]
    ApertureRadius(f32),
    /// A thin lens's focus distance is not positive and finite.
    #[error("focus_distance must be positive and finite, got {0}")]
    FocusDistance(f32),
    /// A lens system that cannot be used as set (its file, focus, f-number, sensor).
    #[error("{0}")]
    Lens(String),
}

impl Camera {
    /// The same camera with another resolution (the field of view stays vertical).
    pub fn with_resolution(&self, width: u32, height: u32) -> Result<Self, CameraError> {
        Ok(match self {
            Camera::Pinhole(pinhole) => Camera::Pinhole(pinhole.with_resolution(width, height)?),
            Camera::ThinLens(lens) => Camera::ThinLens(lens.with_resolution(width, height)?),
            Camera::Lens(lens) => Camera::Lens(lens.with_resolution(width, height)?),
        })
    }

    /// The film, field of view and centre of the camera, as a pinhole.
    pub fn pinhole(&self) -> &Pinhole {
        match self {
            Camera::Pinhole(pinhole) => pinhole,
            Camera::ThinLens(lens) => lens.pinhole(),
            Camera::Lens(lens) => lens.pinhole(),
        }
    }

    /// Image width in pixels.
    pub fn width(&self) -> u32 {
        self.pinhole().width()
    }

    /// Image height in pixels.
    pub fn height(&self) -> u32 {
        self.pinhole().height()
    }

    /// The ray through film position (`x`, `y`) in pixels (x to the right, y down) from the
    /// centre of the camera (the chief ray): the camera's ray for the pinhole; for a lens, the
    /// ray through its centre, the one every ray of that film position is blurred about. For
    /// rendering, [`Self::sample_ray`].
    #[inline]
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        self.pinhole().ray(x, y)
    }

    /// A camera ray from film position (`x`, `y`) in pixels, its point on the lens drawn from
    /// `lens_sample` (two uniform numbers in [0, 1)), which is called only by a camera with a
    /// lens: the pinhole's sample stream stays as it is. The ray's weight is 1 for every kind.
    #[inline]
    pub fn sample_ray(&self, x: f32, y: f32, lens_sample: impl FnOnce() -> (f32, f32)) -> Ray {
        match self {
            Camera::Pinhole(pinhole) => pinhole.ray(x, y),
            Camera::ThinLens(lens) => lens.ray(x, y, lens_sample()),
            // The renderer traces the lens per lane ([`LensCamera::sample_ray`]); this is the
            // chief ray's paraxial approximation.
            Camera::Lens(lens) => lens.pinhole().ray(x, y),
        }
    }

    /// Where the light leaving `point` toward the camera lands on the film, if it does (the
    /// point lies in front of the camera and projects inside the image); for the light tracer.
    /// A camera with a lens draws the lens point it connects to from `lens_sample` (two uniform
    /// numbers in [0, 1), called only then).
    #[inline]
    pub fn project(&self, point: Vec3, lens_sample: impl FnOnce() -> (f32, f32)) -> Option<FilmPoint> {
        match self {
            Camera::Pinhole(pinhole) => pinhole.project(point),
            Camera::ThinLens(lens) => lens.project(point, lens_sample()),
            Camera::Lens(_) => None,
        }
    }

    /// The x axis of the Stokes frame in which the light arriving along a camera ray of
    /// direction `dir` is recorded: normalize(dir × up), with `up` the camera's unit up vector.
    /// It is the image's right for the central ray, as in Mitsuba 3's `stokes` integrator, and
    /// tilts with off-axis rays. Light travels along −dir, so y = (−dir) × x points up. For a
    /// thin lens, `dir` is the ray's own direction (from its lens point), as Mitsuba's `stokes`
    /// integrator takes it whatever the sensor.
    #[inline]
    pub fn stokes_x(&self, dir: Vec3) -> Vec3 {
        self.pinhole().stokes_x(dir)
    }
}

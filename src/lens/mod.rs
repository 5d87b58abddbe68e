//! Lens systems: prescriptions of rotationally symmetric refracting surfaces (a camera made of
//! real glass), read from pbrt-v4 lens files or Zemax `.zmx`, analysed paraxially and traced
//! with real rays per wavelength, in f64.
//!
//! Conventions, those of optical design codes (Zemax, CODE V, rayoptics), so that a
//! prescription reads the same here as in a lens designer's table:
//! - surfaces are listed from the object (scene) side to the image (sensor) side;
//! - the optical axis is +z, from the object toward the image, with the first surface's vertex
//!   at z = 0; lengths in mm;
//! - a radius of curvature is positive when the centre of curvature lies on the image side of
//!   the vertex, and 0 means flat;
//! - a surface's thickness is the axial distance from its vertex to the next surface's vertex
//!   (for the last surface, to the image plane);
//! - a surface's medium is the one behind it (on its image side); object space is air;
//! - air has n = 1 exactly: catalogue indices are relative to air, as in glass makers' data
//!   sheets and in the design codes the lenses are checked against.
//!
//! Modules: [`prescription`] (the types), [`paraxial`] (first-order data per wavelength),
//! [`surface_geometry`] (sag, ray–surface hits, normals), [`fresnel_stack`] (f64 Fresnel and
//! path Mueller matrices), [`trace`] (real rays both ways, ghost branches; `lanes`: a camera sample's wavelengths in SIMD), [`reverse`] (a scene ray
//! back to the sensor, for the camera's hero wavelength), [`pupil`] (aiming
//! camera rays and the radiometric weight), [`file`] with [`pbrt`] and [`zmx`] (reading
//! prescriptions; [`glass_spec`] for a pbrt file's glass column; [`coating`] for coated
//! surfaces).

pub mod analysis;
pub mod coating;
pub mod file;
pub mod fresnel_stack;
pub mod glass_spec;
mod lanes;
pub mod paraxial;
pub mod pbrt;
pub mod prescription;
pub mod pupil;
pub mod reverse;
pub mod surface_geometry;
pub mod trace;
pub mod zmx;

pub use coating::Coating;
pub use file::read_lens_file;
pub use fresnel_stack::{interface_fresnel, InterfaceFresnel, Mueller4};
pub use lanes::ReverseLane;
pub use paraxial::{Paraxial, LAMBDA_D_NM};
pub use prescription::{LensError, LensSystem, Medium, Surface};
pub use pupil::{
    CameraRay, ExitPupilBounds, Normalisation, PupilRegion, PupilSample, RearDisc, SensorSampler,
};
pub use reverse::{ReverseTrace, MAX_REVERSE_SURFACES};
pub use trace::{Blocked, LensSample, LensTracer, Ray, TraceOptions};

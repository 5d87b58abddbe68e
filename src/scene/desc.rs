//! The scene file format: serde types that mirror the TOML text one to one, with no validation
//! beyond types. [`super::build`] turns them into the runtime [`super::Scene`].
//!
//! The format is documented for users in `scenes/README.md`. Every table rejects unknown keys.
//!
//! ```toml
//! [camera]
//! position = [0, 2, -6]
//! look_at = [0, 0, 100]
//! fov_y_deg = 60
//! width = 600
//! height = 400
//!
//! [materials.glass]
//! type = "dielectric"
//! ior = { glass = "N-SF11" }
//!
//! [[shapes]]
//! type = "sphere"
//! center = [2, 0, 3]
//! radius = 1.5
//! material = "glass"
//! ```

use std::collections::BTreeMap;
use std::fmt;

use serde::de::{self, MapAccess, Visitor};
use serde::{Deserialize, Deserializer};
use toml::Spanned;

use super::typed::{TypeNames, Typed};

/// A whole scene file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDesc {
    /// The camera: a pinhole, or a thin lens.
    pub camera: Spanned<CameraDesc>,
    /// Render settings (all optional).
    #[serde(default)]
    pub render: Option<Spanned<RenderDesc>>,
    /// Radiance of rays that escape the scene (W·m⁻²·sr⁻¹·nm⁻¹); zero when absent.
    #[serde(default)]
    pub background: Option<Spanned<SpectrumDesc>>,
    /// Named materials, referenced by shapes.
    #[serde(default)]
    pub materials: BTreeMap<String, Spanned<Typed<MaterialDesc>>>,
    /// The shapes, in order.
    #[serde(default)]
    pub shapes: Vec<Spanned<Typed<ShapeDesc>>>,
    /// The lights, in order.
    #[serde(default)]
    pub lights: Vec<Spanned<Typed<LightDesc>>>,
}

/// `[camera]`: a pinhole camera, or with `aperture_radius` a thin lens ([`crate::camera`]).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CameraDesc {
    /// Eye position (scene units).
    pub position: [f32; 3],
    /// A point the camera looks at.
    pub look_at: [f32; 3],
    /// Up direction (need not be orthogonal to the view); +y when absent.
    #[serde(default = "default_up")]
    pub up: [f32; 3],
    /// Vertical field of view in degrees; required but with a `lens`, which refuses it.
    #[serde(default)]
    pub fov_y_deg: Option<Spanned<f32>>,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Radius of a thin lens (scene units); absent or 0: the pinhole.
    #[serde(default)]
    pub aperture_radius: Option<Spanned<f32>>,
    /// Depth of the thin lens's plane of focus along the view direction (scene units); required
    /// with a positive `aperture_radius`, refused without one.
    #[serde(default)]
    pub focus_distance: Option<Spanned<f32>>,
    /// A lens system's file (pbrt-v4 lens file or Zemax `.zmx`), relative to the scene file
    /// ([`crate::camera::LensCamera`]); `focus_distance` is then the distance in focus from
    /// the lens's first vertex (absent: infinity).
    #[serde(default)]
    pub lens: Option<Spanned<String>>,
    /// With `lens`: the image's height on the sensor (mm).
    #[serde(default)]
    pub sensor_height_mm: Option<Spanned<f64>>,
    /// With `lens`: stop down to this f-number.
    #[serde(default)]
    pub f_number: Option<Spanned<f64>>,
    /// With `lens`: the most ghost reflections a camera ray may take (default 0).
    #[serde(default)]
    pub lens_ghosts: Option<Spanned<u32>>,
    /// With `lens`: how the wavelength lanes of a camera sample find their scene paths,
    /// `"per_lane"` (default) or `"shared"` (`crate::camera::LanePaths`).
    #[serde(default)]
    pub lens_lanes: Option<Spanned<String>>,
}

fn default_up() -> [f32; 3] {
    [0.0, 1.0, 0.0]
}

/// `[render]`: sampling settings; every field has a default.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RenderDesc {
    /// The camera's estimator: `"whitted"` (the default) or `"path"` (full transport).
    pub integrator: Option<String>,
    /// Camera samples per pixel.
    pub spp: Option<u32>,
    /// Maximum number of specular bounces (recursion depth).
    pub max_depth: Option<u32>,
    /// Wavelengths carried by each camera sample (1..=8).
    pub wavelengths: Option<u32>,
    /// Seed of the per-pixel random streams.
    pub seed: Option<u64>,
    /// Stratified samples per quad light at each diffuse shading point.
    pub area_light_samples: Option<u32>,
    /// Branch weight under which Russian roulette may prune a Whitted branch (0 turns pruning
    /// off). Whitted's alone: the path tracer's roulette has no setting.
    pub prune_below: Option<f32>,
    /// Carry Stokes vectors along every path (true, the default) or only radiance, with each
    /// interface's reflectance averaged over s and p (false: faster, approximate).
    pub polarized: Option<bool>,
    /// Add caustics by light tracing (light → mirrors and glass → diffuse → camera).
    pub caustics: Option<bool>,
    /// Light paths traced per pass (one pass per sample per pixel); the pixel count when absent.
    pub light_paths: Option<u64>,
    /// Start light paths by the guide learned from the render's first light paths (true, the
    /// default) or all uniformly (false).
    pub light_guide: Option<bool>,
    /// Camera samples per pass of the pixels an edge crosses, chosen after the first pass (1,
    /// the default, turns edge refinement off).
    pub edge_samples: Option<u32>,
}

/// A material, selected by `type` (read by [`Typed`], which keeps the positions of its values).
#[derive(Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum MaterialDesc {
    /// Lambertian or Oren–Nayar diffuse reflector.
    Diffuse {
        /// Albedo ρ (reflectance spectrum in [0, 1]).
        albedo: SpectrumDesc,
        /// Oren–Nayar roughness σ in degrees (0 or absent: Lambert).
        #[serde(default)]
        roughness_deg: Option<f32>,
    },
    /// Perfect specular mirror.
    Mirror {
        /// Reflectance spectrum; 1 when absent.
        #[serde(default)]
        reflectance: Option<SpectrumDesc>,
        /// A metal of data/metals/ whose Fresnel reflectance applies (silver, aluminium, gold, copper).
        #[serde(default)]
        metal: Option<String>,
        /// A constant complex index [n, k] (n + ik) whose Fresnel reflectance applies.
        #[serde(default)]
        complex_ior: Option<[f32; 2]>,
        /// Thin coherent layers on the metal, from the outside inwards; bare when absent.
        #[serde(default)]
        coating: Option<Vec<CoatingLayerDesc>>,
    },
    /// Smooth dielectric (glass, water...).
    Dielectric {
        /// Index of refraction model.
        ior: IorDesc,
        /// Absorption coefficient inside, per scene unit (Beer–Lambert); none when absent.
        #[serde(default)]
        absorption: Option<SpectrumDesc>,
        /// Thin coherent layers on the interface, from the outside inwards; bare when absent.
        #[serde(default)]
        coating: Option<Vec<CoatingLayerDesc>>,
    },
    /// Free-standing thin film in air (a soap film): coherent reflection and straight
    /// transmission (`material::film`).
    Film {
        /// The film's index of refraction (n ≥ 1); water (`{ glass = "water" }`) when absent.
        #[serde(default)]
        ior: Option<IorDesc>,
        /// Thickness in nm: a number, or a drained film `{ top, bottom, axis, heights }`.
        thickness_nm: ThicknessDesc,
    },
    /// Ideal linear polariser sheet (flat shapes only).
    Polarizer {
        /// Transmission axis in world space (projected onto the sheet).
        axis: [f32; 3],
        /// Fraction of the light along the axis that passes (a spectrum in [0, 1]); 1 when absent.
        #[serde(default)]
        transmittance: Option<SpectrumDesc>,
    },
    /// Ideal linear retarder sheet, a wave plate (flat shapes only).
    Retarder {
        /// Fast axis in world space (projected onto the sheet).
        fast_axis: [f32; 3],
        /// Retardance in degrees (90: quarter-wave, 180: half-wave).
        retardance_deg: f32,
    },
}

impl TypeNames for MaterialDesc {
    const TYPES: &'static [&'static str] =
        &["diffuse", "mirror", "dielectric", "film", "polarizer", "retarder"];
}

/// A shape, selected by `type`.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum ShapeDesc {
    /// A sphere.
    Sphere {
        /// Centre.
        center: [f32; 3],
        /// Radius (> 0).
        radius: f32,
        /// Material name.
        material: String,
    },
    /// An infinite plane.
    Plane {
        /// A point on the plane.
        point: [f32; 3],
        /// Normal (outside direction), any non-zero length.
        normal: [f32; 3],
        /// Material name.
        material: String,
    },
    /// A parallelogram `corner + u·edge1 + v·edge2`.
    Quad {
        /// Corner.
        corner: [f32; 3],
        /// First edge.
        edge1: [f32; 3],
        /// Second edge.
        edge2: [f32; 3],
        /// Material name.
        material: String,
    },
    /// A triangle mesh from an OBJ file.
    Mesh {
        /// OBJ path, relative to the scene file.
        file: String,
        /// Material name.
        material: String,
        /// Uniform scale factor (> 0); 1 when absent.
        #[serde(default)]
        scale: Option<f32>,
        /// Rotations about x, then y, then z, in degrees, applied after scaling.
        #[serde(default)]
        rotate_deg: Option<[f32; 3]>,
        /// Translation applied last (where the mesh's local origin goes).
        #[serde(default)]
        position: Option<[f32; 3]>,
    },
    /// The built-in closed triangular prism.
    Prism {
        /// Apex angle in degrees (0 < A < 180).
        apex_angle_deg: f32,
        /// Slant length of the two faces meeting at the apex.
        side_length: f32,
        /// Extrusion length (along the local z axis).
        length: f32,
        /// Material name.
        material: String,
        /// Rotations about x, then y, then z, in degrees.
        #[serde(default)]
        rotate_deg: Option<[f32; 3]>,
        /// Where the centroid of the prism goes.
        #[serde(default)]
        position: Option<[f32; 3]>,
    },
}

impl TypeNames for ShapeDesc {
    const TYPES: &'static [&'static str] = &["sphere", "plane", "quad", "mesh", "prism"];
}

/// A light, selected by `type`.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum LightDesc {
    /// An isotropic point light.
    Point {
        /// Position.
        position: [f32; 3],
        /// Radiant intensity, W·sr⁻¹·nm⁻¹.
        intensity: SpectrumDesc,
    },
    /// A one-sided parallelogram area light, also visible to the camera.
    Quad {
        /// Corner.
        corner: [f32; 3],
        /// First edge.
        edge1: [f32; 3],
        /// Second edge.
        edge2: [f32; 3],
        /// Emitted radiance, W·m⁻²·sr⁻¹·nm⁻¹.
        radiance: SpectrumDesc,
        /// The side that emits.
        emit: EmitSide,
        /// Diffuse (Lambertian) albedo of the emitting quad's surface, a reflectance in [0, 1]:
        /// light falling on it is reflected as by a `diffuse` material (both sides). Black when
        /// absent.
        #[serde(default)]
        albedo: Option<SpectrumDesc>,
    },
    /// A point light emitting into a cone (Mitsuba's `spot`).
    Spot {
        /// Position.
        position: [f32; 3],
        /// A point on the axis of the cone.
        look_at: [f32; 3],
        /// Radiant intensity on the axis, W·sr⁻¹·nm⁻¹.
        intensity: SpectrumDesc,
        /// Half-angle of the cone in degrees, in (0, 180): dark beyond.
        cutoff_deg: f32,
        /// Half-angle of the fully bright core in degrees, in (0, cutoff]; 3/4 of the cutoff when
        /// absent.
        #[serde(default)]
        beam_width_deg: Option<f32>,
    },
    /// A collimated beam leaving a parallelogram along its normal (Mitsuba's `directionalarea`).
    Beam {
        /// Corner.
        corner: [f32; 3],
        /// First edge.
        edge1: [f32; 3],
        /// Second edge.
        edge2: [f32; 3],
        /// Irradiance on a plane perpendicular to the beam, W·m⁻²·nm⁻¹.
        irradiance: SpectrumDesc,
        /// The direction the beam travels.
        emit: EmitSide,
    },
}

impl TypeNames for LightDesc {
    const TYPES: &'static [&'static str] = &["point", "quad", "spot", "beam"];
}

/// The emitting side of a quad light.
#[derive(Debug, Deserialize, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum EmitSide {
    /// Light leaves along `edge1 × edge2`.
    Edge1CrossEdge2,
    /// Light leaves along `edge2 × edge1`.
    Edge2CrossEdge1,
}

/// A spectrum in the file: a bare number (constant) or a table (see [`SpectrumFields`]).
#[derive(Debug, Clone, PartialEq)]
pub struct SpectrumDesc(pub SpectrumFields);

/// The table form of a spectrum: exactly one of `value`, `rgb`, `table`, `illuminant`,
/// `blackbody_k`, and an optional `scale`.
#[derive(Debug, Clone, PartialEq, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct SpectrumFields {
    /// Constant value.
    pub value: Option<f32>,
    /// Linear sRGB triple.
    pub rgb: Option<[f32; 3]>,
    /// (wavelength nm, value) pairs.
    pub table: Option<Vec<[f32; 2]>>,
    /// A named illuminant: "D65" or "E".
    pub illuminant: Option<String>,
    /// Blackbody temperature in kelvin.
    pub blackbody_k: Option<f32>,
    /// Factor applied to the whole spectrum.
    pub scale: Option<f32>,
}

/// An index of refraction in the file: a bare number or a table (see [`IorFields`]).
#[derive(Debug, Clone, PartialEq)]
pub struct IorDesc(pub IorFields);

/// The table form of an index of refraction: exactly one of `value`, `cauchy`, `sellmeier`,
/// `glass`, `table`.
#[derive(Debug, Clone, PartialEq, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct IorFields {
    /// Constant index.
    pub value: Option<f32>,
    /// Cauchy coefficients [A, B µm², C µm⁴].
    pub cauchy: Option<[f32; 3]>,
    /// Sellmeier three-term coefficients.
    pub sellmeier: Option<SellmeierDesc>,
    /// A glass of the catalogue in data/glasses.toml.
    pub glass: Option<String>,
    /// (wavelength nm, n) pairs.
    pub table: Option<Vec<[f32; 2]>>,
}

/// One layer of a dielectric's or a mirror's coating: exactly one of `ior`, `metal`,
/// `complex_ior`, and a thickness.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CoatingLayerDesc {
    /// A real index of refraction (any form a material's `ior` takes).
    #[serde(default)]
    pub ior: Option<IorDesc>,
    /// An absorbing layer of a metal of data/metals/ (n + ik from its table).
    #[serde(default)]
    pub metal: Option<String>,
    /// An absorbing layer of constant complex index [n, k] (n + ik).
    #[serde(default)]
    pub complex_ior: Option<[f32; 2]>,
    /// Physical thickness in nm.
    pub thickness_nm: f32,
}

/// A film's thickness: a number (nm), or the table of a film drained by gravity.
#[derive(Debug, Clone, PartialEq)]
pub struct ThicknessDesc(pub ThicknessFields);

/// The table form of a film's thickness: `value` (a constant, nm), or `top` and `bottom` (nm)
/// along `axis` (pointing up), between `heights` = [bottom, top] in scene units (the extent of
/// the shapes with the film when absent), or a greyscale `texture` (a PNG, relative to the
/// scene file) from `min` (black) to `max` (white) nm, laid on `corner + s·edge1 + t·edge2`
/// (`material::film::ThicknessTexture`).
#[derive(Debug, Clone, PartialEq, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct ThicknessFields {
    /// Constant thickness (nm).
    pub value: Option<f32>,
    /// Thickness at the top (nm).
    pub top: Option<f32>,
    /// Thickness at the bottom (nm).
    pub bottom: Option<f32>,
    /// The up direction (any non-zero length).
    pub axis: Option<[f32; 3]>,
    /// Heights of the bottom and the top along the unit axis (scene units).
    pub heights: Option<[f32; 2]>,
    /// A greyscale PNG of the thickness, relative to the scene file.
    pub texture: Option<String>,
    /// Thickness (nm) at the texture's black.
    pub min: Option<f32>,
    /// Thickness (nm) at the texture's white.
    pub max: Option<f32>,
    /// The corner of the parallelogram the texture is laid on (scene units).
    pub corner: Option<[f32; 3]>,
    /// Its edge along the image's columns, left to right (scene units).
    pub edge1: Option<[f32; 3]>,
    /// Its edge along the image's rows, bottom to top (scene units).
    pub edge2: Option<[f32; 3]>,
}

/// Sellmeier coefficients.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SellmeierDesc {
    /// B₁, B₂, B₃.
    pub b: [f32; 3],
    /// C₁, C₂, C₃ in µm².
    pub c_um2: [f32; 3],
}

/// Implements `Deserialize` for a newtype over a fields table that has a `value` field, so that
/// a bare number stands for `{ value = number }`.
macro_rules! number_or_table {
    ($newtype:ident, $fields:ident, $what:literal) => {
        impl<'de> Deserialize<'de> for $newtype {
            fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
                struct NumberOrTable;
                impl<'de> Visitor<'de> for NumberOrTable {
                    type Value = $newtype;
                    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                        f.write_str($what)
                    }
                    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Self::Value, E> {
                        Ok($newtype($fields { value: Some(v as f32), ..Default::default() }))
                    }
                    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Self::Value, E> {
                        self.visit_f64(v as f64)
                    }
                    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Self::Value, E> {
                        self.visit_f64(v as f64)
                    }
                    fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Self::Value, A::Error> {
                        $fields::deserialize(de::value::MapAccessDeserializer::new(map)).map($newtype)
                    }
                }
                deserializer.deserialize_any(NumberOrTable)
            }
        }
    };
}

number_or_table!(SpectrumDesc, SpectrumFields, "a number or a spectrum table such as { rgb = [r, g, b] }");
number_or_table!(IorDesc, IorFields, "a number or an IOR table such as { glass = \"N-BK7\" }");
number_or_table!(
    ThicknessDesc,
    ThicknessFields,
    "a number (nm) or a drained film such as { top = 150, bottom = 900, axis = [0, 1, 0] }"
);

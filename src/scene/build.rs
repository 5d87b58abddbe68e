//! Validation of a parsed [`SceneDesc`] into a runtime [`Scene`]: ranges checked, names resolved,
//! spectra and IOR models built, meshes loaded. Every error names the file, the line of the table
//! that holds the bad value and the field.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

use glam::{Affine3A, EulerRot, Quat, Vec3};
use toml::Spanned;

use super::desc::{
    CameraDesc, EmitSide, IorDesc, LightDesc, MaterialDesc, RenderDesc, SceneDesc, ShapeDesc, SpectrumDesc,
};
use super::error::{line_column, one_line};
use super::{RenderSettings, Scene, SceneError, Surface};
use crate::camera::Camera;
use crate::geometry::{Geometry, Mesh, Plane, Quad, Shape, Sphere};
use crate::light::{BeamLight, Light, PointLight, QuadLight, SpotLight};
use crate::material::{Conductor, Dielectric, Diffuse, Material, Mirror, Polarizer, Retarder};
use crate::optics::{catalogue, metals, Ior};
use crate::spectrum::{DenseSpectrum, Spectrum, N_LAMBDA};

/// Largest accepted image side, in pixels.
pub const MAX_RESOLUTION: u32 = 32_768;
/// Largest accepted sample count per pixel.
pub const MAX_SPP: u32 = 1 << 20;
/// Largest accepted recursion depth (deep Whitted chains recurse on the thread stack).
pub const MAX_DEPTH: u32 = 4096;
/// Largest accepted number of light paths per pass.
pub const MAX_LIGHT_PATHS: u64 = 1 << 40;

/// Reads and builds the scene file at `path`.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let text =
        std::fs::read_to_string(path).map_err(|source| SceneError::Io { file: path.to_owned(), source })?;
    parse(&text, path)
}

/// Builds a scene from the TOML `text` of the file `path` (used in messages and to resolve
/// relative mesh paths).
pub fn parse(text: &str, path: &Path) -> Result<Scene, SceneError> {
    let desc: SceneDesc = toml::from_str(text).map_err(|err| {
        let (line, column) = err.span().map_or((1, 1), |span| line_column(text, span.start));
        SceneError::Syntax { file: path.to_owned(), line, column, message: one_line(err.message()) }
    })?;
    Builder { text, path }.build(desc)
}

/// The role of a spectrum decides how an RGB triple is upsampled and what range is valid.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Role {
    /// Reflectance in [0, 1]: RGB upsampled without an illuminant.
    Reflectance,
    /// Emission ≥ 0: RGB times D65.
    Emission,
    /// A non-negative coefficient (absorption): RGB upsampled like a reflectance, then scaled.
    Coefficient,
}

/// The scene's materials while shapes are built: names to indices, and the built materials.
struct Materials<'m> {
    ids: &'m BTreeMap<&'m str, u32>,
    built: &'m [Material],
}

struct Builder<'a> {
    text: &'a str,
    path: &'a Path,
}

impl Builder<'_> {
    fn error(
        &self,
        span: std::ops::Range<usize>,
        field: impl Into<String>,
        message: impl Into<String>,
    ) -> SceneError {
        SceneError::Invalid {
            file: self.path.to_owned(),
            line: line_column(self.text, span.start).0,
            field: field.into(),
            message: one_line(&message.into()),
        }
    }

    fn build(&self, desc: SceneDesc) -> Result<Scene, SceneError> {
        let camera = self.camera(&desc.camera)?;
        let settings = match &desc.render {
            Some(render) => self.settings(render)?,
            None => RenderSettings::default(),
        };
        let background = match &desc.background {
            Some(spectrum) => {
                self.spectrum(spectrum.get_ref(), Role::Emission, spectrum.span(), "background")?
            }
            None => DenseSpectrum::constant(0.0),
        };

        let mut materials = Vec::with_capacity(desc.materials.len() + 1);
        let mut material_ids = BTreeMap::new();
        let mut material_names = Vec::with_capacity(desc.materials.len() + 1);
        for (name, material) in &desc.materials {
            material_ids.insert(name.as_str(), materials.len() as u32);
            materials.push(self.material(name, material)?);
            material_names.push(name.clone());
        }

        let mut shapes = Vec::new();
        let mut surfaces = Vec::new();
        let mut meshes = Vec::new();
        for (index, shape) in desc.shapes.iter().enumerate() {
            let known = Materials { ids: &material_ids, built: &materials };
            self.shape(index, shape, &known, &mut shapes, &mut surfaces, &mut meshes)?;
        }

        let mut lights = Vec::with_capacity(desc.lights.len());
        let mut black = None;
        for (index, light) in desc.lights.iter().enumerate() {
            let built = self.light(index, light)?;
            // Quad lights and beams are black parallelograms in the scene.
            let surface = match &built {
                Light::Quad(quad) => Some(quad.quad),
                Light::Beam(beam) => Some(beam.quad),
                Light::Point(_) | Light::Spot(_) => None,
            };
            if let Some(quad) = surface {
                let material = *black.get_or_insert_with(|| {
                    materials.push(Material::Black);
                    material_names.push("(light)".to_owned());
                    materials.len() as u32 - 1
                });
                shapes.push(Shape::Quad(quad));
                surfaces.push(Surface { material, emitter: Some(lights.len() as u32) });
            }
            lights.push(built);
        }

        let name =
            self.path.file_stem().map_or_else(|| "scene".to_owned(), |s| s.to_string_lossy().into_owned());
        Ok(Scene {
            name,
            camera,
            settings,
            geometry: Geometry::build(shapes, meshes),
            surfaces,
            materials,
            material_names,
            lights,
            background,
        })
    }

    fn camera(&self, camera: &Spanned<CameraDesc>) -> Result<Camera, SceneError> {
        let span = camera.span();
        let desc = camera.get_ref();
        let position = self.point(desc.position, span.clone(), "camera.position")?;
        let look_at = self.point(desc.look_at, span.clone(), "camera.look_at")?;
        let up = self.point(desc.up, span.clone(), "camera.up")?;
        self.resolution(desc.width, span.clone(), "camera.width")?;
        self.resolution(desc.height, span.clone(), "camera.height")?;
        Camera::look_at(position, look_at, up, desc.fov_y_deg, desc.width, desc.height)
            .map_err(|err| self.error(span, "camera", err.to_string()))
    }

    fn resolution(&self, pixels: u32, span: std::ops::Range<usize>, field: &str) -> Result<(), SceneError> {
        if pixels == 0 || pixels > MAX_RESOLUTION {
            return Err(self.error(
                span,
                field,
                format!("must be in 1..={MAX_RESOLUTION} pixels, got {pixels}"),
            ));
        }
        Ok(())
    }

    fn settings(&self, render: &Spanned<RenderDesc>) -> Result<RenderSettings, SceneError> {
        let span = render.span();
        let desc = render.get_ref();
        let defaults = RenderSettings::default();
        let in_range = |value: u32, low: u32, high: u32, field: &str| {
            if (low..=high).contains(&value) {
                Ok(value)
            } else {
                Err(self.error(span.clone(), field, format!("must be in {low}..={high}, got {value}")))
            }
        };
        let spp = in_range(desc.spp.unwrap_or(defaults.spp), 1, MAX_SPP, "render.spp")?;
        let max_depth =
            in_range(desc.max_depth.unwrap_or(defaults.max_depth), 1, MAX_DEPTH, "render.max_depth")?;
        let wavelengths = in_range(
            desc.wavelengths.unwrap_or(defaults.wavelengths as u32),
            1,
            N_LAMBDA as u32,
            "render.wavelengths",
        )?;
        let area_light_samples = in_range(
            desc.area_light_samples.unwrap_or(defaults.area_light_samples),
            1,
            65_536,
            "render.area_light_samples",
        )?;
        let prune_below = desc.prune_below.unwrap_or(defaults.prune_below);
        if !(0.0..1.0).contains(&prune_below) {
            return Err(self.error(
                span,
                "render.prune_below",
                format!("must be in [0, 1), got {prune_below}"),
            ));
        }
        let light_paths = match desc.light_paths {
            Some(paths) if !(1..=MAX_LIGHT_PATHS).contains(&paths) => {
                return Err(self.error(
                    span,
                    "render.light_paths",
                    format!("must be in 1..={MAX_LIGHT_PATHS} light paths per pass, got {paths}"),
                ))
            }
            paths => paths,
        };
        Ok(RenderSettings {
            spp,
            max_depth,
            wavelengths: wavelengths as usize,
            seed: desc.seed.unwrap_or(defaults.seed),
            area_light_samples,
            prune_below,
            polarized: desc.polarized.unwrap_or(defaults.polarized),
            caustics: desc.caustics.unwrap_or(defaults.caustics),
            light_paths,
        })
    }

    fn material(&self, name: &str, material: &Spanned<MaterialDesc>) -> Result<Material, SceneError> {
        let span = material.span();
        let field = |f: &str| format!("materials.{name}.{f}");
        Ok(match material.get_ref() {
            MaterialDesc::Diffuse { albedo, roughness_deg } => {
                let albedo = self.spectrum(albedo, Role::Reflectance, span.clone(), &field("albedo"))?;
                let sigma_deg = roughness_deg.unwrap_or(0.0);
                if !(0.0..=90.0).contains(&sigma_deg) {
                    return Err(self.error(
                        span,
                        field("roughness_deg"),
                        format!("must be in [0, 90] degrees, got {sigma_deg}"),
                    ));
                }
                Material::Diffuse(Diffuse::new(albedo, sigma_deg.to_radians()))
            }
            MaterialDesc::Mirror { reflectance, metal, complex_ior } => {
                let reflectance = match reflectance {
                    Some(r) => self.spectrum(r, Role::Reflectance, span.clone(), &field("reflectance"))?,
                    None => DenseSpectrum::constant(1.0),
                };
                let conductor = match (metal, complex_ior) {
                    (Some(_), Some(_)) => {
                        return Err(self.error(
                            span,
                            field("complex_ior"),
                            "give either metal or complex_ior, not both",
                        ))
                    }
                    (Some(name), None) => Conductor::Metal(metals::metal(name).ok_or_else(|| {
                        self.error(
                            span.clone(),
                            field("metal"),
                            format!(
                                "unknown metal \"{name}\"; known metals: {}",
                                metals::metal_names().join(", ")
                            ),
                        )
                    })?),
                    (None, Some([n, k])) => {
                        if !(n.is_finite()
                            && k.is_finite()
                            && *n > 0.0
                            && *k >= 0.0
                            && *n <= 1e3
                            && *k <= 1e3)
                        {
                            return Err(self.error(
                                span,
                                field("complex_ior"),
                                format!("[n, k] must have 0 < n ≤ 1000 and 0 ≤ k ≤ 1000, got [{n}, {k}]"),
                            ));
                        }
                        Conductor::Index(num_complex::Complex32::new(*n, *k))
                    }
                    (None, None) => Conductor::Perfect,
                };
                Material::Mirror(Mirror { reflectance, conductor })
            }
            MaterialDesc::Dielectric { ior, absorption } => {
                let ior = self.ior(ior, span.clone(), &field("ior"))?;
                let absorption = match absorption {
                    Some(a) => {
                        Some(self.spectrum(a, Role::Coefficient, span.clone(), &field("absorption"))?)
                    }
                    None => None,
                };
                Material::Dielectric(Dielectric { ior, absorption })
            }
            MaterialDesc::Polarizer { axis, transmittance } => {
                let axis = self.direction(*axis, span.clone(), &field("axis"))?.normalize();
                let transmittance = match transmittance {
                    Some(t) => self.spectrum(t, Role::Reflectance, span.clone(), &field("transmittance"))?,
                    None => DenseSpectrum::constant(1.0),
                };
                Material::Polarizer(Polarizer { axis, transmittance })
            }
            MaterialDesc::Retarder { fast_axis, retardance_deg } => {
                let fast_axis = self.direction(*fast_axis, span.clone(), &field("fast_axis"))?.normalize();
                if !(retardance_deg.is_finite() && (0.0..=360.0).contains(retardance_deg)) {
                    return Err(self.error(
                        span,
                        field("retardance_deg"),
                        format!("must be in [0, 360] degrees, got {retardance_deg}"),
                    ));
                }
                Material::Retarder(Retarder { fast_axis, retardance_rad: retardance_deg.to_radians() })
            }
        })
    }

    fn ior(&self, desc: &IorDesc, span: std::ops::Range<usize>, field: &str) -> Result<Ior, SceneError> {
        let fields = &desc.0;
        let given = [
            fields.value.is_some(),
            fields.cauchy.is_some(),
            fields.sellmeier.is_some(),
            fields.glass.is_some(),
            fields.table.is_some(),
        ];
        if given.iter().filter(|&&g| g).count() != 1 {
            return Err(self.error(
                span,
                field,
                "give exactly one of a number, `cauchy`, `sellmeier`, `glass` or `table`",
            ));
        }
        let ior = if let Some(n) = fields.value {
            Ior::Constant(n)
        } else if let Some([a, b_um2, c_um4]) = fields.cauchy {
            Ior::Cauchy { a, b_um2, c_um4 }
        } else if let Some(s) = &fields.sellmeier {
            Ior::Sellmeier { b: s.b, c_um2: s.c_um2 }
        } else if let Some(name) = &fields.glass {
            catalogue::glass_ior(name).ok_or_else(|| {
                self.error(
                    span.clone(),
                    field,
                    format!(
                        "unknown glass \"{name}\"; known glasses: {}",
                        catalogue::glass_names().join(", ")
                    ),
                )
            })?
        } else if let Some(table) = &fields.table {
            Ior::Tabulated(table.iter().map(|&[l, n]| (l, n)).collect::<Arc<[_]>>())
        } else {
            unreachable!("exactly one IOR form was checked above")
        };
        ior.validate().map_err(|err| self.error(span, field, err.to_string()))?;
        Ok(ior)
    }

    fn spectrum(
        &self,
        desc: &SpectrumDesc,
        role: Role,
        span: std::ops::Range<usize>,
        field: &str,
    ) -> Result<DenseSpectrum, SceneError> {
        let fields = &desc.0;
        let err = |message: String| self.error(span.clone(), field, message);
        let given = [
            fields.value.is_some(),
            fields.rgb.is_some(),
            fields.table.is_some(),
            fields.illuminant.is_some(),
            fields.blackbody_k.is_some(),
        ];
        if given.iter().filter(|&&g| g).count() != 1 {
            return Err(err(
                "give exactly one of a number, `value`, `rgb`, `table`, `illuminant` or `blackbody_k`".into(),
            ));
        }
        let scale = fields.scale.unwrap_or(1.0);
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(err(format!("scale must be finite and ≥ 0, got {scale}")));
        }
        let upper = if role == Role::Reflectance { 1.0 } else { f32::INFINITY };
        let check = |value: f32, what: &str| {
            if value.is_finite() && (0.0..=upper).contains(&value) {
                Ok(())
            } else if role == Role::Reflectance {
                Err(err(format!("{what} must be in [0, 1] for a reflectance, got {value}")))
            } else {
                Err(err(format!("{what} must be finite and ≥ 0, got {value}")))
            }
        };
        let spectrum = if let Some(value) = fields.value {
            check(value, "value")?;
            Spectrum::constant(value)
        } else if let Some(rgb) = fields.rgb {
            for c in rgb {
                check(c, "each rgb component")?;
            }
            match role {
                Role::Reflectance => Spectrum::rgb_reflectance(rgb),
                Role::Emission => Spectrum::rgb_illuminant(rgb),
                Role::Coefficient => {
                    let max = rgb.iter().copied().fold(0.0, f32::max);
                    if max == 0.0 {
                        Ok(Spectrum::constant(0.0))
                    } else {
                        Spectrum::rgb_reflectance(rgb.map(|c| c / max)).map(|s| s.scaled(max))
                    }
                }
            }
            .map_err(|e| err(e.to_string()))?
        } else if let Some(table) = &fields.table {
            for &[_, value] in table {
                check(value, "each table value")?;
            }
            Spectrum::table(&table.iter().map(|&[l, v]| (l, v)).collect::<Vec<_>>())
                .map_err(|e| err(e.to_string()))?
        } else if let Some(name) = &fields.illuminant {
            Spectrum::named_illuminant(name).map_err(|e| err(e.to_string()))?
        } else if let Some(kelvin) = fields.blackbody_k {
            Spectrum::blackbody(kelvin).map_err(|e| err(e.to_string()))?
        } else {
            unreachable!("exactly one spectrum form was checked above")
        };
        Ok(DenseSpectrum::new(&spectrum.scaled(scale)))
    }

    fn point(&self, p: [f32; 3], span: std::ops::Range<usize>, field: &str) -> Result<Vec3, SceneError> {
        let v = Vec3::from(p);
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.error(span, field, format!("must be finite, got {p:?}")))
        }
    }

    fn direction(&self, p: [f32; 3], span: std::ops::Range<usize>, field: &str) -> Result<Vec3, SceneError> {
        let v = self.point(p, span.clone(), field)?;
        if v.length_squared() > 0.0 && v.length_squared().is_finite() {
            Ok(v)
        } else {
            Err(self.error(span, field, format!("must have non-zero length, got {p:?}")))
        }
    }

    fn positive(&self, value: f32, span: std::ops::Range<usize>, field: &str) -> Result<f32, SceneError> {
        if value.is_finite() && value > 0.0 {
            Ok(value)
        } else {
            Err(self.error(span, field, format!("must be finite and > 0, got {value}")))
        }
    }

    fn quad(
        &self,
        corner: [f32; 3],
        e1: [f32; 3],
        e2: [f32; 3],
        span: std::ops::Range<usize>,
        at: &str,
    ) -> Result<Quad, SceneError> {
        let quad = Quad {
            corner: self.point(corner, span.clone(), &format!("{at}.corner"))?,
            edge1: self.direction(e1, span.clone(), &format!("{at}.edge1"))?,
            edge2: self.direction(e2, span.clone(), &format!("{at}.edge2"))?,
        };
        // A NaN area cannot happen: the edges were checked finite.
        if quad.area() <= 0.0 {
            return Err(self.error(
                span,
                format!("{at}.edge2"),
                "edge1 and edge2 are parallel: the quad has no area",
            ));
        }
        Ok(quad)
    }

    fn shape(
        &self,
        index: usize,
        shape: &Spanned<ShapeDesc>,
        materials: &Materials,
        shapes: &mut Vec<Shape>,
        surfaces: &mut Vec<Surface>,
        meshes: &mut Vec<Mesh>,
    ) -> Result<(), SceneError> {
        let span = shape.span();
        let at = format!("shapes[{index}]");
        let material_of = |name: &str| {
            materials.ids.get(name).copied().ok_or_else(|| {
                let known: Vec<_> = materials.ids.keys().copied().collect();
                self.error(
                    span.clone(),
                    format!("{at}.material"),
                    format!(
                        "undefined material \"{name}\" (defined: {})",
                        if known.is_empty() { "none".into() } else { known.join(", ") }
                    ),
                )
            })
        };
        // Polarisers and retarders are sheets: a flat shape (normal given), with an axis that
        // has a component in its plane.
        let sheet = |material: u32, normal: Option<Vec3>| {
            let axis = match &materials.built[material as usize] {
                Material::Polarizer(p) => p.axis,
                Material::Retarder(r) => r.fast_axis,
                _ => return Ok(()),
            };
            let Some(normal) = normal else {
                return Err(self.error(
                    span.clone(),
                    format!("{at}.material"),
                    "polarizer and retarder materials need a flat shape (a quad or a plane)",
                ));
            };
            if axis.cross(normal.normalize()).length() < 1e-3 {
                return Err(self.error(
                    span.clone(),
                    format!("{at}.material"),
                    format!("the material's axis {axis} is along this shape's normal: it has no direction in the sheet"),
                ));
            }
            Ok(())
        };
        match shape.get_ref() {
            ShapeDesc::Sphere { center, radius, material } => {
                let material = material_of(material)?;
                sheet(material, None)?;
                let sphere = Sphere {
                    center: self.point(*center, span.clone(), &format!("{at}.center"))?,
                    radius: self.positive(*radius, span.clone(), &format!("{at}.radius"))?,
                };
                shapes.push(Shape::Sphere(sphere));
                surfaces.push(Surface { material, emitter: None });
            }
            ShapeDesc::Plane { point, normal, material } => {
                let material = material_of(material)?;
                let plane = Plane {
                    point: self.point(*point, span.clone(), &format!("{at}.point"))?,
                    normal: self.direction(*normal, span.clone(), &format!("{at}.normal"))?.normalize(),
                };
                sheet(material, Some(plane.normal))?;
                shapes.push(Shape::Plane(plane));
                surfaces.push(Surface { material, emitter: None });
            }
            ShapeDesc::Quad { corner, edge1, edge2, material } => {
                let material = material_of(material)?;
                let quad = self.quad(*corner, *edge1, *edge2, span.clone(), &at)?;
                sheet(material, Some(quad.normal()))?;
                shapes.push(Shape::Quad(quad));
                surfaces.push(Surface { material, emitter: None });
            }
            ShapeDesc::Mesh { file, material, scale, rotate_deg, position } => {
                let material = material_of(material)?;
                sheet(material, None)?;
                let transform = self.transform(*scale, *rotate_deg, *position, span.clone(), &at)?;
                let obj = self.path.parent().unwrap_or(Path::new(".")).join(file);
                let mesh = Mesh::load_obj(&obj)
                    .map_err(|e| self.error(span.clone(), format!("{at}.file"), e.to_string()))?;
                push_mesh(mesh.transformed(&transform), material, shapes, surfaces, meshes);
            }
            ShapeDesc::Prism { apex_angle_deg, side_length, length, material, rotate_deg, position } => {
                let material = material_of(material)?;
                sheet(material, None)?;
                if !(apex_angle_deg.is_finite() && *apex_angle_deg > 0.0 && *apex_angle_deg < 180.0) {
                    return Err(self.error(
                        span,
                        format!("{at}.apex_angle_deg"),
                        format!("must be in (0, 180) degrees, got {apex_angle_deg}"),
                    ));
                }
                let side = self.positive(*side_length, span.clone(), &format!("{at}.side_length"))?;
                let length = self.positive(*length, span.clone(), &format!("{at}.length"))?;
                let transform = self.transform(None, *rotate_deg, *position, span.clone(), &at)?;
                let prism = Mesh::triangular_prism(apex_angle_deg.to_radians(), side, length);
                push_mesh(prism.transformed(&transform), material, shapes, surfaces, meshes);
            }
        }
        Ok(())
    }

    fn transform(
        &self,
        scale: Option<f32>,
        rotate_deg: Option<[f32; 3]>,
        position: Option<[f32; 3]>,
        span: std::ops::Range<usize>,
        at: &str,
    ) -> Result<Affine3A, SceneError> {
        let scale = self.positive(scale.unwrap_or(1.0), span.clone(), &format!("{at}.scale"))?;
        let [rx, ry, rz] =
            self.point(rotate_deg.unwrap_or([0.0; 3]), span.clone(), &format!("{at}.rotate_deg"))?.to_array();
        let position = self.point(position.unwrap_or([0.0; 3]), span, &format!("{at}.position"))?;
        // Rotate about x first, then y, then z (extrinsic), i.e. R = Rz·Ry·Rx.
        let rotation = Quat::from_euler(EulerRot::ZYX, rz.to_radians(), ry.to_radians(), rx.to_radians());
        Ok(Affine3A::from_scale_rotation_translation(Vec3::splat(scale), rotation, position))
    }

    fn light(&self, index: usize, light: &Spanned<LightDesc>) -> Result<Light, SceneError> {
        let span = light.span();
        let at = format!("lights[{index}]");
        Ok(match light.get_ref() {
            LightDesc::Point { position, intensity } => Light::Point(PointLight {
                position: self.point(*position, span.clone(), &format!("{at}.position"))?,
                intensity: self.spectrum(intensity, Role::Emission, span, &format!("{at}.intensity"))?,
            }),
            LightDesc::Quad { corner, edge1, edge2, radiance, emit } => {
                let quad = self.quad(*corner, *edge1, *edge2, span.clone(), &at)?;
                let emit_normal = match emit {
                    EmitSide::Edge1CrossEdge2 => quad.normal(),
                    EmitSide::Edge2CrossEdge1 => -quad.normal(),
                };
                let radiance = self.spectrum(radiance, Role::Emission, span, &format!("{at}.radiance"))?;
                Light::Quad(QuadLight { quad, emit_normal, radiance })
            }
            LightDesc::Spot { position, look_at, intensity, cutoff_deg, beam_width_deg } => {
                let position = self.point(*position, span.clone(), &format!("{at}.position"))?;
                let target = self.point(*look_at, span.clone(), &format!("{at}.look_at"))?;
                let axis = target - position;
                if !(axis.length_squared() > 0.0 && axis.length_squared().is_finite()) {
                    return Err(self.error(
                        span,
                        format!("{at}.look_at"),
                        "equals position: the spot has no axis",
                    ));
                }
                if !(cutoff_deg.is_finite() && *cutoff_deg > 0.0 && *cutoff_deg < 180.0) {
                    return Err(self.error(
                        span,
                        format!("{at}.cutoff_deg"),
                        format!("must be in (0, 180) degrees, got {cutoff_deg}"),
                    ));
                }
                let beam_width_deg = beam_width_deg.unwrap_or(cutoff_deg * 0.75);
                if !(beam_width_deg.is_finite() && beam_width_deg > 0.0 && beam_width_deg <= *cutoff_deg) {
                    return Err(self.error(
                        span,
                        format!("{at}.beam_width_deg"),
                        format!("must be in (0, cutoff_deg = {cutoff_deg}] degrees, got {beam_width_deg}"),
                    ));
                }
                let intensity =
                    self.spectrum(intensity, Role::Emission, span.clone(), &format!("{at}.intensity"))?;
                self.emits(&intensity, span, &format!("{at}.intensity"))?;
                Light::Spot(SpotLight {
                    position,
                    axis: axis.normalize(),
                    intensity,
                    cutoff_rad: cutoff_deg.to_radians(),
                    beam_width_rad: beam_width_deg.to_radians(),
                })
            }
            LightDesc::Beam { corner, edge1, edge2, irradiance, emit } => {
                let quad = self.quad(*corner, *edge1, *edge2, span.clone(), &at)?;
                let emit_normal = match emit {
                    EmitSide::Edge1CrossEdge2 => quad.normal(),
                    EmitSide::Edge2CrossEdge1 => -quad.normal(),
                };
                let irradiance =
                    self.spectrum(irradiance, Role::Emission, span.clone(), &format!("{at}.irradiance"))?;
                self.emits(&irradiance, span, &format!("{at}.irradiance"))?;
                Light::Beam(BeamLight { quad, emit_normal, irradiance })
            }
        })
    }

    /// Rejects a spot or beam whose spectrum is zero everywhere: it has no power.
    fn emits(
        &self,
        spectrum: &DenseSpectrum,
        span: std::ops::Range<usize>,
        field: &str,
    ) -> Result<(), SceneError> {
        if spectrum.integral_nm() > 0.0 {
            Ok(())
        } else {
            Err(self.error(span, field, "must be > 0 somewhere in 360–830 nm: this light has no power"))
        }
    }
}

fn push_mesh(
    mesh: Mesh,
    material: u32,
    shapes: &mut Vec<Shape>,
    surfaces: &mut Vec<Surface>,
    meshes: &mut Vec<Mesh>,
) {
    let mesh_index = meshes.len() as u32;
    for tri in 0..mesh.triangles.len() as u32 {
        shapes.push(Shape::Triangle { mesh: mesh_index, tri });
        surfaces.push(Surface { material, emitter: None });
    }
    meshes.push(mesh);
}

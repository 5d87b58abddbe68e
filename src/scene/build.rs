//! Validation of a parsed [`SceneDesc`] into a runtime [`Scene`]: ranges checked, names resolved,
//! spectra and IOR models built, meshes loaded. Every error names the file, the line of the table
//! that holds the bad value and the field.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

use glam::{Affine3A, EulerRot, Quat, Vec3};
use toml::Spanned;

use super::desc::{
    CameraDesc, CoatingLayerDesc, EmitSide, IorDesc, LightDesc, MaterialDesc, RenderDesc, SceneDesc,
    ShapeDesc, SpectrumDesc, ThicknessDesc,
};
use super::error::{line_column, one_line, shorten};
use super::typed::Typed;
use super::{IntegratorKind, RenderSettings, Scene, SceneError, Surface};
use crate::camera::{Camera, LanePaths, LensCamera, LensSettings, Pinhole, ThinLens};
use crate::geometry::{Geometry, Mesh, Plane, Quad, Shape, Sphere};
use crate::light::{BeamLight, Light, PointLight, QuadLight, SpotLight};
use crate::material::film::ThicknessTexture;
use crate::material::{
    CoatingLayer, Conductor, Dielectric, Diffuse, Film, LayerIndex, Material, Mirror, Polarizer, Retarder,
    Thickness, MAX_COATING_LAYERS,
};
use crate::optics::{catalogue, metals, Ior};
use crate::spectrum::{DenseSpectrum, Spectrum, LAMBDA_MAX_NM, LAMBDA_MIN_NM, N_LAMBDA};

use super::limits::{MAX_COATING_THICKNESS_NM, MAX_COORDINATE, MAX_EMISSION, MAX_IOR, MIN_IOR, MIN_LENGTH};
pub use super::limits::{MAX_DEPTH, MAX_RESOLUTION, MAX_SPP};
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
        let offset = err.span().map_or(0, |span| span.start);
        let (line, column) = line_column(text, offset);
        let message = one_line(err.message());
        match super::locate::field_at(text, offset, err.message()) {
            Some(field) => {
                SceneError::Invalid { file: path.to_owned(), line, field: shorten(&field), message }
            }
            None => SceneError::Syntax { file: path.to_owned(), line, column, message },
        }
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
            field: shorten(&field.into()),
            message: one_line(&message.into()),
        }
    }

    fn build(&self, desc: SceneDesc) -> Result<Scene, SceneError> {
        let camera = self.camera(&desc.camera)?;
        let settings = match &desc.render {
            Some(render) => self.settings(render)?,
            None => RenderSettings::default(),
        };
        if let Some((setting, message)) = crate::render::lens_camera_refusal(&camera, &settings) {
            let at = desc.render.as_ref().map_or(desc.camera.span(), Spanned::span);
            return Err(self.error(at, format!("render.{setting}"), message));
        }
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
        self.film_heights(&desc, &material_ids, &mut materials, &shapes, &surfaces, &meshes)?;

        let mut lights = Vec::with_capacity(desc.lights.len());
        let mut black = None;
        for (index, light) in desc.lights.iter().enumerate() {
            let built = self.light(index, light)?;
            // Quad lights and beams are black parallelograms in the scene, but for a quad light
            // given an `albedo`: a diffuse one.
            let surface = match &built {
                Light::Quad(quad) => Some(quad.quad),
                Light::Beam(beam) => Some(beam.quad),
                Light::Point(_) | Light::Spot(_) => None,
            };
            let albedo = match &light.get_ref().0 {
                LightDesc::Quad { albedo: Some(albedo), .. } => Some(self.spectrum(
                    albedo,
                    Role::Reflectance,
                    light.span(),
                    &format!("lights[{index}].albedo"),
                )?),
                _ => None,
            };
            if let Some(quad) = surface {
                let material = match albedo {
                    Some(albedo) => {
                        materials.push(Material::Diffuse(Diffuse::new(albedo, 0.0)));
                        material_names.push(format!("(light {index})"));
                        materials.len() as u32 - 1
                    }
                    None => *black.get_or_insert_with(|| {
                        materials.push(Material::Black);
                        material_names.push("(light)".to_owned());
                        materials.len() as u32 - 1
                    }),
                };
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
            digest: super::digest::scene_digest(self.text, self.path, &desc),
            input_files: super::digest::input_files(self.path, &desc),
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
        if let Some(lens) = &desc.lens {
            return self.lens_camera(desc, lens, span, (position, look_at, up));
        }
        for (field, given) in [
            ("camera.sensor_height_mm", desc.sensor_height_mm.as_ref().map(Spanned::span)),
            ("camera.f_number", desc.f_number.as_ref().map(Spanned::span)),
            ("camera.lens_ghosts", desc.lens_ghosts.as_ref().map(Spanned::span)),
            ("camera.lens_lanes", desc.lens_lanes.as_ref().map(Spanned::span)),
        ] {
            if let Some(at) = given {
                return Err(self.error(at, field, "needs a lens system (camera.lens)"));
            }
        }
        let Some(fov_y_deg) = desc.fov_y_deg.as_ref().map(|v| *v.get_ref()) else {
            return Err(self.error(span, "camera.fov_y_deg", "is required (or a lens system: camera.lens)"));
        };
        let pinhole = Pinhole::look_at(position, look_at, up, fov_y_deg, desc.width, desc.height)
            .map_err(|err| self.error(span.clone(), "camera", err.to_string()))?;
        // Each value's own line in errors.
        let value = |field: &Option<Spanned<f32>>| field.as_ref().map(|v| (*v.get_ref(), v.span()));
        let (radius, focus) = (value(&desc.aperture_radius), value(&desc.focus_distance));
        if let Some((radius, at)) = &radius {
            if !(*radius >= 0.0 && *radius <= MAX_COORDINATE) {
                let message = format!("must lie in [0, {MAX_COORDINATE:e}], got {}", number(*radius));
                return Err(self.error(at.clone(), "camera.aperture_radius", message));
            }
        }
        if let Some((focus, at)) = &focus {
            if !(*focus > 0.0 && *focus <= MAX_COORDINATE) {
                let message = format!("must lie in (0, {MAX_COORDINATE:e}], got {}", number(*focus));
                return Err(self.error(at.clone(), "camera.focus_distance", message));
            }
        }
        match (radius, focus) {
            (None, None) => Ok(Camera::Pinhole(pinhole)),
            (None, Some((_, at))) => Err(self.error(
                at,
                "camera.focus_distance",
                "needs aperture_radius (a pinhole is in focus everywhere)",
            )),
            // A radius of 0 is the pinhole exactly (every lens point is the pinhole).
            (Some((0.0, _)), _) => Ok(Camera::Pinhole(pinhole)),
            (Some((_, at)), None) => {
                Err(self.error(at, "camera.focus_distance", "is required with a positive aperture_radius"))
            }
            (Some((radius, _)), Some((focus, _))) => ThinLens::new(pinhole, radius, focus)
                .map(Camera::ThinLens)
                .map_err(|err| self.error(span, "camera", err.to_string())),
        }
    }

    /// A lens-system camera ([`LensCamera`]): `lens` relative to the scene file's folder,
    /// `sensor_height_mm` required, `focus_distance` in scene units (metres) or infinity,
    /// `fov_y_deg` and `aperture_radius` refused.
    fn lens_camera(
        &self,
        desc: &CameraDesc,
        lens: &Spanned<String>,
        span: std::ops::Range<usize>,
        (position, look_at, up): (glam::Vec3, glam::Vec3, glam::Vec3),
    ) -> Result<Camera, SceneError> {
        if let Some(fov) = &desc.fov_y_deg {
            let message = "is not allowed with a lens system: the lens and sensor_height_mm set the field";
            return Err(self.error(fov.span(), "camera.fov_y_deg", message));
        }
        if let Some(radius) = &desc.aperture_radius {
            let message = "is not allowed with a lens system (a thin lens); stop down with f_number";
            return Err(self.error(radius.span(), "camera.aperture_radius", message));
        }
        let Some(sensor) = &desc.sensor_height_mm else {
            return Err(self.error(span, "camera.sensor_height_mm", "is required with a lens system (mm)"));
        };
        let sensor_height_mm = *sensor.get_ref();
        if !(sensor_height_mm > 0.0 && sensor_height_mm <= 1e4) {
            let message = format!("must lie in (0, 1e4] mm, got {sensor_height_mm}");
            return Err(self.error(sensor.span(), "camera.sensor_height_mm", message));
        }
        let focus_distance_m = match &desc.focus_distance {
            Some(focus) if !(*focus.get_ref() > 0.0 && *focus.get_ref() <= MAX_COORDINATE) => {
                let message =
                    format!("must lie in (0, {MAX_COORDINATE:e}], got {}", number(*focus.get_ref()));
                return Err(self.error(focus.span(), "camera.focus_distance", message));
            }
            Some(focus) => f64::from(*focus.get_ref()),
            None => f64::INFINITY,
        };
        let f_number = match &desc.f_number {
            Some(n) if !(*n.get_ref() > 0.0 && n.get_ref().is_finite()) => {
                let message = format!("must be positive and finite, got {}", n.get_ref());
                return Err(self.error(n.span(), "camera.f_number", message));
            }
            Some(n) => Some(*n.get_ref()),
            None => None,
        };
        let folder = self.path.parent().unwrap_or(Path::new(""));
        let settings = LensSettings {
            lens: folder.join(lens.get_ref()),
            sensor_height_mm,
            focus_distance_m,
            f_number,
            max_ghost_reflections: desc.lens_ghosts.as_ref().map_or(0, |g| *g.get_ref()),
        };
        let lane_paths = match desc.lens_lanes.as_ref().map(|v| (v.get_ref().as_str(), v.span())) {
            None | Some(("per_lane", _)) => LanePaths::PerLane,
            Some(("shared", at)) if settings.max_ghost_reflections > 0 => {
                return Err(self.error(at, "camera.lens_lanes", "\"shared\" needs lens_ghosts = 0"));
            }
            Some(("shared", _)) => LanePaths::Shared,
            Some((other, at)) => {
                let message = format!("must be \"per_lane\" or \"shared\", got \"{other}\"");
                return Err(self.error(at, "camera.lens_lanes", message));
            }
        };
        LensCamera::new(position, look_at, up, desc.width, desc.height, settings)
            .map(|camera| Camera::Lens(camera.with_lane_paths(lane_paths)))
            .map_err(|err| self.error(lens.span(), "camera.lens", err.to_string()))
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
        let integrator = match &desc.integrator {
            Some(name) => IntegratorKind::from_name(name)
                .map_err(|message| self.error(span.clone(), "render.integrator", message))?,
            None => defaults.integrator,
        };
        if integrator == IntegratorKind::Path {
            let whitted_only = [
                ("prune_below", desc.prune_below.is_some(), "its Russian roulette has no setting"),
                (
                    "area_light_samples",
                    desc.area_light_samples.is_some(),
                    "it samples each quad light once per diffuse vertex, against its BSDF sample",
                ),
            ];
            if let Some((field, _, why)) = whitted_only.into_iter().find(|(_, set, _)| *set) {
                return Err(self.error(
                    span.clone(),
                    format!("render.{field}"),
                    format!(
                        "belongs to the \"whitted\" integrator; the \"path\" integrator has no use for it \
                         ({why}): remove {field}"
                    ),
                ));
            }
        }
        let spp = in_range(desc.spp.unwrap_or(defaults.spp), 1, MAX_SPP, "render.spp")?;
        let max_depth = in_range(
            desc.max_depth.unwrap_or(integrator.default_max_depth()),
            1,
            MAX_DEPTH,
            "render.max_depth",
        )?;
        let wavelengths = in_range(
            desc.wavelengths.unwrap_or(defaults.wavelengths as u32),
            1,
            N_LAMBDA as u32,
            "render.wavelengths",
        )?;
        let area_light_samples = in_range(
            desc.area_light_samples.unwrap_or(integrator.default_area_light_samples()),
            1,
            65_536,
            "render.area_light_samples",
        )?;
        let edge_samples = in_range(
            desc.edge_samples.unwrap_or(defaults.edge_samples),
            1,
            crate::edges::MAX_EDGE_SAMPLES,
            "render.edge_samples",
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
        let settings = RenderSettings {
            integrator,
            spp,
            max_depth,
            wavelengths: wavelengths as usize,
            seed: desc.seed.unwrap_or(defaults.seed),
            area_light_samples,
            prune_below,
            polarized: desc.polarized.unwrap_or(defaults.polarized),
            caustics: desc.caustics.unwrap_or(defaults.caustics),
            light_paths,
            light_guide: desc.light_guide.unwrap_or(defaults.light_guide),
            edge_samples,
        };
        settings.check_ray_tree_bound().map_err(|message| self.error(span, "render.max_depth", message))?;
        Ok(settings)
    }

    fn material(&self, name: &str, material: &Spanned<Typed<MaterialDesc>>) -> Result<Material, SceneError> {
        let span = material.span();
        let field = |f: &str| format!("materials.{name}.{f}");
        Ok(match &material.get_ref().0 {
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
            MaterialDesc::Mirror { reflectance, metal, complex_ior, coating } => {
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
                    (None, Some(n_k)) => {
                        Conductor::Index(self.complex_ior(*n_k, span.clone(), &field("complex_ior"))?)
                    }
                    (None, None) => Conductor::Perfect,
                };
                let coating =
                    self.coating(coating.as_deref().unwrap_or(&[]), span.clone(), &field("coating"))?;
                if !coating.is_empty() && conductor == Conductor::Perfect {
                    return Err(self.error(
                        span,
                        field("coating"),
                        "a coating needs the metal under it: give `metal` or `complex_ior`",
                    ));
                }
                Material::Mirror(Mirror { reflectance, conductor, coating })
            }
            MaterialDesc::Dielectric { ior, absorption, coating } => {
                let ior = self.ior(ior, span.clone(), &field("ior"))?;
                let absorption = match absorption {
                    Some(a) => {
                        Some(self.spectrum(a, Role::Coefficient, span.clone(), &field("absorption"))?)
                    }
                    None => None,
                };
                let coating = self.coating(coating.as_deref().unwrap_or(&[]), span, &field("coating"))?;
                Material::Dielectric(Dielectric { ior, absorption, coating })
            }
            MaterialDesc::Film { ior, thickness_nm } => {
                let ior = match ior {
                    Some(ior) => self.ior(ior, span.clone(), &field("ior"))?,
                    None => catalogue::glass_ior("water").ok_or_else(|| {
                        self.error(span.clone(), field("ior"), "water is missing from the glass catalogue")
                    })?,
                };
                // A film denser than the air around it: no wave in it is evanescent, so its
                // transfer matrix stays bounded at every angle.
                let whole_nm = (LAMBDA_MIN_NM as u32..=LAMBDA_MAX_NM as u32).map(|nm| nm as f32);
                if let Some(lambda_nm) = whole_nm.into_iter().find(|&nm| ior.eval(nm) < 1.0) {
                    return Err(self.error(
                        span,
                        field("ior"),
                        format!(
                            "n = {} at {lambda_nm} nm; a film in air must have n ≥ 1",
                            number(ior.eval(lambda_nm))
                        ),
                    ));
                }
                let thickness = self.film_thickness(thickness_nm, span, &field("thickness_nm"))?;
                Material::Film(Film { ior, thickness })
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

    /// A coating's layers (outside first): at most [`MAX_COATING_LAYERS`], each with an index
    /// like a material's `ior`, a metal's name or a `complex_ior`, and a thickness in
    /// (0, [`MAX_COATING_THICKNESS_NM`]] nm.
    fn coating(
        &self,
        layers: &[CoatingLayerDesc],
        span: std::ops::Range<usize>,
        field: &str,
    ) -> Result<Vec<CoatingLayer>, SceneError> {
        if layers.len() > MAX_COATING_LAYERS {
            return Err(self.error(
                span,
                field,
                format!("{} layers; a coating has at most {MAX_COATING_LAYERS}", layers.len()),
            ));
        }
        layers
            .iter()
            .enumerate()
            .map(|(i, layer)| {
                let index = match (&layer.ior, &layer.metal, layer.complex_ior) {
                    (Some(ior), None, None) => {
                        LayerIndex::Real(self.ior(ior, span.clone(), &format!("{field}[{i}].ior"))?)
                    }
                    (None, Some(name), None) => LayerIndex::Metal(metals::metal(name).ok_or_else(|| {
                        self.error(
                            span.clone(),
                            format!("{field}[{i}].metal"),
                            format!(
                                "unknown metal \"{name}\"; known metals: {}",
                                metals::metal_names().join(", ")
                            ),
                        )
                    })?),
                    (None, None, Some(n_k)) => LayerIndex::Complex(self.complex_ior(
                        n_k,
                        span.clone(),
                        &format!("{field}[{i}].complex_ior"),
                    )?),
                    _ => {
                        return Err(self.error(
                            span.clone(),
                            format!("{field}[{i}]"),
                            "give exactly one of `ior`, `metal` or `complex_ior` for the layer's index",
                        ))
                    }
                };
                let thickness_nm = layer.thickness_nm;
                if !(thickness_nm.is_finite()
                    && thickness_nm > 0.0
                    && thickness_nm <= MAX_COATING_THICKNESS_NM)
                {
                    return Err(self.error(
                        span.clone(),
                        format!("{field}[{i}].thickness_nm"),
                        format!(
                            "must be > 0 and at most {MAX_COATING_THICKNESS_NM} nm (100 µm), got {}",
                            number(thickness_nm)
                        ),
                    ));
                }
                Ok(CoatingLayer { index, thickness_nm })
            })
            .collect()
    }

    /// A complex index [n, k] (n + ik) of a mirror or a coating layer: 0 < n ≤ 1000, 0 ≤ k ≤ 1000.
    fn complex_ior(
        &self,
        [n, k]: [f32; 2],
        span: std::ops::Range<usize>,
        field: &str,
    ) -> Result<num_complex::Complex32, SceneError> {
        if !(n.is_finite() && k.is_finite() && n > 0.0 && k >= 0.0 && n <= 1e3 && k <= 1e3) {
            return Err(self.error(
                span,
                field,
                format!("[n, k] must have 0 < n ≤ 1000 and 0 ≤ k ≤ 1000, got [{n}, {k}]"),
            ));
        }
        Ok(num_complex::Complex32::new(n, k))
    }

    /// A film's thickness: a constant, or a drained profile (`material::film`), each thickness
    /// in [0, [`MAX_COATING_THICKNESS_NM`]] nm. A drained film without `heights` gets
    /// the empty interval here, and the extent of its shapes in [`Self::film_heights`].
    fn film_thickness(
        &self,
        desc: &ThicknessDesc,
        span: std::ops::Range<usize>,
        field: &str,
    ) -> Result<Thickness, SceneError> {
        let fields = &desc.0;
        let err = |at: &str, message: String| self.error(span.clone(), format!("{field}{at}"), message);
        let check = |value: f32, at: &str| {
            if value.is_finite() && (0.0..=MAX_COATING_THICKNESS_NM).contains(&value) {
                Ok(value)
            } else {
                Err(err(
                    at,
                    format!(
                        "must be ≥ 0 and at most {MAX_COATING_THICKNESS_NM} nm (100 µm), got {}",
                        number(value)
                    ),
                ))
            }
        };
        let drained = [fields.top.is_some(), fields.bottom.is_some(), fields.axis.is_some()];
        let textured = [
            fields.texture.is_some(),
            fields.min.is_some(),
            fields.max.is_some(),
            fields.corner.is_some(),
            fields.edge1.is_some(),
            fields.edge2.is_some(),
        ];
        if textured.iter().any(|&given| given) {
            if fields.value.is_some() || drained.iter().any(|&given| given) || fields.heights.is_some() {
                return Err(err(
                    "",
                    "a texture takes no `value`, `top`, `bottom`, `axis` or `heights`".into(),
                ));
            }
            return self.film_texture(fields, span, field).map(Thickness::Textured);
        }
        match (fields.value, drained) {
            (Some(value), [false, false, false]) if fields.heights.is_none() => {
                Ok(Thickness::Constant(check(value, "")?))
            }
            (None, [true, true, true]) => {
                let (Some(top), Some(bottom), Some(axis)) = (fields.top, fields.bottom, fields.axis) else {
                    unreachable!("all three were checked present")
                };
                let top_nm = check(top, ".top")?;
                let bottom_nm = check(bottom, ".bottom")?;
                let axis = self.direction(axis, span.clone(), &format!("{field}.axis"))?.normalize();
                let (low, high) = match fields.heights {
                    Some([low, high]) => {
                        if !(low.is_finite()
                            && high.is_finite()
                            && low < high
                            && low.abs() <= MAX_COORDINATE
                            && high.abs() <= MAX_COORDINATE)
                        {
                            return Err(err(
                                ".heights",
                                format!(
                                    "must be [bottom, top] with bottom < top, within ±{MAX_COORDINATE}, got [{}, {}]",
                                    number(low),
                                    number(high)
                                ),
                            ));
                        }
                        (low, high)
                    }
                    None => (f32::INFINITY, f32::NEG_INFINITY),
                };
                Ok(Thickness::Drained { top_nm, bottom_nm, axis, low, high })
            }
            _ => Err(err(
                "",
                "give a number, all of `top`, `bottom` and `axis` (and optionally `heights`), or a `texture`"
                    .into(),
            )),
        }
    }

    /// A film's thickness from a greyscale image ([`ThicknessTexture`]): all of `texture`,
    /// `min`, `max`, `corner`, `edge1` and `edge2`; 0 ≤ min ≤ max ≤ [`MAX_COATING_THICKNESS_NM`];
    /// the edges not parallel; the file (relative to the scene file's folder) a greyscale PNG.
    fn film_texture(
        &self,
        fields: &crate::scene::desc::ThicknessFields,
        span: std::ops::Range<usize>,
        field: &str,
    ) -> Result<ThicknessTexture, SceneError> {
        let err = |at: &str, message: String| self.error(span.clone(), format!("{field}{at}"), message);
        let (Some(file), Some(min), Some(max), Some(corner), Some(edge1), Some(edge2)) =
            (&fields.texture, fields.min, fields.max, fields.corner, fields.edge1, fields.edge2)
        else {
            return Err(err(
                "",
                "a texture needs all of `texture`, `min`, `max`, `corner`, `edge1` and `edge2`".into(),
            ));
        };
        for (value, at) in [(min, ".min"), (max, ".max")] {
            if !(value.is_finite() && (0.0..=MAX_COATING_THICKNESS_NM).contains(&value)) {
                return Err(err(
                    at,
                    format!(
                        "must be ≥ 0 and at most {MAX_COATING_THICKNESS_NM} nm (100 µm), got {}",
                        number(value)
                    ),
                ));
            }
        }
        if min > max {
            return Err(err(
                ".min",
                format!("must be at most `max` ({} nm), got {} nm", number(max), number(min)),
            ));
        }
        let corner = self.point(corner, span.clone(), &format!("{field}.corner"))?;
        let edge1 = self.direction(edge1, span.clone(), &format!("{field}.edge1"))?;
        let edge2 = self.direction(edge2, span.clone(), &format!("{field}.edge2"))?;
        let normal = edge1.cross(edge2);
        // sin² of the edges' angle: below 1e-12 (1e-6 rad) the projection's dual basis would be
        // as large as f32's rounding of the edges allows, and meaningless.
        let sin_sqr = normal.length_squared() / (edge1.length_squared() * edge2.length_squared());
        if sin_sqr.is_nan() || sin_sqr <= 1e-12 {
            return Err(err(".edge2", "must not be parallel to `edge1`".into()));
        }
        let path = self.path.parent().unwrap_or(Path::new("")).join(file);
        ThicknessTexture::load(&path, min, max, corner, edge1, edge2)
            .map_err(|message| err(".texture", message))
    }

    /// The heights of drained films given without `heights`: the extent along the film's axis
    /// of the shapes that use it (spheres exactly, other shapes by their bounding boxes).
    fn film_heights(
        &self,
        desc: &SceneDesc,
        ids: &BTreeMap<&str, u32>,
        materials: &mut [Material],
        shapes: &[Shape],
        surfaces: &[Surface],
        meshes: &[Mesh],
    ) -> Result<(), SceneError> {
        for (name, material) in &desc.materials {
            let Some(&id) = ids.get(name.as_str()) else { continue };
            let Material::Film(Film { thickness: Thickness::Drained { axis, low, high, .. }, .. }) =
                &mut materials[id as usize]
            else {
                continue;
            };
            if *low <= *high {
                continue; // `heights` given
            }
            let field = format!("materials.{name}.thickness_nm.heights");
            for (shape, surface) in shapes.iter().zip(surfaces) {
                if surface.material != id {
                    continue;
                }
                let (from, to) = match shape {
                    Shape::Sphere(sphere) => {
                        let centre = sphere.center.dot(*axis);
                        (centre - sphere.radius, centre + sphere.radius)
                    }
                    _ => {
                        let Some(bounds) = shape.bounds(meshes) else {
                            return Err(self.error(
                                material.span(),
                                field,
                                "a plane has no top or bottom: give `heights = [bottom, top]`",
                            ));
                        };
                        (0..8).fold((f32::INFINITY, f32::NEG_INFINITY), |(from, to), corner| {
                            let pick =
                                |bit: u32, min: f32, max: f32| if corner & bit == 0 { min } else { max };
                            let point = Vec3::new(
                                pick(1, bounds.min.x, bounds.max.x),
                                pick(2, bounds.min.y, bounds.max.y),
                                pick(4, bounds.min.z, bounds.max.z),
                            );
                            (from.min(point.dot(*axis)), to.max(point.dot(*axis)))
                        })
                    }
                };
                *low = low.min(from);
                *high = high.max(to);
            }
            if *low >= *high {
                return Err(self.error(
                    material.span(),
                    field,
                    "no shape with this film has any height along its axis: give `heights = [bottom, top]`",
                ));
            }
        }
        Ok(())
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
        ior.validate().map_err(|err| self.error(span.clone(), field, err.to_string()))?;
        // Whole nanometres of the rendered range: the models are smooth between them, and a
        // table's knots are checked by `validate`.
        let whole_nm = (LAMBDA_MIN_NM as u32..=LAMBDA_MAX_NM as u32).map(|nm| nm as f32);
        for lambda_nm in whole_nm {
            let n = ior.eval(lambda_nm);
            if !(MIN_IOR..=MAX_IOR).contains(&n) {
                return Err(self.error(
                    span,
                    field,
                    format!(
                        "n = {} at {lambda_nm} nm; an index of refraction must lie in [{MIN_IOR}, {MAX_IOR}]",
                        number(n)
                    ),
                ));
            }
        }
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
        let resolved = DenseSpectrum::new(&spectrum.scaled(scale));
        self.check_resolved(&resolved, role, span, field)?;
        Ok(resolved)
    }

    /// Checks a spectrum as the renderer will evaluate it (after `scale` and tabulation, whatever
    /// form it was written in): finite, ≥ 0, ≤ 1 for a reflectance, ≤ [`MAX_EMISSION`] for an
    /// emitter.
    fn check_resolved(
        &self,
        resolved: &DenseSpectrum,
        role: Role,
        span: std::ops::Range<usize>,
        field: &str,
    ) -> Result<(), SceneError> {
        let (upper, rule) = match role {
            Role::Reflectance => (1.0, "a reflectance must lie in [0, 1]".to_owned()),
            Role::Emission => (MAX_EMISSION, format!("an emission must lie in [0, {MAX_EMISSION:e}]")),
            Role::Coefficient => (f32::MAX, "a coefficient must be finite and ≥ 0".to_owned()),
        };
        let values = resolved.values();
        match values.iter().position(|v| !(0.0..=upper).contains(v)) {
            None => Ok(()),
            Some(index) => {
                let at = if values.len() == 1 {
                    "at every wavelength".to_owned()
                } else {
                    format!("at {} nm", LAMBDA_MIN_NM + index as f32)
                };
                Err(self.error(
                    span,
                    field,
                    format!("the spectrum (after its scale) is {} {at}; {rule}", number(values[index])),
                ))
            }
        }
    }

    fn point(&self, p: [f32; 3], span: std::ops::Range<usize>, field: &str) -> Result<Vec3, SceneError> {
        let v = Vec3::from(p);
        if v.is_finite() && v.abs().max_element() <= MAX_COORDINATE {
            Ok(v)
        } else {
            Err(self.error(
                span,
                field,
                format!("each component must be finite and within ±{MAX_COORDINATE:e}, got {p:?}"),
            ))
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

    /// A length or scale factor: within [[`MIN_LENGTH`], [`MAX_COORDINATE`]].
    fn length(&self, value: f32, span: std::ops::Range<usize>, field: &str) -> Result<f32, SceneError> {
        if (MIN_LENGTH..=MAX_COORDINATE).contains(&value) {
            Ok(value)
        } else {
            Err(self.error(
                span,
                field,
                format!("must lie in [{MIN_LENGTH:e}, {MAX_COORDINATE:e}], got {}", number(value)),
            ))
        }
    }

    /// Checks a mesh as it will be rendered (after its transform): every vertex within
    /// ±[`MAX_COORDINATE`], every normal finite.
    fn check_placed_mesh(
        &self,
        mesh: &Mesh,
        span: std::ops::Range<usize>,
        at: &str,
        what: &str,
    ) -> Result<(), SceneError> {
        if let Some(index) =
            mesh.positions.iter().position(|p| !(p.is_finite() && p.abs().max_element() <= MAX_COORDINATE))
        {
            return Err(self.error(
                span,
                at,
                format!(
                    "{what} puts vertex {index} at {}, beyond ±{MAX_COORDINATE:e} scene units",
                    mesh.positions[index]
                ),
            ));
        }
        mesh.validate().map_err(|e| self.error(span, at, format!("{what}: {e}")))
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
        shape: &Spanned<Typed<ShapeDesc>>,
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
        match &shape.get_ref().0 {
            ShapeDesc::Sphere { center, radius, material } => {
                let material = material_of(material)?;
                sheet(material, None)?;
                let sphere = Sphere {
                    center: self.point(*center, span.clone(), &format!("{at}.center"))?,
                    radius: self.length(*radius, span.clone(), &format!("{at}.radius"))?,
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
                    .map_err(|e| self.error(span.clone(), format!("{at}.file"), e.to_string()))?
                    .transformed(&transform);
                self.check_placed_mesh(&mesh, span, &at, "the transform (scale, rotate_deg, position)")?;
                push_mesh(mesh, material, shapes, surfaces, meshes);
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
                let side = self.length(*side_length, span.clone(), &format!("{at}.side_length"))?;
                let length = self.length(*length, span.clone(), &format!("{at}.length"))?;
                let transform = self.transform(None, *rotate_deg, *position, span.clone(), &at)?;
                // The angle is checked again in radians: 1e-44° is > 0 but underflows to 0 rad.
                let apex_rad = apex_angle_deg.to_radians();
                let prism = Mesh::try_triangular_prism(apex_rad, side, length)
                    .map_err(|_| {
                        self.error(
                            span.clone(),
                            format!("{at}.apex_angle_deg"),
                            format!(
                                "{}° is {} rad in 32-bit floats; the angle must lie strictly between 0 and 180°",
                                number(*apex_angle_deg),
                                number(apex_rad)
                            ),
                        )
                    })?
                    .transformed(&transform);
                self.check_placed_mesh(&prism, span, &at, "the prism's size and placement")?;
                push_mesh(prism, material, shapes, surfaces, meshes);
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
        let scale = self.length(scale.unwrap_or(1.0), span.clone(), &format!("{at}.scale"))?;
        let [rx, ry, rz] =
            self.point(rotate_deg.unwrap_or([0.0; 3]), span.clone(), &format!("{at}.rotate_deg"))?.to_array();
        let position = self.point(position.unwrap_or([0.0; 3]), span, &format!("{at}.position"))?;
        // Rotate about x first, then y, then z (extrinsic), i.e. R = Rz·Ry·Rx.
        let rotation = Quat::from_euler(EulerRot::ZYX, rz.to_radians(), ry.to_radians(), rx.to_radians());
        Ok(Affine3A::from_scale_rotation_translation(Vec3::splat(scale), rotation, position))
    }

    fn light(&self, index: usize, light: &Spanned<Typed<LightDesc>>) -> Result<Light, SceneError> {
        let span = light.span();
        let at = format!("lights[{index}]");
        Ok(match &light.get_ref().0 {
            LightDesc::Point { position, intensity } => Light::Point(PointLight {
                position: self.point(*position, span.clone(), &format!("{at}.position"))?,
                intensity: self.spectrum(intensity, Role::Emission, span, &format!("{at}.intensity"))?,
            }),
            LightDesc::Quad { corner, edge1, edge2, radiance, emit, .. } => {
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
                Light::Spot(SpotLight::new(
                    position,
                    axis.normalize(),
                    intensity,
                    cutoff_deg.to_radians(),
                    beam_width_deg.to_radians(),
                ))
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

/// `x` for a message: scientific notation when it is very large or very small, so that 3e38
/// does not print as 39 digits.
fn number(x: f32) -> String {
    if x != 0.0 && x.is_finite() && !(1e-4..1e6).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
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

/// Regressions found by fuzzing the scene loader (../shared/cases/reliability/ in the issue):
/// each value was accepted and then panicked or rendered NaN or nothing; each must now be
/// refused at load, naming the field.
#[cfg(test)]
mod tests {
    use super::*;

    const CAMERA: &str =
        "[camera]\nposition = [0, 0, -5]\nlook_at = [0, 0, 0]\nfov_y_deg = 40\nwidth = 4\nheight = 3\n";
    const GLASS: &str = "[materials.glass]\ntype = \"dielectric\"\nior = 1.5\n";

    /// The error of loading `body` after a camera, as its message.
    fn rejection(body: &str) -> String {
        let text = format!("{CAMERA}{body}");
        match parse(&text, Path::new("scene.toml")) {
            Ok(_) => panic!("accepted:\n{body}"),
            Err(error) => error.to_string(),
        }
    }

    fn assert_rejected(body: &str, fragments: &[&str]) {
        let message = rejection(body);
        for fragment in fragments {
            assert!(message.contains(fragment), "{fragment:?} missing from: {message}");
        }
    }

    fn obj_scene(transform: &str) -> (tempfile::TempDir, String) {
        let dir = tempfile::tempdir().expect("temporary directory");
        std::fs::write(dir.path().join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").expect("obj");
        let body = format!(
            "{GLASS}[[shapes]]\ntype = \"mesh\"\nfile = \"tri.obj\"\nmaterial = \"glass\"\n{transform}"
        );
        (dir, body)
    }

    #[test]
    fn panic_prism_tiny_apex() {
        // 1e-44° is in (0°, 180°) but 0 rad in f32: the prism builder panicked.
        let prism = "[[shapes]]\ntype = \"prism\"\napex_angle_deg = 1e-44\nside_length = 1\nlength = 1\nmaterial = \"glass\"\n";
        assert_rejected(&format!("{GLASS}{prism}"), &["shapes[0].apex_angle_deg", "0 rad"]);
    }

    #[test]
    fn panic_prism_side_overflow() {
        let prism = "[[shapes]]\ntype = \"prism\"\napex_angle_deg = 60\nside_length = 3e38\nlength = 1\nmaterial = \"glass\"\n";
        assert_rejected(&format!("{GLASS}{prism}"), &["shapes[0].side_length", "3e38"]);
        // Each value within range, the placed prism beyond it: checked after the transform.
        let placed = "[[shapes]]\ntype = \"prism\"\napex_angle_deg = 60\nside_length = 1e10\nlength = 1e10\nposition = [1e10, 0, 0]\nmaterial = \"glass\"\n";
        assert_rejected(&format!("{GLASS}{placed}"), &["shapes[0]", "vertex", "beyond"]);
    }

    #[test]
    fn panic_mesh_transform_overflow() {
        // The reproducer: scale 3e38, position 3e38 (vertex (1, 0, 0) → inf).
        let (dir, body) = obj_scene("scale = 3e38\nposition = [3e38, 0, 0]\n");
        let text = format!("{CAMERA}{body}");
        let error = parse(&text, &dir.path().join("scene.toml")).expect_err("overflow").to_string();
        assert!(error.contains("shapes[0].scale"), "{error}");
        // Scale and position each within range, the transformed vertex (2e10, 0, 0) is not.
        let (dir, body) = obj_scene("scale = 1e10\nposition = [1e10, 0, 0]\n");
        let text = format!("{CAMERA}{body}");
        let error = parse(&text, &dir.path().join("scene.toml")).expect_err("beyond").to_string();
        assert!(error.contains("shapes[0]") && error.contains("vertex 1"), "{error}");
    }

    #[test]
    fn nan_background_1e36() {
        let text = format!("background = 1e36\n{CAMERA}");
        let message = parse(&text, Path::new("s.toml")).expect_err("overflows").to_string();
        assert!(message.contains("s.toml:1: background") && message.contains("1e15"), "{message}");
        // Below the limit, loads.
        parse(&format!("background = 1e15\n{CAMERA}"), Path::new("s.toml")).expect("at the limit");
    }

    #[test]
    fn nan_spectrum_scale_product() {
        // Each factor finite, the product inf.
        let light = "[[lights]]\ntype = \"point\"\nposition = [0, 0, 0]\nintensity = { value = 1e30, scale = 1e30 }\n";
        assert_rejected(light, &["lights[0].intensity", "inf"]);
    }

    #[test]
    fn reflectance_above_one_via_scale() {
        for albedo in [
            "{ value = 1, scale = 100 }",
            "{ illuminant = \"D65\" }",
            "{ illuminant = \"E\", scale = 1.5 }",
            "{ blackbody_k = 3000 }",
            "{ rgb = [1, 1, 1], scale = 1.01 }",
        ] {
            let material = format!("[materials.white]\ntype = \"diffuse\"\nalbedo = {albedo}\n");
            assert_rejected(&material, &["materials.white.albedo", "reflectance must lie in [0, 1]"]);
        }
        let mirror = "[materials.m]\ntype = \"mirror\"\nreflectance = { illuminant = \"D65\", scale = 3 }\n";
        assert_rejected(mirror, &["materials.m.reflectance"]);
        // A reflectance within [0, 1] through scale still loads.
        let fine =
            format!("{CAMERA}[materials.w]\ntype = \"diffuse\"\nalbedo = {{ value = 1, scale = 0.5 }}\n");
        parse(&fine, Path::new("s.toml")).expect("albedo 0.5");
    }

    /// A quad light's `albedo` makes its surface diffuse (black without it), and is checked as
    /// every reflectance is: in [0, 1], the error naming the field.
    #[test]
    fn quad_light_albedo_is_a_diffuse_reflectance() {
        let light = |albedo: &str| {
            format!(
                "[[lights]]\ntype = \"quad\"\ncorner = [0, 0, 0]\nedge1 = [1, 0, 0]\nedge2 = [0, 1, 0]\n\
                 radiance = 1\nemit = \"edge1_cross_edge2\"\n{albedo}"
            )
        };
        for bad in ["albedo = 1.5\n", "albedo = -0.1\n", "albedo = { illuminant = \"D65\" }\n"] {
            assert_rejected(&light(bad), &["lights[0].albedo", "reflectance"]);
        }
        let surface_material = |albedo: &str| {
            let scene = parse(&format!("{CAMERA}{}", light(albedo)), Path::new("s.toml")).expect("loads");
            scene.materials[scene.surfaces[0].material as usize].clone()
        };
        assert!(matches!(surface_material(""), Material::Black));
        match surface_material("albedo = { table = [[400, 0.25], [700, 0.75]] }\n") {
            Material::Diffuse(diffuse) => {
                assert_eq!(diffuse.albedo.eval(400.0), 0.25);
                assert!((diffuse.albedo.eval(550.0) - 0.5).abs() < 1e-6);
            }
            other => panic!("a quad light with an albedo is diffuse, not {other:?}"),
        }
    }

    #[test]
    fn sphere_radius_1e20_invisible() {
        // r² overflowed f32, so the sphere was never hit.
        let sphere =
            "[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1e20\nmaterial = \"glass\"\n";
        assert_rejected(&format!("{GLASS}{sphere}"), &["shapes[0].radius", "1e10"]);
        let tiny = sphere.replace("1e20", "1e-30");
        assert_rejected(&format!("{GLASS}{tiny}"), &["shapes[0].radius"]);
    }

    #[test]
    fn extreme_indices_of_refraction_are_refused() {
        for ior in ["1e30", "1e-30", "{ cauchy = [1000, 0, 0] }"] {
            let material = format!("[materials.g]\ntype = \"dielectric\"\nior = {ior}\n");
            assert_rejected(&material, &["materials.g.ior", "must lie in [0.01, 100]"]);
        }
    }

    #[test]
    fn coordinates_beyond_the_limit_are_refused() {
        let light = "[[lights]]\ntype = \"point\"\nposition = [0, 1e11, 0]\nintensity = 1\n";
        assert_rejected(light, &["lights[0].position", "1e10"]);
    }

    #[test]
    fn prune0_exponential_time() {
        // The reproducer's settings: pruning off with depth 24 (40 s for a small image, hours at
        // depth 32) is refused, naming the rule; depth 20, or pruning at 1e-4, is accepted.
        let settings = |render: &str| format!("{CAMERA}[render]\n{render}\n");
        let message = rejection("[render]\nmax_depth = 24\nprune_below = 0\n");
        assert!(message.contains("render.max_depth") && message.contains("2^24"), "{message}");
        let message = rejection("[render]\nmax_depth = 1000\nprune_below = 1e-30\n");
        assert!(message.contains("at most 20"), "{message}");
        for fine in
            ["max_depth = 20\nprune_below = 0", "max_depth = 4096\nprune_below = 1e-4", "max_depth = 4096"]
        {
            parse(&settings(fine), Path::new("s.toml")).unwrap_or_else(|e| panic!("{fine}: {e}"));
        }
    }

    #[test]
    fn toml_errors_name_the_field_at_the_values_line() {
        let sphere =
            "[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = \"one\"\nmaterial = \"glass\"\n";
        let message = rejection(&format!("{GLASS}{sphere}"));
        // CAMERA has 6 lines, GLASS 3, then [[shapes]], type, center: radius is line 13.
        assert!(message.starts_with("scene.toml:13: shapes[0].radius: invalid type"), "{message}");
    }
}

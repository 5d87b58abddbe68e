//! Where the light tracer's paths start: which light, where on it, in which direction, and with
//! what flux weight.
//!
//! A light path counts only if its first interaction is with a mirror or glass (the light
//! tracer adds L S⁺ D E; Whitted already has L D E), so emission is aimed at them, as photon
//! mapping's projection maps do (Jensen, *Realistic Image Synthesis Using Photon Mapping*,
//! §5.3): every mirror and glass object is bounded by a sphere, and point, spot and quad lights
//! draw directions from the union of the cones those spheres subtend, a mixture sampled in
//! proportion to the cones' solid angles, whose density at ω is (number of cones holding ω) /
//! (sum of their solid angles). Directions outside every cone could only reach a diffuse
//! surface, a light or nothing first, so leaving them out loses no light path that counts, and
//! the estimate stays unbiased. When the cones cover more than the light's own emission
//! (a light inside or close to the glass), or when a mirror is an infinite plane, a light draws
//! from its own distribution instead. In TP6 the two spheres' cones (14.1° half-angle each, seen
//! from the point light) cover 3 % of the sphere of directions: aimed, every path meets a
//! sphere, 33× as many as uniform emission would send there.
//!
//! Lights are chosen in proportion to the power they can send toward the mirrors and glass
//! (their spectra integrated over 360–830 nm), so that no light that can make a caustic is
//! left out and none that cannot is drawn.
//!
//! For validation, [`Emission::everything`] starts paths over the **whole** emission of every
//! light instead (a light tracer that counts every path it can, beside no camera side): lights
//! in proportion to their whole power, quads cosine-weighted over their hemisphere, points
//! uniformly over the sphere, spots over their cutoff cone.

use glam::Vec3;

use crate::geometry::{spawn_origin, Aabb, Ray, Shape};
use crate::light::{Light, QuadLight, SpotLight};
use crate::material::Material;
use crate::polarization::frame::any_perpendicular;
use crate::scene::Scene;

const TAU: f32 = std::f32::consts::TAU;
const FOUR_PI: f32 = 4.0 * std::f32::consts::PI;

/// A sphere bounding a mirror or glass object.
#[derive(Debug, Clone, Copy)]
struct Target {
    center: Vec3,
    radius: f32,
}

/// A cone of directions: those within the half-angle of cosine `cos_half` of the unit `axis`.
#[derive(Debug, Clone, Copy)]
pub struct Cone {
    axis: Vec3,
    cos_half: f32,
    /// A frame (tangent, bitangent) across the axis for sampling, made once for the cones a
    /// light keeps for the whole render ([`Self::framed`]); cones made per light path (a quad
    /// light's) leave it to [`Self::sample`], for the one cone sampled.
    frame: Option<(Vec3, Vec3)>,
}

impl Cone {
    /// The cone around the unit `axis` whose half-angle has cosine `cos_half`.
    fn new(axis: Vec3, cos_half: f32) -> Self {
        Self { axis, cos_half, frame: None }
    }

    /// The same cone with its sampling frame made now.
    fn framed(self) -> Self {
        Self { frame: Some(frame_across(self.axis)), ..self }
    }

    /// The cone of directions from `from` that can meet `target`, or `None` when `from` is
    /// inside its sphere (every direction can).
    fn toward(from: Vec3, target: &Target) -> Option<Cone> {
        let offset = target.center - from;
        let distance_sq = offset.length_squared();
        let radius_sq = target.radius * target.radius;
        if distance_sq <= radius_sq * 1.0001 {
            return None;
        }
        let distance = distance_sq.sqrt();
        // cos of the half-angle asin(r/d), made a little wider against rounding.
        let cos_half = ((distance_sq - radius_sq).sqrt() / distance * 0.99999).min(1.0);
        Some(Cone::new(offset / distance, cos_half))
    }

    /// Solid angle, sr.
    fn solid_angle(&self) -> f32 {
        TAU * (1.0 - self.cos_half)
    }

    /// True when the unit direction `dir` is inside.
    fn contains(&self, dir: Vec3) -> bool {
        dir.dot(self.axis) >= self.cos_half
    }

    /// A direction uniform in the cone from the uniform numbers `u`.
    fn sample(&self, u: (f32, f32)) -> Vec3 {
        let cos_theta = 1.0 - u.0 * (1.0 - self.cos_half);
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let (sin_phi, cos_phi) = (TAU * u.1).sin_cos();
        let (tangent, bitangent) = self.frame.unwrap_or_else(|| frame_across(self.axis));
        (cos_theta * self.axis + sin_theta * (cos_phi * tangent + sin_phi * bitangent)).normalize()
    }
}

/// A tangent and a bitangent across the unit `axis`.
fn frame_across(axis: Vec3) -> (Vec3, Vec3) {
    let tangent = any_perpendicular(axis);
    (tangent, axis.cross(tangent))
}

/// The union of `cones` sampled as a mixture in proportion to their solid angles (`total` is
/// their sum): a direction and its density (sr⁻¹). `next` chooses the cone when there are
/// several.
fn sample_cones(cones: &[Cone], total: f32, next: &mut impl FnMut() -> f32, u: (f32, f32)) -> (Vec3, f32) {
    let mut chosen = cones[cones.len() - 1];
    if cones.len() > 1 {
        let mut pick = next() * total;
        for cone in cones {
            if pick < cone.solid_angle() {
                chosen = *cone;
                break;
            }
            pick -= cone.solid_angle();
        }
    }
    let dir = chosen.sample(u);
    if cones.len() == 1 {
        // What cones_pdf gives for one cone, whether or not rounding leaves `dir` in it.
        return (dir, 1.0 / total);
    }
    (dir, cones_pdf(cones, total, dir))
}

/// The density of [`sample_cones`] at `dir`: cones holding it over the total solid angle.
fn cones_pdf(cones: &[Cone], total: f32, dir: Vec3) -> f32 {
    let holding = cones.iter().filter(|cone| cone.contains(dir)).count().max(1);
    holding as f32 / total
}

/// How a point or spot light draws directions, fixed when the tracer is built.
#[derive(Debug, Clone)]
enum Directions {
    /// The light's own distribution: uniform over the sphere for a point light (quad lights and
    /// beams draw theirs in [`Emission::sample`]). A spot's own distribution, its cutoff cone,
    /// is held as [`Self::Cones`], framed once.
    Own,
    /// The union of the cones toward the mirrors and glass.
    Cones { cones: Vec<Cone>, total: f32 },
}

/// One light as a source of light paths.
#[derive(Debug, Clone)]
struct Source {
    /// Index into the scene's lights.
    light: usize,
    /// Probability of choosing it.
    probability: f32,
    /// Directions of a point or spot light (unused by quads and beams).
    directions: Directions,
}

/// A light path's start: the ray leaving the light, the light, and the flux weight that
/// multiplies the light's emitted spectrum ([`Light::emitted`]): 1/(probability of the light ×
/// densities of position and direction) times the emission's own factors (falloff, cosine,
/// area), so that the weighted spectrum is an unbiased estimate of the light's power (W·nm⁻¹).
#[derive(Debug, Clone, Copy)]
pub struct Emitted {
    /// The ray leaving the light.
    pub ray: Ray,
    /// Index into the scene's lights.
    pub light: usize,
    /// The flux weight (m²·sr for a quad, m² for a beam, sr for point and spot lights).
    pub weight: f32,
    /// For a quad light, the weight of the point alone, 1/(probability of the light × density
    /// of the point on it) (m²): what multiplies the radiance the camera sees there when the
    /// light is connected to the camera (L E). `None` for the other lights, which no pinhole
    /// can see.
    pub area_weight: Option<f32>,
}

/// The lights as sources of light paths.
#[derive(Debug, Clone)]
pub struct Emission {
    sources: Vec<Source>,
    /// Bounding spheres of the mirrors and glass; `None` when one of them is unbounded.
    targets: Option<Vec<Target>>,
}

impl Emission {
    /// The sources of `scene`'s light paths: every light that can send light to a mirror or
    /// glass object.
    pub fn new(scene: &Scene) -> Self {
        let targets = targets(scene);
        let mut sources = Vec::new();
        for (index, light) in scene.lights.iter().enumerate() {
            let (power, directions) = match light {
                Light::Point(point) => {
                    let (solid_angle, directions) = match &targets {
                        Some(targets) => {
                            aimed(targets.iter().map(|t| Cone::toward(point.position, t)), FOUR_PI, None)
                        }
                        None => (FOUR_PI, Directions::Own),
                    };
                    (point.intensity.integral_nm() * f64::from(solid_angle), directions)
                }
                Light::Spot(spot) => {
                    let own = 1.0 - spot.cos_cutoff();
                    let own_solid_angle = TAU * own;
                    let (solid_angle, directions) = match &targets {
                        Some(targets) => aimed(
                            targets.iter().map(|t| Cone::toward(spot.position, t)),
                            own_solid_angle,
                            Some(spot),
                        ),
                        None => (own_solid_angle, Directions::Own),
                    };
                    let reach = solid_angle.min(spot.solid_angle_weight());
                    // Its own distribution is its cutoff cone, framed here once for all paths.
                    let directions = match directions {
                        Directions::Own => Directions::Cones {
                            cones: vec![Cone::new(spot.axis, spot.cos_cutoff()).framed()],
                            total: own_solid_angle,
                        },
                        aimed => aimed,
                    };
                    (spot.intensity.integral_nm() * f64::from(reach), directions)
                }
                Light::Quad(quad) => (
                    quad.radiance.integral_nm() * f64::from(quad.quad.area() * std::f32::consts::PI),
                    Directions::Own,
                ),
                Light::Beam(beam) => {
                    (beam.irradiance.integral_nm() * f64::from(beam.quad.area()), Directions::Own)
                }
            };
            if power > 0.0 && power.is_finite() && targets.as_ref().is_none_or(|t| !t.is_empty()) {
                sources.push(Source { light: index, probability: power as f32, directions });
            }
        }
        let total: f32 = sources.iter().map(|s| s.probability).sum();
        for source in &mut sources {
            source.probability /= total;
        }
        Self { sources, targets }
    }

    /// The sources of light paths over the whole emission of every light of `scene` (module
    /// docs): every light with some power, chosen in proportion to it, each drawing from its own
    /// distribution (no aiming at mirrors and glass).
    pub fn everything(scene: &Scene) -> Self {
        let mut sources = Vec::new();
        for (index, light) in scene.lights.iter().enumerate() {
            let (power, directions) = match light {
                Light::Point(point) => (point.intensity.integral_nm() * f64::from(FOUR_PI), Directions::Own),
                Light::Spot(spot) => (
                    spot.intensity.integral_nm() * f64::from(spot.solid_angle_weight()),
                    Directions::Cones {
                        cones: vec![Cone::new(spot.axis, spot.cos_cutoff()).framed()],
                        total: TAU * (1.0 - spot.cos_cutoff()),
                    },
                ),
                Light::Quad(quad) => (
                    quad.radiance.integral_nm() * f64::from(quad.quad.area() * std::f32::consts::PI),
                    Directions::Own,
                ),
                Light::Beam(beam) => {
                    (beam.irradiance.integral_nm() * f64::from(beam.quad.area()), Directions::Own)
                }
            };
            if power > 0.0 && power.is_finite() {
                sources.push(Source { light: index, probability: power as f32, directions });
            }
        }
        let total: f32 = sources.iter().map(|s| s.probability).sum();
        for source in &mut sources {
            source.probability /= total;
        }
        // No targets: quads draw cosine-weighted directions over their hemisphere.
        Self { sources, targets: None }
    }

    /// True when no light can send light to a mirror or glass object (no light, no mirror or
    /// glass, or none within reach of a spot); for [`Self::everything`], when no light emits.
    pub fn is_empty(&self) -> bool {
        self.sources.is_empty()
    }

    /// The start of a light path: `u_dir` chooses the direction (a beam: the position), and
    /// `next` supplies further uniform numbers, drawn only for the choices this scene has: the
    /// light (when there are several), the cone (when there are several) and the position on a
    /// quad light, in that order. `cones` is scratch space. `None` when the drawn direction
    /// carries no light.
    pub fn sample(
        &self,
        scene: &Scene,
        u_dir: (f32, f32),
        next: &mut impl FnMut() -> f32,
        cones: &mut Vec<Cone>,
    ) -> Option<Emitted> {
        let mut chosen = self.sources.last()?;
        if self.sources.len() > 1 {
            let mut pick = next();
            for source in &self.sources {
                if pick < source.probability {
                    chosen = source;
                    break;
                }
                pick -= source.probability;
            }
        }
        let light = &scene.lights[chosen.light];
        let mut area_weight = None;
        let (origin, normal, dir, weight) = match light {
            Light::Point(point) => {
                let (dir, pdf) = directions(&chosen.directions, next, u_dir);
                (point.position, None, dir, 1.0 / pdf)
            }
            Light::Spot(spot) => {
                // Its directions are always cones (its own cutoff cone, or those aimed at the
                // targets); were they the whole sphere, the falloff would still weigh them.
                let (dir, pdf) = directions(&chosen.directions, next, u_dir);
                (spot.position, None, dir, spot.falloff(dir) / pdf)
            }
            Light::Quad(quad) => {
                let (u_x, u_y) = (next(), next());
                let origin = quad.quad.point_at(u_x, u_y);
                let (dir, pdf) = self.quad_direction(quad, origin, next, u_dir, cones);
                let cos_theta = dir.dot(quad.emit_normal);
                area_weight = Some(quad.quad.area() / chosen.probability);
                (origin, Some(quad.emit_normal), dir, quad.quad.area() * cos_theta.max(0.0) / pdf)
            }
            Light::Beam(beam) => {
                let origin = beam.quad.point_at(u_dir.0, u_dir.1);
                (origin, Some(beam.emit_normal), beam.emit_normal, beam.quad.area())
            }
        };
        let weight = weight / chosen.probability;
        if !(weight > 0.0 && weight.is_finite()) {
            return None;
        }
        let origin = match normal {
            Some(normal) => spawn_origin(origin, normal, dir),
            None => origin,
        };
        Some(Emitted { ray: Ray::new(origin, dir), light: chosen.light, weight, area_weight })
    }

    /// A direction from `origin` on a quad light and its density: toward the mirrors and glass
    /// when their cones cover less than the hemisphere, else cosine-weighted.
    fn quad_direction(
        &self,
        quad: &QuadLight,
        origin: Vec3,
        next: &mut impl FnMut() -> f32,
        u: (f32, f32),
        cones: &mut Vec<Cone>,
    ) -> (Vec3, f32) {
        cones.clear();
        let mut total = 0.0;
        if let Some(targets) = &self.targets {
            for target in targets {
                match Cone::toward(origin, target) {
                    Some(cone) => {
                        total += cone.solid_angle();
                        cones.push(cone);
                    }
                    None => {
                        total = f32::INFINITY;
                        break;
                    }
                }
            }
        } else {
            total = f32::INFINITY;
        }
        if total < TAU && !cones.is_empty() {
            return sample_cones(cones, total, next, u);
        }
        let normal = quad.emit_normal;
        let radius = u.0.sqrt();
        let (sin_phi, cos_phi) = (TAU * u.1).sin_cos();
        let cos_theta = (1.0 - u.0).max(0.0).sqrt();
        let tangent = any_perpendicular(normal);
        let bitangent = normal.cross(tangent);
        let dir = (cos_theta * normal + radius * (cos_phi * tangent + sin_phi * bitangent)).normalize();
        (dir, dir.dot(normal).max(1e-8) * std::f32::consts::FRAC_1_PI)
    }
}

/// A direction drawn from a point or spot light's `directions` with `u`, and its density (sr⁻¹).
fn directions(directions: &Directions, next: &mut impl FnMut() -> f32, u: (f32, f32)) -> (Vec3, f32) {
    match directions {
        Directions::Own => (uniform_sphere(u), 1.0 / FOUR_PI),
        Directions::Cones { cones, total } => sample_cones(cones, *total, next, u),
    }
}

/// A uniform direction on the unit sphere.
fn uniform_sphere(u: (f32, f32)) -> Vec3 {
    let z = 1.0 - 2.0 * u.0;
    let radius = (1.0 - z * z).max(0.0).sqrt();
    let (sin_phi, cos_phi) = (TAU * u.1).sin_cos();
    Vec3::new(radius * cos_phi, radius * sin_phi, z)
}

/// The directions of a point or spot light given the cones toward each target (`None`: inside
/// one), and the solid angle they span: the cones when they span less than `own` (the light's
/// own solid angle), else the light's own distribution. A spot keeps only the cones its cutoff
/// cone overlaps.
fn aimed(cones: impl Iterator<Item = Option<Cone>>, own: f32, spot: Option<&SpotLight>) -> (f32, Directions) {
    let mut kept = Vec::new();
    for cone in cones {
        let Some(cone) = cone else { return (own, Directions::Own) };
        if let Some(spot) = spot {
            // Disjoint when the angle between the axes exceeds the sum of the half-angles.
            let between = spot.axis.dot(cone.axis).clamp(-1.0, 1.0).acos();
            if between >= spot.cutoff_rad() + cone.cos_half.clamp(-1.0, 1.0).acos() {
                continue;
            }
        }
        kept.push(cone.framed());
    }
    let total: f32 = kept.iter().map(Cone::solid_angle).sum();
    if kept.is_empty() {
        return (0.0, Directions::Cones { cones: kept, total: 0.0 });
    }
    if total >= own {
        return (own, Directions::Own);
    }
    (total, Directions::Cones { cones: kept, total })
}

/// Bounding spheres of every mirror, glass and film object (spheres, quads, one per mesh), or
/// `None` when one is an infinite plane. Polarisers and retarders are not targets: light passes them
/// unchanged in direction, and a path that meets only them ends at a diffuse surface Whitted
/// already lights through them.
fn targets(scene: &Scene) -> Option<Vec<Target>> {
    let mut targets = Vec::new();
    let mut meshes: Vec<Option<Aabb>> = vec![None; scene.geometry.meshes().len()];
    for (shape, surface) in scene.geometry.shapes().iter().zip(&scene.surfaces) {
        if !matches!(
            scene.materials[surface.material as usize],
            Material::Mirror(_) | Material::Dielectric(_) | Material::Film(_)
        ) {
            continue;
        }
        match shape {
            Shape::Sphere(sphere) => targets.push(Target { center: sphere.center, radius: sphere.radius }),
            Shape::Plane(_) => return None,
            Shape::Quad(quad) => targets.push(sphere_of(&quad.bounds())),
            Shape::Triangle { mesh, .. } => {
                let bounds = shape.bounds(scene.geometry.meshes())?;
                let slot = &mut meshes[*mesh as usize];
                *slot = Some(slot.map_or(bounds, |b| b.union(bounds)));
            }
        }
    }
    targets.extend(meshes.iter().flatten().map(sphere_of));
    Some(targets)
}

/// The sphere around a box (centre and half diagonal), a little larger against rounding.
fn sphere_of(bounds: &Aabb) -> Target {
    let center = bounds.centroid();
    let radius = 0.5 * (bounds.max - bounds.min).length() * 1.0001 + 1e-6 * center.abs().max_element();
    Target { center, radius }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The mixture over overlapping cones is a density: its integral over the sphere is 1
    /// (Monte Carlo with uniform directions, 200 000 samples: standard error about 0.5 %).
    #[test]
    fn cone_mixture_density_integrates_to_one() {
        let targets = [
            Target { center: Vec3::new(0.0, 0.0, 3.0), radius: 1.0 },
            Target { center: Vec3::new(0.5, 0.0, 3.0), radius: 1.2 },
            Target { center: Vec3::new(-4.0, 1.0, 0.0), radius: 0.5 },
        ];
        let cones: Vec<Cone> = targets.iter().filter_map(|t| Cone::toward(Vec3::ZERO, t)).collect();
        let total: f32 = cones.iter().map(Cone::solid_angle).sum();
        let n = 200_000;
        let mut integral = 0.0f64;
        for k in 0..n {
            let u = ((k as f32 + 0.5) / n as f32, (k as f32 * 0.618_034).fract());
            integral += f64::from(cones_pdf(&cones, total, uniform_sphere(u)))
                * f64::from(cones.iter().any(|c| c.contains(uniform_sphere(u))) as u8);
        }
        integral *= f64::from(FOUR_PI) / f64::from(n);
        assert!((integral - 1.0).abs() < 0.02, "∫ pdf = {integral}");
    }

    /// A spot that cannot aim (an infinite glass plane has no bounding sphere) draws from its
    /// own cutoff cone: every direction within the cutoff, and the mean weight (falloff over
    /// density) the integral of its falloff over directions. For a falloff linear in angle from
    /// 1 at the beam width θb to 0 at the cutoff θc, that is 2π·(1 + (sin θb − sin θc)/(θc − θb))
    /// (integration by parts); 30° and 40° give 1.1428 sr. 2¹⁶ stratified directions; a density
    /// 0.2 % off fails.
    #[test]
    fn a_spot_that_cannot_aim_emits_over_its_own_cone() {
        let text = r#"
            [camera]
            position = [0, 0, -5]
            look_at = [0, 0, 0]
            fov_y_deg = 40
            width = 8
            height = 8
            [materials.glass]
            type = "dielectric"
            ior = 1.5
            [[shapes]]
            type = "plane"
            point = [0, -1, 0]
            normal = [0, 1, 0]
            material = "glass"
            [[lights]]
            type = "spot"
            position = [0, 2, 0]
            look_at = [1, 0, 1]
            cutoff_deg = 40
            beam_width_deg = 30
            intensity = 1
        "#;
        let scene = crate::scene::parse(text, std::path::Path::new("spot.toml")).expect("scene");
        let Light::Spot(spot) = &scene.lights[0] else { panic!("a spot") };
        let emission = Emission::new(&scene);
        let (cutoff, beam) = (40f64.to_radians(), 30f64.to_radians());
        let expected = std::f64::consts::TAU * (1.0 + (beam.sin() - cutoff.sin()) / (cutoff - beam));
        let side = 256;
        let mut sum = 0.0f64;
        for i in 0..side {
            for j in 0..side {
                let u = ((i as f32 + 0.5) / side as f32, (j as f32 + 0.5) / side as f32);
                let emitted = emission
                    .sample(
                        &scene,
                        u,
                        &mut || panic!("one light, one cone: no further choice"),
                        &mut Vec::new(),
                    )
                    .expect("inside the cone");
                let cos_axis = f64::from(emitted.ray.dir.dot(spot.axis));
                assert!(cos_axis >= cutoff.cos() - 1e-6, "{} outside the cutoff", emitted.ray.dir);
                sum += f64::from(emitted.weight);
            }
        }
        let mean = sum / f64::from(side * side);
        assert!((mean - expected).abs() < 1e-3 * expected, "mean weight {mean} sr, expected {expected}");
    }

    /// Over the whole emission ([`Emission::everything`]), a quad light's paths leave its
    /// emitting side cosine-weighted, beside a mirror that [`Emission::new`] would aim them at:
    /// the mean flux weight is the quad's étendue π·A (1.5 × 2 m²: 9.42 m²·sr) divided by the
    /// probability of the quad (¾ of the power, beside a second quad of the same radiance and a
    /// third of its area), the point weight A over that probability exactly, and the mean cosine toward
    /// the emitting normal 2/3 (cosine-weighted). 2¹⁶ stratified directions; a uniform hemisphere
    /// (mean cosine ½) or a missing cosine fails.
    #[test]
    fn everything_emits_over_the_whole_hemisphere() {
        let text = r#"
            [camera]
            position = [0, 0, -5]
            look_at = [0, 0, 0]
            fov_y_deg = 40
            width = 8
            height = 8
            [materials.mirror]
            type = "mirror"
            [[shapes]]
            type = "sphere"
            center = [0, -2, 0]
            radius = 0.1
            material = "mirror"
            [[lights]]
            type = "quad"
            corner = [0, 3, 0]
            edge1 = [1.5, 0, 0]
            edge2 = [0, 0, 2]
            radiance = 1
            emit = "edge1_cross_edge2"
            [[lights]]
            type = "quad"
            corner = [5, 3, 0]
            edge1 = [1, 0, 0]
            edge2 = [0, 0, 1]
            radiance = 1
            emit = "edge1_cross_edge2"
        "#;
        let scene = crate::scene::parse(text, std::path::Path::new("quads.toml")).expect("scene");
        let emission = Emission::everything(&scene);
        let (area, other) = (3.0f64, 1.0f64);
        let probability = area / (area + other);
        let side = 256;
        let (mut weight, mut cosine, mut count) = (0.0f64, 0.0f64, 0u32);
        for i in 0..side {
            for j in 0..side {
                let u = ((i as f32 + 0.5) / side as f32, (j as f32 + 0.5) / side as f32);
                // The first quad (pick 0.1 < ¾), the middle of it.
                let mut numbers = [0.1f32, 0.5, 0.5].into_iter();
                let emitted = emission
                    .sample(&scene, u, &mut || numbers.next().expect("three numbers"), &mut Vec::new())
                    .expect("every direction of the hemisphere carries light");
                assert_eq!(emitted.light, 0);
                let area_weight = f64::from(emitted.area_weight.expect("a quad"));
                assert!((area_weight - area / probability).abs() < 1e-5 * area_weight, "{area_weight}");
                weight += f64::from(emitted.weight);
                cosine += f64::from(-emitted.ray.dir.y);
                count += 1;
            }
        }
        let expected = std::f64::consts::PI * area / probability;
        let (weight, cosine) = (weight / f64::from(count), cosine / f64::from(count));
        assert!((weight - expected).abs() < 1e-3 * expected, "mean weight {weight}, expected {expected}");
        assert!((cosine - 2.0 / 3.0).abs() < 1e-3, "mean cosine {cosine}");
    }

    /// Every direction that meets a target sphere lies in its cone.
    #[test]
    fn cones_hold_every_direction_that_meets_the_sphere() {
        let target = Target { center: Vec3::new(1.0, 2.0, 5.0), radius: 0.7 };
        let cone = Cone::toward(Vec3::ZERO, &target).unwrap();
        for k in 0..2000 {
            let dir = uniform_sphere(((k as f32 + 0.5) / 2000.0, (k as f32 * 0.754_877).fract()));
            let along = target.center.dot(dir);
            let miss_sq = target.center.length_squared() - along * along;
            if along > 0.0 && miss_sq < target.radius * target.radius {
                assert!(cone.contains(dir), "{dir}");
            }
        }
        assert!(Cone::toward(target.center, &target).is_none(), "inside the sphere");
    }
}

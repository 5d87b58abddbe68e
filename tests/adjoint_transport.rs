//! The light side and the camera side agree (issue 39; the adjoint check of polarised
//! bidirectional transport, Mojzík, Skřivan, Wilkie & Křivánek, EGSR 2016): on a room lit by
//! one-sided quad lights alone (the background black), with diffuse walls, a glass sphere and a
//! mirror sphere, the path tracer alone (`integrator = "path"`, `caustics = false`: the camera
//! side counts every path it can) and the light tracer alone
//! ([`LightTracer::counting_everything`]: light paths over the whole emission, connected to the
//! camera at every diffuse vertex and at the light) estimate the same Stokes image on every pixel
//! whose camera ray first meets a diffuse surface or a light. There each counts every path of
//! light (L E, L X\* D E): the two are adjoint estimators of one integral, written with no code in
//! common but the materials' Mueller matrices and the geometry. Pixels that see a sphere are
//! masked: the light tracer cannot finish a path through a mirror or glass into a pinhole
//! (L … S⁺ E).
//!
//! Compared with `prisma validate`'s metrics ([`prisma::validate::metrics`]): each side renders
//! twice with independent seeds; per pixel and channel (S0–S3), z of the difference of the means
//! against the pooled variance of the pairs, the excess of |z| > 5 outliers over the null
//! comparison, and the z of the image-wide means, with `prisma validate`'s default thresholds
//! (validation/README.md, "Metrics and thresholds", and "Full transport: the light side against
//! the camera side" for what this test measured).

mod adjoint;

use adjoint::passes;
use prisma::film::Film;
use prisma::geometry::{spawn_origin, Ray};
use prisma::integrator::Fault;
use prisma::material::Material;
use prisma::polarization::Stokes;
use prisma::render::{render, Job};
use prisma::scene::{IntegratorKind, Scene};
use prisma::validate::metrics::{compare_with, Comparison, Options, Planes};

/// A room (floor, ceiling, back and side walls; open behind the camera, the background black)
/// lit by a 1.5 × 1.5 quad light under the ceiling, emitting down, and a 2 × 1.2 one just in
/// front of the back wall, facing the camera (which sees it directly); a glass sphere (n = 1.5)
/// and a mirror sphere on the floor. Monochromatic (550 nm) and polarised.
fn room_text() -> String {
    let head = r#"
background = 0.0

[camera]
position = [0, 2.0, -3.5]
look_at = [0, 1.5, 3]
up = [0, 1, 0]
fov_y_deg = 50
width = 48
height = 32

[render]
integrator = "path"
caustics = false
max_depth = 64
wavelengths = 1
polarized = true

[materials.floor]
type = "diffuse"
albedo = 0.6

[materials.back]
type = "diffuse"
albedo = 0.5

[materials.left]
type = "diffuse"
albedo = 0.7

[materials.right]
type = "diffuse"
albedo = 0.4

[materials.glass]
type = "dielectric"
ior = 1.5

[materials.mirror]
type = "mirror"

"#;
    let tail = r#"
[[shapes]]
type = "sphere"
center = [1.1, 0.8, 2.5]
radius = 0.8
material = "glass"

[[shapes]]
type = "sphere"
center = [-1.1, 0.8, 3.0]
radius = 0.8
material = "mirror"

[[lights]] # edge1 × edge2 = -y: emits down
type = "quad"
corner = [-0.75, 3.2, 2.9]
edge1 = [1.5, 0, 0]
edge2 = [0, 0, 1.5]
radiance = 8.0
emit = "edge1_cross_edge2"

[[lights]] # on the back wall, facing the camera (edge2 × edge1 = -z)
type = "quad"
corner = [-1, 1.8, 5.95]
edge1 = [2, 0, 0]
edge2 = [0, 1.2, 0]
radiance = 3.0
emit = "edge2_cross_edge1"
"#;
    format!("{head}{}{tail}", adjoint::room_walls(["floor", "back", "back", "left", "right"]))
}

/// Added to [`room_text`]: a polariser (axis at 30° to x) and, on the camera's side of it, a
/// quarter-wave plate (fast axis at −20°), hanging 0.15 and 0.2 in front of the back light, over
/// its left part and the back wall's left side: the diffuse wall and
/// the light seen through them are polarised (linear at 30°, then elliptical: S1–S3 all
/// non-zero), and light from both lights crosses them on its way into the room.
const SHEETS: &str = r#"
[materials.polarizer]
type = "polarizer"
axis = [0.866025, 0.5, 0]

[materials.quarter_wave]
type = "retarder"
fast_axis = [0.939693, -0.342020, 0]
retardance_deg = 90

[[shapes]]
type = "quad"
corner = [0.2, 1.7, 5.8]
edge1 = [2.6, 0, 0]
edge2 = [0, 1.6, 0]
material = "polarizer"

[[shapes]]
type = "quad"
corner = [0.2, 1.7, 5.75]
edge1 = [2.6, 0, 0]
edge2 = [0, 1.6, 0]
material = "quarter_wave"
"#;

/// The wavelength of every render, nm.
const LAMBDA_NM: f32 = 550.0;
/// Camera samples per pixel of each path-tracer render.
const SPP: u32 = 512;
/// Light paths of each light-tracer render, per pixel of the image.
const LIGHT_PATHS_PER_PIXEL: u64 = 1024;
/// Threads for each render (the test's budget is two cores).
const THREADS: usize = 2;

/// [`room_text`], with [`SHEETS`] when `sheets`.
fn room(sheets: bool) -> Scene {
    let text = if sheets { format!("{}{SHEETS}", room_text()) } else { room_text() };
    prisma::scene::parse(&text, std::path::Path::new("adjoint_room.toml")).expect("the room parses")
}

/// S0–S3 of `film` (monochromatic: the radiance, W·m⁻²·sr⁻¹·nm⁻¹), as planes.
fn stokes_planes(film: &Film) -> Planes {
    let data = (0..4)
        .map(|k| film.stokes_srgb(k).expect("a polarised film").iter().map(|v| f64::from(v.y)).collect())
        .collect();
    Planes { width: film.width() as usize, height: film.height() as usize, data }
}

/// The path tracer alone, seed `seed`, `spp` samples per pixel, with `fault`.
fn camera_side(scene: &Scene, seed: u64, spp: u32, fault: Option<Fault>) -> Planes {
    let mut settings = scene.settings.clone();
    assert_eq!(settings.integrator, IntegratorKind::Path);
    assert!(!settings.caustics && settings.polarized);
    settings.spp = spp;
    settings.seed = seed;
    let job = Job { threads: THREADS, monochromatic_nm: Some(LAMBDA_NM), fault, ..Job::new(settings) };
    let (film, _) = render(scene, &job).expect("the path tracer renders");
    stokes_planes(&film)
}

/// The light tracer alone ([`LightTracer::counting_everything`]), `fault` on the light side
/// only, seed `seed`: `paths` light paths over [`THREADS`] threads, divided by `paths`.
fn light_side(scene: &Scene, seed: u64, paths: u64, fault: Option<Fault>) -> Planes {
    stokes_planes(&adjoint::light_side_film::<Stokes>(scene, (LAMBDA_NM, fault), seed, paths, THREADS))
}

/// What `ray` meets first past the polarising sheets (which are no vertex of a path): whether
/// it is a light, and its material; `None` when it escapes.
fn first_vertex(scene: &Scene, mut ray: Ray) -> Option<(bool, &Material)> {
    // A ray crosses each of the two sheets at most once.
    for _ in 0..3 {
        let hit = scene.geometry.intersect(&ray, f32::INFINITY)?;
        let surface = scene.surfaces[hit.prim as usize];
        let material = &scene.materials[surface.material as usize];
        if !matches!(material, Material::Polarizer(_) | Material::Retarder(_)) {
            return Some((surface.emitter.is_some(), material));
        }
        ray = Ray::new(spawn_origin(hit.point, hit.normal, ray.dir), ray.dir);
    }
    None
}

/// Per pixel (row-major), true when `seen` holds for what the camera ray meets first
/// ([`first_vertex`]) over the whole pixel: a 4 × 4 grid of rays.
fn over_each_pixel(scene: &Scene, seen: impl Fn(Option<(bool, &Material)>) -> bool) -> Vec<bool> {
    every_ray_of_each_pixel(scene, |ray| seen(first_vertex(scene, ray)))
}

/// Per pixel (row-major), true when `holds` for every camera ray of a 4 × 4 grid over it.
fn every_ray_of_each_pixel(scene: &Scene, holds: impl Fn(Ray) -> bool) -> Vec<bool> {
    let (w, h) = (scene.camera.width() as usize, scene.camera.height() as usize);
    (0..w * h)
        .map(|i| {
            (0..16).all(|k| {
                let (x, y) = (
                    (i % w) as f32 + (k % 4) as f32 * 0.25 + 0.125,
                    (i / w) as f32 + (k / 4) as f32 * 0.25 + 0.125,
                );
                holds(scene.camera.ray(x, y))
            })
        })
        .collect()
}

/// Per pixel (row-major), true when the camera sees a diffuse surface or a light over the
/// whole pixel and its eight neighbours (the neighbours keep out a pixel whose corner holds a
/// sliver of a sphere the grid of rays missed).
fn diffuse_or_light_seen_directly(scene: &Scene) -> Vec<bool> {
    let (w, h) = (scene.camera.width() as usize, scene.camera.height() as usize);
    let seen = over_each_pixel(scene, |first| {
        first.is_some_and(|(emitter, material)| emitter || matches!(material, Material::Diffuse(_)))
    });
    (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            (y.saturating_sub(1)..(y + 2).min(h))
                .all(|yy| (x.saturating_sub(1)..(x + 2).min(w)).all(|xx| seen[yy * w + xx]))
        })
        .collect()
}

/// Per pixel, true when the camera sees a light over the whole pixel.
fn light_seen(scene: &Scene) -> Vec<bool> {
    over_each_pixel(scene, |first| first.is_some_and(|(emitter, _)| emitter))
}

/// The comparison of the light side (`light`, two seeds) with the camera side (`camera`, two
/// seeds) on `mask`.
fn compare(light: &[Planes; 2], camera: &[Planes; 2], mask: &[bool]) -> Comparison {
    compare_with(
        &light[0],
        &light[1],
        &camera[0],
        &camera[1],
        &Options { mask: Some(mask), reference_variance: None, mean_tolerance: 0.0 },
    )
}

fn report(label: &str, comparison: &Comparison) {
    eprintln!(
        "{label}: outliers {:.4} (null {:.4}), |z| of means {:.2}, mean ratios (light/camera) {:?}, \
         relMSE beyond noise {:.2e}",
        comparison.outlier_fraction,
        comparison.null_outlier_fraction,
        comparison.mean_z,
        comparison.mean_ratio.iter().map(|r| format!("{r:.4}")).collect::<Vec<_>>(),
        comparison.rel_mse_excess,
    );
}

/// Renders `scene` with both sides alone (two seeds each) and compares them on the pixels whose
/// camera ray first meets a diffuse surface or a light: the comparison, and that of the light
/// side traced with `fault` (on the light side only; a quarter of the paths: the faults tried
/// are far beyond the noise) against the same camera side; and the light side's two images and
/// the mask, for further comparisons.
fn both_sides(scene: &Scene, fault: Fault) -> (Comparison, Comparison, [Planes; 2], Vec<bool>) {
    let mask = diffuse_or_light_seen_directly(scene);
    let compared = mask.iter().filter(|&&m| m).count();
    let lit = light_seen(scene).iter().zip(&mask).filter(|(l, m)| **l && **m).count();
    eprintln!("{compared} of {} pixels compared, {lit} of them on a light", mask.len());
    // Most of the image is diffuse, the spheres take a tenth or more, and a light is seen.
    assert!(compared > mask.len() / 2, "{compared}");
    assert!(compared < mask.len() * 9 / 10, "{compared}: the spheres must be seen");
    assert!(lit >= 8, "{lit}: a light must be seen directly");

    let camera = [camera_side(scene, 1, SPP, None), camera_side(scene, 2, SPP, None)];
    let paths = LIGHT_PATHS_PER_PIXEL * mask.len() as u64;
    let light = [light_side(scene, 11, paths, None), light_side(scene, 12, paths, None)];
    let comparison = compare(&light, &camera, &mask);
    report("light alone vs camera alone", &comparison);
    let faulty =
        [light_side(scene, 13, paths / 4, Some(fault)), light_side(scene, 14, paths / 4, Some(fault))];
    let faulty = compare(&faulty, &camera, &mask);
    report(&format!("{fault:?} on the light side"), &faulty);
    (comparison, faulty, light, mask)
}

/// The two sides agree on the pixels whose camera ray first meets a diffuse surface or the back
/// light, S0–S3 (S1–S3 are zero there on both: a diffuse vertex depolarises, and the lights are
/// unpolarised); the light side with the cosine at the receiver dropped
/// (`Fault::NoReceiverCosine`: every diffuse connection too bright by 1/cos θ) does not, nor
/// does the camera side with multiple-importance weights that add up to two
/// (`Fault::MisWeightsUnnormalized`: direct light from the quads counted twice; a quarter of the
/// samples) against the correct light side.
#[test]
fn the_light_tracer_alone_and_the_path_tracer_alone_agree() {
    let scene = room(false);
    let (comparison, faulty, light, mask) = both_sides(&scene, Fault::NoReceiverCosine);
    assert!(passes(&comparison));
    assert!(!passes(&faulty));

    let fault = Some(Fault::MisWeightsUnnormalized);
    let faulty_camera = [camera_side(&scene, 3, SPP / 4, fault), camera_side(&scene, 4, SPP / 4, fault)];
    let faulty = compare(&light, &faulty_camera, &mask);
    report("MisWeightsUnnormalized on the camera side", &faulty);
    assert!(!passes(&faulty));
}

/// As [`the_light_tracer_alone_and_the_path_tracer_alone_agree`] with polarising sheets in the
/// room ([`SHEETS`]): S1–S3 are non-zero on the pixels seen through them, where the light side's
/// connection to the camera and the camera side's ray cross the same sheets in opposite
/// directions. A Stokes frame rotation built transposed on the light side alone
/// (`Fault::TransposedRotation`) turns the polarisation the wrong way there and fails.
///
/// This test found a bug: the path tracer weighed a quad light met through a sheet with the last
/// segment's distance (sheet to light) where the distance from the diffuse vertex is right, so
/// its multiple-importance weights added to more than one and the camera side came out 2.6 %
/// brighter than the light side (light/camera 0.974 in S0, |z| of the means 17.4; fixed: 0.9970
/// and |z| 2.00).
#[test]
fn the_two_sides_agree_through_polarising_sheets() {
    let scene = room(true);
    let (comparison, faulty, ..) = both_sides(&scene, Fault::TransposedRotation);
    // The sheets polarise what the camera sees through them.
    let ratios = &comparison.mean_ratio;
    assert!(ratios.iter().all(|r| r.is_finite()), "S1–S3 must be non-zero: {ratios:?}");
    assert!(passes(&comparison));
    assert!(!passes(&faulty));
}

/// A coarse sphere (6 segments around, 4 rings) as an OBJ with the true sphere's normals at its
/// vertices: over each flat triangle the interpolated shading normal tilts up to about 30° off
/// the geometric one.
fn coarse_sphere_obj() -> String {
    let (segments, rings) = (6, 4);
    let mut obj = String::new();
    let mut vertex = |theta: f64, phi: f64| {
        let p = [theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin()];
        obj.push_str(&format!("v {} {} {}\nvn {} {} {}\n", p[0], p[1], p[2], p[0], p[1], p[2]));
    };
    vertex(0.0, 0.0);
    for ring in 1..rings {
        for segment in 0..segments {
            let theta = std::f64::consts::PI * ring as f64 / rings as f64;
            vertex(theta, std::f64::consts::TAU * segment as f64 / segments as f64);
        }
    }
    vertex(std::f64::consts::PI, 0.0);
    // 1-based: the north pole 1, ring r's segment s at 2 + (r − 1)·segments + s, the south pole last.
    let at = |ring: usize, segment: usize| 2 + (ring - 1) * segments + segment % segments;
    let south = 2 + (rings - 1) * segments;
    let mut faces = String::new();
    for s in 0..segments {
        faces.push_str(&format!("f 1//1 {a}//{a} {b}//{b}\n", a = at(1, s + 1), b = at(1, s)));
        for ring in 1..rings - 1 {
            let (a, b, c, d) = (at(ring, s), at(ring, s + 1), at(ring + 1, s + 1), at(ring + 1, s));
            faces.push_str(&format!("f {a}//{a} {b}//{b} {c}//{c}\nf {a}//{a} {c}//{c} {d}//{d}\n"));
        }
        faces.push_str(&format!(
            "f {south}//{south} {a}//{a} {b}//{b}\n",
            a = at(rings - 1, s),
            b = at(rings - 1, s + 1)
        ));
    }
    obj + &faces
}

/// Where [`coarse_sphere_obj`] stands in [`room_text`] (scaled by [`MESH_RADIUS`]).
const MESH_CENTRE: [f32; 3] = [0.0, 0.8, 0.6];
/// Its radius.
const MESH_RADIUS: f32 = 0.8;

/// Per pixel, true when every ray of a 4 × 4 grid over the pixel first meets the smooth-shaded
/// mesh (a point within its bounding sphere; the room's other shapes are farther away).
fn mesh_seen(scene: &Scene) -> Vec<bool> {
    let centre = glam::Vec3::from(MESH_CENTRE);
    every_ray_of_each_pixel(scene, |ray| {
        scene
            .geometry
            .intersect(&ray, f32::INFINITY)
            .is_some_and(|hit| (hit.point - centre).length() < MESH_RADIUS * 1.01)
    })
}

/// Shading normals (Veach's thesis §5.3): [`room_text`] with a coarse diffuse sphere whose vertex
/// normals are smooth (an OBJ with `vn`) in front of the spheres. On the pixels that see it,
/// the light side, which carries the adjoint of the shading normal's BSDF, agrees with the
/// camera side, and so does the whole image; the light side shading the mesh as the camera
/// side does (`Fault::NoShadingNormalAdjoint`, what prisma did before) does not.
#[test]
fn the_two_sides_agree_on_a_smooth_shaded_mesh() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    std::fs::write(dir.path().join("coarse_sphere.obj"), coarse_sphere_obj()).expect("the mesh is written");
    let mesh = format!(
        "\n[materials.coarse]\ntype = \"diffuse\"\nalbedo = 0.8\n\n[[shapes]]\ntype = \"mesh\"\n\
         file = \"coarse_sphere.obj\"\nscale = {MESH_RADIUS}\nposition = {MESH_CENTRE:?}\nmaterial = \"coarse\"\n"
    );
    let text = format!("{}{mesh}", room_text());
    let scene = prisma::scene::parse(&text, &dir.path().join("adjoint_mesh.toml")).expect("the room parses");
    let on_mesh = mesh_seen(&scene);
    let mesh_pixels = on_mesh.iter().filter(|&&m| m).count();
    eprintln!("{mesh_pixels} pixels see the mesh");
    assert!(mesh_pixels >= 40, "{mesh_pixels}: the mesh must fill part of the image");

    let mask = diffuse_or_light_seen_directly(&scene);
    let camera = [camera_side(&scene, 1, SPP, None), camera_side(&scene, 2, SPP, None)];
    let paths = LIGHT_PATHS_PER_PIXEL * mask.len() as u64;
    let light = [light_side(&scene, 11, paths, None), light_side(&scene, 12, paths, None)];
    let comparison = compare(&light, &camera, &mask);
    report("light alone vs camera alone", &comparison);
    assert!(passes(&comparison));
    let on_mesh_and_diffuse: Vec<bool> = on_mesh.iter().zip(&mask).map(|(a, b)| *a && *b).collect();
    let comparison = compare(&light, &camera, &on_mesh_and_diffuse);
    report("on the mesh: light alone vs camera alone", &comparison);
    assert!(passes(&comparison));

    let fault = Some(Fault::NoShadingNormalAdjoint);
    let faulty = [light_side(&scene, 13, paths, fault), light_side(&scene, 14, paths, fault)];
    let faulty = compare(&faulty, &camera, &on_mesh_and_diffuse);
    report("on the mesh: NoShadingNormalAdjoint on the light side", &faulty);
    assert!(!passes(&faulty));
}

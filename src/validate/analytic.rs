//! Validation cases with analytic answers (no Mitsuba): white furnaces, a plane-parallel slab,
//! minimum deviation of a prism, and Snell's window. Each builds its scene in code, renders it with
//! prisma, and compares with a closed-form value computed here, independently of prisma's optics
//! code (textbook formulas in f64).

use std::path::Path;

use super::textbook::{reference_reflectance, reference_reflectances};
use super::{CaseResult, Check, Kind, ValidateError};
use crate::integrator::Fault;
use crate::optics::catalogue;
use crate::render::{render, Job};
use crate::scene::{parse, Scene};

/// Names of the analytic cases, in the order [`run`] runs them: the radiometric cases of this
/// module, the polarisation cases of [`super::polarization`], the caustic cases of
/// [`super::caustics`], the closed forms of full transport of [`super::furnace`], then the
/// soap-film colour of [`super::film`].
pub const CASES: [&str; 24] = [
    "lambert_point_light",
    "furnace_glass",
    "furnace_dispersive_glass",
    "furnace_mirror",
    "slab_transmittance",
    "prism_minimum_deviation",
    "snell_window",
    "one_reflection",
    "camera_roll",
    "skew_reflections",
    "tir_retardance",
    "conductor_pair",
    "polarizer_chain",
    "coated_reflection",
    "newton_lines",
    "prism_band_edges",
    "ball_lens_focus",
    "caustic_power",
    "closed_sphere_point_light",
    "closed_sphere_point_light_whitted",
    "emitting_box",
    "emitting_box_whitted",
    "sphere_under_sky",
    "soap_film_colour",
];

/// What the analytic case `name` is compared with: the electric-field tracer for the
/// polarisation cases, a closed-form answer for the others.
pub fn kind(name: &str) -> Kind {
    if super::polarization::CASES.contains(&name) {
        Kind::FieldTracer
    } else {
        Kind::Analytic
    }
}

/// Runs the analytic case `name` with `threads` threads and an optional injected `fault`.
pub fn run(name: &str, threads: usize, fault: Option<Fault>) -> Result<CaseResult, ValidateError> {
    let ctx = Context { threads, fault };
    match name {
        "furnace_glass" => ctx.furnace(name, "type = \"dielectric\"\nior = 1.5"),
        "furnace_dispersive_glass" => {
            ctx.furnace(name, "type = \"dielectric\"\nior = { glass = \"N-SF11\" }")
        }
        "furnace_mirror" => ctx.furnace(name, "type = \"mirror\"\nreflectance = 1"),
        "lambert_point_light" => ctx.lambert(name),
        "slab_transmittance" => ctx.slab(name),
        "prism_minimum_deviation" => ctx.prism(name),
        "snell_window" => ctx.snell_window(name),
        name if super::polarization::CASES.contains(&name) => super::polarization::run(name, threads, fault),
        name if super::caustics::CASES.contains(&name) => super::caustics::run(name, threads, fault),
        name if super::furnace::CASES.contains(&name) => super::furnace::run(name, threads, fault),
        name if super::film::CASES.contains(&name) => super::film::run(name, threads, fault),
        _ => Err(ValidateError::Input(format!(
            "unknown analytic case \"{name}\"; known: {}",
            CASES.join(", ")
        ))),
    }
}

/// The white-furnace check for an object of any `material` (a TOML material body such as
/// `type = "dielectric"\nior = 1.5`): passes only if the object is invisible.
pub fn furnace(material: &str, threads: usize) -> Result<CaseResult, ValidateError> {
    Context { threads, fault: None }.furnace("furnace", material)
}

struct Context {
    threads: usize,
    fault: Option<Fault>,
}

impl Context {
    fn render(&self, scene: &Scene, wavelength_nm: Option<f32>) -> Result<crate::film::Film, ValidateError> {
        let job = Job {
            threads: self.threads,
            monochromatic_nm: wavelength_nm,
            fault: self.fault,
            ..Job::new(scene.settings.clone())
        };
        Ok(render(scene, &job)?.0)
    }

    fn scene(&self, text: &str, name: &str) -> Result<Scene, ValidateError> {
        parse(text, Path::new(&format!("<{name}>"))).map_err(|e| ValidateError::Input(e.to_string()))
    }

    /// A Lambertian plane (albedo ρ) under a point light of intensity I at height h: the radiance
    /// leaving the point at horizontal distance r is ρ/π · I·cos θ/d², d² = h² + r², cos θ = h/d.
    fn lambert(&self, name: &str) -> Result<CaseResult, ValidateError> {
        let (albedo, intensity, light_height, size) = (0.5f64, 3.0f64, 2.0f64, 32u32);
        let (camera_height, fov_deg) = (4.0f64, 60.0f64);
        let text = format!(
            "[camera]\nposition = [0, {camera_height}, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, 1]\nfov_y_deg = {fov_deg}\n\
             width = {size}\nheight = {size}\n[render]\nspp = 1024\n\
             [materials.paper]\ntype = \"diffuse\"\nalbedo = {albedo}\n\
             [[shapes]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\nmaterial = \"paper\"\n\
             [[lights]]\ntype = \"point\"\nposition = [0, {light_height}, 0]\nintensity = {intensity}\n"
        );
        let film = self.render(&self.scene(&text, name)?, Some(550.0))?;
        let tan_half = (fov_deg.to_radians() / 2.0).tan();
        let mut worst = 0.0f64;
        // The radiance at a film position (x, y) in pixels: the camera looks straight down, so its
        // ray meets the plane at horizontal offsets proportional to the image-plane coordinates.
        let radiance = |x: f64, y: f64| {
            let u = (2.0 * x / f64::from(size) - 1.0) * tan_half * camera_height;
            let v = (1.0 - 2.0 * y / f64::from(size)) * tan_half * camera_height;
            let d2 = light_height * light_height + u * u + v * v;
            albedo / std::f64::consts::PI * intensity * (light_height / d2.sqrt()) / d2
        };
        for (i, p) in film.xyz().iter().enumerate() {
            let (x0, y0) = ((i % size as usize) as f64, (i / size as usize) as f64);
            // The box-filtered pixel value: the mean over the pixel (16 × 16 midpoint rule).
            let n = 16;
            let expected = (0..n * n)
                .map(|k| {
                    radiance(x0 + ((k % n) as f64 + 0.5) / n as f64, y0 + ((k / n) as f64 + 0.5) / n as f64)
                })
                .sum::<f64>()
                / (n * n) as f64;
            worst = worst.max((f64::from(p.y) / expected - 1.0).abs());
        }
        Ok(CaseResult {
            name: name.into(),
            checks: vec![Check { metric: "max relative error".into(), value: worst, threshold: 5e-3 }],
            why: "a Lambertian plane under a point light: ρ/π · I·cos θ / d² (units of intensity and albedo)"
                .into(),
        })
    }

    /// A lossless object inside a uniform background renders exactly as the background. A depth
    /// cap of 400 bounces: at most ≈ 1/(e·401) ≈ 9·10⁻⁴ of a ray entering near grazing
    /// incidence is lost. Pruning off: Russian roulette is unbiased but its noise is not small
    /// here (a pruned branch returns 10⁻⁴·L or nothing, and near grazing entry a ray spawns
    /// hundreds of weak internal reflections: 2·10⁻³ per pixel at 4 spp). The scene file asks for
    /// pruning at 10⁻⁴, the weakest the loader accepts at this depth (an arbitrary scene's ray tree
    /// grows as 2^depth without it); the case turns it off after loading, which is safe for one
    /// convex object: every interaction spawns at most one branch that stays inside, so a sample
    /// costs at most 2·400 rays.
    fn furnace(&self, name: &str, material: &str) -> Result<CaseResult, ValidateError> {
        let text = format!(
            "background = {{ rgb = [0.8, 0.6, 0.4] }}\n[camera]\nposition = [0, 0, -4]\nlook_at = [0, 0, 0]\n\
             fov_y_deg = 40\nwidth = 48\nheight = 48\n[render]\nspp = 4\nmax_depth = 400\nprune_below = 1e-4\nseed = 11\n\
             [materials.object]\n{material}\n[[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"object\"\n"
        );
        let mut scene = self.scene(&text, name)?;
        scene.settings.prune_below = 0.0;
        let mut empty = scene.clone();
        empty.geometry = crate::geometry::Geometry::build(Vec::new(), Vec::new());
        empty.surfaces.clear();
        let (with, without) = (self.render(&scene, None)?, self.render(&empty, None)?);
        let (mut diff_sum, mut max_diff) = (0.0f64, 0.0f64);
        for (a, b) in with.linear_srgb().iter().zip(without.linear_srgb()) {
            for c in 0..3 {
                let d = f64::from(a[c]) - f64::from(b[c]);
                diff_sum += d;
                max_diff = max_diff.max(d.abs());
            }
        }
        let mean_diff = (diff_sum / (with.xyz().len() * 3) as f64).abs();
        Ok(CaseResult {
            name: name.into(),
            checks: vec![
                Check { metric: "|mean difference|".into(), value: mean_diff, threshold: 1e-4 },
                Check { metric: "max pixel difference".into(), value: max_diff, threshold: 1e-3 },
            ],
            why: format!(
                "white furnace: a lossless object ({}) inside a uniform background is invisible",
                material.replace('\n', ", ")
            ),
        })
    }

    /// A plane-parallel slab before a uniform emitter, on black: the radiance seen through it at
    /// incidence θ is L·½[(1 − R_s)/(1 + R_s) + (1 − R_p)/(1 + R_p)], each polarisation summing
    /// its own series (1 − R)²·Σ R²ᵏ of internal reflections: s and p never mix, since both faces
    /// share the plane of incidence, and unpolarised light is half of each. (The per-interface
    /// average R = (R_s + R_p)/2 in (1 − R)/(1 + R) is 0.5 % low at 50° for n = 1.5 and more for
    /// denser glass and at grazing angles: polarisation off must fail this case.) Checked from
    /// normal to near-grazing incidence for a constant index, N-BK7 and N-SF11 at several
    /// wavelengths.
    fn slab(&self, name: &str) -> Result<CaseResult, ValidateError> {
        let mut worst = 0.0f64;
        let glass = |name: &str| {
            catalogue::glass(name)
                .ok_or_else(|| ValidateError::Input(format!("{name} missing from the catalogue")))
        };
        let (bk7, sf11) = (glass("N-BK7")?, glass("N-SF11")?);
        for (ior_text, lambda_nm, n) in [
            ("1.5".to_owned(), 550.0f32, 1.5f64),
            ("{ glass = \"N-BK7\" }".to_owned(), 450.0, f64::from(bk7.ior().eval(450.0))),
            ("{ glass = \"N-BK7\" }".to_owned(), 650.0, f64::from(bk7.ior().eval(650.0))),
            ("{ glass = \"N-SF11\" }".to_owned(), 450.0, f64::from(sf11.ior().eval(450.0))),
            ("{ glass = \"N-SF11\" }".to_owned(), 650.0, f64::from(sf11.ior().eval(650.0))),
        ] {
            for theta_deg in [0.0f64, 30.0, 50.0, 60.0, 75.0, 85.0] {
                let (s, c) = theta_deg.to_radians().sin_cos();
                let text = format!(
                    "[camera]\nposition = [{px}, 0, {pz}]\nlook_at = [0, 0, 0.5]\nfov_y_deg = 0.2\nwidth = 8\nheight = 8\n\
                     [render]\nspp = 4\nmax_depth = 20\nprune_below = 0\n\
                     [materials.glass]\ntype = \"dielectric\"\nior = {ior_text}\n\
                     [[shapes]]\ntype = \"quad\"\ncorner = [-1000, -1000, 0]\nedge1 = [0, 2000, 0]\nedge2 = [2000, 0, 0]\nmaterial = \"glass\"\n\
                     [[shapes]]\ntype = \"quad\"\ncorner = [-1000, -1000, 1]\nedge1 = [2000, 0, 0]\nedge2 = [0, 2000, 0]\nmaterial = \"glass\"\n\
                     [[lights]]\ntype = \"quad\"\ncorner = [-5000, -5000, 60]\nedge1 = [10000, 0, 0]\nedge2 = [0, 10000, 0]\nradiance = 2.0\nemit = \"edge2_cross_edge1\"\n",
                    px = -10.0 * s,
                    pz = 0.5 - 10.0 * c,
                );
                // 64 bounces (R_s^64 < 10⁻⁸ even at 85° in N-SF11; 20, the deepest the loader
                // accepts without pruning, leaves 2.5·10⁻³ there): safe for a slab, whose ray tree is
                // a chain (every internal reflection spawns one refraction that leaves).
                let mut scene = self.scene(&text, name)?;
                scene.settings.max_depth = 64;
                let film = self.render(&scene, Some(lambda_nm))?;
                let seen = film.xyz().iter().map(|p| f64::from(p.y)).sum::<f64>() / film.xyz().len() as f64;
                let (r_s, r_p) = reference_reflectances(c, 1.0, n);
                let expected = 2.0 * 0.5 * ((1.0 - r_s) / (1.0 + r_s) + (1.0 - r_p) / (1.0 + r_p));
                worst = worst.max((seen / expected - 1.0).abs());
            }
        }
        Ok(CaseResult {
            name: name.into(),
            checks: vec![Check { metric: "max relative error".into(), value: worst, threshold: 1e-4 }],
            why: "slab transmittance ½[(1 − R_s)/(1 + R_s) + (1 − R_p)/(1 + R_p)] at 0°–85° (n = 1.5; N-BK7, N-SF11 at 450 and 650 nm)"
                .into(),
        })
    }

    /// A 60° prism of N-SF11 turned to minimum deviation for wavelength λ, viewed through its faces:
    /// a thin line light placed 10⁴ units away along the direction deviated by
    /// D = 2·asin(n(λ)·sin(A/2)) − A must appear at the centre row of the image. Measures the
    /// angle between the line's image (brightness centroid) and the image centre.
    fn prism(&self, name: &str) -> Result<CaseResult, ValidateError> {
        let apex_deg = 60.0f64;
        let sf11 = catalogue::glass("N-SF11").ok_or_else(|| ValidateError::Input("N-SF11 missing".into()))?;
        let (fov_deg, height) = (2.0f64, 200u32);
        let mut worst = 0.0f64;
        for lambda_nm in [450.0f32, 550.0, 650.0] {
            let n = f64::from(sf11.ior().eval(lambda_nm));
            let half_apex = (apex_deg / 2.0).to_radians();
            let theta_1 = (n * half_apex.sin()).asin();
            let deviation = 2.0 * theta_1 - apex_deg.to_radians();
            // Turn the prism about its axis (z) so that the camera ray (+x) meets the first face at
            // θ₁ and crosses the prism parallel to its base.
            let turn = -(theta_1 - half_apex);
            let turn_deg = turn.to_degrees();
            // Shift the prism so that the camera ray enters the middle of its first face (local
            // centroid at the origin: apex at 2H/3, base at −H/3, H = s·cos(A/2), half-base
            // s·sin(A/2); the first face's midpoint is (−s·sin(A/2)/2, H/6) before the turn).
            let side = 3.0f64;
            let height_h = side * half_apex.cos();
            let (mx, my) = (-0.5 * side * half_apex.sin(), height_h / 6.0);
            let shift_y = -(mx * turn.sin() + my * turn.cos());
            let (sd, cd) = deviation.sin_cos();
            let distance = 1.0e4;
            let thickness = 2.0; // 2·10⁻⁴ rad, a tenth of a pixel
            let centre = [distance * cd, -distance * sd];
            let across = [sd * thickness, cd * thickness];
            let text = format!(
                "[camera]\nposition = [-6, 0, 0]\nlook_at = [0, 0, 0]\nfov_y_deg = {fov_deg}\nwidth = 8\nheight = {height}\n\
                 [render]\nspp = 16\nmax_depth = 8\nprune_below = 0\n\
                 [materials.flint]\ntype = \"dielectric\"\nior = {{ glass = \"N-SF11\" }}\n\
                 [[shapes]]\ntype = \"prism\"\napex_angle_deg = {apex_deg}\nside_length = {side}\nlength = 4\nrotate_deg = [0, 0, {turn_deg}]\nposition = [0, {shift_y}, 0]\nmaterial = \"flint\"\n\
                 [[lights]]\ntype = \"quad\"\ncorner = [{cx}, {cy}, -3000]\nedge1 = [0, 0, 6000]\nedge2 = [{ax}, {ay}, 0]\nradiance = 1.0\nemit = \"edge1_cross_edge2\"\n",
                cx = centre[0] - 0.5 * across[0],
                cy = centre[1] - 0.5 * across[1],
                ax = across[0],
                ay = across[1],
            );
            let scene = self.scene(&text, name)?;
            let film = self.render(&scene, Some(lambda_nm))?;
            let width = film.width() as usize;
            let (mut weight, mut moment) = (0.0f64, 0.0f64);
            for (i, p) in film.xyz().iter().enumerate() {
                let row = (i / width) as f64 + 0.5;
                weight += f64::from(p.y);
                moment += f64::from(p.y) * row;
            }
            // The line must be in view: it spans thickness/distance radians, (thickness/distance)
            // / (fov/height) ≈ 1.1 rows, so a render that shows it sums to about width · 1.1 ·
            // T in radiance units, T ≈ 0.8 the prism's transmittance. Secondary paths (internal
            // reflections, reflections off the faces) put about 0.1 in view when the line itself
            // is not, so the line counts as seen above a quarter of the unit-transmittance sum.
            let rows_covered = (thickness / distance) / (fov_deg.to_radians() / f64::from(height));
            let angle_deg = if weight > 0.25 * width as f64 * rows_covered {
                let ndc = 1.0 - 2.0 * (moment / weight) / f64::from(height);
                (ndc * (fov_deg.to_radians() / 2.0).tan()).atan().to_degrees()
            } else {
                f64::INFINITY // the line is not in view at all
            };
            worst = worst.max(angle_deg.abs());
        }
        Ok(CaseResult {
            name: name.into(),
            checks: vec![Check {
                metric: "max |image offset| (degrees)".into(),
                value: worst,
                threshold: 0.01,
            }],
            why: "minimum deviation D = 2·asin(n·sin(A/2)) − A of a 60° N-SF11 prism at 450, 550, 650 nm"
                .into(),
        })
    }

    /// Looking up from under a flat water surface (n = 1.333) at a uniform sky of radiance L: the
    /// sky fills the cone θ < θc = asin(1/n) with radiance (1 − R(θ))·n²·L (radiance gains n²
    /// entering the denser medium), and beyond θc total internal reflection shows the black depths.
    fn snell_window(&self, name: &str) -> Result<CaseResult, ValidateError> {
        let n = 1.333f64;
        let (size, fov_deg) = (64u32, 120.0f64);
        let text = format!(
            "[camera]\nposition = [0, -1, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, 1]\nfov_y_deg = {fov_deg}\nwidth = {size}\nheight = {size}\n\
             [render]\nspp = 64\nmax_depth = 8\nprune_below = 0\n\
             [materials.water]\ntype = \"dielectric\"\nior = {n}\n\
             [[shapes]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\nmaterial = \"water\"\n\
             [[lights]]\ntype = \"quad\"\ncorner = [-1e4, 20, -1e4]\nedge1 = [2e4, 0, 0]\nedge2 = [0, 0, 2e4]\nradiance = 1.0\nemit = \"edge1_cross_edge2\"\n"
        );
        let film = self.render(&self.scene(&text, name)?, Some(550.0))?;
        let critical = (1.0 / n).asin();
        let tan_half = (fov_deg.to_radians() / 2.0).tan();
        let pixel_angle = 2.0 * tan_half / f64::from(size); // upper bound of a pixel's angular size
        let (mut worst, mut checked) = (0.0f64, 0usize);
        for (i, p) in film.xyz().iter().enumerate() {
            let (x, y) = ((i % size as usize) as f64 + 0.5, (i / size as usize) as f64 + 0.5);
            let u = (2.0 * x / f64::from(size) - 1.0) * tan_half;
            let v = (1.0 - 2.0 * y / f64::from(size)) * tan_half;
            let theta = (u * u + v * v).sqrt().atan(); // angle from the vertical
            if (theta - critical).abs() < 2.0 * pixel_angle {
                continue; // the window's edge crosses this pixel
            }
            let expected = if theta < critical {
                (1.0 - reference_reflectance(theta.cos(), n, 1.0)) * n * n
            } else {
                0.0
            };
            // The pixel average of a smooth function differs from its centre value by a
            // curvature term: the error is relative to the expected value plus a small floor.
            let error = (f64::from(p.y) - expected).abs() / (expected + 0.05);
            worst = worst.max(error);
            checked += 1;
        }
        if checked == 0 {
            return Err(ValidateError::Input("snell_window: no pixel checked".into()));
        }
        Ok(CaseResult {
            name: name.into(),
            checks: vec![Check { metric: "max relative error".into(), value: worst, threshold: 5e-3 }],
            why: "Snell's window under water (n = 1.333): (1 − R)·n²·L inside θc = 48.6°, black beyond"
                .into(),
        })
    }
}

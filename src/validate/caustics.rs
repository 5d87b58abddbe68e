//! Analytic validation of the light tracer (caustics): the spectral lines a prism casts on a
//! screen, the focus of a ball lens, and the conservation of a point light's power through
//! glass. Each builds its scene in code, renders it with prisma (Whitted plus the light tracer),
//! and compares with answers computed here in f64 from textbook optics (vector Snell's law,
//! the ball lens's paraxial focal length), independently of prisma's optics and camera code.

use std::path::Path;

use super::textbook::reference_reflectances;
use super::{CaseResult, Check, ValidateError};
use crate::film::{Film, SpectralBands};
use crate::integrator::Fault;
use crate::optics::catalogue;
use crate::render::{render, Job};
use crate::scene::{parse, Scene};

/// Names of the caustic cases, in the order [`run`] runs them.
pub const CASES: [&str; 4] = ["newton_lines", "prism_band_edges", "ball_lens_focus", "caustic_power"];

/// Runs the caustic case `name` with `threads` threads and an optional injected `fault`.
pub fn run(name: &str, threads: usize, fault: Option<Fault>) -> Result<CaseResult, ValidateError> {
    let ctx = Context { threads, fault };
    match name {
        "newton_lines" => ctx.newton_lines(name),
        "prism_band_edges" => ctx.band_edges(name),
        "ball_lens_focus" => ctx.ball_lens(name),
        "caustic_power" => ctx.power(name),
        _ => {
            Err(ValidateError::Input(format!("unknown caustic case \"{name}\"; known: {}", CASES.join(", "))))
        }
    }
}

type V3 = [f64; 3];

fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn scale(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V3, b: V3) -> V3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}
fn normalize(a: V3) -> V3 {
    scale(a, 1.0 / dot(a, a).sqrt())
}

/// Snell's law in vector form (Hecht §4.4): the unit direction refracted from unit `dir` at a
/// surface of unit normal `normal` (either side) into relative index `eta` = n_t/n_i; `None`
/// under total internal reflection.
fn refract(dir: V3, normal: V3, eta: f64) -> Option<V3> {
    let normal = if dot(dir, normal) > 0.0 { scale(normal, -1.0) } else { normal };
    let cos_i = -dot(dir, normal);
    let sin_t_sq = (1.0 - cos_i * cos_i) / (eta * eta);
    if sin_t_sq >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin_t_sq).sqrt();
    Some(normalize(add(scale(dir, 1.0 / eta), scale(normal, cos_i / eta - cos_t))))
}

/// Where the ray `origin + t·dir` meets the plane through `point` with normal `normal`.
fn hit_plane(origin: V3, dir: V3, point: V3, normal: V3) -> V3 {
    let t = dot(sub(point, origin), normal) / dot(dir, normal);
    add(origin, scale(dir, t))
}

/// A pinhole camera as the scene file defines it (Mitsuba's handedness: +x of a camera looking
/// down +z is the image's left), for projecting points to continuous pixel coordinates.
struct Pinhole {
    position: V3,
    forward: V3,
    right: V3,
    up: V3,
    tan_half: f64,
    width: f64,
    height: f64,
}

impl Pinhole {
    fn new(position: V3, look_at: V3, up: V3, fov_y_deg: f64, width: u32, height: u32) -> Self {
        let forward = normalize(sub(look_at, position));
        let left = normalize(cross(up, forward));
        Self {
            position,
            forward,
            right: scale(left, -1.0),
            up: cross(forward, left),
            tan_half: (fov_y_deg.to_radians() / 2.0).tan(),
            width: f64::from(width),
            height: f64::from(height),
        }
    }

    /// Continuous film coordinates (x right, y down, in pixels) of `point`.
    fn project(&self, point: V3) -> (f64, f64) {
        let v = sub(point, self.position);
        let depth = dot(v, self.forward);
        let aspect = self.width / self.height;
        let ndc_x = dot(v, self.right) / depth / (self.tan_half * aspect);
        let ndc_y = dot(v, self.up) / depth / self.tan_half;
        ((ndc_x + 1.0) * 0.5 * self.width, (1.0 - ndc_y) * 0.5 * self.height)
    }
}

/// The equilateral N-SF11 prism of the prism cases: the built-in prism (side 1.2, length 0.8)
/// turned 90° about x, so that its cross-section in the xz-plane has the apex at z = 2H/3 and
/// the base at z = −H/3, with a beam at minimum deviation for index `n_min` aimed at the middle
/// of its left face.
struct MinimumDeviationPrism {
    apex: V3,
    /// Outward unit normals of the entry (left) and exit (right) faces.
    entry_normal: V3,
    exit_normal: V3,
    /// The beam's unit direction, in the xz-plane.
    beam_dir: V3,
    /// The middle of the entry face, where the beam's central ray enters.
    entry: V3,
    /// Across the beam, in the xz-plane (unit).
    across_beam: V3,
}

impl MinimumDeviationPrism {
    const SIDE: f64 = 1.2;
    const LENGTH: f64 = 0.8;

    fn new(n_min: f64) -> Self {
        let apex_angle = 60f64.to_radians();
        let height = Self::SIDE * (apex_angle / 2.0).cos();
        let (apex, left, right) = (
            [0.0, 0.0, 2.0 * height / 3.0],
            [-Self::SIDE / 2.0, 0.0, -height / 3.0],
            [Self::SIDE / 2.0, 0.0, -height / 3.0],
        );
        let face_normal = |a: V3, b: V3, outward_hint: V3| {
            let n = normalize(cross(sub(b, a), [0.0, 1.0, 0.0]));
            if dot(n, outward_hint) < 0.0 {
                scale(n, -1.0)
            } else {
                n
            }
        };
        let deviation = 2.0 * (n_min * (apex_angle / 2.0).sin()).asin() - apex_angle;
        let elevation = (deviation + apex_angle) / 2.0 - apex_angle / 2.0;
        Self {
            apex,
            entry_normal: face_normal(left, apex, [-1.0, 0.0, 0.5]),
            exit_normal: face_normal(apex, right, [1.0, 0.0, 0.5]),
            beam_dir: [elevation.cos(), 0.0, elevation.sin()],
            entry: [-Self::SIDE / 4.0, 0.0, height / 6.0],
            across_beam: [-elevation.sin(), 0.0, elevation.cos()],
        }
    }

    /// The beam ray that enters the prism at `entry` (on the entry face) with index `n`: where
    /// it leaves the exit face and its direction then (vector Snell at both faces).
    fn trace_from(&self, entry: V3, n: f64) -> Option<(V3, V3)> {
        let inside = refract(self.beam_dir, self.entry_normal, n)?;
        let exit = hit_plane(entry, inside, self.apex, self.exit_normal);
        Some((exit, refract(inside, self.exit_normal, 1.0 / n)?))
    }

    /// Where the beam ray starting at `origin` meets the entry face's plane.
    fn entry_of(&self, origin: V3) -> V3 {
        hit_plane(origin, self.beam_dir, self.apex, self.entry_normal)
    }

    /// A scene file of this prism in flint, a white (ρ = 0.8) screen quad at `screen_corner`
    /// with edges `screen_across` and (0, `screen_height`, 0), and a beam light of irradiance 10
    /// from `beam_corner` with edges `beam_across` and (0, `beam_height`, 0), emitting along
    /// edge2 × edge1; `camera` and `render` are the bodies of those tables.
    #[allow(clippy::too_many_arguments)] // a scene's numbers, passed flat
    fn scene_text(
        &self,
        camera: &str,
        render: &str,
        screen_corner: V3,
        screen_across: V3,
        screen_height: f64,
        beam_corner: V3,
        beam_across: V3,
        beam_height: f64,
    ) -> String {
        format!(
            "[camera]\n{camera}[render]\n{render}\
             [materials.flint]\ntype = \"dielectric\"\nior = {{ glass = \"N-SF11\" }}\n\
             [materials.white]\ntype = \"diffuse\"\nalbedo = 0.8\n\
             [[shapes]]\ntype = \"prism\"\napex_angle_deg = 60\nside_length = {side}\nlength = {length}\nrotate_deg = [90, 0, 0]\nmaterial = \"flint\"\n\
             [[shapes]]\ntype = \"quad\"\ncorner = {sc}\nedge1 = {se1}\nedge2 = [0, {screen_height}, 0]\nmaterial = \"white\"\n\
             [[lights]]\ntype = \"beam\"\ncorner = {bc}\nedge1 = {be1}\nedge2 = [0, {beam_height}, 0]\nirradiance = 10\nemit = \"edge2_cross_edge1\"\n",
            side = Self::SIDE,
            length = Self::LENGTH,
            sc = fmt(screen_corner),
            se1 = fmt(screen_across),
            bc = fmt(beam_corner),
            be1 = fmt(beam_across),
        )
    }
}

fn fmt(v: V3) -> String {
    format!("[{}, {}, {}]", v[0], v[1], v[2])
}

struct Context {
    threads: usize,
    fault: Option<Fault>,
}

impl Context {
    fn scene(&self, text: &str, name: &str) -> Result<Scene, ValidateError> {
        parse(text, Path::new(&format!("<{name}>"))).map_err(|e| ValidateError::Input(e.to_string()))
    }

    fn render(
        &self,
        scene: &Scene,
        wavelength_nm: Option<f32>,
        bands: Option<SpectralBands>,
    ) -> Result<Film, ValidateError> {
        let job = Job {
            threads: self.threads,
            monochromatic_nm: wavelength_nm,
            fault: self.fault,
            bands,
            ..Job::new(scene.settings.clone())
        };
        Ok(render(scene, &job)?.0)
    }

    /// Newton's experiment in miniature: a 1 cm slit of white light crosses an equilateral
    /// N-SF11 prism at minimum deviation for 550 nm and lands on a screen 2.5 units on. One
    /// spectral render (4 nm bands) gives the line each wavelength draws; its centroid across
    /// the screen must be where the slit's central ray lands, traced here exactly (vector Snell
    /// at both faces with n(λ) from the catalogue's Sellmeier data, then the screen plane, then
    /// the pinhole projection), for the bands centred on 450, 502, 550, 602 and 650 nm. The deviation it checks is
    /// D(λ) = 2·asin(n·sin(A/2)) − A at 550 nm and the exact off-minimum deviation elsewhere.
    fn newton_lines(&self, name: &str) -> Result<CaseResult, ValidateError> {
        let sf11 = catalogue::glass("N-SF11").ok_or_else(|| ValidateError::Input("N-SF11 missing".into()))?;
        let n_at = |nm: f64| f64::from(sf11.ior().eval(nm as f32));
        let prism = MinimumDeviationPrism::new(n_at(550.0));
        let (beam_dir, entry) = (prism.beam_dir, prism.entry);
        let trace = |nm: f64| prism.trace_from(entry, n_at(nm));
        let (exit_550, out_550) = trace(550.0)
            .ok_or_else(|| ValidateError::Input("the 550 nm ray does not leave the prism".into()))?;
        let screen_centre = add(exit_550, scale(out_550, 2.5));
        let screen_normal = scale(out_550, -1.0);
        let across = normalize(cross([0.0, 1.0, 0.0], screen_normal));
        let slit_width = 0.01;
        let slit_centre = sub(entry, scale(beam_dir, 2.0));
        let slit_across = prism.across_beam;
        let slit_corner = add(sub(slit_centre, scale(slit_across, slit_width / 2.0)), [0.0, -0.15, 0.0]);
        let screen_corner = add(sub(screen_centre, scale(across, 0.8)), [0.0, -0.5, 0.0]);
        let camera_pos = add(screen_centre, scale(screen_normal, 1.2));
        let (width, height, fov_y) = (160u32, 48u32, 2.0 * (0.25f64 / (160.0 / 48.0)).atan().to_degrees());
        let text = prism.scene_text(
            &format!(
                "position = {}\nlook_at = {}\nfov_y_deg = {fov_y}\nwidth = {width}\nheight = {height}\n",
                fmt(camera_pos),
                fmt(screen_centre)
            ),
            "spp = 1\nmax_depth = 12\nprune_below = 0\nwavelengths = 4\ncaustics = true\nlight_paths = 300000\nseed = 7\n",
            screen_corner,
            scale(across, 1.6),
            1.0,
            slit_corner,
            scale(slit_across, slit_width),
            0.3,
        );
        let scene = self.scene(&text, name)?;
        let bands = SpectralBands { count: 51, min_nm: 448.0, max_nm: 652.0 };
        let film = self.render(&scene, None, Some(bands))?;
        let camera = Pinhole::new(camera_pos, screen_centre, [0.0, 1.0, 0.0], fov_y, width, height);
        // The window of a band's line: ±6 px of its brightest column (a faint ghost, about 1 %
        // of the light, reflected inside the prism off its second face and base, lands 12 px or
        // more away and is left out).
        let line = |band: usize| -> (Vec<f64>, std::ops::Range<usize>) {
            let plane = film.band(0, band).unwrap_or_default();
            let mut columns = vec![0.0f64; width as usize];
            for (i, value) in plane.iter().enumerate() {
                columns[i % width as usize] += f64::from(*value);
            }
            let peak = (0..columns.len()).max_by(|&a, &b| columns[a].total_cmp(&columns[b])).unwrap_or(0);
            (columns, peak.saturating_sub(6)..(peak + 7).min(width as usize))
        };
        let mut worst = 0.0f64;
        for nm in [450.0f32, 500.0, 550.0, 600.0, 650.0] {
            let band = bands.band_of(nm).unwrap_or(0);
            let centre_nm = f64::from(bands.center_nm(band));
            let expected = match trace(centre_nm) {
                Some((exit, out)) => camera.project(hit_plane(exit, out, screen_centre, screen_normal)).0,
                None => f64::NAN,
            };
            // The band is 4 nm wide; its line is the mean of lines up to 2 nm off the band's
            // centre, which sits at the centre's within 0.01 px (the dispersion is smooth:
            // |d²x/dλ²| < 0.005 px/nm²).
            let (columns, window) = line(band);
            let weight: f64 = columns[window.clone()].iter().sum();
            let moment: f64 = window.map(|x| columns[x] * (x as f64 + 0.5)).sum();
            let measured = if weight > 0.0 { moment / weight } else { f64::INFINITY };
            let error = (measured - expected).abs();
            worst = worst.max(if error.is_nan() { f64::INFINITY } else { error });
        }
        // The flux in the lines, 448–652 nm: the screen is parallel to the image plane at
        // distance D = 1.2, so a pixel covers A_pixel·D² of it and receives π·L/ρ times that; the
        // view shows a height h = 2·D·tan(fov/2) of each line (less than the slit's 0.3), which
        // receives E·w·h·T(λ) per nm, T the transmittance of the two faces for unpolarised light,
        // ½(T_s1·T_s2 + T_p1·T_p2): s and p do not mix, the faces sharing the plane of incidence
        // (textbook Fresnel in f64, `textbook::reference_reflectances`).
        let tan_half = (fov_y.to_radians() / 2.0).tan();
        let aspect = f64::from(width) / f64::from(height);
        let pixel_area =
            (2.0 * tan_half * aspect / f64::from(width)) * (2.0 * tan_half / f64::from(height)) * 1.2 * 1.2;
        let view_height = 2.0 * 1.2 * tan_half;
        let (mut received, mut expected_flux) = (0.0f64, 0.0f64);
        for band in 0..bands.count {
            let (columns, window) = line(band);
            let radiance_sum: f64 = columns[window].iter().sum();
            received += std::f64::consts::PI * radiance_sum / 0.8 * pixel_area * f64::from(bands.width_nm());
            let nm = f64::from(bands.center_nm(band));
            let n = n_at(nm);
            let cos_1 = -dot(beam_dir, prism.entry_normal);
            let inside = refract(beam_dir, prism.entry_normal, n).unwrap_or(beam_dir);
            let cos_2 = dot(inside, prism.exit_normal);
            let (rs1, rp1) = reference_reflectances(cos_1, 1.0, n);
            let (rs2, rp2) = reference_reflectances(cos_2, n, 1.0);
            let transmittance = 0.5 * ((1.0 - rs1) * (1.0 - rs2) + (1.0 - rp1) * (1.0 - rp2));
            expected_flux += 10.0 * slit_width * view_height * transmittance * f64::from(bands.width_nm());
        }
        Ok(CaseResult {
            name: name.into(),
            checks: vec![
                Check { metric: "max |line centre − exact| (px)".into(), value: worst, threshold: 0.1 },
                Check {
                    metric: "|line flux / (E·w·h·T) − 1|".into(),
                    value: (received / expected_flux - 1.0).abs(),
                    threshold: 5e-3,
                },
            ],
            why: "a white slit through an N-SF11 prism at minimum deviation: each wavelength's line on the screen \
                  (light tracer, one spectral render, 4 nm bands) lies where the exactly traced ray lands \
                  (D = 2·asin(n·sin(A/2)) − A at 550 nm); 1 px = 0.086° of deviation"
                .into(),
        })
    }

    /// The edges of a narrow collimated beam through the prism, seen at 10⁻⁴ scene units per
    /// pixel: a 3 × 2.4 mm beam at minimum deviation for 550 nm (one wavelength) lands on a
    /// screen 2.5 units past the prism, perpendicular to the central ray, and a camera 1.2 units
    /// in front of it looks square at it (64 × 16 pixels, 6.4 × 1.6 mm), so that the band's two
    /// side edges are columns of the image and its top and bottom lie outside the view. Each
    /// edge's position is read off the image to a fraction of a pixel: the light of the columns
    /// around it over the band's level (the screen is Lambertian and evenly lit, so the band's
    /// radiance is flat), and compared with where the beam's side rays land, traced here in f64
    /// (vector Snell at both faces, the screen plane, the pinhole projection). A pixel here is
    /// 10⁻⁴ units; the light tracer's rays must follow Snell's law to 10⁻⁶ units through the two
    /// faces: an offset of the kind Mitsuba 3 gives its continued rays ((1 + max|p|)·8.9·10⁻⁵
    /// along the normal, validation/README.md) would move the edges by about 0.8 px, an index
    /// 10⁻⁵ too high by 1.0 px (2·10⁻⁶: 0.2 px, tested).
    fn band_edges(&self, name: &str) -> Result<CaseResult, ValidateError> {
        let sf11 = catalogue::glass("N-SF11").ok_or_else(|| ValidateError::Input("N-SF11 missing".into()))?;
        let n = f64::from(sf11.ior().eval(550.0));
        let prism = MinimumDeviationPrism::new(n);
        let (exit, out) = prism
            .trace_from(prism.entry, n)
            .ok_or_else(|| ValidateError::Input("the central ray does not leave the prism".into()))?;
        let screen_centre = add(exit, scale(out, 2.5));
        let screen_normal = scale(out, -1.0);
        let across = normalize(cross([0.0, 1.0, 0.0], screen_normal));
        let (beam_width, beam_height) = (0.003, 0.0024);
        let slit_centre = sub(prism.entry, scale(prism.beam_dir, 2.0));
        let slit_corner =
            add(sub(slit_centre, scale(prism.across_beam, beam_width / 2.0)), [0.0, -beam_height / 2.0, 0.0]);
        let distance = 1.2;
        let (width, height) = (64u32, 16u32);
        // Scene units per pixel at the screen.
        let pixel = 1e-4;
        // The view's centre 0.37 px off the central ray, so that the edges (30 px apart at
        // minimum deviation) do not fall on pixel boundaries.
        let view_centre = add(screen_centre, scale(across, 0.37 * pixel));
        let camera_pos = add(view_centre, scale(screen_normal, distance));
        let fov_y = 2.0 * (0.5 * f64::from(height) * pixel / distance).atan().to_degrees();
        let camera = Pinhole::new(camera_pos, view_centre, [0.0, 1.0, 0.0], fov_y, width, height);
        // Where the beam's two side rays land, in image columns.
        let mut exact = Vec::new();
        for side in [0.0, 1.0] {
            let origin = add(slit_corner, scale(prism.across_beam, side * beam_width));
            let (exit, out) = prism
                .trace_from(prism.entry_of(origin), n)
                .ok_or_else(|| ValidateError::Input("a side ray does not leave the prism".into()))?;
            exact.push(camera.project(hit_plane(exit, out, screen_centre, screen_normal)).0);
        }
        exact.sort_by(f64::total_cmp);
        let (left, right) = (exact[0], exact[1]);
        let text = prism.scene_text(
            &format!(
                "position = {}\nlook_at = {}\nfov_y_deg = {fov_y}\nwidth = {width}\nheight = {height}\n",
                fmt(camera_pos),
                fmt(view_centre)
            ),
            "spp = 1\nmax_depth = 12\nprune_below = 0\ncaustics = true\nlight_paths = 2000000\nseed = 11\n",
            add(sub(screen_centre, scale(across, 0.1)), [0.0, -0.1, 0.0]),
            scale(across, 0.2),
            0.2,
            slit_corner,
            scale(prism.across_beam, beam_width),
            beam_height,
        );
        let film = self.render(&self.scene(&text, name)?, Some(550.0), None)?;
        let mut columns = vec![0.0f64; width as usize];
        for (i, value) in film.xyz().iter().enumerate() {
            columns[i % width as usize] += f64::from(value.y);
        }
        let column = |x: f64| x.floor() as i64;
        let sum = |from: i64, to: i64| -> f64 {
            (from..to)
                .map(|c| usize::try_from(c).ok().and_then(|c| columns.get(c)).copied().unwrap_or(0.0))
                .sum()
        };
        // The band's level: its columns at least 3 px from either edge.
        let (inner_from, inner_to) = (column(left) + 4, column(right) - 3);
        let level = sum(inner_from, inner_to) / (inner_to - inner_from).max(1) as f64;
        // Each edge from the light of the columns from 3 px outside it to 3 px inside.
        let measured_left = (column(left) + 3) as f64 - sum(column(left) - 3, column(left) + 3) / level;
        let measured_right = (column(right) - 2) as f64 + sum(column(right) - 2, column(right) + 4) / level;
        let error = (measured_left - left).abs().max((measured_right - right).abs());
        Ok(CaseResult {
            name: name.into(),
            checks: vec![Check {
                metric: "max |band edge − exact| (px of 1e-4)".into(),
                value: if error.is_nan() { f64::INFINITY } else { error },
                threshold: 0.05,
            }],
            why:
                "a 3 mm collimated beam through an N-SF11 prism at minimum deviation (550 nm), its band on a \
                  screen seen at 1e-4 scene units per pixel: both side edges (light tracer) lie where the \
                  beam's side rays land, traced in f64 with Snell's law"
                    .into(),
        })
    }

    /// A glass ball (N-BK7, R = 1) under a narrow collimated beam (0.14 square): the irradiance
    /// at the axis point of a screen behind it, for 15 screens 0.005 apart around the paraxial
    /// focus, peaks between the marginal rays' axis crossing and the paraxial back focal length
    /// f = n·R/(2(n − 1)) − R (both computed here in f64), at 450, 550 and 650 nm.
    fn ball_lens(&self, name: &str) -> Result<CaseResult, ValidateError> {
        let bk7 = catalogue::glass("N-BK7").ok_or_else(|| ValidateError::Input("N-BK7 missing".into()))?;
        let half_width = 0.07f64;
        let step = 0.005f64;
        let mut worst = 0.0f64;
        for nm in [450.0f32, 550.0, 650.0] {
            let n = f64::from(bk7.ior().eval(nm));
            let paraxial = n / (2.0 * (n - 1.0)) - 1.0;
            // The beam's corner ray (height √2·0.07) crosses the axis first.
            let marginal = {
                let h = half_width * 2f64.sqrt();
                let start = [h, 2.0, 0.0];
                let down = [0.0, -1.0, 0.0];
                let entry_t = 2.0 - (1.0 - h * h).sqrt();
                let entry = add(start, scale(down, entry_t));
                let inside = refract(down, entry, n).unwrap_or(down);
                let exit_t = -2.0 * dot(entry, inside);
                let exit = add(entry, scale(inside, exit_t));
                let out = refract(inside, exit, 1.0 / n).unwrap_or(inside);
                let t = -exit[0] / out[0];
                -(exit[1] + t * out[1]) - 1.0
            };
            let offsets: Vec<f64> = (-7..=7).map(|k| paraxial + f64::from(k) * step).collect();
            let mut irradiance = Vec::with_capacity(offsets.len());
            for &z in &offsets {
                let y = -(1.0 + z);
                let (s, c) = 55f64.to_radians().sin_cos();
                let text = format!(
                    "[camera]\nposition = [{cx}, {cy}, 0]\nlook_at = [0, {y}, 0]\nup = [0, 0, 1]\nfov_y_deg = {fov}\nwidth = 9\nheight = 9\n\
                     [render]\nspp = 1\nmax_depth = 8\nprune_below = 0\ncaustics = true\nlight_paths = 20000\nseed = 3\n\
                     [materials.glass]\ntype = \"dielectric\"\nior = {{ glass = \"N-BK7\" }}\n\
                     [materials.white]\ntype = \"diffuse\"\nalbedo = 1\n\
                     [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"glass\"\n\
                     [[shapes]]\ntype = \"quad\"\ncorner = [-0.1, {y}, -0.1]\nedge1 = [0, 0, 0.2]\nedge2 = [0.2, 0, 0]\nmaterial = \"white\"\n\
                     [[lights]]\ntype = \"beam\"\ncorner = [-{half_width}, 2, -{half_width}]\nedge1 = [{w}, 0, 0]\nedge2 = [0, 0, {w}]\nirradiance = 1\nemit = \"edge1_cross_edge2\"\n",
                    cx = 0.3 * s,
                    cy = y + 0.3 * c,
                    fov = 2.0 * (0.002f64 / 0.3).atan().to_degrees(),
                    w = 2.0 * half_width,
                );
                let film = self.render(&self.scene(&text, name)?, Some(nm), None)?;
                irradiance.push(f64::from(film.xyz()[4 * 9 + 4].y) * std::f64::consts::PI);
            }
            let best =
                (0..irradiance.len()).max_by(|&a, &b| irradiance[a].total_cmp(&irradiance[b])).unwrap_or(0);
            let peak = if best == 0 || best + 1 == irradiance.len() {
                f64::INFINITY // at the window's edge: no peak in view
            } else {
                // The vertex of the parabola through the maximum and its neighbours.
                let (a, b, c) = (irradiance[best - 1], irradiance[best], irradiance[best + 1]);
                let denominator = a - 2.0 * b + c;
                let shift = if denominator < 0.0 { 0.5 * (a - c) / denominator } else { 0.0 };
                offsets[best] + shift.clamp(-1.0, 1.0) * step
            };
            let (low, high) = (marginal.min(paraxial), marginal.max(paraxial));
            let outside = if peak < low {
                low - peak
            } else if peak > high {
                peak - high
            } else {
                0.0
            };
            worst = worst.max(if outside.is_nan() { f64::INFINITY } else { outside });
        }
        Ok(CaseResult {
            name: name.into(),
            checks: vec![Check { metric: "peak outside [marginal, paraxial]".into(), value: worst, threshold: 0.003 }],
            why: "a ball lens (N-BK7, R = 1) under a narrow beam: the brightest point along the axis (light tracer, \
                  15 screens 0.005 apart) lies between the marginal focus and the paraxial back focal length \
                  f = nR/(2(n − 1)) − R at 450, 550 and 650 nm"
                .into(),
        })
    }

    /// A point light (I = 1 W·sr⁻¹·nm⁻¹ at 550 nm) inside a glass sphere (n = 1.5), inside a
    /// closed cube of white (ρ = 1) diffuse walls: all 4π W·nm⁻¹ it emits leave the glass and
    /// reach the walls, through the light tracer alone (Whitted's shadow rays are blocked by the
    /// glass). Each wall is rendered by a camera facing it squarely from 1 unit away with a
    /// view that is exactly the wall, so a pixel covers (6/64)² of it and the wall receives
    /// Σ π·L·(6/64)². The six renders share their light paths (one seed), so every path is
    /// counted on exactly one wall, and since a path keeps its flux through glass (the branch
    /// is chosen by flux, and R + T = 1) the walls' sum is 4π up to float rounding: within
    /// 10⁻⁴ (f32 pixel values; the depth cap loses less than 0.05⁶⁴).
    fn power(&self, name: &str) -> Result<CaseResult, ValidateError> {
        let walls: [(V3, V3); 6] = [
            ([0.0, 0.0, 1.0], [0.0, 1.0, 0.0]),
            ([0.0, 0.0, -1.0], [0.0, 1.0, 0.0]),
            ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
            ([-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
            ([0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
            ([0.0, -1.0, 0.0], [0.0, 0.0, 1.0]),
        ];
        let mut shapes = String::new();
        for (normal, up) in &walls {
            let side = cross(*up, *normal);
            let corner = sub(sub(scale(*normal, 3.0), scale(side, 3.0)), scale(*up, 3.0));
            shapes += &format!(
                "[[shapes]]\ntype = \"quad\"\ncorner = {}\nedge1 = {}\nedge2 = {}\nmaterial = \"white\"\n",
                fmt(corner),
                fmt(scale(side, 6.0)),
                fmt(scale(*up, 6.0))
            );
        }
        let size = 64u32;
        let mut received = 0.0f64;
        for (normal, up) in &walls {
            let text = format!(
                "[camera]\nposition = {p}\nlook_at = {l}\nup = {u}\nfov_y_deg = {fov}\nwidth = {size}\nheight = {size}\n\
                 [render]\nspp = 1\nmax_depth = 64\ncaustics = true\nlight_paths = 150000\nseed = 5\n\
                 [materials.glass]\ntype = \"dielectric\"\nior = 1.5\n\
                 [materials.white]\ntype = \"diffuse\"\nalbedo = 1\n\
                 [[shapes]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"glass\"\n{shapes}\
                 [[lights]]\ntype = \"point\"\nposition = [0.35, 0.2, -0.25]\nintensity = 1\n",
                p = fmt(scale(*normal, 2.0)),
                l = fmt(scale(*normal, 3.0)),
                u = fmt(*up),
                fov = 2.0 * 3f64.atan().to_degrees(),
            );
            let film = self.render(&self.scene(&text, name)?, Some(550.0), None)?;
            let pixel_area = (6.0 / f64::from(size)).powi(2);
            received +=
                film.xyz().iter().map(|p| std::f64::consts::PI * f64::from(p.y) * pixel_area).sum::<f64>();
        }
        let emitted = 4.0 * std::f64::consts::PI;
        Ok(CaseResult {
            name: name.into(),
            checks: vec![Check {
                metric: "|received/emitted − 1|".into(),
                value: (received / emitted - 1.0).abs(),
                threshold: 1e-4,
            }],
            why: "a point light inside a glass sphere inside a closed white box: the power the six walls receive \
                  (light tracer only, read off six renders) equals the 4π·I emitted"
                .into(),
        })
    }
}

//! Analytic validation cases for polarisation, one per known class of polarisation bug: the
//! sign of S1 at Brewster's angle and the degree of polarisation of one reflection (s and p
//! swapped), a rolled camera (a transposed rotation shows in the sign of S2), two reflections
//! in different planes of incidence (a missing or wrong frame rotation), total internal
//! reflection as a Fresnel rhomb and two gold mirrors (the sign of the phase, seen in S3),
//! polarisers and wave plates (Malus's law; retarder handedness), polarisers on a shadow
//! ray, and coated surfaces (issue 41: a film on gold and a quarter wave on glass, whose
//! amplitudes come from the `tmm` package's fixtures, not from prisma's stack: the film's
//! phase, s and p, and the sign of S3 from a coating).
//!
//! Each renders a scene built here, one wavelength, a pinhole of 0.01° so that every camera
//! ray follows the same specular path, and compares the Stokes vector the camera records with
//! the one [`super::field`] computes for that path from the electric field itself.

use std::path::Path;

use glam::DVec3;
use num_complex::Complex64;

use super::field::{self, Element};
use super::tmm_fixture::TmmFixture;
use super::{CaseResult, Check, ValidateError};
use crate::integrator::Fault;
use crate::render::{render, Job};
use crate::scene::parse;

/// Names of the polarisation cases, in the order they run.
pub const CASES: [&str; 7] = [
    "one_reflection",
    "camera_roll",
    "skew_reflections",
    "tir_retardance",
    "conductor_pair",
    "polarizer_chain",
    "coated_reflection",
];

/// Largest error of a Stokes ratio S_k/S0 (k = 1..3) and of S0 relative to the reference: the
/// renders are noiseless (one wavelength, one specular path, every sample the same up to a
/// 0.01° field of view), so what remains is float32 rounding, about 1e-6.
const TOLERANCE: f64 = 1e-4;

/// Below this reference radiance (the sources have radiance 1) a configuration is dark: its
/// rendered S0 is compared in absolute terms and its ratios are undefined.
const DARK: f64 = 1e-9;

/// The wavelength every case renders at, nm (the cases use constant indices).
const LAMBDA_NM: f32 = 550.0;

/// Runs the polarisation case `name` with `threads` threads and an optional injected `fault`.
pub fn run(name: &str, threads: usize, fault: Option<Fault>) -> Result<CaseResult, ValidateError> {
    let ctx = Context { threads, fault };
    let (comparisons, why) = match name {
        "one_reflection" => (ctx.one_reflection()?, "one reflection off glass at 10°–85° (n = 1.5, 1.9): S1/S0 = (R_s − R_p)/(R_s + R_p) in the s frame, +1 at Brewster's angle"),
        "camera_roll" => (ctx.camera_roll()?, "Brewster reflection seen by a camera rolled 30° and 45°: S1, S2 follow the s axis in the image"),
        "skew_reflections" => (ctx.skew_reflections()?, "two glass reflections in planes of incidence 60° apart: the second sees the first's polarisation turned"),
        "tir_retardance" => (ctx.tir_retardance()?, "a Fresnel rhomb: two total internal reflections at 54.6° in n = 1.51 turn light at 45° circular"),
        "conductor_pair" => (ctx.conductor_pair()?, "two gold mirrors (n + ik = 0.35 + 2.71i) in different planes of incidence make unpolarised light elliptical"),
        "polarizer_chain" => (ctx.polarizer_chain()?, "polarisers at 0°–90° (Malus), a quarter-wave and a half-wave plate, polarisers on a shadow ray"),
        "coated_reflection" => (ctx.coated_reflection()?, "100 nm of SiO₂ on gold (0.18 + 3.43i) and quarter-wave MgF₂ on N-BK7 at 15°–85°, unpolarised and through a polariser at 45° (S3 from the film's phase), against tmm 0.2.0's amplitudes (tests/fixtures/thin_film_*.csv)"),
        _ => {
            return Err(ValidateError::Input(format!(
                "unknown polarisation case \"{name}\"; known: {}",
                CASES.join(", ")
            )))
        }
    };
    let mut worst_ratio = 0.0f64;
    let mut worst_radiance = 0.0f64;
    for (seen, expected) in &comparisons {
        if expected[0] < DARK {
            // Crossed polarisers: nothing should pass (relative to the unit source radiance).
            worst_radiance = worst_radiance.max(seen[0].abs());
            continue;
        }
        worst_radiance = worst_radiance.max((seen[0] / expected[0] - 1.0).abs());
        for k in 1..4 {
            worst_ratio = worst_ratio.max((seen[k] / seen[0] - expected[k] / expected[0]).abs());
        }
    }
    Ok(CaseResult {
        name: name.into(),
        checks: vec![
            Check {
                metric: "max |S0 / reference − 1|".into(), value: worst_radiance, threshold: TOLERANCE
            },
            Check {
                metric: "max |S_k/S0 − reference|, k = 1..3".into(),
                value: worst_ratio,
                threshold: TOLERANCE,
            },
        ],
        why: why.into(),
    })
}

/// Rendered and reference Stokes vectors of one configuration.
type Comparison = ([f64; 4], [f64; 4]);

struct Context {
    threads: usize,
    fault: Option<Fault>,
}

/// A camera at `position` looking along `dir` with `up`, a 2×2-pixel image over 0.01°.
fn camera(position: DVec3, dir: DVec3, up: DVec3) -> String {
    let look = position + dir;
    format!(
        "[camera]\nposition = {}\nlook_at = {}\nup = {}\nfov_y_deg = 0.01\nwidth = 2\nheight = 2\n\
         [render]\nspp = 2\nmax_depth = 16\nprune_below = 0\n",
        array(position),
        array(look),
        array(up)
    )
}

fn array(v: DVec3) -> String {
    format!("[{:.12}, {:.12}, {:.12}]", v.x, v.y, v.z)
}

/// Two edges of a square of side `size` perpendicular to `normal`, with edge1 × edge2 along it.
fn square_edges(normal: DVec3, size: f64) -> (DVec3, DVec3) {
    let first = normal.any_orthonormal_vector();
    (first * size, normal.cross(first) * size)
}

/// A square quad light of radiance `radiance` centred at `center`, emitting along `towards`.
fn quad_light(center: DVec3, towards: DVec3, size: f64, radiance: f64) -> String {
    let (e1, e2) = square_edges(towards, size);
    format!(
        "[[lights]]\ntype = \"quad\"\ncorner = {}\nedge1 = {}\nedge2 = {}\nradiance = {radiance}\nemit = \"edge1_cross_edge2\"\n",
        array(center - 0.5 * (e1 + e2)),
        array(e1),
        array(e2)
    )
}

/// A square quad shape of material `material` centred at `center`, of normal `normal`.
fn quad(center: DVec3, normal: DVec3, size: f64, material: &str) -> String {
    let (e1, e2) = square_edges(normal, size);
    format!(
        "[[shapes]]\ntype = \"quad\"\ncorner = {}\nedge1 = {}\nedge2 = {}\nmaterial = \"{material}\"\n",
        array(center - 0.5 * (e1 + e2)),
        array(e1),
        array(e2)
    )
}

fn reflect(d: DVec3, normal: DVec3) -> DVec3 {
    d - 2.0 * d.dot(normal) * normal
}

/// `v` turned by `angle` radians about the unit `axis` (Rodrigues).
fn rotate(v: DVec3, axis: DVec3, angle: f64) -> DVec3 {
    let (s, c) = angle.sin_cos();
    v * c + axis.cross(v) * s + axis * axis.dot(v) * (1.0 - c)
}

/// The reference's Stokes frame at the camera: x = normalize(d × up) for the camera ray
/// direction d = −k (light arriving along k), as the renderer documents its output.
fn camera_frame(up: DVec3) -> impl Fn(DVec3) -> DVec3 {
    move |k: DVec3| (-k).cross(up).normalize()
}

impl Context {
    /// Renders `text` at one wavelength and returns the mean Stokes vector of its pixels (S1–S3
    /// zero when the film has none).
    fn stokes(&self, text: &str, name: &str) -> Result<[f64; 4], ValidateError> {
        let scene =
            parse(text, Path::new(&format!("<{name}>"))).map_err(|e| ValidateError::Input(e.to_string()))?;
        let job = Job {
            threads: self.threads,
            monochromatic_nm: Some(LAMBDA_NM),
            fault: self.fault,
            ..Job::new(scene.settings.clone())
        };
        let film = render(&scene, &job)?.0;
        let mut mean = [0.0; 4];
        for (k, value) in mean.iter_mut().enumerate() {
            if let Some(pixels) = film.stokes_xyz(k) {
                *value = pixels.iter().map(|p| f64::from(p.x)).sum::<f64>() / pixels.len() as f64;
            }
        }
        Ok(mean)
    }

    /// A camera looking down at a glass half-space (the plane y = 0) at incidence θ, with the
    /// plane of incidence vertical in the image (so that s is image-horizontal), and a quad
    /// light where the reflection goes; the camera rolled by `roll` about its view.
    fn glass_reflection(&self, theta: f64, n: f64, roll: f64) -> Result<Comparison, ValidateError> {
        let (s, c) = theta.sin_cos();
        let distance = 10.0;
        let dir = DVec3::new(s, -c, 0.0);
        let up = rotate(DVec3::Y, dir, roll);
        let reflected = reflect(dir, DVec3::Y);
        let text = format!(
            "{}[materials.glass]\ntype = \"dielectric\"\nior = {n}\n\
             [[shapes]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\nmaterial = \"glass\"\n{}",
            camera(-distance * dir, dir, up),
            quad_light(50.0 * reflected, -reflected, 20.0, 1.0),
        );
        let seen = self.stokes(&text, "glass_reflection")?;
        let elements = [Element::Reflection { normal: DVec3::Y, eta: Complex64::new(n, 0.0) }];
        let expected = field::unpolarized_through(1.0, -reflected, &elements, camera_frame(up));
        Ok((seen, expected))
    }

    fn one_reflection(&self) -> Result<Vec<Comparison>, ValidateError> {
        let mut all = Vec::new();
        for (n, angles) in [
            (1.5f64, vec![10.0, 30.0, 45.0, 1.5f64.atan().to_degrees(), 70.0, 85.0]),
            (1.9, vec![1.9f64.atan().to_degrees(), 60.0]),
        ] {
            for theta_deg in angles {
                all.push(self.glass_reflection(theta_deg.to_radians(), n, 0.0)?);
            }
        }
        Ok(all)
    }

    fn camera_roll(&self) -> Result<Vec<Comparison>, ValidateError> {
        let brewster = 1.5f64.atan();
        [30.0f64, 45.0, -30.0]
            .iter()
            .map(|roll| self.glass_reflection(brewster, 1.5, roll.to_radians()))
            .collect()
    }

    /// A chain of two mirrors (quads of material `material`, of TOML body `body`): the camera
    /// meets the first at 45° in the xy plane, the second in a plane of incidence turned by
    /// about 60°, then a quad light.
    fn two_mirrors(
        &self,
        body: &str,
        element: impl Fn(DVec3) -> Element,
    ) -> Result<Comparison, ValidateError> {
        let up = DVec3::Z;
        let dir = DVec3::new(1.0, -1.0, 0.0).normalize();
        let normal_a = DVec3::Y;
        let d1 = reflect(dir, normal_a);
        let point_b = 4.0 * d1;
        let normal_b = DVec3::new(-1.0, -0.2, 1.2).normalize();
        let d2 = reflect(d1, normal_b);
        let text = format!(
            "{}[materials.surface]\n{body}\n{}{}{}",
            camera(-6.0 * dir, dir, up),
            quad(DVec3::ZERO, normal_a, 1.0, "surface"),
            quad(point_b, normal_b, 1.0, "surface"),
            quad_light(point_b + 40.0 * d2, -d2, 10.0, 1.0),
        );
        let seen = self.stokes(&text, "two_mirrors")?;
        let elements = [element(normal_b), element(normal_a)];
        let expected = field::unpolarized_through(1.0, -d2, &elements, camera_frame(up));
        Ok((seen, expected))
    }

    fn skew_reflections(&self) -> Result<Vec<Comparison>, ValidateError> {
        let n = 1.5;
        Ok(vec![self.two_mirrors(&format!("type = \"dielectric\"\nior = {n}"), |normal| {
            Element::Reflection { normal, eta: Complex64::new(n, 0.0) }
        })?])
    }

    fn conductor_pair(&self) -> Result<Vec<Comparison>, ValidateError> {
        let eta = Complex64::new(0.35, 2.71);
        let gold = format!("type = \"mirror\"\ncomplex_ior = [{}, {}]", eta.re, eta.im);
        let mut all = vec![self.two_mirrors(&gold, |normal| Element::Reflection { normal, eta })?];
        all.push(self.two_mirrors("type = \"mirror\"", |normal| Element::PerfectMirror { normal })?);
        Ok(all)
    }

    /// A Fresnel rhomb: inside a slab of glass (n = 1.51) between z = 0 and z = 1, the camera
    /// ray reflects totally at 54.6° off the top, then the bottom, then meets a polariser at
    /// 45° to the plane of incidence and a quad light behind it.
    fn tir_retardance(&self) -> Result<Vec<Comparison>, ValidateError> {
        let n = 1.51f64;
        let mut all = Vec::new();
        for angle_deg in [54.6f64, 48.0, 70.0] {
            let alpha = angle_deg.to_radians();
            let (s, c) = alpha.sin_cos();
            let dir = DVec3::new(s, 0.0, c);
            let start = DVec3::new(0.0, 0.0, 0.5);
            let top = start + dir * (0.5 / c);
            let d1 = reflect(dir, DVec3::Z);
            let bottom = top + d1 * (1.0 / c);
            let d2 = reflect(d1, DVec3::Z);
            let sheet = bottom + 0.3 * d2;
            let axis = (DVec3::Y + d2.cross(DVec3::Y)).normalize();
            let up = DVec3::Z;
            let text = format!(
                "{}[materials.glass]\ntype = \"dielectric\"\nior = {n}\n\
                 [materials.polarizer]\ntype = \"polarizer\"\naxis = {}\n\
                 [[shapes]]\ntype = \"plane\"\npoint = [0, 0, 1]\nnormal = [0, 0, 1]\nmaterial = \"glass\"\n\
                 [[shapes]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 0, -1]\nmaterial = \"glass\"\n{}{}",
                camera(start, dir, up),
                array(axis),
                quad(sheet, d2, 0.1, "polarizer"),
                quad_light(sheet + 0.05 * d2, -d2, 0.1, 1.0),
            );
            let seen = self.stokes(&text, "tir_retardance")?;
            let inside = Complex64::new(1.0 / n, 0.0);
            let elements = [
                Element::Polarizer { normal: d2, axis },
                Element::Reflection { normal: DVec3::Z, eta: inside },
                Element::Reflection { normal: DVec3::Z, eta: inside },
            ];
            all.push((seen, field::unpolarized_through(1.0, -d2, &elements, camera_frame(up))));
        }
        Ok(all)
    }

    fn polarizer_chain(&self) -> Result<Vec<Comparison>, ValidateError> {
        // The camera looks along +z with +y up: image right is −x.
        let (dir, up) = (DVec3::Z, DVec3::Y);
        let right = dir.cross(up);
        let axis = |deg: f64| {
            let (s, c) = deg.to_radians().sin_cos();
            right * c + up * s
        };
        let mut all = Vec::new();
        // Sheets in front of a quad light, nearest the camera first: (polariser?, axis in degrees,
        // retardance in degrees for a retarder).
        let chains: [&[(bool, f64, f64)]; 6] = [
            &[(true, 20.0, 0.0), (true, 20.0, 0.0)],
            &[(true, 20.0, 0.0), (true, 50.0, 0.0)],
            &[(true, 20.0, 0.0), (true, 80.0, 0.0)],
            &[(true, 0.0, 0.0), (true, 90.0, 0.0)],
            &[(false, 0.0, 90.0), (true, 45.0, 0.0)],
            &[(false, 22.5, 180.0), (true, 0.0, 0.0)],
        ];
        for chain in chains {
            let mut text = camera(DVec3::ZERO, dir, up);
            let mut elements = Vec::new();
            for (index, &(polarizer, angle, retardance)) in chain.iter().enumerate() {
                let name = format!("sheet{index}");
                let a = axis(angle);
                if polarizer {
                    text += &format!("[materials.{name}]\ntype = \"polarizer\"\naxis = {}\n", array(a));
                    elements.push(Element::Polarizer { normal: DVec3::Z, axis: a });
                } else {
                    text += &format!(
                        "[materials.{name}]\ntype = \"retarder\"\nfast_axis = {}\nretardance_deg = {retardance}\n",
                        array(a)
                    );
                    elements.push(Element::Retarder {
                        normal: DVec3::Z,
                        fast_axis: a,
                        retardance: retardance.to_radians(),
                    });
                }
                text += &quad(DVec3::new(0.0, 0.0, 1.0 + index as f64), DVec3::Z, 1.0, &name);
            }
            text += &quad_light(DVec3::new(0.0, 0.0, 1.0 + chain.len() as f64), -DVec3::Z, 1.0, 1.0);
            elements.reverse();
            let seen = self.stokes(&text, "polarizer_chain")?;
            all.push((seen, field::unpolarized_through(1.0, -DVec3::Z, &elements, camera_frame(up))));
        }
        // Polarisers on a shadow ray: a point light of intensity I at height h above a Lambertian
        // plane (albedo ρ), seen through two sheets at θ: ρ/π · I·½cos²θ / h², unpolarised
        // (the diffuse surface depolarises).
        let (albedo, intensity, height) = (0.5f64, 10.0f64, 4.0f64);
        for theta_deg in [0.0f64, 30.0, 60.0] {
            let theta = theta_deg.to_radians();
            let second = DVec3::new(theta.cos(), 0.0, theta.sin());
            let position = DVec3::new(3.0, 1.0, 0.0);
            let text = format!(
                "{}[materials.paper]\ntype = \"diffuse\"\nalbedo = {albedo}\n\
                 [materials.first]\ntype = \"polarizer\"\naxis = [1, 0, 0]\n\
                 [materials.second]\ntype = \"polarizer\"\naxis = {}\n\
                 [[shapes]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\nmaterial = \"paper\"\n{}{}\
                 [[lights]]\ntype = \"point\"\nposition = [0, {height}, 0]\nintensity = {intensity}\n",
                camera(position, -position.normalize(), DVec3::Y),
                array(second),
                quad(DVec3::new(0.0, 2.0, 0.0), DVec3::Y, 2.0, "first"),
                quad(DVec3::new(0.0, 3.0, 0.0), DVec3::Y, 2.0, "second"),
            );
            let seen = self.stokes(&text, "polarizer_shadow")?;
            let sheets = [
                Element::Polarizer { normal: DVec3::Y, axis: second },
                Element::Polarizer { normal: DVec3::Y, axis: DVec3::X },
            ];
            let through = field::unpolarized_through(1.0, -DVec3::Y, &sheets, |_| DVec3::X)[0];
            let radiance = albedo / std::f64::consts::PI * intensity * through / (height * height);
            all.push((seen, [radiance, 0.0, 0.0, 0.0]));
        }
        Ok(all)
    }

    /// A coated surface, the plane y = 0 (normal +y), met at `theta_deg` by a camera whose
    /// plane of incidence is vertical in the image, lit by a quad light where the reflection
    /// goes, unpolarised or through a polariser at 45° to the plane of incidence (linear light
    /// at 45° comes back elliptical: S3 has the sign of the film's phase difference). The
    /// reference is the field tracer with the fixture's r_s, r_p at that angle.
    fn coated_surface(
        &self,
        fixture: &TmmFixture,
        material: &str,
        theta_deg: f64,
        polarized_light: bool,
    ) -> Result<Comparison, ValidateError> {
        let (r_s, r_p) = fixture.reflection(f64::from(LAMBDA_NM), theta_deg).ok_or_else(|| {
            ValidateError::Input(format!("{}: no row at {LAMBDA_NM} nm, {theta_deg}°", fixture.name))
        })?;
        let theta = theta_deg.to_radians();
        let (s, c) = theta.sin_cos();
        let distance = 10.0;
        let dir = DVec3::new(s, -c, 0.0);
        let up = DVec3::Y;
        let reflected = reflect(dir, DVec3::Y);
        // s is ±z here; the reflected p direction is reflected × z: the axis halfway between.
        let axis = (DVec3::Z + reflected.cross(DVec3::Z).normalize()).normalize();
        let sheet = 20.0 * reflected;
        let (sheet_text, light_at) = if polarized_light {
            (
                format!(
                    "[materials.polarizer]\ntype = \"polarizer\"\naxis = {}\n{}",
                    array(axis),
                    quad(sheet, reflected, 4.0, "polarizer")
                ),
                sheet + 1.0 * reflected,
            )
        } else {
            (String::new(), 50.0 * reflected)
        };
        let text = format!(
            "{}[materials.coated]\n{material}\n\
             [[shapes]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\nmaterial = \"coated\"\n{sheet_text}{}",
            camera(-distance * dir, dir, up),
            quad_light(light_at, -reflected, 20.0, 1.0),
        );
        let seen = self.stokes(&text, "coated_reflection")?;
        // The fixture's amplitudes are in prisma's e^{+iωt} convention; the field tracer's
        // are their conjugates (tmm's own).
        let coated = Element::Amplitudes { normal: DVec3::Y, r_s: r_s.conj(), r_p: r_p.conj() };
        let elements: Vec<Element> = if polarized_light {
            vec![Element::Polarizer { normal: reflected, axis }, coated]
        } else {
            vec![coated]
        };
        Ok((seen, field::unpolarized_through(1.0, -reflected, &elements, camera_frame(up))))
    }

    fn coated_reflection(&self) -> Result<Vec<Comparison>, ValidateError> {
        let gold = TmmFixture::parse("thin_film_sio2_on_gold.csv", super::tmm_fixture::SIO2_ON_GOLD)?;
        let glass = TmmFixture::parse("thin_film_mgf2_on_bk7.csv", super::tmm_fixture::MGF2_ON_BK7)?;
        let mut all = Vec::new();
        for (fixture, kind, substrate) in [(&gold, "mirror", "complex_ior"), (&glass, "dielectric", "ior")] {
            let substrate_value = if fixture.substrate.im == 0.0 {
                format!("{}", fixture.substrate.re)
            } else {
                format!("[{}, {}]", fixture.substrate.re, fixture.substrate.im)
            };
            let material = format!(
                "type = \"{kind}\"\n{substrate} = {substrate_value}\ncoating = [{}]",
                fixture.coating_toml()
            );
            for theta_deg in [15.0, 45.0, 70.0, 85.0] {
                for polarized_light in [false, true] {
                    all.push(self.coated_surface(fixture, &material, theta_deg, polarized_light)?);
                }
            }
        }
        Ok(all)
    }
}

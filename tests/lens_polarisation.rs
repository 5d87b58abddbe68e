//! Off-axis light leaves a lens partly polarised: a polarised render of a uniform unpolarised
//! background through the double Gauss 50 mm (data/lenses/dgauss50.dat), stopped down so that
//! a pixel's light follows its chief ray closely, against an independent closed form: the
//! exact Fresnel transmittances T_s and T_p of every surface at the incidence angles of the
//! chief ray that rayoptics traced (validation/lens/fixtures/dgauss50.json), multiplied along
//! the ray. At the image centre the degree of linear polarisation is 0.

use std::path::{Path, PathBuf};

use prisma::film::PixelWindow;
use prisma::lens::read_lens_file;
use prisma::render::{render, Job};
use serde_json::Value;

/// The wavelength of the renders and of the closed form (nm; one of the fixture's).
const LAMBDA_NM: f64 = 550.0;

/// A path inside the repository.
fn repo(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(relative)
}

fn number(value: &Value) -> f64 {
    value.as_f64().expect("a number")
}

fn triple(value: &Value) -> [f64; 3] {
    let a = value.as_array().expect("an array");
    [number(&a[0]), number(&a[1]), number(&a[2])]
}

/// The chief ray's Π T_s, Π T_p and its image height (mm) at `field_fraction` of the
/// fixture's field, at [`LAMBDA_NM`]: a meridional (y, z) trace written here, independent of
/// prisma's tracer, from the fixture's start point and direction through its surfaces
/// (curvature, thickness), the media's indices at 550 nm from data/glasses.toml as the
/// shipped lens names them; at each surface the exact Fresnel reflectances
/// R_s = ((n cos θi − n′ cos θt)/(n cos θi + n′ cos θt))², R_p = ((n cos θt − n′ cos θi)/
/// (n cos θt + n′ cos θi))² (Hecht, *Optics*, §4.6), T = 1 − R. The trace's image height
/// must equal rayoptics' (`image_mm`) to 1e-9 mm, which checks the angles it used.
fn chief_ray_transmittances(fixture: &Value, field_fraction: f64) -> (f64, f64, f64) {
    let lens = read_lens_file(&repo("data/lenses/dgauss50.dat")).expect("the shipped lens reads");
    let ray = fixture["rays"]["list"]
        .as_array()
        .expect("rays")
        .iter()
        .find(|r| {
            r["kind"] == "chief"
                && (number(&r["wavelength_nm"]) - LAMBDA_NM).abs() < 1e-9
                && (number(&r["field_fraction"]) - field_fraction).abs() < 1e-9
        })
        .expect("the fixture's chief ray");
    let start = triple(&ray["start_mm"]);
    let dir = triple(&ray["direction"]);
    // (y, z) and the direction (m, l), unit.
    let (mut y, mut z) = (start[1], start[2]);
    let (mut m, mut l) = (dir[1], dir[2]);
    let (mut ts, mut tp) = (1.0, 1.0);
    let mut vertex = 0.0;
    let mut n = 1.0;
    let surfaces = fixture["surfaces"].as_array().expect("surfaces");
    for (i, surface) in surfaces.iter().enumerate() {
        let c = number(&surface["curvature_per_mm"]);
        let n_after = lens.surfaces[i].medium.n_at_nm(LAMBDA_NM);
        // The sphere c(y² + (z − v)²) − 2(z − v) = 0 met at t from (y, z) along (m, l): the
        // root on the vertex's side, in the form that stays exact for c → 0.
        let (py, pz) = (y, z - vertex);
        let b = l - c * (py * m + pz * l);
        let cc = c * (py * py + pz * pz) - 2.0 * pz;
        let t = cc / (b + (b * b - c * cc).sqrt());
        y += t * m;
        z += t * l;
        // The unit normal toward +z, (−c y, 1 − c (z − v)).
        let (ny, nz) = (-c * y, 1.0 - c * (z - vertex));
        let norm = ny.hypot(nz);
        let (ny, nz) = (ny / norm, nz / norm);
        let cos_i = m * ny + l * nz;
        let eta = n / n_after;
        let cos_t = (1.0 - eta * eta * (1.0 - cos_i * cos_i)).sqrt();
        let r_s = ((n * cos_i - n_after * cos_t) / (n * cos_i + n_after * cos_t)).powi(2);
        let r_p = ((n * cos_t - n_after * cos_i) / (n * cos_t + n_after * cos_i)).powi(2);
        ts *= 1.0 - r_s;
        tp *= 1.0 - r_p;
        // Snell's law: d′ = η d + (cos θt − η cos θi) N, N toward +z.
        m = eta * m + (cos_t - eta * cos_i) * ny;
        l = eta * l + (cos_t - eta * cos_i) * nz;
        n = n_after;
        vertex += number(&surface["thickness_mm"]);
    }
    // To the image plane (the last thickness ends there).
    let height = y + (vertex - z) * m / l;
    let expected = triple(&{
        let mut image = ray["image_mm"].as_array().expect("image").clone();
        image.push(Value::from(0.0));
        Value::from(image)
    })[1];
    assert!((height - expected).abs() < 1e-9, "the chief ray lands at {height} mm, rayoptics {expected} mm");
    (ts, tp, height)
}

/// The render's image: `SIZE`² pixels on a `SENSOR_MM`-high square sensor (0.1 mm pixels),
/// the double Gauss stopped down to f/16 and focused at infinity (the fixture's image plane).
const SIZE: u32 = 401;
const SENSOR_MM: f64 = 40.0;

/// The fixture.
fn fixture() -> Value {
    let text = std::fs::read_to_string(repo("validation/lens/fixtures/dgauss50.json")).expect("fixture");
    serde_json::from_str(&text).expect("fixture JSON")
}

/// The uniform unpolarised background of radiance 1 through the lens, polarised, at 550 nm,
/// 4096 samples per pixel, in the 3 × 3 pixels about the sensor point (0, `height_mm`):
/// per pixel, its sensor height (mm) and S0, S1/S0, S2/S0 (S1 = I along the image's right −
/// I along its up), row by row.
fn render_stokes(height_mm: f64) -> Vec<(f64, [f64; 3])> {
    let text = format!(
        "background = 1\n\n[camera]\nposition = [0, 0, 0]\nlook_at = [0, 0, 10]\n\
         lens = \"../data/lenses/dgauss50.dat\"\nsensor_height_mm = {SENSOR_MM}\nwidth = {SIZE}\n\
         height = {SIZE}\nf_number = 16\n\n[render]\nspp = 4096\npolarized = true\n"
    );
    let scene = prisma::scene::parse(&text, &repo("tests/lens_polarisation.toml")).expect("the scene parses");
    // The sensor point (0, h) is the film point (0, −h) turned by 180° (src/camera/lens_system.rs):
    // row r's centre reads h = ((r + 0.5)/SIZE − 0.5)·SENSOR_MM.
    let row = (f64::from(SIZE) * (0.5 + height_mm / SENSOR_MM)) as u32;
    let col = SIZE / 2;
    let job = Job {
        threads: 2,
        monochromatic_nm: Some(LAMBDA_NM as f32),
        window: Some(PixelWindow { x0: col - 1, y0: row - 1, x1: col + 2, y1: row + 2 }),
        ..Job::new(scene.settings.clone())
    };
    let (film, _) = render(&scene, &job).expect("the scene renders");
    let stokes: Vec<Vec<f64>> = (0..3)
        .map(|k| film.stokes_xyz(k).expect("a polarised film").iter().map(|v| f64::from(v.y)).collect())
        .collect();
    (0..9)
        .map(|i| {
            let r = row - 1 + i as u32 / 3;
            let h = ((f64::from(r) + 0.5) / f64::from(SIZE) - 0.5) * SENSOR_MM;
            (h, [stokes[0][i], stokes[1][i] / stokes[0][i], stokes[2][i] / stokes[0][i]])
        })
        .collect()
}

/// The mean and standard error of `values`.
fn mean_and_error(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (variance / n).sqrt())
}

/// At 0.7 and 1.0 of the field (14° and 20°, image heights 12.49 and 18.13 mm) the rendered
/// degree of linear polarisation equals the chief ray's (T_p − T_s)/(T_p + T_s) (0.0276 and
/// 0.0577: the uncoated lens passes p better than s at every tilted surface), and the light is
/// polarised along the meridional plane (S1 < 0: along the image's vertical through the
/// centre; S2 = 0 in the middle column). The DoLP of each pixel row (the mean of its three
/// pixels, whose azimuths ±0.3° about the vertical only turn the polarisation into S2) is
/// interpolated linearly to the chief ray's height between the two rows about it (pixel
/// centres 0.1 mm apart, where the DoLP changes by 1 % of itself).
///
/// Tolerance: 4 standard errors (the rows' pixel scatter, ≈ 1e-5) plus 0.5 % of the DoLP for
/// what the closed form leaves out: the pupil's other rays about the chief ray (at f/16 within
/// ±1.8° of it; at f/8 the edge rows read within 5e-5 of f/16's in a trial) and the linear
/// interpolation (the DoLP's curvature over 0.1 mm, ~1e-4 of itself). Measured: 0.027554 ±
/// 8e-6 against 0.027580, and 0.057678 ± 3e-5 against 0.057701.
#[test]
fn the_off_axis_image_is_polarised_as_the_chief_rays_fresnel_transmittances_say() {
    let fixture = fixture();
    for field_fraction in [0.7, 1.0] {
        let (ts, tp, height) = chief_ray_transmittances(&fixture, field_fraction);
        let closed_form = (tp - ts) / (tp + ts);
        let pixels = render_stokes(height);
        let rows: Vec<(f64, f64, f64)> = (0..3)
            .map(|r| {
                let dolp: Vec<f64> = pixels[3 * r..3 * r + 3].iter().map(|(_, s)| s[1].hypot(s[2])).collect();
                let (mean, error) = mean_and_error(&dolp);
                (pixels[3 * r].0, mean, error)
            })
            .collect();
        let pair = if height < rows[1].0 { [rows[0], rows[1]] } else { [rows[1], rows[2]] };
        let t = (height - pair[0].0) / (pair[1].0 - pair[0].0);
        let rendered = pair[0].1 + t * (pair[1].1 - pair[0].1);
        let error = pair[0].2.hypot(pair[1].2);
        eprintln!(
            "field {field_fraction}: rendered DoLP {rendered:.6} ± {error:.1e} at {height:.4} mm; chief ray \
             (T_p − T_s)/(T_p + T_s) = {closed_form:.6} (T_s {ts:.6}, T_p {tp:.6}); rows {rows:.6?}"
        );
        assert!(
            (rendered - closed_form).abs() < 4.0 * error + 0.005 * closed_form,
            "field {field_fraction}: {rendered} ± {error} vs {closed_form}"
        );
        for (h, s) in &pixels {
            assert!(s[1] < -0.9 * closed_form, "at {h} mm S1/S0 = {}: not along the meridian", s[1]);
        }
        let middle: Vec<f64> = (0..3).map(|r| pixels[3 * r + 1].1[2]).collect();
        let (s2, s2_error) = mean_and_error(&middle);
        assert!(s2.abs() < 4.0 * s2_error + 1e-4, "S2/S0 in the middle column {s2} ± {s2_error}");
    }
}

/// At the image centre the light stays unpolarised: the pupil is symmetric about the axis, so
/// every ray's partial polarisation is cancelled by its twin's. Tolerance: 4 standard errors of
/// the 3 × 3 pixels' mean (≈ 1e-5) plus 1e-5, the chief rays' own DoLP at the edge of those
/// pixels (0.15 mm, 0.17° off axis: 0.058 × (0.17°/20°)² ≈ 4e-6).
#[test]
fn the_centre_is_unpolarised() {
    let pixels = render_stokes(0.0);
    for k in 1..3 {
        let values: Vec<f64> = pixels.iter().map(|(_, s)| s[k]).collect();
        let (mean, error) = mean_and_error(&values);
        eprintln!("centre: S{k}/S0 = {mean:.2e} ± {error:.1e}");
        assert!(mean.abs() < 4.0 * error + 1e-5, "S{k}/S0 = {mean} ± {error}");
    }
}

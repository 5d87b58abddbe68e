//! Caustics by light tracing: determinism whatever the thread count, the decomposition (no
//! mirror or glass: the image with caustics is Whitted's, bit for bit), the new lights in plain
//! Whitted renders, and the command line's warning when no caustic can form.

use std::process::Command;

use prisma::film::{Film, SpectralBands};
use prisma::render::{render, Job};

fn scene(name: &str) -> prisma::scene::Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name);
    prisma::scene::load(&path).unwrap()
}

/// Every value of the film: the Stokes components (S0 alone when unpolarised) and the bands.
fn bits(film: &Film, bands: &SpectralBands) -> Vec<u32> {
    let mut bits = Vec::new();
    for k in 0..film.layout().components() {
        bits.extend(film.stokes_xyz(k).unwrap().iter().flat_map(|p| p.to_array().map(f32::to_bits)));
        for band in 0..bands.count {
            bits.extend(film.band(k, band).unwrap().iter().map(|v| v.to_bits()));
        }
    }
    bits
}

/// Same seed, same image, bit for bit, on 1, 2 and 3 threads: the light paths come in fixed
/// blocks whose splats are summed in block order. Polarised and not, several blocks (10 000
/// light paths in blocks of 512), spectral bands too, the second pass guided by the first.
#[test]
fn caustics_are_bit_identical_for_any_thread_count() {
    let mut scene = scene("tp6_mirror_glass_caustics.toml");
    scene.camera = scene.camera.with_resolution(60, 40).unwrap();
    let bands = SpectralBands { count: 5, min_nm: 400.0, max_nm: 700.0 };
    for polarized in [true, false] {
        let mut settings = scene.settings.clone();
        settings.spp = 2;
        settings.light_paths = Some(5000);
        settings.polarized = polarized;
        let job = |threads| Job { threads, bands: Some(bands), ..Job::new(settings.clone()) };
        let (one, stats) = render(&scene, &job(1)).unwrap();
        assert_eq!(stats.light_paths, 10_000);
        assert!(stats.light_rays > 10_000, "{stats:?}");
        // The second pass starts its paths by the guide learned from the first.
        assert!(stats.light_guide_gain.is_some_and(|g| g >= prisma::integrator::guide::MIN_PREDICTED_GAIN));
        let (two, _) = render(&scene, &job(2)).unwrap();
        let (three, _) = render(&scene, &job(3)).unwrap();
        assert_eq!(bits(&one, &bands), bits(&two, &bands), "polarized = {polarized}");
        assert_eq!(bits(&one, &bands), bits(&three, &bands), "polarized = {polarized}");
    }
}

/// The caustics add light: the glass sphere's focus under it is bright with caustics and black
/// (its shadow) without.
#[test]
fn caustics_light_the_shadow_of_the_glass_sphere() {
    let mut scene = scene("tp6_mirror_glass_caustics.toml");
    scene.camera = scene.camera.with_resolution(60, 40).unwrap();
    let mut settings = scene.settings.clone();
    settings.spp = 2;
    settings.light_paths = Some(20_000);
    let (with, _) = render(&scene, &Job { threads: 2, ..Job::new(settings.clone()) }).unwrap();
    settings.caustics = false;
    let (without, _) = render(&scene, &Job { threads: 2, ..Job::new(settings) }).unwrap();
    let sum = |film: &Film| film.xyz().iter().map(|p| f64::from(p.y)).sum::<f64>();
    assert!(sum(&with) > sum(&without) * 1.01, "{} vs {}", sum(&with), sum(&without));
    // Where the camera sees the spheres or the background, nothing changes.
    let unchanged = with.xyz().iter().zip(without.xyz()).filter(|(a, b)| a == b).count();
    assert!(unchanged > 60 * 40 / 10, "{unchanged} pixels unchanged");
}

/// The decomposition: Whitted counts every path whose first diffuse vertex sees a light
/// directly, the light tracer only paths through a mirror or glass first. With neither in the
/// scene, caustics on and off give the same EXR values, bit for bit.
#[test]
fn without_mirrors_or_glass_caustics_change_nothing() {
    let scene = scene("tp6_point.toml");
    let mut settings = scene.settings.clone();
    settings.spp = 2;
    settings.light_paths = Some(5000);
    let bands = SpectralBands { count: 3, min_nm: 400.0, max_nm: 700.0 };
    let mut small = scene.clone();
    small.camera = small.camera.with_resolution(60, 40).unwrap();
    let off = render(&small, &Job { threads: 2, bands: Some(bands), ..Job::new(settings.clone()) }).unwrap();
    settings.caustics = true;
    let on = render(&small, &Job { threads: 2, bands: Some(bands), ..Job::new(settings) }).unwrap();
    assert_eq!(on.1.light_paths, 0, "no light path is traced where no caustic can form");
    assert_eq!(bits(&on.0, &bands), bits(&off.0, &bands));
}

/// The command line warns (one line, exit 0) when caustics are asked for where none can form,
/// and renders Whitted's image; the EXR is the same file as without the flag.
#[test]
fn caustics_without_glass_warn_and_render_whitted() {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/tp6_point.toml");
    let run = |out: &str, extra: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_prisma"))
            .arg("render")
            .arg(&scene_path)
            .args(["--width", "30", "--spp", "1", "-o"])
            .arg(dir.path().join(out))
            .args(extra)
            .output()
            .unwrap()
    };
    let with = run("with.exr", &["--caustics"]);
    assert!(with.status.success());
    let stderr = String::from_utf8_lossy(&with.stderr);
    assert!(stderr.contains("warning") && stderr.contains("no mirror or glass"), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    let without = run("without.exr", &[]);
    assert!(without.status.success());
    // The same pixels, bit for bit (the headers differ: wall time).
    let read = |name: &str| prisma::output::exr::read_exr(&dir.path().join(name)).unwrap();
    let (with, without) = (read("with.exr"), read("without.exr"));
    let names: Vec<&str> = with.channel_names().collect();
    assert_eq!(names, without.channel_names().collect::<Vec<_>>());
    for name in names {
        let bits = |image: &prisma::output::exr::ExrImage| -> Vec<u32> {
            image.channel(name).unwrap().iter().map(|v| v.to_bits()).collect()
        };
        assert!(bits(&with) == bits(&without), "channel {name} differs");
    }
}

/// A beam at normal incidence on a Lambertian plane (ρ = 0.5, E = 2) gives it radiance
/// ρ/π·E inside the beam's footprint and nothing outside; a spot light at height h gives
/// ρ/π·I/h² under it (Whitted's direct light, no caustics).
#[test]
fn beams_and_spots_light_diffuse_surfaces_in_whitted() {
    let text = |light: &str| {
        format!(
            "[camera]\nposition = [0, 2.5, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, 1]\nfov_y_deg = 40\nwidth = 21\nheight = 21\n\
             [render]\nspp = 4\n[materials.paper]\ntype = \"diffuse\"\nalbedo = 0.5\n\
             [[shapes]]\ntype = \"plane\"\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\nmaterial = \"paper\"\n{light}"
        )
    };
    let beam = "[[lights]]\ntype = \"beam\"\ncorner = [-0.5, 3, -0.5]\nedge1 = [1, 0, 0]\nedge2 = [0, 0, 1]\nirradiance = 2\nemit = \"edge1_cross_edge2\"\n";
    let spot = "[[lights]]\ntype = \"spot\"\nposition = [0, 2, 0]\nlook_at = [0, 0, 0]\nintensity = 3\ncutoff_deg = 10\n";
    let render_at = |light: &str| {
        let scene = prisma::scene::parse(&text(light), std::path::Path::new("<test>")).unwrap();
        let job = Job { threads: 2, monochromatic_nm: Some(550.0), ..Job::new(scene.settings.clone()) };
        render(&scene, &job).unwrap().0
    };
    let centre = 10 * 21 + 10;
    let lit = render_at(beam);
    let expected = 0.5 / std::f32::consts::PI * 2.0;
    assert!((lit.xyz()[centre].y - expected).abs() < 1e-4 * expected, "{}", lit.xyz()[centre].y);
    assert_eq!(lit.xyz()[0].y, 0.0, "outside the beam");
    let spotlit = render_at(spot);
    let expected = 0.5 / std::f32::consts::PI * 3.0 / 4.0;
    assert!((spotlit.xyz()[centre].y - expected).abs() < 2e-3 * expected, "{}", spotlit.xyz()[centre].y);
    assert_eq!(spotlit.xyz()[0].y, 0.0, "outside the cone");
}

/// `--width` and `--height` scale the scene file's `light_paths` with the pixel count (a
/// preview keeps the caustics' light paths per pixel, and their noise, as the camera samples
/// do); `--light-paths` is taken as given; a scaled count above the limit is a one-line input
/// error (exit 2, no image) when caustics are on, and ignored, as the count is, when they are off.
#[test]
fn resolution_flags_scale_the_scenes_light_paths() {
    let dir = tempfile::tempdir().unwrap();
    let render = |scene: &std::path::Path, extra: &[&str]| {
        let stats = dir.path().join("stats.json");
        let _ = std::fs::remove_file(&stats);
        let output = Command::new(env!("CARGO_BIN_EXE_prisma"))
            .arg("render")
            .arg(scene)
            .args(["--spp", "1", "--quiet", "-o"])
            .arg(dir.path().join("image.exr"))
            .arg("--stats")
            .arg(&stats)
            .args(extra)
            .output()
            .unwrap();
        let figures = std::fs::read_to_string(&stats).ok().map(|text| {
            serde_json::from_str::<serde_json::Value>(&text).unwrap()["light_paths"].as_u64().unwrap()
        });
        (output, figures)
    };
    // glass_sphere_spot: 360 000 light paths per pass at 800 × 450. At 40 × 23 (the height
    // follows the 16:9 aspect, 22.5 rounded up): 360 000 · 920 / 360 000 = 920.
    let spot = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/glass_sphere_spot.toml");
    let (output, paths) = render(&spot, &["--width", "40"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert_eq!(paths, Some(920));
    let (output, paths) = render(&spot, &["--width", "40", "--light-paths", "300"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert_eq!(paths, Some(300));

    // 2⁴⁰ per pass at 2 × 1 pixels, rendered at 4 × 2: four times the limit.
    let text = std::fs::read_to_string(&spot).unwrap();
    let huge = text
        .replace("width = 800", "width = 2")
        .replace("height = 450", "height = 1")
        .replace("light_paths = 360000", "light_paths = 1099511627776");
    let huge_path = dir.path().join("huge.toml");
    std::fs::write(&huge_path, huge).unwrap();
    std::fs::remove_file(dir.path().join("image.exr")).unwrap();
    let (output, paths) = render(&huge_path, &["--width", "4", "--height", "2"]);
    assert_eq!(output.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(stderr.contains("huge.toml") && stderr.contains("render.light_paths"), "{stderr}");
    assert_eq!(paths, None);
    assert!(!dir.path().join("image.exr").exists(), "no image after an input error");
    // Without caustics the count is not used, so it is not refused either.
    let (output, paths) = render(&huge_path, &["--width", "4", "--height", "2", "--no-caustics"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert_eq!(paths, Some(0));
}

/// Where light straight from the light meets glass, the light tracer follows both Fresnel
/// branches (module docs of `integrator::light_tracer`, "Branches at glass"). The ball of the
/// caustic bench reflects part of its spot light over the floor around it, dimly (0.1–1 % of
/// the directly lit floor's brightest pixel) and thinly: chosen with probability R ≈ 0.08, that
/// reflection came as rare photons of the full flux, and one pass of 12,288 light paths lit 7 %
/// of those floor pixels; with the reflected branch traced from every path that meets the ball,
/// 23 %. The region is found from a 64-pass render's light-tracer part (caustics on minus off,
/// the same seed, so the same camera samples), outside the directly lit floor and the caustic;
/// either way of branching finds nearly the same region there (3,768 and 3,894 pixels).
#[test]
fn one_pass_spreads_the_balls_reflection_over_the_floor() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("validation/scenes/caustic_sphere.toml");
    let scene = prisma::scene::load(&path).unwrap();
    // Luminance Y of the directly lit part and of the light tracer's part, per pixel.
    let parts = |spp: u32| {
        let mut settings = scene.settings.clone();
        settings.spp = spp;
        settings.polarized = false;
        settings.seed = 3;
        let job = |settings: prisma::scene::RenderSettings| Job {
            threads: 2,
            monochromatic_nm: Some(550.0),
            ..Job::new(settings)
        };
        let (on, _) = render(&scene, &job(settings.clone())).unwrap();
        settings.caustics = false;
        let (off, _) = render(&scene, &job(settings)).unwrap();
        let direct: Vec<f32> = off.xyz().iter().map(|p| p.y).collect();
        let light: Vec<f32> = on.xyz().iter().zip(off.xyz()).map(|(a, b)| a.y - b.y).collect();
        (direct, light)
    };
    let (direct, converged) = parts(64);
    let (_, one_pass) = parts(1);
    let brightest_direct = direct.iter().copied().fold(0.0, f32::max);
    let dim = |value: f32| value > 1e-3 * brightest_direct && value < 1e-2 * brightest_direct;
    let region: Vec<usize> = (0..direct.len()).filter(|&i| direct[i] == 0.0 && dim(converged[i])).collect();
    let lit = region.iter().filter(|&&i| one_pass[i] > 0.0).count();
    assert!(region.len() > 3000, "{} pixels", region.len());
    assert!(lit as f64 > 0.15 * region.len() as f64, "{lit} of {} pixels lit in one pass", region.len());
}

/// The pass that holds both the guide's learning paths and guided ones weighs them unequally
/// (`integrator::guide::PathWeights`): the pass must stay an unbiased estimate, checked against
/// Mitsuba's particle tracer. One pass of 6,144 light paths (512 learning, at 0.522 each, and
/// 5,632 guided, at 1.043) of the caustic bench's ball at 550 nm, 48 seeds: their mean light on
/// the floor outside the spot's direct light (pixels whose Whitted image and neighbours' are
/// black: the caustic, the ball's shadow and the dim floor its reflection lights, where the
/// light tracer makes all the light) against the committed 50 M-path references, within four
/// standard errors (the seeds' spread and the two references' difference; measured 146.71 ±
/// 0.06 against 146.85 ± 0.01, and 146.80, 146.85 and 146.86 with three other sets of 48
/// seeds). Weights that do not add up to the pass's paths (the learning paths halved alone)
/// leave it 4 % darker (140.6) and fail.
#[test]
fn a_pass_of_learning_and_guided_paths_is_unbiased() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = prisma::scene::load(&root.join("validation/scenes/caustic_sphere.toml")).unwrap();
    let luminance =
        |film: &Film| -> Vec<f64> { film.stokes_srgb(0).unwrap().iter().map(|p| f64::from(p[1])).collect() };
    let job = |seed: u64, caustics: bool, spp: u32| {
        let mut settings = scene.settings.clone();
        (settings.spp, settings.seed, settings.caustics, settings.polarized) = (spp, seed, caustics, false);
        settings.light_paths = Some(6144);
        Job { threads: 2, monochromatic_nm: Some(550.0), progress: false, ..Job::new(settings) }
    };
    let reference = |name: &str| -> Vec<f64> {
        let image = prisma::output::exr::read_exr(&root.join("validation/references").join(name)).unwrap();
        image.channel("Y").unwrap().iter().map(|&v| f64::from(v)).collect()
    };
    let (ref_a, ref_b) =
        (reference("caustic_sphere_550_seed1.exr"), reference("caustic_sphere_550_seed2.exr"));
    // No direct light in a pixel or its neighbours (16 camera samples each), and floor in both
    // references (ptracer leaves the ball black).
    let (direct, _) = render(&scene, &job(1, false, 16)).unwrap();
    let direct = luminance(&direct);
    let (w, h) = (scene.camera.width() as usize, scene.camera.height() as usize);
    let dark =
        |x: usize, y: usize| direct[y * w + x] == 0.0 && ref_a[y * w + x] > 0.0 && ref_b[y * w + x] > 0.0;
    let unlit: Vec<usize> = (1..h - 1)
        .flat_map(|y| (1..w - 1).map(move |x| (x, y)))
        .filter(|&(x, y)| (y - 1..=y + 1).all(|ny| (x - 1..=x + 1).all(|nx| dark(nx, ny))))
        .map(|(x, y)| y * w + x)
        .collect();
    assert!(unlit.len() > 300, "{} unlit pixels", unlit.len());
    let total = |image: &[f64]| unlit.iter().map(|&i| image[i]).sum::<f64>();
    let totals: Vec<f64> = (0..48)
        .map(|seed| total(&luminance(&render(&scene, &job(100 + seed, true, 1)).unwrap().0)))
        .collect();
    let mean = totals.iter().sum::<f64>() / totals.len() as f64;
    let spread = totals.iter().map(|t| (t - mean).powi(2)).sum::<f64>() / (totals.len() - 1) as f64;
    let expected = 0.5 * (total(&ref_a) + total(&ref_b));
    let reference_variance = (0.5 * (total(&ref_a) - total(&ref_b))).powi(2);
    let standard_error = (spread / totals.len() as f64 + reference_variance).sqrt();
    eprintln!(
        "unlit light: {mean:.5} (seeds' standard error {:.5}) against Mitsuba {expected:.5} (± {:.5}), {} pixels",
        (spread / totals.len() as f64).sqrt(),
        reference_variance.sqrt(),
        unlit.len()
    );
    assert!((mean - expected).abs() < 4.0 * standard_error, "{mean} against {expected} ± {standard_error}");
    assert!(standard_error < 0.02 * expected, "too noisy to see a bias: ± {standard_error} of {expected}");
}

//! Same scene and seed give bit-identical output whatever the thread count, and an EXR written and
//! read back holds exactly the rendered values.

use prisma::film::SpectralBands;
use prisma::output::exr::{read_exr, spectral_channel_name, write_exr};
use prisma::render::{render, Job};

fn small_scene() -> prisma::scene::Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/tp6_mirror_flint.toml");
    let mut scene = prisma::scene::load(&path).unwrap();
    scene.camera = scene.camera.with_resolution(60, 40).unwrap();
    scene.settings.spp = 3;
    scene
}

#[test]
fn one_and_two_threads_give_identical_images() {
    let scene = small_scene();
    let bands = SpectralBands { count: 6, min_nm: 400.0, max_nm: 700.0 };
    let job = |threads| Job { threads, bands: Some(bands), ..Job::new(scene.settings.clone()) };
    let (one, _) = render(&scene, &job(1)).unwrap();
    let (two, _) = render(&scene, &job(2)).unwrap();
    let (three, _) = render(&scene, &job(3)).unwrap();
    assert!(one.layout().stokes, "renders are polarised by default");
    // Every value of the film: the Stokes components and the spectral bands too.
    let bits = |f: &prisma::film::Film| {
        let mut bits = Vec::new();
        for k in 0..4 {
            bits.extend(f.stokes_xyz(k).unwrap().iter().flat_map(|p| p.to_array().map(f32::to_bits)));
            for band in 0..bands.count {
                bits.extend(f.band(k, band).unwrap().iter().map(|v| v.to_bits()));
            }
        }
        bits
    };
    assert_eq!(bits(&one), bits(&two));
    assert_eq!(bits(&one), bits(&three));
}

/// The path tracer too: its paths are a loop, its dispersive splits queued in a fixed order, and
/// its random numbers drawn per sample, so the thread count cannot change a bit.
#[test]
fn the_path_tracer_gives_identical_images_on_any_thread_count() {
    let mut scene = small_scene();
    scene.settings.integrator = prisma::scene::IntegratorKind::Path;
    scene.settings.max_depth = 64;
    scene.settings.area_light_samples = 1;
    let job = |threads| Job { threads, ..Job::new(scene.settings.clone()) };
    let (one, _) = render(&scene, &job(1)).unwrap();
    let (two, _) = render(&scene, &job(2)).unwrap();
    let (three, _) = render(&scene, &job(3)).unwrap();
    let bits = |f: &prisma::film::Film| {
        (0..4)
            .flat_map(|k| {
                f.stokes_xyz(k)
                    .unwrap()
                    .iter()
                    .flat_map(|p| p.to_array().map(f32::to_bits))
                    .collect::<Vec<_>>()
            })
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&one), bits(&two));
    assert_eq!(bits(&one), bits(&three));
    // And it is another image than Whitted's (interreflection adds light).
    let mut whitted = scene.settings.clone();
    whitted.integrator = prisma::scene::IntegratorKind::Whitted;
    let (w, _) = render(&scene, &Job { threads: 2, ..Job::new(whitted) }).unwrap();
    assert_ne!(bits(&one), bits(&w));
}

#[test]
fn different_seeds_give_different_images() {
    let scene = small_scene();
    let mut settings = scene.settings.clone();
    let (a, _) =
        render(&scene, &Job { threads: 2, monochromatic_nm: None, ..Job::new(settings.clone()) }).unwrap();
    settings.seed += 1;
    let (b, _) = render(&scene, &Job { threads: 2, ..Job::new(settings) }).unwrap();
    assert_ne!(a.xyz(), b.xyz());
}

#[test]
fn exr_round_trip_is_exact() {
    let scene = small_scene();
    let bands = SpectralBands { count: 4, min_nm: 380.0, max_nm: 780.0 };
    let job = Job { threads: 2, bands: Some(bands), ..Job::new(scene.settings.clone()) };
    let (film, _) = render(&scene, &job).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("round_trip.exr");
    write_exr(&path, &film).unwrap();
    let image = read_exr(&path).unwrap();
    assert_eq!((image.width, image.height), (60, 40));
    let rgb = film.linear_srgb();
    assert_eq!(image.rgb(["R", "G", "B"]).unwrap(), rgb);
    assert_eq!(image.rgb(["XYZ.X", "XYZ.Y", "XYZ.Z"]).unwrap(), film.xyz());
    assert!(image.channel("A").unwrap().iter().all(|&a| a == 1.0));
    // The Stokes layers as Mitsuba's `stokes` integrator names them, S0 equal to RGB.
    assert_eq!(image.rgb(["S0.R", "S0.G", "S0.B"]).unwrap(), rgb);
    for k in 1..4 {
        let names = ["R", "G", "B"].map(|c| format!("S{k}.{c}"));
        let stokes = image.rgb([names[0].as_str(), names[1].as_str(), names[2].as_str()]).unwrap();
        assert_eq!(stokes, film.stokes_srgb(k).unwrap());
    }
    // The spectral layout: a channel per band and component, at the band centres.
    assert_eq!(spectral_channel_name(0, 430.0), "S0.430,000000nm");
    for k in 0..4 {
        for band in 0..bands.count {
            let name = spectral_channel_name(k, bands.center_nm(band));
            assert_eq!(image.channel(&name).unwrap(), film.band(k, band).unwrap().as_slice(), "{name}");
        }
    }
    assert_eq!(image.attribute("spectralLayoutVersion"), Some("1.0"));
    assert_eq!(image.attribute("emissiveUnits"), Some("W.m^-2.sr^-1"));
    assert_eq!(image.attribute("polarisationHandedness"), Some("right"));
}

/// A single-wavelength render is written as what it is: one spectral radiance channel per
/// Stokes component, its wavelength in the header, no colour channels.
#[test]
fn monochromatic_exr_is_one_spectral_channel() {
    let scene = small_scene();
    let job = Job { threads: 2, monochromatic_nm: Some(532.0), ..Job::new(scene.settings.clone()) };
    let (film, _) = render(&scene, &job).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mono.exr");
    write_exr(&path, &film).unwrap();
    let image = read_exr(&path).unwrap();
    let names: Vec<&str> = image.channel_names().collect();
    assert_eq!(names, ["S0.532,000000nm", "S1.532,000000nm", "S2.532,000000nm", "S3.532,000000nm"]);
    let radiance: Vec<f32> = film.xyz().iter().map(|p| p.x).collect();
    assert_eq!(image.channel("S0.532,000000nm").unwrap(), radiance.as_slice());
    assert_eq!(image.attribute("wavelengthNm"), Some("532"));
    assert_eq!(image.attribute("chromaticities"), None);
}

/// Regression: the EXR file itself, not only its pixels, is the same every time. The exr crate
/// compresses blocks in parallel and, with an unspecified line order, wrote them in whatever order
/// they finished, so two writes of one image differed in their offset tables.
#[test]
fn exr_files_are_byte_identical() {
    // Large enough for the writer to compress blocks in parallel.
    let mut scene = small_scene();
    scene.camera = scene.camera.with_resolution(800, 450).unwrap();
    scene.settings.spp = 1;
    let job = Job { threads: 2, monochromatic_nm: None, ..Job::new(scene.settings.clone()) };
    let (film, _) = render(&scene, &job).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let bytes: Vec<Vec<u8>> = (0..8)
        .map(|k| {
            let path = dir.path().join(format!("write{k}.exr"));
            write_exr(&path, &film).unwrap();
            std::fs::read(&path).unwrap()
        })
        .collect();
    for other in &bytes[1..] {
        assert!(other == &bytes[0], "two writes of the same image differ");
    }
}

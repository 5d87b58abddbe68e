//! Same scene and seed give bit-identical output whatever the thread count, and an EXR written and
//! read back holds exactly the rendered values.

use prisma::output::exr::{read_exr, write_exr};
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
    let job = |threads| Job { threads, monochromatic_nm: None, ..Job::new(scene.settings.clone()) };
    let (one, _) = render(&scene, &job(1)).unwrap();
    let (two, _) = render(&scene, &job(2)).unwrap();
    let (three, _) = render(&scene, &job(3)).unwrap();
    let bits = |f: &prisma::film::Film| {
        f.xyz().iter().flat_map(|p| p.to_array().map(f32::to_bits)).collect::<Vec<_>>()
    };
    assert_eq!(bits(&one), bits(&two));
    assert_eq!(bits(&one), bits(&three));
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
    let job = Job { threads: 2, monochromatic_nm: None, ..Job::new(scene.settings.clone()) };
    let (film, _) = render(&scene, &job).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("round_trip.exr");
    let rgb = film.linear_srgb();
    write_exr(&path, film.width(), film.height(), &rgb, film.xyz()).unwrap();
    let image = read_exr(&path).unwrap();
    assert_eq!((image.width, image.height), (60, 40));
    assert_eq!(image.rgb(["R", "G", "B"]).unwrap(), rgb);
    assert_eq!(image.rgb(["XYZ.X", "XYZ.Y", "XYZ.Z"]).unwrap(), film.xyz());
    assert!(image.channel("A").unwrap().iter().all(|&a| a == 1.0));
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
    let rgb: Vec<glam::Vec3> =
        film.xyz().iter().map(|&xyz| prisma::spectrum::color::xyz_to_linear_srgb(xyz)).collect();
    let dir = tempfile::tempdir().unwrap();
    let bytes: Vec<Vec<u8>> = (0..8)
        .map(|k| {
            let path = dir.path().join(format!("write{k}.exr"));
            write_exr(&path, film.width(), film.height(), &rgb, film.xyz()).unwrap();
            std::fs::read(&path).unwrap()
        })
        .collect();
    for other in &bytes[1..] {
        assert!(other == &bytes[0], "two writes of the same image differ");
    }
}

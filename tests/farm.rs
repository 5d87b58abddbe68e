//! Split renders (issue 18): any split of a render's samples and pixels into parts merges into
//! the single render's bits, parts that do not belong together are refused, and an interrupted
//! render resumes into the uninterrupted image. Tiny images: each test takes about a second.

mod shipped;

use std::path::PathBuf;

use prisma::film::{SpectralBands, WindowSums};
use prisma::part::{merge, Part, PartHeader, PixelWindow, SampleSet};
use prisma::render::{render_sums, Job, Rendered};
use prisma::scene::Scene;
use shipped::scene;

/// Renders `samples` of `window` and wraps the result as a part (as `prisma render` does).
fn part(
    scene: &Scene,
    job: &Job,
    samples: &str,
    window: Option<PixelWindow>,
    threads: usize,
) -> (PathBuf, Part) {
    let job = Job { samples: Some(SampleSet::parse(samples).unwrap()), window, threads, ..job.clone() };
    let rendered: Rendered = render_sums(scene, &job).unwrap();
    assert!(!rendered.interrupted);
    let window = rendered.sums.window();
    let mut header =
        PartHeader::new("test", scene, &job.settings, &job.layout(), rendered.light_paths_per_pass, window);
    header.samples = rendered.samples.clone();
    (PathBuf::from(format!("{samples} of {window}")), Part { header, sums: rendered.sums })
}

/// Every bit of the image of some sums.
fn image_bits(sums: &WindowSums, samples: u64, light_paths: u64, display: (u32, u32)) -> Vec<u32> {
    let film = sums.film(samples, light_paths, display);
    let mut bits = Vec::new();
    for k in 0..film.layout().components() {
        bits.extend(film.stokes_xyz(k).unwrap().iter().flat_map(|v| v.to_array().map(f32::to_bits)));
        if let Some(bands) = film.layout().bands {
            for band in 0..bands.count {
                bits.extend(film.band(k, band).unwrap().iter().map(|v| v.to_bits()));
            }
        }
    }
    bits
}

/// Checks that each partition (lists of (samples, window)) merges, in the order given and
/// reversed, into the sums and image of the single render.
fn check_partitions(scene: &Scene, job: &Job, partitions: &[Vec<(&str, Option<PixelWindow>)>]) {
    // With edge refinement, which parts that do not hold the first pass or whose window has
    // neighbours outside it must reproduce.
    let mut job = job.clone();
    job.settings.edge_samples = 4;
    let job = &job;
    let display = (scene.camera.width(), scene.camera.height());
    let whole = format!("0..{}", job.settings.spp);
    let (_, single) = part(scene, job, &whole, None, 2);
    let single_bits =
        image_bits(&single.sums, u64::from(job.settings.spp), single.header.light_paths_per_pass, display);
    // The plain render path gives the same image as the sums of a "part" of everything.
    let (film, stats) = prisma::render::render(scene, &Job { threads: 1, ..job.clone() }).unwrap();
    // Parts that do not hold the first pass, or whose window has neighbours outside it, render
    // the first pass for the edge map alone: the splits below must meet refined pixels.
    assert!(stats.edge_pixels > 0, "no edge pixel: the splits do not exercise edge refinement");
    assert_eq!(
        film.xyz(),
        single.sums.film(u64::from(job.settings.spp), single.header.light_paths_per_pass, display).xyz()
    );
    for (i, partition) in partitions.iter().enumerate() {
        let mut parts: Vec<(PathBuf, Part)> = partition
            .iter()
            .enumerate()
            .map(|(j, (samples, window))| part(scene, job, samples, *window, 1 + j % 2))
            .collect();
        for order in 0..2 {
            if order == 1 {
                parts.reverse();
            }
            let merged = merge(&parts, true).unwrap_or_else(|e| panic!("partition {i}: {e}"));
            assert_eq!(merged.header.samples.to_string(), whole);
            assert!(merged.sums == single.sums, "partition {i}, order {order}: the sums differ");
            let bits = image_bits(
                &merged.sums,
                merged.header.samples.len(),
                merged.header.light_paths_per_pass,
                display,
            );
            assert!(bits == single_bits, "partition {i}, order {order}: the image differs");
        }
    }
}

fn halves(width: u32, height: u32) -> [Option<PixelWindow>; 2] {
    [
        Some(PixelWindow { x0: 0, y0: 0, x1: width, y1: height / 2 }),
        Some(PixelWindow { x0: 0, y0: height / 2, x1: width, y1: height }),
    ]
}

/// Polarised Whitted with spectral bands, a dispersive prism: sample splits, crop splits, a mix
/// of both where different pixels are split differently, in two orders and with 1 and 2
/// threads, all give the single render's bits.
#[test]
fn polarised_spectral_splits_merge_bit_identically() {
    let scene = scene("tp6_mirror_flint.toml", 24, 16);
    let mut job = Job::new(scene.settings.clone());
    job.settings.spp = 6;
    job.bands = Some(SpectralBands { count: 5, min_nm: 400.0, max_nm: 700.0 });
    let [top, bottom] = halves(24, 16);
    let left = Some(PixelWindow { x0: 0, y0: 8, x1: 10, y1: 16 });
    let right = Some(PixelWindow { x0: 10, y0: 8, x1: 24, y1: 16 });
    check_partitions(
        &scene,
        &job,
        &[
            vec![("0..2", None), ("2..6", None)],
            vec![("3..4", None), ("0..1,4..6", None), ("1..3", None)],
            vec![("0..6", top), ("0..6", bottom)],
            vec![("0..3", None), ("3..6", top), ("3..5", left), ("3..5", right), ("5..6", bottom)],
        ],
    );
}

/// The path tracer (full transport) with the light tracer beside it, polarised, through a
/// dispersive flint sphere (lanes split into paths of their own): the same splits give the
/// single render's bits.
#[test]
fn path_tracer_splits_merge_bit_identically() {
    let scene = scene("tp6_mirror_flint.toml", 24, 16);
    let mut job = Job::new(scene.settings.clone());
    job.settings.integrator = prisma::scene::IntegratorKind::Path;
    job.settings.max_depth = 64;
    job.settings.area_light_samples = 1;
    job.settings.caustics = true;
    job.settings.light_paths = Some(700);
    job.settings.spp = 4;
    let [top, bottom] = halves(24, 16);
    check_partitions(
        &scene,
        &job,
        &[vec![("0..1", None), ("1..4", None)], vec![("0..4", top), ("0..2", bottom), ("2..4", bottom)]],
    );
}

/// Unpolarised transport, the same way.
#[test]
fn unpolarised_splits_merge_bit_identically() {
    let scene = scene("showcase.toml", 32, 18);
    let mut job = Job::new(scene.settings.clone());
    job.settings.spp = 4;
    job.settings.polarized = false;
    let [top, bottom] = halves(32, 18);
    check_partitions(&scene, &job, &[vec![("0..1", top), ("1..4", top), ("0..4", bottom)]]);
}

/// With caustics, light paths are split by samples (passes), here of 700 paths, so that parts
/// start and end inside the light tracer's blocks of 512 paths; a crop traces all the light
/// paths of its samples and keeps the splats in its window.
#[test]
fn caustic_splits_by_samples_merge_bit_identically() {
    let scene = scene("tp6_mirror_glass_caustics.toml", 24, 16);
    let mut job = Job::new(scene.settings.clone());
    job.settings.spp = 7;
    job.settings.caustics = true;
    job.settings.light_paths = Some(700);
    let [top, bottom] = halves(24, 16);
    check_partitions(
        &scene,
        &job,
        &[vec![("0..3", None), ("3..7", None)], vec![("0..7", top), ("0..5", bottom), ("5..7", bottom)]],
    );
    let (_, whole) = part(&scene, &job, "0..7", None, 2);
    assert!(whole.sums.light().iter().any(|s| !s.is_zero()), "the light tracer splatted");
    // The guide learns from the first 512 light paths (most of the first pass): parts without
    // them (3..7, 5..7) trace those paths to learn it, and must learn the same guide.
    let guided = render_sums(&scene, &job).unwrap();
    let gain = guided.stats.light_guide_gain.expect("a guide was learned");
    assert!(gain >= prisma::integrator::guide::MIN_PREDICTED_GAIN, "the guide is used: {gain}");
}

/// A render with caustics stopped after its first sample block, resumed and merged, gives the
/// uninterrupted render: the resumed part, which lacks the guide's learning pass, learns the
/// same guide.
#[test]
fn an_interrupted_caustic_render_resumes_into_the_uninterrupted_image() {
    let scene = scene("tp6_mirror_glass_caustics.toml", 24, 16);
    let mut job = Job::new(scene.settings.clone());
    job.settings.spp = 4;
    job.settings.caustics = true;
    job.settings.light_paths = Some(5000);
    job.settings.edge_samples = 4;
    let stopped = render_sums(&scene, &Job { stop_after_blocks: Some(1), ..job.clone() }).unwrap();
    assert_eq!(stopped.samples.to_string(), "0..1", "the first block is one sample");
    let rest = stopped.samples.missing_below(4);
    let resumed = render_sums(&scene, &Job { samples: Some(rest), ..job.clone() }).unwrap();
    let whole = render_sums(&scene, &job).unwrap();
    assert!(whole.stats.edge_pixels > 0);
    assert!(whole.stats.light_guide_gain.is_some_and(|g| g >= prisma::integrator::guide::MIN_PREDICTED_GAIN));
    assert_eq!(resumed.stats.light_guide_gain, whole.stats.light_guide_gain);
    let mut sums = stopped.sums.clone();
    sums.add(&resumed.sums).unwrap();
    assert!(sums == whole.sums);
}

/// The same for full transport: the path tracer with the light tracer past the first diffuse
/// vertex, stopped after its first block and resumed, gives the uninterrupted sums.
#[test]
fn an_interrupted_path_render_resumes_into_the_uninterrupted_image() {
    let scene = scene("tp6_mirror_glass_caustics.toml", 24, 16);
    let mut job = Job::new(scene.settings.clone());
    job.settings.integrator = prisma::scene::IntegratorKind::Path;
    job.settings.max_depth = 64;
    job.settings.area_light_samples = 1;
    job.settings.spp = 4;
    job.settings.light_paths = Some(3000);
    let stopped = render_sums(&scene, &Job { stop_after_blocks: Some(1), ..job.clone() }).unwrap();
    assert!(stopped.interrupted);
    let rest = stopped.samples.missing_below(4);
    let resumed = render_sums(&scene, &Job { samples: Some(rest), ..job.clone() }).unwrap();
    let whole = render_sums(&scene, &job).unwrap();
    let mut sums = stopped.sums.clone();
    sums.add(&resumed.sums).unwrap();
    assert!(sums == whole.sums);
}

/// A render stopped after its first sample block holds the first samples exactly; rendering
/// the rest and merging gives the uninterrupted render.
#[test]
fn an_interrupted_render_resumes_into_the_uninterrupted_image() {
    let scene = scene("tp6_mirror_flint.toml", 20, 12);
    let mut job = Job::new(scene.settings.clone());
    job.settings.spp = 5;
    job.settings.edge_samples = 4;
    let stopped = render_sums(&scene, &Job { stop_after_blocks: Some(1), ..job.clone() }).unwrap();
    assert!(stopped.interrupted);
    assert_eq!(stopped.samples.to_string(), "0..1", "the first block is one sample");
    let rest = stopped.samples.missing_below(5);
    let resumed = render_sums(&scene, &Job { samples: Some(rest), ..job.clone() }).unwrap();
    let whole = render_sums(&scene, &job).unwrap();
    assert!(whole.stats.edge_pixels > 0);
    let mut sums = stopped.sums.clone();
    sums.add(&resumed.sums).unwrap();
    assert!(sums == whole.sums);
    let nothing = render_sums(&scene, &Job { stop_after_blocks: Some(0), ..job }).unwrap();
    assert!(nothing.interrupted && nothing.samples.is_empty());
}

/// The one-line message of a refused merge (no runs of spaces: two messages once carried a
/// line's indentation in the middle).
fn refusal(parts: &[(PathBuf, Part)], complete: bool) -> String {
    let message = merge(parts, complete).expect_err("refused").to_string();
    assert!(!message.contains('\n') && !message.contains("  "), "{message:?}");
    message
}

/// Each reason to refuse a merge, with a message naming it.
#[test]
fn merges_of_parts_that_do_not_belong_together_are_refused() {
    let scene = scene("showcase.toml", 16, 8);
    let mut job = Job::new(scene.settings.clone());
    job.settings.spp = 4;
    let [top, bottom] = halves(16, 8);
    let a = part(&scene, &job, "0..2", None, 1);
    let b = part(&scene, &job, "2..4", None, 1);
    let with = |header: fn(&mut PartHeader)| {
        let mut changed = b.clone();
        header(&mut changed.1.header);
        vec![a.clone(), changed]
    };
    assert!(refusal(&with(|h| h.scene_sha256 = "0".repeat(64)), false).contains("different scene"));
    assert!(refusal(&with(|h| h.seed += 1), false).contains("different seed"));
    assert!(refusal(
        &with(|h| h.settings = h.settings.replace("\"max_depth\":12", "\"max_depth\":3")),
        false
    )
    .contains("different settings"));
    assert!(refusal(&with(|h| h.commit = "another".into()), false).contains("different prisma commit"));
    // Parts with and without edge refinement sample edge pixels differently: refused. Without
    // it, the settings do not mention it (parts of earlier versions merge with these).
    assert!(!a.1.header.settings.contains("edge_samples"), "{}", a.1.header.settings);
    let refined = Job {
        settings: prisma::scene::RenderSettings { edge_samples: 4, ..job.settings.clone() },
        ..job.clone()
    };
    let b_refined = part(&scene, &refined, "2..4", None, 1);
    assert!(b_refined.1.header.settings.contains("\"edge_samples\":4"), "{}", b_refined.1.header.settings);
    assert!(refusal(&[a.clone(), b_refined], false).contains("different settings"));
    // Overlapping samples, and overlapping windows with overlapping samples.
    let c = part(&scene, &job, "1..3", None, 1);
    assert!(refusal(&[a.clone(), c], false).contains("overlapping parts"));
    let top_part = part(&scene, &job, "0..4", top, 1);
    assert!(refusal(&[top_part.clone(), a.clone()], false).contains("overlapping parts"));
    // A missing range, with --complete only.
    let message = refusal(std::slice::from_ref(&a), true);
    assert!(message.contains("samples 2..4 of 0..4 are missing"), "{message}");
    assert!(merge(std::slice::from_ref(&a), false).is_ok());
    // A window left out, and windows with different samples.
    let message = refusal(std::slice::from_ref(&top_part), true);
    assert!(message.contains("not the whole 16×8 image"), "{message}");
    let bottom_half = part(&scene, &job, "0..2", bottom, 1);
    let message = refusal(&[top_part.clone(), bottom_half], false);
    assert!(message.contains("every pixel needs the same samples"), "{message}");
    let corner = part(&scene, &job, "0..4", Some(PixelWindow { x0: 0, y0: 4, x1: 8, y1: 8 }), 1);
    let message = refusal(&[top_part, corner], false);
    assert!(message.contains("leave pixels"), "{message}");
    assert!(merge(&[b, a], true).is_ok());
}

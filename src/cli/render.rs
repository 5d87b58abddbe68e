//! `prisma render`: a scene file to `out/<scene>.exr` and `out/<scene>.png`.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, Context};
use clap::Args;

use indicatif::{ProgressBar, ProgressStyle};

use super::destinations::Destinations;
use super::{say, CliError};
use prisma::film::{FilmLayout, SpectralBands, WindowSums};
use prisma::integrator::LightTracer;
use prisma::output::exr::encode_exr_part;
use prisma::output::file::{check_not_inputs, check_regular_input, same_file, text_into, Outputs};
use prisma::output::png::encode_png;
use prisma::part::{read_part, PartHeader, PixelWindow, SampleSet};
use prisma::render::{render_sums, Job, RenderError};
use prisma::scene::build::{MAX_DEPTH, MAX_LIGHT_PATHS, MAX_RESOLUTION, MAX_SPP};
use prisma::scene::{IntegratorKind, RenderSettings};
use prisma::spectrum::{LAMBDA_MAX_NM, LAMBDA_MIN_NM};

/// Arguments of `prisma render`. Flags override the scene file's settings.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Scene file (TOML; see scenes/README.md).
    scene: PathBuf,
    /// Output EXR path [default: out/<scene>.exr, or out/<scene>_<NM>nm.exr with --wavelength].
    #[arg(short, long, value_name = "OUT.exr")]
    output: Option<PathBuf>,
    /// PNG preview path [default: the EXR path with a .png extension].
    #[arg(long, value_name = "OUT.png")]
    preview: Option<PathBuf>,
    /// Samples per pixel.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_SPP)))]
    spp: Option<u32>,
    /// Image width in pixels (alone, the height follows the scene's aspect ratio).
    #[arg(long, value_name = "W", value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_RESOLUTION)))]
    width: Option<u32>,
    /// Image height in pixels (alone, the width follows the scene's aspect ratio).
    #[arg(long, value_name = "H", value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_RESOLUTION)))]
    height: Option<u32>,
    /// The camera's estimator: whitted (Whitted's recursion) or path (full transport)
    /// [default: the scene's `integrator`, else whitted].
    #[arg(long, value_name = "NAME")]
    integrator: Option<String>,
    /// Maximum number of specular bounces (whitted) or of bounces of any kind (path).
    #[arg(long, value_name = "D", value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_DEPTH)))]
    max_depth: Option<u32>,
    /// Render threads [default: one per core]. The image does not depend on it.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    /// Seed of the per-pixel sample sequences.
    #[arg(long, value_name = "S")]
    seed: Option<u64>,
    /// Exposure of the PNG preview in stops (the EXR is never scaled).
    #[arg(long, value_name = "EV", default_value_t = 0.0, allow_negative_numbers = true)]
    exposure: f32,
    /// Render a single wavelength (nm, 360–830): every channel holds the spectral radiance.
    #[arg(long, value_name = "NM", allow_negative_numbers = true)]
    wavelength: Option<f32>,
    /// Do not print the progress bar and the closing summary.
    #[arg(short, long)]
    quiet: bool,
    /// Also write the render's figures (time without loading and writing, rays, samples) as JSON.
    #[arg(long, value_name = "STATS.json")]
    stats: Option<PathBuf>,
    /// Unpolarised transport: each interface's reflectance averaged over s and p, no Stokes
    /// layers. Faster, and wrong wherever light meets a second interface polarised.
    #[arg(long, conflicts_with = "polarized")]
    unpolarized: bool,
    /// Polarised transport even if the scene file turns it off.
    #[arg(long)]
    polarized: bool,
    /// Add caustics by light tracing (light through mirrors and glass onto diffuse surfaces).
    #[arg(long, conflicts_with = "no_caustics")]
    caustics: bool,
    /// No caustics, even if the scene file asks for them.
    #[arg(long)]
    no_caustics: bool,
    /// Start every light path uniformly over its light's emission, without the guide learned
    /// from the render's first light paths (the scene's `light_guide = false`).
    #[arg(long)]
    no_light_guide: bool,
    /// Camera samples per pass of the pixels an edge crosses (shadow borders, silhouettes),
    /// chosen after the first pass; 1 turns edge refinement off [default: the scene's
    /// `edge_samples`, else 1].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=i64::from(prisma::edges::MAX_EDGE_SAMPLES)))]
    edge_samples: Option<u32>,
    /// Light paths per pass with caustics (a render makes one pass per sample per pixel)
    /// [default: the scene's `light_paths`, scaled with the pixel count when --width or --height
    /// change it; else one per pixel].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=MAX_LIGHT_PATHS))]
    light_paths: Option<u64>,
    /// Also write the mean spectral radiance in N bands (Fichet et al. 2021 spectral EXR layout).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024))]
    spectral_bands: Option<u32>,
    /// Wavelength range of the spectral bands, in nm [default: 360-830].
    #[arg(long, value_name = "MIN-MAX", requires = "spectral_bands")]
    spectral_range: Option<String>,
    /// Render only sample indices A ≤ i < B of every pixel (a part of a split render; several
    /// ranges: A..B,C..D). Implies --part.
    #[arg(long, value_name = "A..B", conflicts_with = "resume")]
    samples: Option<String>,
    /// Render only the pixels X0 ≤ x < X1, Y0 ≤ y < Y1 (the EXR's data window; its display window
    /// is the whole image). Implies --part.
    #[arg(long, value_name = "X0,Y0,X1,Y1")]
    crop: Option<String>,
    /// Also write the exact per-pixel sums, so that `prisma merge` and `--resume` can use the file.
    #[arg(long)]
    part: bool,
    /// Render the samples PART.exr (an interrupted render or any part) lacks, up to --spp (or its
    /// own total), and write them merged with it. Implies --part.
    #[arg(long, value_name = "PART.exr")]
    resume: Option<PathBuf>,
    /// Render the embedded default scene instead of reading `scene`.
    #[arg(skip)]
    builtin: bool,
}

impl RenderArgs {
    /// Arguments that render the embedded default scene (scenes/showcase.toml) with its own
    /// settings.
    pub fn default_scene() -> Self {
        Self {
            scene: PathBuf::from(DEFAULT_SCENE_NAME),
            builtin: true,
            output: None,
            preview: None,
            spp: None,
            width: None,
            height: None,
            integrator: None,
            max_depth: None,
            threads: None,
            seed: None,
            exposure: 0.0,
            wavelength: None,
            quiet: false,
            stats: None,
            unpolarized: false,
            polarized: false,
            caustics: false,
            no_caustics: false,
            no_light_guide: false,
            edge_samples: None,
            light_paths: None,
            spectral_bands: None,
            spectral_range: None,
            samples: None,
            crop: None,
            part: false,
            resume: None,
        }
    }
}

/// The bundled default scene, embedded so that an installed or moved binary still has it.
const DEFAULT_SCENE: &str = include_str!("../../scenes/showcase.toml");
/// The name the default scene is known by in messages and output names.
const DEFAULT_SCENE_NAME: &str = "showcase.toml";

/// Runs `prisma render`.
pub fn run(args: &RenderArgs) -> Result<(), CliError> {
    if let Some(nm) = args.wavelength {
        if !(LAMBDA_MIN_NM..=LAMBDA_MAX_NM).contains(&nm) {
            return Err(CliError::Input(anyhow!(
                "--wavelength must be in {LAMBDA_MIN_NM}–{LAMBDA_MAX_NM} nm, got {nm}"
            )));
        }
    }
    if !args.exposure.is_finite() {
        return Err(CliError::Input(anyhow!("--exposure must be finite, got {}", args.exposure)));
    }
    let bands =
        spectral_bands(args.spectral_bands, args.spectral_range.as_deref()).map_err(CliError::Input)?;
    let mut scene = if args.builtin {
        prisma::scene::parse(DEFAULT_SCENE, Path::new(DEFAULT_SCENE_NAME))
    } else {
        prisma::scene::load(&args.scene)
    }
    .map_err(|e| CliError::Input(e.into()))?;

    let scene_pixels = u64::from(scene.camera.width()) * u64::from(scene.camera.height());
    let (width, height) = resolution(scene.camera.width(), scene.camera.height(), args.width, args.height)
        .map_err(CliError::Input)?;
    scene.camera = scene
        .camera
        .with_resolution(width, height)
        .map_err(|e| CliError::Input(anyhow!("{}: {e}", args.scene.display())))?;
    let mut settings = scene.settings.clone();
    if let Some(name) = &args.integrator {
        let integrator =
            IntegratorKind::from_name(name).map_err(|e| CliError::Input(anyhow!("--integrator: {e}")))?;
        if integrator != settings.integrator {
            // A depth left at one integrator's default takes the other's (they count different
            // bounces); Whitted's pruning threshold means nothing to the path tracer.
            if settings.max_depth == settings.integrator.default_max_depth() {
                settings.max_depth = integrator.default_max_depth();
            }
            if integrator == IntegratorKind::Path {
                let defaults = RenderSettings::default();
                let ignored = [
                    ("prune_below", settings.prune_below != defaults.prune_below),
                    ("area_light_samples", settings.area_light_samples != defaults.area_light_samples),
                ];
                for (field, _) in ignored.iter().filter(|(_, set)| *set) {
                    eprintln!(
                        "warning: {}: {field} belongs to the \"whitted\" integrator; \"path\" ignores it",
                        args.scene.display()
                    );
                }
            }
            settings.area_light_samples = integrator.default_area_light_samples();
            settings.integrator = integrator;
        }
    }
    settings.spp = args.spp.unwrap_or(settings.spp);
    settings.seed = args.seed.unwrap_or(settings.seed);
    settings.max_depth = args.max_depth.unwrap_or(settings.max_depth);
    if args.unpolarized {
        settings.polarized = false;
    } else if args.polarized {
        settings.polarized = true;
    }
    if args.caustics {
        settings.caustics = true;
    } else if args.no_caustics {
        settings.caustics = false;
    }
    if args.no_light_guide {
        settings.light_guide = false;
    }
    if let Some(edge_samples) = args.edge_samples {
        settings.edge_samples = edge_samples;
    }
    settings.light_paths = match (args.light_paths, settings.light_paths) {
        (Some(paths), _) => Some(paths),
        // Without caustics the count is unused: nothing to scale, nothing to refuse.
        (None, Some(paths)) if settings.caustics => Some(
            light_paths_at(paths, scene_pixels, u64::from(width) * u64::from(height))
                .map_err(|e| CliError::Input(anyhow!("{}: {e}", args.scene.display())))?,
        ),
        (None, paths) => paths,
    };
    if settings.caustics {
        // Asked for caustics where none can form: say so, and render Whitted's image alone
        // (which is then the whole image: there is nothing for the light tracer to add).
        if let Some(why) = LightTracer::new(&scene, &settings, None).why_none() {
            eprintln!("warning: {}: caustics are on but {why}: rendering without them", args.scene.display());
            settings.caustics = false;
        }
    }

    settings.check_ray_tree_bound().map_err(|message| {
        CliError::Input(anyhow!("{}: with --max-depth: {message}", args.scene.display()))
    })?;
    let input = |e: anyhow::Error| CliError::Input(e);

    // The default name says what the command line changed that makes another image than the
    // scene file's (a wavelength, caustics turned on or off), so that the README's Whitted and
    // caustic renders of one scene do not replace each other.
    let mut stem = match args.wavelength {
        Some(nm) => format!("{}_{nm}nm", scene.name),
        None => scene.name.clone(),
    };
    if settings.integrator != scene.settings.integrator {
        stem.push('_');
        stem.push_str(settings.integrator.name());
    }
    if settings.caustics != scene.settings.caustics {
        stem.push_str(if settings.caustics { "_with_caustics" } else { "_without_caustics" });
    }
    let exr_path = args.output.clone().unwrap_or_else(|| Path::new("out").join(format!("{stem}.exr")));
    let destinations = Destinations::check(&exr_path, args.preview.as_deref(), args.stats.as_deref())?;
    let mut inputs: Vec<(&Path, &str)> = Vec::new();
    if !args.builtin {
        inputs.push((&args.scene, "the scene file"));
    }
    inputs.extend(scene.input_files.iter().map(|(file, what)| (file.as_path(), *what)));
    if let Some(part) = &args.resume {
        check_regular_input(part, "the part being resumed").map_err(|e| input(anyhow!(e)))?;
        inputs.push((part, "the part being resumed"));
    }
    check_not_inputs(destinations.named(), &inputs).map_err(|e| input(e.into()))?;

    let prior = match &args.resume {
        Some(path) => Some(read_part(path).map_err(|e| input(e.into()))?),
        None => None,
    };
    if let (Some(prior), None) = (&prior, args.spp) {
        // The part knows how many samples its render is to have.
        settings.spp = prior.header.spp;
    }
    let window = match (&args.crop, &prior) {
        (Some(text), _) => {
            PixelWindow::parse(text, width, height).map_err(|e| input(anyhow!("--crop: {e}")))?
        }
        (None, Some(prior)) => prior.header.window,
        (None, None) => PixelWindow::full(width, height),
    };
    let samples = match (&args.samples, &prior) {
        (Some(text), _) => {
            let samples = SampleSet::parse(text).map_err(|e| input(anyhow!("--samples: {e}")))?;
            if samples.end() > settings.spp {
                return Err(input(anyhow!(
                    "--samples {samples} goes past the render's {} samples per pixel (raise --spp)",
                    settings.spp
                )));
            }
            samples
        }
        (None, Some(prior)) => prior.header.samples.missing_below(settings.spp),
        (None, None) => SampleSet::range(0..settings.spp),
    };
    let light_paths_per_pass = if settings.caustics {
        settings.light_paths.unwrap_or(u64::from(width) * u64::from(height))
    } else {
        0
    };
    let bands = bands.filter(|_| args.wavelength.is_none());
    let layout = FilmLayout { stokes: settings.polarized, bands, monochromatic_nm: args.wavelength };
    let threads = args.threads.unwrap_or(0) as usize;
    let mut header = PartHeader::new(
        &args.scene.display().to_string(),
        &scene,
        &settings,
        &layout,
        light_paths_per_pass,
        window,
    );
    header.samples = samples.clone();
    header.threads = threads;
    if args.output.is_none() {
        warn_if_replacing_another_render(&destinations.exr, &header);
    }
    if let Some(prior) = &prior {
        let resumed = args.resume.as_deref().unwrap_or(Path::new("")).display();
        if let Some((what, theirs, mine)) = prior.header.mismatch(&header) {
            return Err(input(anyhow!(
                "--resume {resumed}: the part has a different {what} ({theirs}) from this render's ({mine})"
            )));
        }
        if window != prior.header.window {
            return Err(input(anyhow!(
                "--resume {resumed}: --crop {window} is not the part's window {}",
                prior.header.window
            )));
        }
        if samples.is_empty() {
            return Err(input(anyhow!(
                "--resume {resumed}: the part already holds samples {} of 0..{}: nothing to render (raise --spp for more)",
                prior.header.samples,
                settings.spp
            )));
        }
    }
    let is_part = args.part || args.samples.is_some() || args.crop.is_some() || prior.is_some();

    let terminal = std::io::stderr().is_terminal();
    let show = !args.quiet && terminal;
    let job = Job {
        settings: settings.clone(),
        threads,
        monochromatic_nm: args.wavelength,
        progress: show,
        fault: None,
        // A monochromatic render is written as its one wavelength already.
        bands,
        samples: Some(samples.clone()),
        window: Some(window),
        progress_log: (!args.quiet && !terminal).then_some(PROGRESS_LOG_EVERY),
        stop_after_blocks: std::env::var(STOP_AFTER_BLOCKS_VARIABLE).ok().and_then(|v| v.parse().ok()),
    };
    let stops = prisma::interrupt::accept_stops();
    let rendered = render_sums(&scene, &job).map_err(|e| render_error(e, &args.scene))?;
    // From here a signal abandons the outputs being written, as before any render.
    drop(stops);
    let stats = rendered.stats;

    let interrupted = rendered.interrupted;
    // Moved, not copied: the sums of a frame are tens of MB.
    let (mut sums, mut done) = (rendered.sums, rendered.samples);
    if let Some(prior) = &prior {
        let (new_sums, new_samples) = (sums, done);
        sums = WindowSums::new(window, layout, light_paths_per_pass > 0);
        for part in [&prior.sums, &new_sums] {
            sums.add(part)
                .map_err(|e| input(anyhow::Error::from(e).context(args.scene.display().to_string())))?;
        }
        done = prior.header.samples.union(&new_samples);
        header.wall_seconds = prior.header.wall_seconds;
        header.threads = prior.header.threads;
        header.parts = prior.header.parts.checked_add(1).ok_or_else(|| {
            input(anyhow!(
                "--resume {}: the part counts 4294967295 merged parts already",
                prior_name(&args.resume)
            ))
        })?;
    }
    header.samples = done.clone();
    header.wall_seconds += stats.elapsed.as_secs_f64();
    header.threads = header.threads.max(stats.threads);
    if done.is_empty() {
        return Err(CliError::Interrupted(anyhow!(
            "interrupted before the first sample block finished: nothing was written"
        )));
    }
    let film = sums.film(done.len(), light_paths_per_pass, (width, height));
    film.check_finite().map_err(|e| render_error(RenderError::NonFinite(e), &args.scene))?;

    if interrupted && destinations.exr_special {
        // `/dev/null.partial.exr` would be a regular file among the devices; a pipe's reader
        // expects the image, not a part.
        return Err(CliError::Interrupted(anyhow!(
            "interrupted after samples {done} of 0..{}: nothing was written, as -o {} is not a regular \
             file and has no place beside it for a part (render to a file to be able to resume)",
            settings.spp,
            destinations.exr.display()
        )));
    }
    if interrupted {
        let partial = partial_path(&destinations.exr);
        let mut outputs = Outputs::new();
        outputs
            .stage(&partial, |sink| encode_exr_part(sink, &partial, &film, Some(&header), Some(&sums)))
            .and_then(|()| outputs.commit())
            .context("writing the interrupted render's part")
            .map_err(CliError::Failed)?;
        let resume = if args.builtin { String::new() } else { format!("{} ", args.scene.display()) };
        return Err(CliError::Interrupted(anyhow!(
            "interrupted: wrote samples {done} of 0..{} to {} (a part; {} is untouched); finish it with: \
             prisma render {resume}--resume {} -o {}",
            settings.spp,
            partial.display(),
            destinations.exr.display(),
            partial.display(),
            destinations.exr.display()
        )));
    }

    let seconds = stats.elapsed.as_secs_f64();
    let figures = serde_json::json!({
        "scene": args.scene.display().to_string(),
        "width": width,
        "height": height,
        "spp": settings.spp,
        "samples_rendered": samples.to_string(),
        "crop": window.to_string(),
        "wavelengths_per_sample": settings.wavelengths,
        "polarized": settings.polarized,
        "caustics": settings.caustics,
        "light_paths": stats.light_paths,
        "light_rays": stats.light_rays,
        "light_tracer_seconds": stats.light_elapsed.as_secs_f64(),
        "light_guide_predicted_gain": stats.light_guide_gain,
        "edge_pixels": stats.edge_pixels,
        "threads": stats.threads,
        "render_seconds": seconds,
        "render_cpu_seconds": stats.cpu.map(|cpu| cpu.as_secs_f64()),
        "samples": stats.samples,
        "rays": stats.rays,
        "samples_per_second": stats.samples as f64 / seconds.max(1e-9),
        "rays_per_second": stats.rays as f64 / seconds.max(1e-9),
    });
    let writing = show.then(|| writing_spinner(&destinations));
    let rgb = film.linear_srgb();
    let (crop_width, crop_height) = (window.width(), window.height());
    let mut outputs = Outputs::new();
    let part_sums = is_part.then_some(&sums);
    let written = outputs
        .stage(&destinations.exr, |sink| {
            encode_exr_part(sink, &destinations.exr, &film, Some(&header), part_sums)
        })
        .and_then(|()| match &destinations.preview {
            Some(png) => {
                outputs.stage(png, |sink| encode_png(sink, png, crop_width, crop_height, &rgb, args.exposure))
            }
            None => Ok(()),
        })
        .and_then(|()| match &destinations.stats {
            Some(path) => outputs.stage(path, |sink| text_into(sink, path, &format!("{figures:#}\n"))),
            None => Ok(()),
        })
        .and_then(|()| outputs.commit());
    if let Some(spinner) = writing {
        spinner.finish_and_clear();
    }
    written.context("writing the outputs (none was written)").map_err(CliError::Failed)?;
    // A resumed render that finished its own `OUT.partial.exr`: the output now holds every
    // sample of the part (with its sums), so the part is removed rather than left to be
    // mistaken for unfinished work. Any other resumed file is left as it is.
    let finished_partial = args.resume.as_deref().filter(|resumed| {
        done.missing_below(settings.spp).is_empty() && same_file(resumed, &partial_path(&destinations.exr))
    });
    let removed = match finished_partial {
        Some(partial) => match std::fs::remove_file(partial) {
            Ok(()) => Some(format!(
                "removed {} (its samples are in {})",
                partial.display(),
                destinations.exr.display()
            )),
            Err(e) => Some(format!("could not remove {}: {e}", partial.display())),
        },
        None => None,
    };

    if !args.quiet {
        let caustics = if stats.light_paths > 0 {
            format!(
                " + {:.2} M light paths ({:.2} s)",
                stats.light_paths as f64 * 1e-6,
                stats.light_elapsed.as_secs_f64()
            )
        } else {
            String::new()
        };
        let part = if is_part { format!(" (part: samples {done}, window {window})") } else { String::new() };
        say!(
            "rendered {}: {width}×{height}, {}, {} spp{caustics}{part}, {}, {} in {seconds:.2} s on {} thread{} ({:.1} M rays, {:.2} M rays/s)",
            args.scene.display(),
            settings.integrator.name(),
            settings.spp,
            if settings.polarized { "polarised" } else { "unpolarised" },
            match args.wavelength {
                Some(nm) => format!("λ = {nm} nm"),
                None => format!("{} λ/sample", settings.wavelengths),
            },
            stats.threads,
            if stats.threads == 1 { "" } else { "s" },
            stats.rays as f64 * 1e-6,
            stats.rays as f64 * 1e-6 / seconds.max(1e-9),
        );
        let mut wrote = vec![destinations.exr.display().to_string()];
        wrote.extend(destinations.preview.iter().chain(&destinations.stats).map(|p| p.display().to_string()));
        say!("wrote {}", wrote.join(", "));
        if let Some(removed) = &removed {
            say!("{removed}");
        }
    }
    Ok(())
}

/// How often a render without a terminal prints a line of progress (for batch logs).
const PROGRESS_LOG_EVERY: std::time::Duration = std::time::Duration::from_secs(10);
/// A test hook: the environment variable that stops a render after that many sample blocks, as
/// Ctrl-C would (the interruption tests use it instead of timing a signal).
pub const STOP_AFTER_BLOCKS_VARIABLE: &str = "PRISMA_TEST_STOP_AFTER_BLOCKS";

/// Warns when the default output `exr` holds a prisma render of other settings, scene, seed,
/// samples or size than `header`'s, which this render will replace (a name given with `-o` is
/// the user's choice and replaced without a word).
fn warn_if_replacing_another_render(exr: &Path, header: &PartHeader) {
    let Ok(summary) = prisma::part::file::read_summary(exr) else { return };
    let theirs = |name: &str| summary.attribute(name).unwrap_or_default();
    let differs = [
        ("settings", theirs("prisma.settings") != header.settings),
        ("scene", theirs("prisma.sceneSha256") != header.scene_sha256),
        ("seed", theirs("prisma.seed") != header.seed.to_string()),
        ("spp", theirs("prisma.spp") != header.spp.to_string()),
        ("size", summary.display != header.display),
    ];
    let what: Vec<&str> = differs.iter().filter(|(_, d)| *d).map(|(what, _)| *what).collect();
    if summary.attribute("prisma.version").is_some() && !what.is_empty() {
        eprintln!(
            "warning: replacing {}, a render of other {} (give -o a name to keep both)",
            exr.display(),
            what.join(", ")
        );
    }
}

/// The `--resume` file's name for messages.
fn prior_name(resume: &Option<PathBuf>) -> String {
    resume.as_deref().map(|path| path.display().to_string()).unwrap_or_default()
}

/// Where an interrupted render writing `exr` puts its part: `NAME.partial.exr` beside it, so that
/// an existing `exr` (an earlier complete render) is never replaced by a partial one.
fn partial_path(exr: &Path) -> PathBuf {
    let stem = exr.file_stem().map_or_else(|| "render".into(), |s| s.to_string_lossy().into_owned());
    let stem = stem.strip_suffix(".partial").unwrap_or(&stem).to_owned();
    exr.with_file_name(format!("{stem}.partial.exr"))
}

/// A render error as a command error: bad input unless the thread pool failed.
fn render_error(error: RenderError, scene: &Path) -> CliError {
    match error {
        RenderError::ThreadPool { .. } => CliError::Failed(error.into()),
        // Too large for this machine, or magnitudes that overflow: the input must change.
        RenderError::TooLarge(_) | RenderError::NonFinite(_) | RenderError::Camera(_) => {
            CliError::Input(anyhow::Error::from(error).context(scene.display().to_string()))
        }
    }
}

/// The spectral bands asked for by `--spectral-bands N` and `--spectral-range MIN-MAX`.
fn spectral_bands(count: Option<u32>, range: Option<&str>) -> anyhow::Result<Option<SpectralBands>> {
    let Some(count) = count else { return Ok(None) };
    let (min_nm, max_nm) = match range {
        None => (LAMBDA_MIN_NM, LAMBDA_MAX_NM),
        Some(text) => {
            let parsed = text
                .split_once('-')
                .and_then(|(a, b)| Some((a.trim().parse::<f32>().ok()?, b.trim().parse::<f32>().ok()?)));
            let Some((min_nm, max_nm)) = parsed else {
                return Err(anyhow!("--spectral-range must be MIN-MAX in nm (e.g. 400-700), got \"{text}\""));
            };
            (min_nm, max_nm)
        }
    };
    if !(LAMBDA_MIN_NM <= min_nm && min_nm < max_nm && max_nm <= LAMBDA_MAX_NM) {
        return Err(anyhow!(
            "--spectral-range must satisfy {LAMBDA_MIN_NM} ≤ MIN < MAX ≤ {LAMBDA_MAX_NM} nm, got {min_nm}-{max_nm}"
        ));
    }
    let bands = SpectralBands { count: count as usize, min_nm, max_nm };
    if let Some((first, second, name)) = prisma::output::exr::shared_band_name(&bands) {
        return Err(anyhow!(
            "--spectral-bands {count} over --spectral-range {min_nm}-{max_nm}: bands {first} and {second} would both be \
             channel {name} (centres closer than 0.000001 nm); use fewer bands or a wider range"
        ));
    }
    Ok(Some(bands))
}

/// A spinner on standard error while the outputs are encoded and written (an 8K EXR takes
/// seconds).
fn writing_spinner(destinations: &Destinations) -> ProgressBar {
    let spinner = ProgressBar::new_spinner();
    if let Ok(style) = ProgressStyle::with_template("{spinner} [{elapsed_precise}] {msg}") {
        spinner.set_style(style);
    }
    spinner.set_message(format!("writing {}", destinations.exr.display()));
    spinner.enable_steady_tick(std::time::Duration::from_millis(120));
    spinner
}

/// The output resolution: the scene's, or the flags', keeping the aspect ratio when only one is given.
fn resolution(
    scene_w: u32,
    scene_h: u32,
    width: Option<u32>,
    height: Option<u32>,
) -> anyhow::Result<(u32, u32)> {
    let aspect = f64::from(scene_w) / f64::from(scene_h);
    let (w, h) = match (width, height) {
        (Some(w), Some(h)) => (w, h),
        (Some(w), None) => (w, (f64::from(w) / aspect).round().max(1.0) as u32),
        (None, Some(h)) => ((f64::from(h) * aspect).round().max(1.0) as u32, h),
        (None, None) => (scene_w, scene_h),
    };
    if w > MAX_RESOLUTION || h > MAX_RESOLUTION {
        return Err(anyhow!("resolution {w}×{h} exceeds {MAX_RESOLUTION} pixels per side"));
    }
    Ok((w, h))
}

/// The scene file's `light_paths`, `paths` per pass for its own `scene_pixels`, for a render of
/// `pixels` pixels (`--width`, `--height`): scaled with the pixel count, rounded to the nearest
/// (at least 1), so that a render at another size keeps the light paths per pixel, and with them
/// the noise of its caustics, as the one-per-pixel default does and as the camera samples do.
/// Unchanged at the scene's own resolution; `--light-paths` is never scaled.
fn light_paths_at(paths: u64, scene_pixels: u64, pixels: u64) -> anyhow::Result<u64> {
    if pixels == scene_pixels {
        return Ok(paths);
    }
    let scaled =
        (u128::from(paths) * u128::from(pixels) + u128::from(scene_pixels / 2)) / u128::from(scene_pixels);
    match u64::try_from(scaled.max(1)) {
        Ok(scaled) if scaled <= MAX_LIGHT_PATHS => Ok(scaled),
        _ => Err(anyhow!(
            "render.light_paths = {paths} scaled to {pixels} pixels is {scaled} light paths per pass, above \
             {MAX_LIGHT_PATHS}: pass --light-paths"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The file's light paths per pass follow the pixel count: a quarter of the pixels, a
    /// quarter of the paths (rounded, at least one); the scene's own resolution keeps them.
    #[test]
    fn scene_light_paths_scale_with_the_pixel_count() {
        assert_eq!(light_paths_at(400_000, 360_000, 360_000).unwrap(), 400_000);
        assert_eq!(light_paths_at(400_000, 360_000, 90_000).unwrap(), 100_000);
        // 1000 · 7/3 = 2333.3 → 2333; 1000 · 8/3 = 2666.7 → 2667.
        assert_eq!(light_paths_at(1000, 3, 7).unwrap(), 2333);
        assert_eq!(light_paths_at(1000, 3, 8).unwrap(), 2667);
        assert_eq!(light_paths_at(1, 1_000_000, 1).unwrap(), 1);
        let too_many = light_paths_at(MAX_LIGHT_PATHS, 1, 4).unwrap_err().to_string();
        assert!(too_many.contains("render.light_paths") && too_many.contains("--light-paths"), "{too_many}");
    }

    /// `prisma` without arguments renders the showcase embedded in the binary, so that an
    /// installed or moved binary still has it (it used to be read from the build directory).
    #[test]
    fn the_default_scene_is_embedded_and_loads() {
        let scene =
            prisma::scene::parse(DEFAULT_SCENE, Path::new(DEFAULT_SCENE_NAME)).expect("the showcase loads");
        assert_eq!(scene.name, "showcase");
        assert!(RenderArgs::default_scene().builtin);
    }
}

//! `prisma render`: a scene file to `out/<scene>.exr` and `out/<scene>.png`.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, Context};
use clap::Args;

use indicatif::{ProgressBar, ProgressStyle};

use super::{say, CliError};
use prisma::film::SpectralBands;
use prisma::integrator::LightTracer;
use prisma::output::exr::encode_exr;
use prisma::output::file::{check_destination, same_file, text_into, Destination, Outputs};
use prisma::output::png::encode_png;
use prisma::output::OutputError;
use prisma::render::{render, Job, RenderError};
use prisma::scene::build::{MAX_DEPTH, MAX_LIGHT_PATHS, MAX_RESOLUTION, MAX_SPP};
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
    /// Maximum number of specular bounces.
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
    /// Light paths per pass with caustics (a render makes one pass per sample per pixel)
    /// [default: the scene's `light_paths`, else one per pixel].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..=MAX_LIGHT_PATHS))]
    light_paths: Option<u64>,
    /// Also write the mean spectral radiance in N bands (Fichet et al. 2021 spectral EXR layout).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024))]
    spectral_bands: Option<u32>,
    /// Wavelength range of the spectral bands, in nm [default: 360-830].
    #[arg(long, value_name = "MIN-MAX", requires = "spectral_bands")]
    spectral_range: Option<String>,
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
            light_paths: None,
            spectral_bands: None,
            spectral_range: None,
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

    let (width, height) = resolution(scene.camera.width(), scene.camera.height(), args.width, args.height)
        .map_err(CliError::Input)?;
    scene.camera = scene
        .camera
        .with_resolution(width, height)
        .map_err(|e| CliError::Input(anyhow!("{}: {e}", args.scene.display())))?;
    let mut settings = scene.settings.clone();
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
    settings.light_paths = args.light_paths.or(settings.light_paths);
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
    let stem = match args.wavelength {
        Some(nm) => format!("{}_{nm}nm", scene.name),
        None => scene.name.clone(),
    };
    let exr_path = args.output.clone().unwrap_or_else(|| Path::new("out").join(format!("{stem}.exr")));
    let destinations = Destinations::check(&exr_path, args.preview.as_deref(), args.stats.as_deref())?;

    let show = !args.quiet && std::io::stderr().is_terminal();
    let job = Job {
        settings: settings.clone(),
        threads: args.threads.unwrap_or(0) as usize,
        monochromatic_nm: args.wavelength,
        progress: show,
        fault: None,
        // A monochromatic render is written as its one wavelength already.
        bands: bands.filter(|_| args.wavelength.is_none()),
    };
    let (film, stats) = render(&scene, &job).map_err(|e| match e {
        RenderError::ThreadPool { .. } => CliError::Failed(e.into()),
        // Too large for this machine, or magnitudes that overflow: the input must change.
        RenderError::TooLarge(_) | RenderError::NonFinite(_) => {
            CliError::Input(anyhow::Error::from(e).context(args.scene.display().to_string()))
        }
    })?;

    let seconds = stats.elapsed.as_secs_f64();
    let figures = serde_json::json!({
        "scene": args.scene.display().to_string(),
        "width": width,
        "height": height,
        "spp": settings.spp,
        "wavelengths_per_sample": settings.wavelengths,
        "polarized": settings.polarized,
        "caustics": settings.caustics,
        "light_paths": stats.light_paths,
        "light_rays": stats.light_rays,
        "light_tracer_seconds": stats.light_elapsed.as_secs_f64(),
        "threads": stats.threads,
        "render_seconds": seconds,
        "samples": stats.samples,
        "rays": stats.rays,
        "samples_per_second": stats.samples as f64 / seconds.max(1e-9),
        "rays_per_second": stats.rays as f64 / seconds.max(1e-9),
    });
    let writing = show.then(|| writing_spinner(&destinations));
    let rgb = film.linear_srgb();
    let mut outputs = Outputs::new();
    let written = outputs
        .stage(&destinations.exr, |sink| encode_exr(sink, &destinations.exr, &film))
        .and_then(|()| match &destinations.preview {
            Some(png) => outputs.stage(png, |sink| encode_png(sink, png, width, height, &rgb, args.exposure)),
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
        say!(
            "rendered {}: {width}×{height}, {} spp{caustics}, {}, {} in {seconds:.2} s on {} threads ({:.1} M rays, {:.2} M rays/s)",
            args.scene.display(),
            settings.spp,
            if settings.polarized { "polarised" } else { "unpolarised" },
            match args.wavelength {
                Some(nm) => format!("λ = {nm} nm"),
                None => format!("{} λ/sample", settings.wavelengths),
            },
            stats.threads,
            stats.rays as f64 * 1e-6,
            stats.rays as f64 * 1e-6 / seconds.max(1e-9),
        );
        let mut wrote = vec![destinations.exr.display().to_string()];
        wrote.extend(destinations.preview.iter().chain(&destinations.stats).map(|p| p.display().to_string()));
        say!("wrote {}", wrote.join(", "));
    }
    Ok(())
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
    Ok(Some(SpectralBands { count: count as usize, min_nm, max_nm }))
}

/// The files a render writes, checked before it starts.
struct Destinations {
    exr: PathBuf,
    preview: Option<PathBuf>,
    stats: Option<PathBuf>,
}

impl Destinations {
    /// Checks the outputs before any work: each can be written (not a directory, a block device,
    /// an unwritable place), the EXR is named `.exr` and the preview `.png` (unless they are
    /// special files such as /dev/null), and no two are the same file. Without `--preview` the
    /// preview goes beside the EXR with a `.png` extension, or nowhere when the EXR goes to a
    /// special file.
    fn check(exr: &Path, preview: Option<&Path>, stats: Option<&Path>) -> Result<Self, CliError> {
        let input = |e: OutputError| CliError::Input(e.into());
        let exr_destination = check_destination(exr).map_err(input)?;
        require_extension(&exr_destination, exr, "exr", "-o", "--preview names the PNG preview")?;
        let preview = match (preview, &exr_destination) {
            (Some(path), _) => Some(path.to_owned()),
            (None, Destination::Replace(_)) => Some(exr.with_extension("png")),
            (None, Destination::Special(_)) => None,
        };
        if let Some(path) = &preview {
            let destination = check_destination(path).map_err(input)?;
            require_extension(&destination, path, "png", "--preview", "-o names the EXR image")?;
        }
        if let Some(path) = stats {
            check_destination(path).map_err(input)?;
        }
        let named = [("-o", Some(exr)), ("--preview", preview.as_deref()), ("--stats", stats)];
        for (i, (flag_a, a)) in named.iter().enumerate() {
            for (flag_b, b) in &named[i + 1..] {
                if let (Some(a), Some(b)) = (a, b) {
                    let special = matches!(check_destination(a), Ok(Destination::Special(_)));
                    if same_file(a, b) && !special {
                        return Err(CliError::Input(anyhow!(
                            "{flag_a} and {flag_b} name the same file {}: each output needs its own",
                            a.display()
                        )));
                    }
                }
            }
        }
        Ok(Self { exr: exr.to_owned(), preview, stats: stats.map(Path::to_owned) })
    }
}

/// A regular file written as `format` must be named so.
fn require_extension(
    destination: &Destination,
    path: &Path,
    format: &str,
    flag: &str,
    hint: &str,
) -> Result<(), CliError> {
    let named = path.extension().is_some_and(|e| e.eq_ignore_ascii_case(format));
    if matches!(destination, Destination::Replace(_)) && !named {
        return Err(CliError::Input(anyhow!(
            "{flag} {}: the file is written as {}, so its name must end in .{format} ({hint})",
            path.display(),
            format.to_uppercase()
        )));
    }
    Ok(())
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

#[cfg(test)]
mod tests {
    use super::*;

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

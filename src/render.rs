//! [`render`]: the image of a scene, rows in parallel on a rayon pool, sample block by sample
//! block.
//!
//! Every camera sample draws its sample values from a sequence keyed by (seed, pixel, sample),
//! and is added to its pixel's exact sums ([`crate::fixed::FixedSum`]), so the image is
//! bit-identical whatever the thread count, the row schedule and the size of the sample blocks,
//! and any split of the samples and pixels into parts adds up to the same bits
//! ([`crate::part`]).
//!
//! After the first pass the pixels an edge crosses get more camera samples per pass
//! ([`crate::edges`], the scene's `edge_samples`): their first pass is completed with them, and
//! each of their passes adds the mean of its samples, so a pass still counts one sample for the
//! film and the merges.
//!
//! A render takes the sample indices of its [`Job`] (all of `0..spp` unless told) over its pixel
//! window (the whole image unless told) in **sample blocks**: each block adds some samples to
//! every pixel of the window. Between blocks the render may stop (Ctrl-C, [`crate::interrupt`]):
//! what it has then is exact, the sums of the samples done. Blocks grow to about
//! [`TARGET_BLOCK_SECONDS`], so a stop comes soon and the progress estimate is current.
//!
//! With caustics on, sample `i` is also pass `i` of the light tracer: light paths `i·L` to
//! `(i+1)·L − 1` for `L` light paths per pass. Light paths come in fixed blocks of
//! [`LIGHT_PATH_BLOCK`] by their number; light path n of the render draws point n of one sample
//! sequence keyed by the seed ([`LightPathSequence`]), whichever block or part traces it, and a
//! pass that starts or ends inside a block traces only its own paths of it.
//! Their splats are summed exactly like camera samples; splats outside the window are dropped.
//! The light sums divided by the number of light paths are added to the camera means.
//!
//! A sample block traces its light passes before its camera samples, into zero light sums
//! while those of the blocks done are set aside ([`WindowSums::swap_light`]), and adds these
//! back when the block is whole. A stop within a pass (a pass of 2^31 paths takes hours) thus
//! skips the light-path blocks not yet started, drops the block's light sums and ends the
//! render at the samples done: a part holds whole passes. The camera samples of a block are
//! not interrupted.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;

use crate::camera::Camera;
use crate::edges::{self, EdgeMap};
use crate::film::{add_weighted_sample, Film, FilmLayout, NonFinitePixel, SpectralBands, Splats, WindowSums};
use crate::fixed::FixedSum;
use crate::integrator::light_tracer::Scratch;
use crate::integrator::{
    guide, CameraIntegrator, Fault, LightTracer, PathBeam, PathTracer, TraceStats, Whitted,
};
use crate::memory;
use crate::part::{PixelWindow, SampleSet};
use crate::polarization::Stokes;
use crate::sampler::{LightPathSequence, PixelKey, PixelRng};
use crate::scene::{IntegratorKind, RenderSettings, Scene};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, N_LAMBDA};

/// Stack of each render thread: Whitted recursion runs on it, one frame per bounce.
const THREAD_STACK_BYTES: usize = 64 << 20;
/// Light paths per block: the unit of parallel work of the light tracer (a power of two, so that
/// a block's paths are a whole Sobol net of the render's one sequence). Small enough that a
/// pass of a small render splits evenly over the threads: with 4096, the 12,288 paths of a pass
/// of the caustic bench made 3 blocks on 2 threads, and its 1- and 2-spp renders took 1.27× the
/// time they take with 1024 (`validation/bench/caustics_bench.py` scene, best of 7); with 1024,
/// the 1,024 paths a pass of 16,384 then learned the guide from ([`guide::learning_paths`]) were
/// one block on one thread, and a one-pass render of 16,384 paths took 6.25 / 7.33 / 9.7 ms
/// (least, first quartile, median of 30 alternating runs) against 5.5 / 6.43 / 7.0 with 512. The
/// image is the same bits whatever the block (exact sums).
pub const LIGHT_PATH_BLOCK: u64 = 512;
/// Light-path blocks handed to the pool at a time ([`light_block`]): a pass iterates ranges of
/// this many, never a list of all its blocks. Enough that the threads wait for each other at
/// the end of a chunk rarely (at most once per 2,097,152 paths; smaller passes are one chunk,
/// scheduled as before), few enough that skipping the rest of a chunk after a stop is
/// instantaneous.
const LIGHT_BLOCKS_PER_CHUNK: u64 = 4096;
/// Mixed into the seed of the light paths' sample sequences, so that they are independent of
/// the camera samples'.
const LIGHT_PATH_SEED_SALT: u64 = 0x6c69_6768_7470_6174;
/// When a render without a terminal logs its first progress line.
const FIRST_PROGRESS_LOG: Duration = Duration::from_secs(1);
/// Wall time a sample block aims at: how long a stop may wait (the camera samples of a block
/// are not interrupted; its light passes are, within a block of 512 light paths), and how often
/// the progress estimate is refreshed at the least. One second, as a user expects Ctrl-C to
/// answer (issue 37).
pub const TARGET_BLOCK_SECONDS: f64 = 1.0;

/// What to render, beyond the scene.
#[derive(Debug, Clone)]
pub struct Job {
    /// Sampling settings.
    pub settings: RenderSettings,
    /// Worker threads; 0 picks one per core.
    pub threads: usize,
    /// Render one wavelength (nm) as a radiance image instead of colour.
    pub monochromatic_nm: Option<f32>,
    /// Show a progress bar (on a terminal).
    pub progress: bool,
    /// A deliberate physics error, for proving that validation catches it; `None` normally.
    pub fault: Option<Fault>,
    /// Also record the mean spectral radiance in these bands (spectral output).
    pub bands: Option<SpectralBands>,
    /// The sample indices to render; `None`: `0..spp`.
    pub samples: Option<SampleSet>,
    /// The pixels to render; `None`: the whole image.
    pub window: Option<PixelWindow>,
    /// Print a one-line progress report with the time left to standard error this often (for
    /// logs, where no progress bar can be drawn).
    pub progress_log: Option<Duration>,
    /// Stop after this many sample blocks as if interrupted (a test hook for interruption).
    pub stop_after_blocks: Option<u32>,
}

impl Job {
    /// A colour render with `settings`, one thread per core, no progress bar, no fault, no
    /// spectral bands, all samples of the whole image.
    pub fn new(settings: RenderSettings) -> Self {
        Self {
            settings,
            threads: 0,
            monochromatic_nm: None,
            progress: false,
            fault: None,
            bands: None,
            samples: None,
            window: None,
            progress_log: None,
            stop_after_blocks: None,
        }
    }

    /// True when the render carries Stokes vectors: the scene asks for it and no fault drops it.
    pub fn polarized(&self) -> bool {
        self.settings.polarized && self.fault != Some(Fault::Unpolarized)
    }

    /// What each pixel of the film holds.
    pub fn layout(&self) -> FilmLayout {
        FilmLayout { stokes: self.polarized(), bands: self.bands, monochromatic_nm: self.monochromatic_nm }
    }

    /// The sample indices to render.
    pub fn sample_set(&self) -> SampleSet {
        self.samples.clone().unwrap_or_else(|| SampleSet::range(0..self.settings.spp))
    }
}

/// Figures of a finished render.
#[derive(Debug, Clone, Copy)]
pub struct RenderStats {
    /// Rays cast (camera, specular and shadow, light paths and their connections).
    pub rays: u64,
    /// Camera samples in the image: one per pixel and pass, `edge_samples` per pass at edge
    /// pixels ([`crate::edges`]).
    pub samples: u64,
    /// Wall-clock time.
    pub elapsed: Duration,
    /// CPU time of the whole process over the same span (every thread, user and system), if
    /// the platform reports it ([`crate::cpu_time::process_cpu_time`]).
    pub cpu: Option<Duration>,
    /// Threads used.
    pub threads: usize,
    /// Light paths traced for caustics (0 without).
    pub light_paths: u64,
    /// Rays of the light tracer (included in `rays`).
    pub light_rays: u64,
    /// Wall-clock time of the light tracer, learning its guide included (included in `elapsed`).
    pub light_elapsed: Duration,
    /// The gain in efficiency the light tracer's guide was predicted to bring
    /// ([`crate::integrator::guide::learn`]; used when at least
    /// [`crate::integrator::guide::MIN_PREDICTED_GAIN`]), if it learned one.
    pub light_guide_gain: Option<f64>,
    /// Pixels of the window that took `edge_samples` camera samples per pass
    /// ([`crate::edges`]).
    pub edge_pixels: usize,
}

/// Why a render could not run.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The thread pool could not be built.
    #[error("cannot start {threads} render threads")]
    ThreadPool {
        /// Threads asked for.
        threads: usize,
        /// The cause.
        source: rayon::ThreadPoolBuildError,
    },
    /// The image would not fit in memory (checked before rendering).
    #[error(transparent)]
    TooLarge(#[from] memory::TooLarge),
    /// A pixel came out NaN or infinite: radiance overflowed f32.
    #[error(transparent)]
    NonFinite(#[from] NonFinitePixel),
    /// The camera cannot render with these settings (a lens system with caustics,
    /// [`lens_camera_refusal`]).
    #[error("{0}")]
    Camera(String),
}

/// Why a lens-system camera cannot render with `settings`, if it cannot, as the setting's name
/// and the reason: light paths cannot be connected to the camera through glass (`caustics`).
/// `None` for every other camera.
pub fn lens_camera_refusal(camera: &Camera, settings: &RenderSettings) -> Option<(&'static str, String)> {
    let Camera::Lens(lens) = camera else { return None };
    let file = lens.lens_file().display();
    if settings.caustics {
        return Some((
            "caustics",
            format!(
                "light paths cannot be connected to the camera through the lens system {file}; \
                 render without caustics (or with a thin lens)"
            ),
        ));
    }
    None
}

/// Bytes of memory a render of `width`×`height` pixels of `layout` on `threads` threads needs,
/// with its EXR and PNG output and its exact sums, the light tracer's of `light` (if any)
/// included ([`memory::estimate`], fitted to measured peaks). A pass holds nothing per light
/// path: its blocks are ranges, not a list, each thread's splats are one block's, and the
/// guide's record is of at most [`guide::MAX_LEARNING_PATHS`] paths (a few hundred kB, within
/// the fixed costs' margin).
pub fn memory_needed(
    width: u32,
    height: u32,
    layout: &FilmLayout,
    threads: usize,
    light: Option<&FilmLayout>,
) -> u64 {
    let light_values = light.map_or(0, FilmLayout::values_per_pixel);
    memory::estimate(width, height, layout, light_values, threads as u64 * THREAD_STACK_BYTES as u64)
}

/// A render's exact sums and what they hold.
#[derive(Debug, Clone)]
pub struct Rendered {
    /// The per-pixel sums over the window.
    pub sums: WindowSums,
    /// The samples done: all those asked for, or the first of them when stopped early.
    pub samples: SampleSet,
    /// True when the render stopped before all its samples (interrupted).
    pub interrupted: bool,
    /// Light paths per pass (per sample), 0 without caustics.
    pub light_paths_per_pass: u64,
    /// Its figures.
    pub stats: RenderStats,
}

impl Rendered {
    /// The image of the samples done (checked finite).
    pub fn film(&self, display: (u32, u32)) -> Result<Film, NonFinitePixel> {
        let film = self.sums.film(self.samples.len(), self.light_paths_per_pass, display);
        film.check_finite()?;
        Ok(film)
    }
}

/// Renders `scene` (its camera decides the resolution) as `job` says: the image of all the
/// job's samples over its window.
///
/// Errors before any work when the image cannot fit in memory, and after the render when a
/// pixel is not finite (naming the first one).
pub fn render(scene: &Scene, job: &Job) -> Result<(Film, RenderStats), RenderError> {
    let rendered = render_sums(scene, job)?;
    let film = rendered.film((scene.camera.width(), scene.camera.height()))?;
    Ok((film, rendered.stats))
}

/// Renders the job's samples over its window into exact sums, stopping early at a sample block
/// boundary when interrupted ([`crate::interrupt::stop_requested`]) or after
/// [`Job::stop_after_blocks`] blocks.
///
/// Errors before any work when the sums cannot fit in memory, and when a sample's value cannot
/// be summed (not finite, or beyond [`FixedSum`]'s range), naming the first such pixel.
pub fn render_sums(scene: &Scene, job: &Job) -> Result<Rendered, RenderError> {
    if let Some((setting, message)) = lens_camera_refusal(&scene.camera, &job.settings) {
        return Err(RenderError::Camera(format!("{setting}: {message}")));
    }
    let (width, height) = (scene.camera.width(), scene.camera.height());
    let window = job.window.unwrap_or(PixelWindow::full(width, height));
    let samples = job.sample_set();
    // The pool's thread count, without starting a pool to ask it.
    let threads = match job.threads {
        0 => std::thread::available_parallelism().map_or(1, usize::from),
        n => n,
    };
    // In full transport the light tracer follows its paths past the first diffuse vertex
    // (ARCHITECTURE.md, "Path space").
    let tracer = LightTracer::new(scene, &job.settings, job.monochromatic_nm)
        .with_fault(job.fault)
        .with_interreflection(
            job.settings.integrator == IntegratorKind::Path && job.fault != Some(Fault::CausticsCountedNever),
        );
    let light_paths_per_pass = if job.settings.caustics && tracer.why_none().is_none() {
        job.settings.light_paths.unwrap_or(u64::from(width) * u64::from(height))
    } else {
        0
    };
    let layout = job.layout();
    let light_layout = (light_paths_per_pass > 0).then(|| tracer.splat_layout(&layout));
    memory::check(
        window.width(),
        window.height(),
        memory_needed(window.width(), window.height(), &layout, threads, light_layout.as_ref()),
    )?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(job.threads)
        .stack_size(THREAD_STACK_BYTES)
        .build()
        .map_err(|source| RenderError::ThreadPool { threads: job.threads, source })?;
    let threads = pool.current_num_threads();
    let integrator = match job.settings.integrator {
        IntegratorKind::Whitted => CameraIntegrator::Whitted(
            Whitted::new(
                scene,
                job.settings.max_depth,
                job.settings.prune_below,
                job.settings.area_light_samples,
            )
            .with_monochromatic(job.monochromatic_nm)
            .with_fault(job.fault),
        ),
        IntegratorKind::Path => CameraIntegrator::Path(
            PathTracer::new(
                scene,
                job.settings.max_depth,
                job.settings.area_light_samples,
                light_paths_per_pass > 0,
            )
            .with_monochromatic(job.monochromatic_nm)
            .with_fault(job.fault),
        ),
    };

    // Progress in camera samples and light paths. (A light path costs about what a camera
    // sample does.)
    let per_sample = window.pixels() as u64 + light_paths_per_pass;
    let progress =
        if job.progress { ProgressBar::new(samples.len() * per_sample) } else { ProgressBar::hidden() };
    if job.progress {
        if let Ok(style) =
            ProgressStyle::with_template("{spinner} [{elapsed_precise}] {wide_bar} {percent}% eta {eta}")
        {
            progress.set_style(style);
        }
    } else {
        progress.set_length(samples.len() * per_sample);
    }
    let start = Instant::now();
    let start_cpu = crate::cpu_time::process_cpu_time();
    let mut light = LightPasses::new(tracer, job, light_paths_per_pass);
    let mut light_elapsed = Duration::ZERO;
    let mut interrupted = false;
    // A part whose first samples do not hold the learning paths learns from them first.
    if light.learning_paths > 0
        && !samples
            .ranges()
            .first()
            .is_some_and(|r| r.start == 0 && u64::from(r.end) * light_paths_per_pass >= light.learning_paths)
    {
        let learning = 0..light.learning_paths;
        let hidden = ProgressBar::hidden();
        let run = LightRun { pool: &pool, job, display: (width, height), progress: &hidden };
        interrupted = light.trace(&run, None, learning)?.is_none();
        light_elapsed = start.elapsed();
    }
    // Edge refinement needs the first pass: from the sums right after it when this render
    // holds it, else rendered for the map alone now.
    let refine = job.settings.edge_samples > 1 && !samples.ranges().is_empty();
    let mut edges = EdgeMap::uniform(window);
    if refine && samples.ranges().first().is_none_or(|r| r.start != 0) {
        edges = pool.install(|| find_edges(scene, &integrator, job, None));
    }
    let mut sums = match light_layout {
        Some(light_layout) => WindowSums::with_light_layout(window, layout, light_layout),
        None => WindowSums::new(window, layout, false),
    };
    // The light sums of the blocks done, set aside while a block's passes add to `sums`.
    let mut light_done = sums.zero_light();
    // Blocks go through the samples in order: the first `done` of them are done.
    let mut done = 0u64;
    let mut rays = 0;
    let mut light_rays = 0;
    let finished = AtomicBool::new(false);
    let light_run = LightRun { pool: &pool, job, display: (width, height), progress: &progress };
    let result: Result<(), RenderError> = std::thread::scope(|scope| {
        let logger = job.progress_log.map(|every| {
            let (progress, finished) = (&progress, &finished);
            let unit =
                if light_paths_per_pass > 0 { "camera samples and light paths" } else { "camera samples" };
            scope.spawn(move || log_progress(progress, every, finished, start, unit))
        });
        let result = (|| {
            let mut blocks = 0;
            let mut block_len = 1u32;
            for range in samples.ranges() {
                let mut first = range.start;
                while first < range.end {
                    if interrupted
                        || crate::interrupt::stop_requested()
                        || job.stop_after_blocks == Some(blocks)
                    {
                        interrupted = true;
                        return Ok(());
                    }
                    let end = range.end.min(first.saturating_add(block_len));
                    let block_start = Instant::now();
                    let paths =
                        u64::from(first) * light_paths_per_pass..u64::from(end) * light_paths_per_pass;
                    if light_paths_per_pass > 0 {
                        // The block's light passes first, into zero light sums, the passes done
                        // set aside: a stop abandons them halfway and restores those (a part
                        // holds whole passes). The paths that teach the guide come first, then
                        // the rest, by the guide.
                        let light_start = Instant::now();
                        sums.swap_light(&mut light_done);
                        let traced = light.trace(&light_run, Some(&mut sums), paths.clone())?;
                        light_elapsed += light_start.elapsed();
                        let Some(traced_rays) = traced else {
                            sums.swap_light(&mut light_done);
                            interrupted = true;
                            return Ok(());
                        };
                        light_rays += traced_rays;
                    }
                    let (block_rays, failed) = pool.install(|| {
                        camera_block(scene, &integrator, job, &edges, &mut sums, first..end, &progress)
                    });
                    rays += block_rays;
                    if let Some((x, y)) = failed {
                        return Err(not_summable(x, y));
                    }
                    if refine && first == 0 {
                        // The edge map from the first pass in the camera sums, and the first pass
                        // of the edge pixels completed with their samples per pass.
                        edges = pool.install(|| find_edges(scene, &integrator, job, Some(&sums)));
                        let (completing_rays, failed) =
                            pool.install(|| complete_first_pass(scene, &integrator, job, &edges, &mut sums));
                        rays += completing_rays;
                        if let Some((x, y)) = failed {
                            return Err(not_summable(x, y));
                        }
                    }
                    if light_paths_per_pass > 0 {
                        // The block is whole: the passes done join its light.
                        sums.add_light(&light_done)
                            .map_err(|overflow| not_summable(overflow.x, overflow.y))?;
                        light_done.fill(FixedSum::ZERO);
                    }
                    done += u64::from(end - first);
                    blocks += 1;
                    // The next block: about TARGET_BLOCK_SECONDS, growing at most fourfold.
                    let seconds_per_sample = block_start.elapsed().as_secs_f64() / f64::from(end - first);
                    let target = (TARGET_BLOCK_SECONDS / seconds_per_sample.max(1e-9)).floor();
                    block_len = (target.min(f64::from(block_len) * 4.0) as u32).max(1);
                    first = end;
                }
            }
            Ok(())
        })();
        finished.store(true, Ordering::SeqCst);
        // Wake the logger now rather than at its next tick, which the render would wait for.
        if let Some(logger) = &logger {
            logger.thread().unpark();
        }
        result
    });
    result?;
    progress.finish_and_clear();
    let done = samples.first(done);
    let stats = RenderStats {
        rays: rays + light_rays,
        // Every pass of an edge pixel takes its `edge_samples` (the first pass completed included).
        samples: done.len()
            * (window.pixels() as u64
                + edges.edge_pixels() as u64 * u64::from(job.settings.edge_samples.saturating_sub(1))),
        elapsed: start.elapsed(),
        cpu: crate::cpu_time::process_cpu_time()
            .zip(start_cpu)
            .and_then(|(end, start)| end.checked_sub(start)),
        threads,
        light_paths: done.len() * light_paths_per_pass,
        light_rays,
        light_elapsed,
        light_guide_gain: light.predicted_gain,
        edge_pixels: edges.edge_pixels(),
    };
    Ok(Rendered { sums, samples: done, interrupted, light_paths_per_pass, stats })
}

/// The error for a pixel whose samples cannot be summed.
fn not_summable(x: u32, y: u32) -> RenderError {
    RenderError::NonFinite(NonFinitePixel { x, y, xyz: glam::Vec3::NAN })
}

/// Prints a line of progress with the time left after the first [`FIRST_PROGRESS_LOG`] (so that
/// even a short part's log says how long it expects to take), then every `every`, until
/// `finished`.
fn log_progress(progress: &ProgressBar, every: Duration, finished: &AtomicBool, start: Instant, unit: &str) {
    let mut next = FIRST_PROGRESS_LOG.min(every);
    while !finished.load(Ordering::SeqCst) {
        // Unparked when the render finishes (a wake-up without it just loops).
        std::thread::park_timeout(Duration::from_millis(100));
        if finished.load(Ordering::SeqCst) {
            break;
        }
        if start.elapsed() < next {
            continue;
        }
        next = start.elapsed() + every;
        let (done, total) = (progress.position(), progress.length().unwrap_or(0).max(1));
        let elapsed = start.elapsed().as_secs_f64();
        let left = if done > 0 { elapsed * (total - done.min(total)) as f64 / done as f64 } else { f64::NAN };
        eprintln!(
            "progress: {:.1}% ({done} of {total} {unit}), {} elapsed, about {} left",
            100.0 * done as f64 / total as f64,
            clock(elapsed),
            if left.is_finite() { clock(left) } else { "?".to_owned() }
        );
    }
}

/// Seconds as h:mm:ss.
pub fn clock(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
}

/// Adds samples `block` of every pixel of the window to `sums`, rows in parallel: the rays
/// cast, and the first pixel whose samples could not be summed, if any.
fn camera_block(
    scene: &Scene,
    integrator: &CameraIntegrator,
    job: &Job,
    edges: &EdgeMap,
    sums: &mut WindowSums,
    block: std::ops::Range<u32>,
    progress: &ProgressBar,
) -> (u64, Option<(u32, u32)>) {
    let window = sums.window();
    let layout = *sums.layout();
    let row_values = window.width() as usize * layout.values_per_pixel();
    sums.camera_mut()
        .par_chunks_mut(row_values)
        // One row per work item: rows of glass and rows of wall cost very different times.
        .with_max_len(1)
        .enumerate()
        .map(|(row, row_sums)| {
            let y = window.y0 + row as u32;
            let result = render_span(
                scene,
                integrator,
                job,
                &layout,
                edges,
                (window.x0, y),
                row_sums,
                block.clone(),
                0,
            );
            progress.inc(u64::from(window.width()) * u64::from(block.end - block.start));
            result
        })
        .reduce(|| (0, None), |a, b| (a.0 + b.0, a.1.or(b.1)))
}

/// The edge map of the job's window ([`crate::edges`]) from the first pass's camera luminance
/// of the window and the pixels around it: read from `first_pass` (sums holding exactly the
/// first pass of the window) where given, rendered for the map alone elsewhere.
fn find_edges(
    scene: &Scene,
    integrator: &CameraIntegrator,
    job: &Job,
    first_pass: Option<&WindowSums>,
) -> EdgeMap {
    let (width, height) = (scene.camera.width(), scene.camera.height());
    let window = job.window.unwrap_or(PixelWindow::full(width, height));
    let area = edges::surrounding(window, width, height);
    let layout = job.layout();
    let stride = layout.values_per_pixel();
    let luminance = layout.luminance_index();
    if let Some(sums) = first_pass.filter(|_| area == window) {
        // All in the sums (the whole image): read them here, no work for the pool.
        let camera = sums.camera();
        let at = |x: u32, y: u32| {
            let index = (y - window.y0) as usize * window.width() as usize + (x - window.x0) as usize;
            camera[index * stride + luminance].mean(1.0)
        };
        return EdgeMap::find(window, area, at, job.settings.edge_samples);
    }
    let none = EdgeMap::uniform(area);
    let rows: Vec<Vec<f64>> = (area.y0..area.y1)
        .into_par_iter()
        .map(|y| {
            // The first pass of the pixels of this row that the sums do not hold.
            let mut rendered = vec![FixedSum::ZERO; area.width() as usize * stride];
            let held = |x: u32| first_pass.is_some() && window.contains(x, y);
            for x in (area.x0..area.x1).filter(|&x| !held(x)) {
                let at = (x - area.x0) as usize * stride;
                let pixel = &mut rendered[at..at + stride];
                // A value that cannot be summed fails the render in its own pass; here it only
                // leaves the pixel dark.
                let _ = render_span(scene, integrator, job, &layout, &none, (x, y), pixel, 0..1, 0);
            }
            (area.x0..area.x1)
                .map(|x| match first_pass {
                    Some(sums) if held(x) => {
                        let index =
                            (y - window.y0) as usize * window.width() as usize + (x - window.x0) as usize;
                        sums.camera()[index * stride + luminance].mean(1.0)
                    }
                    _ => rendered[(x - area.x0) as usize * stride + luminance].mean(1.0),
                })
                .collect()
        })
        .collect();
    EdgeMap::find(
        window,
        area,
        |x, y| rows[(y - area.y0) as usize][(x - area.x0) as usize],
        job.settings.edge_samples,
    )
}

/// Completes the first pass of `edges`' edge pixels (`sums` hold the first pass only): the one
/// sample each took is weighed 1/m and joined by the pass's other m − 1 samples, as in every
/// later pass. The rays cast, and the first pixel whose samples could not be summed, if any.
fn complete_first_pass(
    scene: &Scene,
    integrator: &CameraIntegrator,
    job: &Job,
    edges: &EdgeMap,
    sums: &mut WindowSums,
) -> (u64, Option<(u32, u32)>) {
    let window = sums.window();
    let layout = *sums.layout();
    let stride = layout.values_per_pixel();
    sums.camera_mut()
        .par_chunks_mut(window.width() as usize * stride)
        .enumerate()
        .map(|(row, row_sums)| {
            let y = window.y0 + row as u32;
            let mut result = (0, None);
            for (i, pixel) in row_sums.chunks_exact_mut(stride).enumerate() {
                let x = window.x0 + i as u32;
                if edges.samples(x, y) == 1 {
                    continue;
                }
                // The first sample stays, at its weight 1/m like the others.
                let weight = 1.0 / f64::from(edges.samples(x, y));
                let mut scaled = true;
                for sum in pixel.iter_mut().filter(|sum| !sum.is_zero()) {
                    match FixedSum::from_f64(sum.to_f64() * weight) {
                        Some(value) => *sum = value,
                        None => scaled = false,
                    }
                }
                let (rays, failed) =
                    render_span(scene, integrator, job, &layout, edges, (x, y), pixel, 0..1, 1);
                let failed = failed.or((!scaled).then_some((x, y)));
                result = (result.0 + rays, result.1.or(failed));
            }
            result
        })
        .reduce(|| (0, None), |a, b| (a.0 + b.0, a.1.or(b.1)))
}

/// [`render_row`] from pixel `at` on (as many pixels as `sums` hold), carrying the layout's
/// beams: Stokes vectors or spectra.
#[allow(clippy::too_many_arguments)] // the pixels' place and the render's state, passed flat
fn render_span(
    scene: &Scene,
    integrator: &CameraIntegrator,
    job: &Job,
    layout: &FilmLayout,
    edges: &EdgeMap,
    (x, y): (u32, u32),
    sums: &mut [FixedSum],
    passes: std::ops::Range<u32>,
    first_sub: u32,
) -> (u64, Option<(u32, u32)>) {
    if layout.stokes {
        render_row::<Stokes>(scene, integrator, job, layout, edges, y, x, sums, passes, first_sub)
    } else {
        render_row::<SampledSpectrum>(scene, integrator, job, layout, edges, y, x, sums, passes, first_sub)
    }
}

/// The light tracer's passes: the first `learning_paths` light paths of the render start
/// uniformly and teach the guide that the others start by ([`guide`]). Light paths are
/// numbered over the whole render.
struct LightPasses<'a> {
    uniform: LightTracer<'a>,
    guided: Option<LightTracer<'a>>,
    learning_paths: u64,
    weights: guide::PathWeights,
    record: guide::Record,
    predicted_gain: Option<f64>,
}

impl<'a> LightPasses<'a> {
    /// The passes of `tracer` (uniform) for `job`, `per_pass` light paths a pass (0 without
    /// caustics).
    fn new(tracer: LightTracer<'a>, job: &Job, per_pass: u64) -> Self {
        let learning_paths =
            if per_pass > 0 && job.settings.light_guide { guide::learning_paths(per_pass) } else { 0 };
        Self {
            uniform: tracer,
            guided: None,
            learning_paths,
            weights: guide::PathWeights::new(per_pass, learning_paths),
            record: guide::Record::default(),
            predicted_gain: None,
        }
    }

    /// Learns the guide from the paths recorded, once, when light paths up to `paths_end` have
    /// been traced and they include all the learning paths.
    fn learn_after(&mut self, paths_end: u64, display: (u32, u32)) {
        if self.guided.is_some() || self.learning_paths == 0 || paths_end < self.learning_paths {
            return;
        }
        let learned = guide::learn(&self.record, display);
        self.record = guide::Record::default();
        self.predicted_gain = learned.predicted_gain;
        self.guided = Some(self.uniform.clone().with_guide(learned.guide));
    }

    /// Traces the light paths `paths` (adding their splats to `sums`, unless `None`): the
    /// light tracer's rays, or `None` when a stop cut them short ([`light_block`]).
    fn trace(
        &mut self,
        run: &LightRun,
        mut sums: Option<&mut WindowSums>,
        paths: std::ops::Range<u64>,
    ) -> Result<Option<u64>, RenderError> {
        let Some(rays) = self.trace_learning(run, sums.as_deref_mut(), &paths)? else {
            return Ok(None);
        };
        self.learn_after(paths.end, run.display);
        Ok(self.trace_guided(run, sums, &paths)?.map(|guided| rays + guided))
    }

    /// Traces the learning paths among `paths` (uniformly, recorded for the guide unless it is
    /// learned already: a part that learned first): the rays, or `None` when a stop cut them
    /// short (and nothing was recorded).
    fn trace_learning(
        &mut self,
        run: &LightRun,
        sums: Option<&mut WindowSums>,
        paths: &std::ops::Range<u64>,
    ) -> Result<Option<u64>, RenderError> {
        let learning = paths.start..paths.end.min(self.learning_paths);
        if learning.is_empty() {
            return Ok(Some(0));
        }
        let traced = light_block(run, &self.uniform, self.weights, sums, learning, self.guided.is_none())?;
        Ok(traced.map(|(rays, record)| {
            self.record.append(record);
            rays
        }))
    }

    /// Traces the paths among `paths` past the learning paths, by the guide once learned
    /// ([`Self::learn_after`]; uniformly without one): the rays, or `None` when a stop cut
    /// them short.
    fn trace_guided(
        &self,
        run: &LightRun,
        sums: Option<&mut WindowSums>,
        paths: &std::ops::Range<u64>,
    ) -> Result<Option<u64>, RenderError> {
        let rest = paths.start.max(self.learning_paths)..paths.end;
        if rest.is_empty() {
            return Ok(Some(0));
        }
        let tracer = self.guided.as_ref().unwrap_or(&self.uniform);
        Ok(light_block(run, tracer, self.weights, sums, rest, false)?.map(|(rays, _)| rays))
    }
}

/// Where light paths are traced: the render's pool and job, the display (width, height) their
/// splats land on, and the progress bar they advance.
struct LightRun<'r> {
    pool: &'r rayon::ThreadPool,
    job: &'r Job,
    display: (u32, u32),
    progress: &'r ProgressBar,
}

/// Traces the light paths `paths` in blocks on `run`'s pool and adds their splats in the window to
/// `sums` (unless `None`): the rays cast, and when `record` the paths' record for learning a
/// guide (in path order; [`guide::Record`]); `None` when a stop ([`crate::interrupt`]) came
/// first: then only some of the blocks were traced, and the caller abandons what they added.
///
/// The blocks are handed to the pool [`LIGHT_BLOCKS_PER_CHUNK`] at a time, as ranges (a pass
/// of 2^40 paths is 2^31 blocks: their list alone would be 17 GB), and a block whose turn comes
/// after a stop is skipped, so a stop waits for one block per thread.
///
/// Each block's splats are added to `sums` (unless `None`) by the thread that traced it, as soon
/// as it is done, under a lock: exact sums do not depend on the order of their terms, so the
/// image is the same bits whatever the schedule, and no thread waits for a serial summation
/// between batches of blocks. A failure names the pixel of the lowest-numbered block that had
/// one.
#[allow(clippy::too_many_arguments)] // the render's state, passed flat
fn light_block(
    run: &LightRun,
    tracer: &LightTracer,
    weights: guide::PathWeights,
    sums: Option<&mut WindowSums>,
    paths: std::ops::Range<u64>,
    record: bool,
) -> Result<Option<(u64, guide::Record)>, RenderError> {
    let LightRun { pool, job, display: (display_width, _), progress } = *run;
    let layout = tracer.splat_layout(&job.layout());
    let first_block = paths.start / LIGHT_PATH_BLOCK;
    let end_block = paths.end.div_ceil(LIGHT_PATH_BLOCK);
    let shared = Mutex::new(LightSums { sums, rays: 0, failed: None, records: Vec::new() });
    let trace = |block: u64| {
        if crate::interrupt::stop_requested() {
            return;
        }
        let first = paths.start.max(block * LIGHT_PATH_BLOCK);
        let end = paths.end.min((block + 1) * LIGHT_PATH_BLOCK);
        let (splats, stats, block_record) = if job.polarized() {
            trace_block::<Stokes>(tracer, job, &layout, weights, first..end, record)
        } else {
            trace_block::<SampledSpectrum>(tracer, job, &layout, weights, first..end, record)
        };
        // A panic elsewhere poisons the lock; the sums it guards are still whole.
        let mut shared = shared.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some(pixel) = shared.sums.as_mut().and_then(|sums| sums.add_splats(&splats, display_width)) {
            if shared.failed.is_none_or(|(earliest, _)| block < earliest) {
                shared.failed = Some((block, pixel));
            }
        }
        shared.rays += stats.rays;
        if let Some(block_record) = block_record {
            shared.records.push((block, block_record));
        }
        drop(shared);
        progress.inc(end - first);
    };
    pool.install(|| {
        let mut chunk_start = first_block;
        while chunk_start < end_block && !crate::interrupt::stop_requested() {
            let chunk_len = (end_block - chunk_start).min(LIGHT_BLOCKS_PER_CHUNK);
            // A chunk holds at most LIGHT_BLOCKS_PER_CHUNK blocks: its offsets fit in usize.
            (0..chunk_len as usize)
                .into_par_iter()
                .with_max_len(1)
                .for_each(|k| trace(chunk_start + k as u64));
            chunk_start += chunk_len;
        }
    });
    // A stop is never withdrawn while the render runs: after this check, no block was skipped.
    if crate::interrupt::stop_requested() {
        return Ok(None);
    }
    let mut shared = shared.into_inner().unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some((_, (x, y))) = shared.failed {
        return Err(not_summable(x, y));
    }
    // The blocks' records in path order, whatever order they finished in.
    shared.records.sort_by_key(|(block, _)| *block);
    let mut all = guide::Record::default();
    for (_, block_record) in shared.records {
        all.append(block_record);
    }
    Ok(Some((shared.rays, all)))
}

/// What the light tracer's blocks add to, shared between the render threads.
struct LightSums<'a> {
    sums: Option<&'a mut WindowSums>,
    rays: u64,
    /// The first block (by number) whose splats could not be summed, and the pixel.
    failed: Option<(u64, (u32, u32))>,
    /// The blocks' records for learning, by block number.
    records: Vec<(u64, guide::Record)>,
}

/// Traces the light paths `paths` (all inside one block): their splats in path order, their
/// counters, and when `record` their record for learning a guide (only for a tracer whose
/// paths start uniformly: the record files each path under its unwarped start).
fn trace_block<B: crate::integrator::Beam>(
    tracer: &LightTracer,
    job: &Job,
    layout: &FilmLayout,
    weights: guide::PathWeights,
    paths: std::ops::Range<u64>,
    record: bool,
) -> (Splats, TraceStats, Option<guide::Record>) {
    // One sequence over all the render's light paths, whichever block or part traces them.
    let sequence = LightPathSequence::new(job.settings.seed ^ LIGHT_PATH_SEED_SALT);
    let mut splats = Splats::default();
    let mut scratch = Scratch::<B>::default();
    let mut stats = TraceStats::default();
    debug_assert!(!(record && tracer.is_guided()), "a guided path's start is not what it recorded");
    let mut block_record = record.then(guide::Record::default);
    for (path, mut rng) in paths.clone().zip(sequence.paths(paths)) {
        let (splats_before, rays_before) = (splats.len(), stats.rays);
        let u = tracer.trace_path::<B>(&mut rng, layout, &mut splats, &mut scratch, &mut stats);
        if let Some(block_record) = block_record.as_mut() {
            let landings = (splats_before..splats.len()).map(|k| splats.luminance(k, layout));
            block_record.add_path(u, stats.rays - rays_before, landings);
        }
        let weight = weights.weight(path);
        if weight != 1.0 {
            splats.scale_from(splats_before, weight, layout);
        }
    }
    (splats, stats, block_record)
}

/// Adds samples (passes) `block` of the pixels `x0..` of row `y` to their sums `row_sums` (the
/// row of the window), carrying beams of type `B`, each pass of a pixel the mean of its
/// [`EdgeMap::samples`] camera samples (from sample `first_sub` of each pass on: 1 to complete
/// a first pass whose first sample is in already): the rays cast, and the first pixel whose
/// samples could not be summed, if any.
#[allow(clippy::too_many_arguments)] // the row's place and the render's state, passed flat
fn render_row<B: PathBeam>(
    scene: &Scene,
    integrator: &CameraIntegrator,
    job: &Job,
    layout: &FilmLayout,
    edges: &EdgeMap,
    y: u32,
    x0: u32,
    row_sums: &mut [FixedSum],
    block: std::ops::Range<u32>,
    first_sub: u32,
) -> (u64, Option<(u32, u32)>) {
    let settings = &job.settings;
    let mut stats = TraceStats::default();
    let mut failed = None;
    let stride = layout.values_per_pixel();
    // A monochromatic render's one wavelength, made once (with its place on the spectral grid).
    let monochromatic = job.monochromatic_nm.map(SampledWavelengths::monochromatic);
    for (i, pixel_sums) in row_sums.chunks_exact_mut(stride).enumerate() {
        let x = x0 + i as u32;
        let key = PixelKey::new(settings.seed, x, y);
        let mut sample = |index: u32, sums: &mut [FixedSum], weight: f32| {
            let mut rng = PixelRng::for_sample(key, index);
            // The position first: the sampler's first two dimensions are stratified jointly.
            let (jx, jy) = (rng.uniform(), rng.uniform());
            // Dimension 2 (`sampler::WAVELENGTH_DIMENSION`): evenly spaced over the pixel's samples.
            let u_lambda = rng.uniform();
            let sampled;
            let wavelengths = match &monochromatic {
                Some(wavelengths) => wavelengths,
                None => {
                    sampled = SampledWavelengths::sample_visible(u_lambda, settings.wavelengths);
                    &sampled
                }
            };
            if let Camera::Lens(lens) = &scene.camera {
                let film = (x as f32 + jx, y as f32 + jy);
                return add_lens_sample::<B>(
                    lens,
                    integrator,
                    (x, y),
                    film,
                    wavelengths,
                    &mut rng,
                    &mut stats,
                    sums,
                    layout,
                    weight,
                    job.fault,
                );
            }
            // A lens takes the next two dimensions (3 and 4); the pinhole none.
            let ray =
                scene.camera.sample_ray(x as f32 + jx, y as f32 + jy, || (rng.uniform(), rng.uniform()));
            let frame_x = if B::POLARIZED { scene.camera.stokes_x(ray.dir) } else { ray.dir };
            let light: B = integrator.radiance(&ray, frame_x, wavelengths, &mut rng, &mut stats);
            add_weighted_sample(sums, &light, wavelengths, layout, weight)
        };
        for pass in block.clone() {
            let per_pass = edges.samples(x, y);
            let mut ok = true;
            // The pass adds the mean of its samples: each weighs 1/m (1 exactly for one).
            let weight = 1.0 / per_pass as f32;
            for sub in first_sub..per_pass {
                ok &= sample(edges::sample_index(pass, per_pass, sub), pixel_sums, weight);
            }
            if !ok {
                failed.get_or_insert((x, y));
            }
        }
    }
    (stats.rays, failed)
}

/// Adds to `sums` (weighted by `weight`, as [`add_weighted_sample`]) what a lens-system camera
/// records for one camera sample at film position `film` (pixels) of pixel `pixel`, with the
/// pupil numbers (dimensions 3 and 4, as a thin lens's). The lens bends every wavelength its
/// own way. Without ghosts (and with more than one lane) the lanes share one scene path: a
/// hero lane drawn by the next number (dimension 5) sends its ray out, the lens camera weighs
/// every lane by spectral MIS through the lens's inverse map
/// ([`crate::camera::LensCamera::sample_shared_path`]), and one integrator call with all the
/// lanes live brings the light back. Otherwise each live lane gets its own ray, traced through
/// the lens at its wavelength with the same film position and pupil numbers, and its own
/// integrator call with that lane alone live ([`SampledWavelengths::lane_alone`]). The light
/// is weighted by the lane's [`crate::lens::CameraRay::weight`] (unpolarised), or goes through
/// the lens's Mueller matrix times the sensor weight (polarised). A lane whose ray does not
/// pass the lens (or, shared, whose preimage is outside the pixel) adds 0.
#[allow(clippy::too_many_arguments)] // the sample's place and the render's state, passed flat
fn add_lens_sample<B: PathBeam>(
    lens: &crate::camera::LensCamera,
    integrator: &CameraIntegrator,
    pixel: (u32, u32),
    film: (f32, f32),
    wavelengths: &SampledWavelengths,
    rng: &mut PixelRng,
    stats: &mut TraceStats,
    sums: &mut [FixedSum],
    layout: &FilmLayout,
    weight: f32,
    fault: Option<Fault>,
) -> bool {
    let u_pupil = (rng.uniform(), rng.uniform());
    let mut stokes = [SampledSpectrum::zero(); 4];
    let active = wavelengths.active();
    let lambdas: [f32; N_LAMBDA] = std::array::from_fn(|lane| wavelengths.lambda_nm(lane));
    // Lane `lane`'s light `components` (of the ray's Stokes frame) through its camera ray.
    let mut record = |lane: usize, camera_ray: &crate::lens::CameraRay, components: &[SampledSpectrum]| {
        if B::POLARIZED {
            let arriving: [f64; 4] = std::array::from_fn(|k| f64::from(components[k][lane]));
            for (row, out) in stokes.iter_mut().enumerate() {
                let value: f64 = (0..4).map(|k| camera_ray.sample.mueller[row][k] * arriving[k]).sum();
                out[lane] = (camera_ray.sensor_weight * value) as f32;
            }
        } else {
            stokes[0][lane] = (camera_ray.weight * f64::from(components[0][lane])) as f32;
        }
    };
    if active > 1 && lens.shares_scene_path() {
        let u_hero = rng.uniform();
        let hero_pdf_only = fault == Some(Fault::LensHeroPdfOnly);
        let shared = lens.sample_shared_path(
            pixel,
            film,
            u_pupil,
            u_hero,
            &lambdas[..active],
            B::POLARIZED,
            hero_pdf_only,
        );
        if let Some(hero) = shared.filter(|hero| hero.lanes.iter().any(Option::is_some)) {
            let frame_x = if B::POLARIZED { lens.pinhole().stokes_x(hero.ray.dir) } else { hero.ray.dir };
            let light: B = integrator.radiance(&hero.ray, frame_x, wavelengths, rng, stats);
            let components = light.components();
            for (lane, camera_ray) in hero.lanes[..active].iter().enumerate() {
                if let Some(camera_ray) = camera_ray {
                    record(lane, camera_ray, components);
                }
            }
        }
    } else {
        // Without ghosts every lane's ray is traced at once (the same rays as one by one,
        // faster); with them each lane's branch choices draw from `rng` in turn.
        let all_lanes = lens.sample_rays_for_lanes(film.0, film.1, u_pupil, &lambdas[..active], B::POLARIZED);
        for lane in 0..active {
            let lambda_nm = wavelengths.lambda_nm(lane);
            let traced = match &all_lanes {
                Some(rays) => rays[lane],
                None => lens.sample_ray_for(film.0, film.1, u_pupil, lambda_nm, B::POLARIZED, &mut || {
                    f64::from(rng.uniform())
                }),
            };
            let Some((ray, camera_ray)) = traced else { continue };
            let frame_x = if B::POLARIZED { lens.pinhole().stokes_x(ray.dir) } else { ray.dir };
            let alone = wavelengths.lane_alone(lane);
            let light: B = integrator.radiance(&ray, frame_x, &alone, rng, stats);
            record(lane, &camera_ray, light.components());
        }
    }
    if B::POLARIZED {
        add_weighted_sample(sums, &Stokes { s: stokes }, wavelengths, layout, weight)
    } else {
        add_weighted_sample(sums, &stokes[0], wavelengths, layout, weight)
    }
}

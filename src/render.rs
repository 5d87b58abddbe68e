//! [`render`]: the image of a scene, tiles in parallel on a rayon pool.
//!
//! Every camera sample draws its sample values from a sequence keyed by (seed, pixel, sample),
//! and each pixel's samples are summed in a fixed order, so the image is bit-identical whatever
//! the thread count and tile schedule.
//!
//! With caustics on, the light tracer then traces `spp` passes of light paths (one per pixel per
//! pass unless the settings say otherwise) in fixed blocks of [`LIGHT_PATH_BLOCK`] paths: light
//! path n of the render draws point n of one sample sequence keyed by the seed
//! ([`LightPathSequence`]), and each block records its splats in order; the blocks' splats are summed into one film in block order, whichever thread traced
//! them, and the sums divided by the number of light paths are added to the Whitted image.

use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;

use crate::film::{
    Film, FilmLayout, NonFinitePixel, PixelMeans, PixelSums, SpectralBands, SplatSums, Splats,
};
use crate::integrator::light_tracer::Scratch;
use crate::integrator::{Beam, Fault, LightTracer, TraceStats, Whitted};
use crate::memory;
use crate::polarization::Stokes;
use crate::sampler::{LightPathSequence, PixelKey, PixelRng};
use crate::scene::{RenderSettings, Scene};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};

/// Side of the square tiles rendered as units of parallel work, in pixels.
const TILE: u32 = 16;
/// Stack of each render thread: Whitted recursion runs on it, one frame per bounce.
const THREAD_STACK_BYTES: usize = 64 << 20;
/// Light paths per block: the unit of parallel work of the light tracer, and of its sample
/// sequences (a power of two, so that a block's paths are a whole Sobol net).
pub const LIGHT_PATH_BLOCK: u64 = 4096;
/// Blocks traced before their splats are summed: bounds the memory the splats take.
const BLOCKS_PER_WAVE: u64 = 64;
/// Mixed into the seed of the light paths' sample sequences, so that they are independent of
/// the camera samples'.
const LIGHT_PATH_SEED_SALT: u64 = 0x6c69_6768_7470_6174;

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
}

impl Job {
    /// A colour render with `settings`, one thread per core, no progress bar, no fault, no
    /// spectral bands.
    pub fn new(settings: RenderSettings) -> Self {
        Self { settings, threads: 0, monochromatic_nm: None, progress: false, fault: None, bands: None }
    }

    /// True when the render carries Stokes vectors: the scene asks for it and no fault drops it.
    pub fn polarized(&self) -> bool {
        self.settings.polarized && self.fault != Some(Fault::Unpolarized)
    }

    /// What each pixel of the film holds.
    pub fn layout(&self) -> FilmLayout {
        FilmLayout { stokes: self.polarized(), bands: self.bands, monochromatic_nm: self.monochromatic_nm }
    }
}

/// Figures of a finished render.
#[derive(Debug, Clone, Copy)]
pub struct RenderStats {
    /// Rays cast (camera, specular and shadow, light paths and their connections).
    pub rays: u64,
    /// Camera samples taken.
    pub samples: u64,
    /// Wall-clock time.
    pub elapsed: Duration,
    /// Threads used.
    pub threads: usize,
    /// Light paths traced for caustics (0 without).
    pub light_paths: u64,
    /// Rays of the light tracer (included in `rays`).
    pub light_rays: u64,
    /// Wall-clock time of the light tracer (included in `elapsed`).
    pub light_elapsed: Duration,
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
}

/// Bytes of memory a render of `width`×`height` pixels of `layout` on `threads` threads needs,
/// with its EXR and PNG output ([`memory::estimate`]), and with the light tracer's f64 splat sums
/// (XYZ per Stokes component and the band values) when `caustics` is on.
pub fn memory_needed(width: u32, height: u32, layout: &FilmLayout, threads: usize, caustics: bool) -> u64 {
    let splat_sums = if caustics {
        u64::from(width) * u64::from(height) * 8 * (3 * layout.components() + layout.band_values()) as u64
    } else {
        0
    };
    memory::estimate(width, height, layout.band_values(), threads as u64 * THREAD_STACK_BYTES as u64)
        + splat_sums
}

/// Renders `scene` (its camera decides the resolution) as `job` says.
///
/// Errors before any work when the image cannot fit in memory, and after the render when a
/// pixel is not finite (naming the first one).
pub fn render(scene: &Scene, job: &Job) -> Result<(Film, RenderStats), RenderError> {
    let (width, height) = (scene.camera.width(), scene.camera.height());
    // The pool's thread count, without starting a pool to ask it.
    let threads = match job.threads {
        0 => std::thread::available_parallelism().map_or(1, usize::from),
        n => n,
    };
    memory::check(
        width,
        height,
        memory_needed(width, height, &job.layout(), threads, job.settings.caustics),
    )?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(job.threads)
        .stack_size(THREAD_STACK_BYTES)
        .build()
        .map_err(|source| RenderError::ThreadPool { threads: job.threads, source })?;
    let threads = pool.current_num_threads();
    let tiles: Vec<(u32, u32)> = (0..height.div_ceil(TILE))
        .flat_map(|ty| (0..width.div_ceil(TILE)).map(move |tx| (tx * TILE, ty * TILE)))
        .collect();
    let tracer = LightTracer::new(scene, &job.settings, job.monochromatic_nm).with_fault(job.fault);
    let light_paths = if tracer.why_none().is_none() {
        job.settings.total_light_paths(u64::from(width) * u64::from(height))
    } else {
        0
    };
    let blocks = light_paths.div_ceil(LIGHT_PATH_BLOCK);
    // Progress in camera samples and light paths, not tiles: edge tiles are smaller, and a count
    // of tiles done overstated the progress of images whose width or height is not a multiple of
    // the tile. (A light path costs about what a camera sample does.)
    let samples = u64::from(width) * u64::from(height) * u64::from(job.settings.spp);
    let progress = if job.progress { ProgressBar::new(samples + light_paths) } else { ProgressBar::hidden() };
    if let Ok(style) =
        ProgressStyle::with_template("{spinner} [{elapsed_precise}] {wide_bar} {percent}% eta {eta}")
    {
        progress.set_style(style);
    }
    let start = Instant::now();
    let integrator = Whitted::new(
        scene,
        job.settings.max_depth,
        job.settings.prune_below,
        job.settings.area_light_samples,
    )
    .with_fault(job.fault);
    let layout = job.layout();
    let rendered: Vec<(Vec<PixelMeans>, TraceStats)> = pool.install(|| {
        tiles
            .par_iter()
            // One tile per work item: rayon's default splitting stops early and left one core
            // idle at the end of a render (1.67× → 1.98× from 1 to 2 threads on the showcase).
            .with_max_len(1)
            .map(|&(x0, y0)| {
                let tile = if layout.stokes {
                    render_tile::<Stokes>(scene, &integrator, job, &layout, x0, y0)
                } else {
                    render_tile::<SampledSpectrum>(scene, &integrator, job, &layout, x0, y0)
                };
                progress.inc(tile.0.len() as u64 * u64::from(job.settings.spp));
                tile
            })
            .collect()
    });

    let mut pixels = vec![PixelMeans::default(); width as usize * height as usize];
    let mut rays = 0;
    for (&(x0, y0), (tile_pixels, stats)) in tiles.iter().zip(rendered) {
        rays += stats.rays;
        let tile_width = TILE.min(width - x0) as usize;
        for (index, means) in tile_pixels.into_iter().enumerate() {
            let (row, column) = (index / tile_width, index % tile_width);
            pixels[(y0 as usize + row) * width as usize + x0 as usize + column] = means;
        }
    }

    let light_start = Instant::now();
    let mut light_rays = 0;
    if blocks > 0 {
        let mut sums = SplatSums::new(pixels.len(), &layout);
        for wave_start in (0..blocks).step_by(BLOCKS_PER_WAVE as usize) {
            let wave: Vec<u64> = (wave_start..blocks.min(wave_start + BLOCKS_PER_WAVE)).collect();
            let traced: Vec<(Splats, TraceStats)> = pool.install(|| {
                wave.par_iter()
                    .with_max_len(1)
                    .map(|&block| {
                        let traced = if layout.stokes {
                            trace_block::<Stokes>(&tracer, job, &layout, block, light_paths)
                        } else {
                            trace_block::<SampledSpectrum>(&tracer, job, &layout, block, light_paths)
                        };
                        progress.inc(LIGHT_PATH_BLOCK.min(light_paths - block * LIGHT_PATH_BLOCK));
                        traced
                    })
                    .collect()
            });
            for (splats, stats) in &traced {
                sums.add(splats);
                light_rays += stats.rays;
            }
        }
        sums.add_to(&mut pixels, light_paths, &layout);
    }
    progress.finish_and_clear();
    let stats = RenderStats {
        rays: rays + light_rays,
        samples,
        elapsed: start.elapsed(),
        threads,
        light_paths,
        light_rays,
        light_elapsed: light_start.elapsed(),
    };
    let film = Film::assemble(width, height, layout, pixels);
    film.check_finite()?;
    Ok((film, stats))
}

/// Traces light-path block `block` of a render of `light_paths` paths: its splats in path
/// order, and its counters.
fn trace_block<B: Beam>(
    tracer: &LightTracer,
    job: &Job,
    layout: &FilmLayout,
    block: u64,
    light_paths: u64,
) -> (Splats, TraceStats) {
    let first = block * LIGHT_PATH_BLOCK;
    let count = LIGHT_PATH_BLOCK.min(light_paths - first) as u32;
    // One sequence over all the render's light paths, whichever block traces them.
    let sequence = LightPathSequence::new(job.settings.seed ^ LIGHT_PATH_SEED_SALT);
    let mut splats = Splats::default();
    let mut scratch = Scratch::<B>::default();
    let mut stats = TraceStats::default();
    for path in 0..count {
        let mut rng = sequence.path(first + u64::from(path));
        tracer.trace_path::<B>(&mut rng, layout, &mut splats, &mut scratch, &mut stats);
    }
    (splats, stats)
}

/// The means of every pixel of the tile at (`x0`, `y0`), row-major, carrying beams of type `B`.
fn render_tile<B: Beam>(
    scene: &Scene,
    integrator: &Whitted,
    job: &Job,
    layout: &FilmLayout,
    x0: u32,
    y0: u32,
) -> (Vec<PixelMeans>, TraceStats) {
    let (width, height) = (scene.camera.width(), scene.camera.height());
    let settings = &job.settings;
    let mut stats = TraceStats::default();
    let mut pixels = Vec::with_capacity((TILE * TILE) as usize);
    let mut sums = PixelSums::new(layout);
    for y in y0..(y0 + TILE).min(height) {
        for x in x0..(x0 + TILE).min(width) {
            sums.clear();
            let key = PixelKey::new(settings.seed, x, y);
            for sample in 0..settings.spp {
                let mut rng = PixelRng::for_sample(key, sample);
                // The position first: the sampler's first two dimensions are stratified jointly.
                let (jx, jy) = (rng.uniform(), rng.uniform());
                let u_lambda = rng.uniform();
                let wavelengths = match job.monochromatic_nm {
                    Some(nm) => SampledWavelengths::monochromatic(nm),
                    None => SampledWavelengths::sample_visible(u_lambda, settings.wavelengths),
                };
                let ray = scene.camera.ray(x as f32 + jx, y as f32 + jy);
                let frame_x = if B::POLARIZED { scene.camera.stokes_x(ray.dir) } else { ray.dir };
                let light: B = integrator.radiance(&ray, frame_x, &wavelengths, &mut rng, &mut stats);
                sums.add(&light, &wavelengths, layout);
            }
            pixels.push(sums.means(settings.spp));
        }
    }
    (pixels, stats)
}

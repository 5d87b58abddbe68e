//! The light tracer alone on one thread: the cost of a light path (emission, Fresnel branches
//! through glass, the connection to the camera and its splat), without camera samples, thread
//! pool or film sums.
//!
//! The scene is the caustic bench's (`validation/scenes/caustic_sphere.toml`: a spot light
//! through an N-SF11 ball onto a floor), traced as `validation/bench/caustics_bench.py` traces it
//! (one wavelength, 550 nm, unpolarised) and as a colour render does (eight wavelengths per path,
//! polarised). Criterion's "elements/s" is light paths per second; the rays and splats per path
//! are printed once. `cargo bench --bench light_tracer`.

use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use prisma::film::{FilmLayout, Splats};
use prisma::integrator::light_tracer::Scratch;
use prisma::integrator::{Beam, LightTracer, TraceStats};
use prisma::polarization::Stokes;
use prisma::sampler::LightPathSequence;
use prisma::scene::Scene;
use prisma::spectrum::SampledSpectrum;

/// Light paths per iteration: four of the render's blocks.
const PATHS: u64 = 4096;

/// Traces paths `0..PATHS` of the sequence of seed 1: the splats made and the rays cast.
fn trace<B: Beam>(tracer: &LightTracer, layout: &FilmLayout) -> (usize, u64) {
    let sequence = LightPathSequence::new(1);
    let mut splats = Splats::default();
    let mut scratch = Scratch::<B>::default();
    let mut stats = TraceStats::default();
    for path in 0..PATHS {
        let mut rng = sequence.path(path);
        tracer.trace_path::<B>(&mut rng, layout, &mut splats, &mut scratch, &mut stats);
    }
    (splats.len(), stats.rays)
}

/// Benchmarks beams of type `B` under `name`, at `monochromatic_nm` or over the spectrum.
fn bench_case<B: Beam>(c: &mut Criterion, scene: &Scene, name: &str, monochromatic_nm: Option<f32>) {
    let tracer = LightTracer::new(scene, &scene.settings, monochromatic_nm);
    let layout = FilmLayout { stokes: B::POLARIZED, bands: None, monochromatic_nm };
    let (splats, rays) = trace::<B>(&tracer, &layout);
    eprintln!(
        "{name}: {:.2} rays and {:.2} splats per light path",
        rays as f64 / PATHS as f64,
        splats as f64 / PATHS as f64
    );
    let mut group = c.benchmark_group("light_tracer");
    group.sample_size(20);
    group.throughput(Throughput::Elements(PATHS));
    group.bench_function(name, |b| b.iter(|| trace::<B>(&tracer, &layout)));
    group.finish();
}

fn light_tracer_benchmark(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("validation/scenes/caustic_sphere.toml");
    let scene = prisma::scene::load(&path).expect("the caustic bench scene is valid");
    bench_case::<SampledSpectrum>(c, &scene, "ball_lens_550nm_unpolarized", Some(550.0));
    bench_case::<Stokes>(c, &scene, "ball_lens_spectral_polarized", None);
}

criterion_group!(benches, light_tracer_benchmark);
criterion_main!(benches);

//! Shared by the tests that render one scene from both ends (`adjoint_transport.rs`,
//! `thin_lens.rs`): the light tracer alone over the whole emission, and `prisma validate`'s
//! pass rule for bias.

use prisma::film::{Film, FilmLayout, Splats, WindowSums};
use prisma::integrator::light_tracer::Scratch;
use prisma::integrator::{Fault, LightTracer, TraceStats};
use prisma::part::PixelWindow;
use prisma::polarization::Beam;
use prisma::sampler::LightPathSequence;
use prisma::scene::Scene;
use prisma::validate::cases::{DEFAULT_MAX_MEAN_Z, DEFAULT_MAX_OUTLIER_FRACTION};
use prisma::validate::metrics::Comparison;

/// The light tracer alone ([`LightTracer::counting_everything`]) at `lambda_nm`, `fault` on
/// the light side, seed `seed`: `paths` light paths split over `threads` threads, their splats
/// summed exactly (the image does not depend on the split), divided by `paths`. `B` is
/// `Stokes` for a polarised film, `SampledSpectrum` for an unpolarised one.
pub fn light_side_film<B: Beam>(
    scene: &Scene,
    (lambda_nm, fault): (f32, Option<Fault>),
    seed: u64,
    paths: u64,
    threads: usize,
) -> Film {
    let tracer =
        LightTracer::new(scene, &scene.settings, Some(lambda_nm)).with_fault(fault).counting_everything();
    assert_eq!(tracer.why_none(), None);
    let (width, height) = (scene.camera.width(), scene.camera.height());
    let layout = FilmLayout { stokes: B::POLARIZED, bands: None, monochromatic_nm: Some(lambda_nm) };
    let light_layout = tracer.splat_layout(&layout);
    let sequence = LightPathSequence::new(seed);
    let per_thread = paths.div_ceil(threads as u64);
    let splats: Vec<Splats> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads as u64)
            .map(|t| {
                let (tracer, sequence) = (&tracer, &sequence);
                let range = (t * per_thread).min(paths)..((t + 1) * per_thread).min(paths);
                scope.spawn(move || {
                    let (mut splats, mut scratch, mut stats) =
                        (Splats::default(), Scratch::<B>::default(), TraceStats::default());
                    for mut rng in sequence.paths(range) {
                        tracer.trace_path::<B>(
                            &mut rng,
                            &light_layout,
                            &mut splats,
                            &mut scratch,
                            &mut stats,
                        );
                    }
                    splats
                })
            })
            .collect();
        workers.into_iter().map(|w| w.join().expect("a light-tracing thread")).collect()
    });
    let mut sums = WindowSums::with_light_layout(PixelWindow::full(width, height), layout, light_layout);
    for part in &splats {
        assert_eq!(sums.add_splats(part, width), None);
    }
    sums.film(1, paths, (width, height))
}

/// True when `comparison` passes `prisma validate`'s default checks for bias: outliers beyond
/// the null at most [`DEFAULT_MAX_OUTLIER_FRACTION`], and |z| of the image means at most
/// [`DEFAULT_MAX_MEAN_Z`].
pub fn passes(comparison: &Comparison) -> bool {
    comparison.outlier_fraction - comparison.null_outlier_fraction <= DEFAULT_MAX_OUTLIER_FRACTION
        && comparison.mean_z <= DEFAULT_MAX_MEAN_Z
}

/// The walls shared by the two rooms rendered from both ends (floor y = 0, ceiling y = 3.5, back
/// wall z = 6, side walls x = ±3; open toward −z behind the camera) as scene TOML, with the
/// materials of the floor, ceiling, back, left (x = 3) and right (x = −3) walls in that order.
pub fn room_walls([floor, ceiling, back, left, right]: [&str; 5]) -> String {
    format!(
        r#"[[shapes]] # floor, y = 0
type = "quad"
corner = [-3, 0, -4]
edge1 = [6, 0, 0]
edge2 = [0, 0, 10]
material = "{floor}"

[[shapes]] # ceiling, y = 3.5
type = "quad"
corner = [-3, 3.5, -4]
edge1 = [6, 0, 0]
edge2 = [0, 0, 10]
material = "{ceiling}"

[[shapes]] # back wall, z = 6
type = "quad"
corner = [-3, 0, 6]
edge1 = [6, 0, 0]
edge2 = [0, 3.5, 0]
material = "{back}"

[[shapes]] # left wall, x = 3
type = "quad"
corner = [3, 0, -4]
edge1 = [0, 0, 10]
edge2 = [0, 3.5, 0]
material = "{left}"

[[shapes]] # right wall, x = -3
type = "quad"
corner = [-3, 0, -4]
edge1 = [0, 0, 10]
edge2 = [0, 3.5, 0]
material = "{right}"

"#
    )
}

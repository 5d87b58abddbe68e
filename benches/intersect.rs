//! Ray–scene intersection on a large mesh: BVH build time and memory, and closest-hit and
//! occlusion throughput (rays per second, single thread) for coherent camera rays and incoherent
//! random rays, traced one by one and in packets of 16 consecutive rays.
//!
//! The mesh is a displaced tessellated sphere of 2·500·1000 = 1 000 000 triangles (radius 1 with
//! a 10 % bump, the mesh of `geometry::accel::tests::benchmark`, so the numbers compare with the
//! earlier measurements). Rays:
//! * `camera`: a 1024² pinhole camera 4 units from the centre, in scanline order (36 % hit);
//! * `incoherent`: origins uniform on the sphere of radius 5, aimed at points uniform in the cube
//!   [−1, 1]³ (81 % hit), 250 000 per iteration.
//!
//! Criterion reports "elements/s": rays per second. `cargo bench --bench intersect`. Under
//! `cargo test --benches` (criterion's quick test mode, one iteration) the mesh is 20 000
//! triangles so that the test stays fast, unless `PRISMA_BENCH_FULL` is set.

use std::hint::black_box;
use std::time::Instant;

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use glam::Vec3;
use prisma::geometry::{Geometry, Mesh, Ray, Shape, PACKET_RAYS};
use rand_core::{RngCore, SeedableRng};
use rand_pcg::Pcg64;

/// True under `cargo bench` (cargo passes `--bench`) or with `PRISMA_BENCH_FULL` set (to profile
/// one iteration of each benchmark on the full mesh, e.g. under valgrind, in criterion's test
/// mode); false in `cargo test`'s quick mode.
fn full_size() -> bool {
    std::env::args().any(|arg| arg == "--bench") || std::env::var_os("PRISMA_BENCH_FULL").is_some()
}

fn displaced_sphere(rings: u32, segments: u32) -> Mesh {
    Mesh::displaced_sphere(rings, segments)
}

/// Every triangle of `mesh` as a shape.
fn triangle_shapes(mesh: &Mesh) -> Vec<Shape> {
    (0..mesh.triangles.len() as u32).map(|tri| Shape::Triangle { mesh: 0, tri }).collect()
}

/// Uniform in [0, 1) from 24 random bits.
fn uniform(rng: &mut Pcg64) -> f32 {
    (rng.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// Uniform on the unit sphere.
fn unit_vector(rng: &mut Pcg64) -> Vec3 {
    let z = 2.0 * uniform(rng) - 1.0;
    let phi = std::f32::consts::TAU * uniform(rng);
    let r = (1.0 - z * z).max(0.0).sqrt();
    Vec3::new(r * phi.cos(), r * phi.sin(), z).normalize()
}

fn incoherent_rays(count: usize) -> Vec<Ray> {
    let mut rng = Pcg64::seed_from_u64(1);
    (0..count)
        .map(|_| {
            let from = 5.0 * unit_vector(&mut rng);
            let target = Vec3::new(uniform(&mut rng), uniform(&mut rng), uniform(&mut rng)) * 2.0 - 1.0;
            Ray::new(from, (target - from).normalize())
        })
        .collect()
}

fn camera_rays(pixels: u32) -> Vec<Ray> {
    let camera = Vec3::new(0.0, 0.0, 4.0);
    (0..pixels * pixels)
        .map(|i| {
            let x = ((i % pixels) as f32 + 0.5) / pixels as f32 * 2.0 - 1.0;
            let y = ((i / pixels) as f32 + 0.5) / pixels as f32 * 2.0 - 1.0;
            Ray::new(camera, Vec3::new(0.4 * x, 0.4 * y, -1.0).normalize())
        })
        .collect()
}

fn intersect_benchmarks(c: &mut Criterion) {
    let (rings, segments, incoherent_count, pixels) =
        if full_size() { (500, 1000, 250_000, 1024) } else { (100, 100, 1_000, 32) };
    let mesh = displaced_sphere(rings, segments);
    let shapes = triangle_shapes(&mesh);
    let triangles = shapes.len();

    let start = Instant::now();
    let geometry = Geometry::build(shapes.clone(), vec![mesh.clone()]);
    let stats = geometry.bvh_stats();
    eprintln!(
        "{triangles} triangles: first build {:.3} s; BVH {} nodes, {} leaves, depth {}; nodes {:.1} MB \
         ({:.1} bytes/triangle), leaf data {:.1} MB, total {:.1} bytes/triangle (shapes and mesh \
         excluded)",
        start.elapsed().as_secs_f64(),
        stats.nodes,
        stats.leaves,
        stats.max_depth,
        stats.bytes as f64 / 1e6,
        stats.bytes_per_primitive(),
        stats.primitive_bytes as f64 / 1e6,
        stats.total_bytes_per_primitive()
    );

    let mut group = c.benchmark_group("build");
    group.sample_size(10);
    group.throughput(Throughput::Elements(triangles as u64));
    group.bench_function(format!("mesh_{triangles}"), |b| {
        b.iter_batched(
            || (shapes.clone(), vec![mesh.clone()]),
            |(shapes, meshes)| Geometry::build(shapes, meshes),
            BatchSize::PerIteration,
        )
    });
    group.finish();

    let ray_sets = [("camera", camera_rays(pixels)), ("incoherent", incoherent_rays(incoherent_count))];
    let mut group = c.benchmark_group(format!("mesh_{triangles}"));
    group.sample_size(10);
    for (name, rays) in &ray_sets {
        let hits = rays.iter().filter(|ray| geometry.intersect(ray, f32::INFINITY).is_some()).count();
        eprintln!("{name} rays: {hits} of {} hit", rays.len());
        group.throughput(Throughput::Elements(rays.len() as u64));
        group.bench_function(format!("{name}/closest"), |b| {
            b.iter(|| {
                rays.iter().filter(|ray| geometry.intersect(black_box(ray), f32::INFINITY).is_some()).count()
            })
        });
        group.bench_function(format!("{name}/occluded"), |b| {
            b.iter(|| rays.iter().filter(|ray| geometry.occluded(black_box(ray), f32::INFINITY)).count())
        });
        // The same rays in packets of 16 consecutive ones.
        let unlimited = [f32::INFINITY; PACKET_RAYS];
        group.bench_function(format!("{name}/closest_packets"), |b| {
            b.iter(|| {
                let mut hits = [None; PACKET_RAYS];
                let mut count = 0;
                for packet in rays.chunks(PACKET_RAYS) {
                    let hits = &mut hits[..packet.len()];
                    geometry.intersect_packet(black_box(packet), &unlimited[..packet.len()], hits);
                    count += hits.iter().flatten().count();
                }
                count
            })
        });
        group.bench_function(format!("{name}/occluded_packets"), |b| {
            b.iter(|| {
                rays.chunks(PACKET_RAYS)
                    .map(|packet| {
                        geometry.occluded_packet(black_box(packet), &unlimited[..packet.len()]).count_ones()
                    })
                    .sum::<u32>()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, intersect_benchmarks);
criterion_main!(benches);

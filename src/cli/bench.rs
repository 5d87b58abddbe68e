//! `prisma bench-rays`: raw ray throughput of prisma's BVH on an OBJ mesh, for a ray set stored
//! in a file, so that another renderer (Mitsuba's Embree, in validation/bench/) can trace exactly
//! the same rays in the same run of the comparison script.
//!
//! Ray file: little-endian f32, six per ray (origin x, y, z, unit direction x, y, z).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{anyhow, Context};
use clap::Args;
use glam::Vec3;
use rayon::prelude::*;

use super::{say, CliError};
use prisma::geometry::{Geometry, Mesh, Ray, Shape, PACKET_RAYS};

/// One way of tracing a chunk of rays, writing each ray's result (its hit distance, or 0 when
/// occluded) into the matching slot.
type Trace<'a> = dyn Fn(&[Ray], &mut [Option<f32>]) + Sync + 'a;

/// Arguments of `prisma bench-rays`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// The mesh (OBJ).
    #[arg(long, value_name = "FILE.obj")]
    obj: PathBuf,
    /// The rays (little-endian f32 × 6 per ray).
    #[arg(long, value_name = "FILE")]
    rays: PathBuf,
    /// Passes over the ray set; the best pass is reported.
    #[arg(long, value_name = "N", default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=100))]
    repeat: u32,
    /// Threads [default: one per core].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
}

/// Runs `prisma bench-rays`: prints one JSON line.
pub fn run(args: &BenchArgs) -> Result<(), CliError> {
    let bytes = std::fs::read(&args.rays)
        .with_context(|| format!("{}: cannot read", args.rays.display()))
        .map_err(CliError::Input)?;
    if bytes.len() % 24 != 0 || bytes.is_empty() {
        return Err(CliError::Input(anyhow!("{}: not a whole number of 24-byte rays", args.rays.display())));
    }
    let floats: Vec<f32> =
        bytes.chunks_exact(4).map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
    let rays: Vec<Ray> = floats
        .chunks_exact(6)
        .map(|r| Ray { origin: Vec3::new(r[0], r[1], r[2]), dir: Vec3::new(r[3], r[4], r[5]).normalize() })
        .collect();

    let start = Instant::now();
    let mesh = Mesh::load_obj(&args.obj).map_err(|e| CliError::Input(e.into()))?;
    let triangles = mesh.triangles.len();
    let shapes = (0..triangles as u32).map(|tri| Shape::Triangle { mesh: 0, tri }).collect();
    let load_seconds = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let geometry = Geometry::build(shapes, vec![mesh]);
    let build_seconds = start.elapsed().as_secs_f64();
    let stats = geometry.bvh_stats();

    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0) as usize)
        .build()
        .map_err(|e| CliError::Failed(e.into()))?;
    // Each pass traces the rays one by one and then in packets of sixteen consecutive rays (as
    // Mitsuba hands them to Embree), for nearest and any hits; the best pass of each is kept.
    let mut best = [f64::INFINITY; 4];
    let mut counts = [0usize; 4];
    let mut t_sums = [0f64; 2];
    // Every pass writes each ray's result (its hit distance, or 0 for an occluded ray) into
    // the same preallocated slots, in parallel over chunks of sixteen rays.
    let mut results = vec![None; rays.len()];
    let mut time = |slot: usize, trace: &Trace| {
        let start = Instant::now();
        pool.install(|| {
            rays.par_chunks(PACKET_RAYS)
                .zip(results.par_chunks_mut(PACKET_RAYS))
                .for_each(|(rays, out)| trace(rays, out))
        });
        best[slot] = best[slot].min(start.elapsed().as_secs_f64());
        counts[slot] = results.iter().flatten().count();
        if slot < 2 {
            t_sums[slot] = results.iter().flatten().map(|&t| f64::from(t)).sum();
        }
    };
    let unlimited = [f32::INFINITY; PACKET_RAYS];
    for _ in 0..args.repeat {
        time(0, &|rays, out| {
            for (ray, out) in rays.iter().zip(out) {
                *out = geometry.intersect(ray, f32::INFINITY).map(|h| h.t);
            }
        });
        time(1, &|rays, out| {
            let mut hits = [None; PACKET_RAYS];
            let hits = &mut hits[..rays.len()];
            geometry.intersect_packet(rays, &unlimited[..rays.len()], hits);
            for (hit, out) in hits.iter().zip(out) {
                *out = hit.map(|h| h.t);
            }
        });
        time(2, &|rays, out| {
            for (ray, out) in rays.iter().zip(out) {
                *out = geometry.occluded(ray, f32::INFINITY).then_some(0.0);
            }
        });
        time(3, &|rays, out| {
            let occluded = geometry.occluded_packet(rays, &unlimited[..rays.len()]);
            for (lane, out) in out.iter_mut().enumerate() {
                *out = (occluded & 1 << lane != 0).then_some(0.0);
            }
        });
    }
    let million = 1e-6 * rays.len() as f64;
    let [single_closest, packet_closest, single_any, packet_any] = best.map(|seconds| million / seconds);
    say!(
        "{{\"renderer\": \"prisma\", \"triangles\": {triangles}, \"rays\": {}, \"threads\": {}, \"load_s\": {load_seconds:.3}, \"build_s\": {build_seconds:.3}, \"bvh_bytes_per_triangle\": {:.1}, \"total_bytes_per_triangle\": {:.1}, \"closest_mrays_s\": {packet_closest:.3}, \"any_mrays_s\": {packet_any:.3}, \"single_closest_mrays_s\": {single_closest:.3}, \"single_any_mrays_s\": {single_any:.3}, \"hits\": {}, \"packet_hits\": {}, \"occluded\": {}, \"packet_occluded\": {}, \"mean_t\": {:.6}, \"packet_mean_t\": {:.6}}}",
        rays.len(),
        pool.current_num_threads(),
        stats.bytes_per_primitive(),
        stats.total_bytes_per_primitive(),
        counts[0],
        counts[1],
        counts[2],
        counts[3],
        t_sums[0] / counts[0].max(1) as f64,
        t_sums[1] / counts[1].max(1) as f64,
    );
    Ok(())
}

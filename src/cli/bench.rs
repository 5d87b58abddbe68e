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
use prisma::geometry::{Geometry, Mesh, Ray, Shape};

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
    let (mut best_closest, mut best_any) = (f64::INFINITY, f64::INFINITY);
    let (mut hits, mut t_sum, mut occluded) = (0usize, 0f64, 0usize);
    for _ in 0..args.repeat {
        let start = Instant::now();
        let results: Vec<Option<f32>> = pool.install(|| {
            rays.par_iter().map(|ray| geometry.intersect(ray, f32::INFINITY).map(|h| h.t)).collect()
        });
        best_closest = best_closest.min(start.elapsed().as_secs_f64());
        hits = results.iter().flatten().count();
        t_sum = results.iter().flatten().map(|&t| f64::from(t)).sum();
        let start = Instant::now();
        occluded =
            pool.install(|| rays.par_iter().filter(|ray| geometry.occluded(ray, f32::INFINITY)).count());
        best_any = best_any.min(start.elapsed().as_secs_f64());
    }
    let million = 1e-6 * rays.len() as f64;
    say!(
        "{{\"renderer\": \"prisma\", \"triangles\": {triangles}, \"rays\": {}, \"threads\": {}, \"load_s\": {load_seconds:.3}, \"build_s\": {build_seconds:.3}, \"bvh_bytes_per_triangle\": {:.1}, \"total_bytes_per_triangle\": {:.1}, \"closest_mrays_s\": {:.3}, \"any_mrays_s\": {:.3}, \"hits\": {hits}, \"occluded\": {occluded}, \"mean_t\": {:.6}}}",
        rays.len(),
        pool.current_num_threads(),
        stats.bytes_per_primitive(),
        stats.total_bytes_per_primitive(),
        million / best_closest,
        million / best_any,
        t_sum / hits.max(1) as f64
    );
    Ok(())
}

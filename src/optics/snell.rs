//! Mirror reflection and Snell refraction of directions.

use glam::Vec3;

/// Mirror reflection of the incoming travel direction `dir` about the unit normal `normal`
/// (either orientation).
#[inline]
pub fn reflect(dir: Vec3, normal: Vec3) -> Vec3 {
    dir - 2.0 * dir.dot(normal) * normal
}

/// Refraction of the unit travel direction `dir` through an interface with unit `normal` (either
/// orientation), where `eta_ratio` = n_incident / n_transmitted. `None` under total internal
/// reflection.
#[inline]
pub fn refract(dir: Vec3, normal: Vec3, eta_ratio: f32) -> Option<Vec3> {
    let _ = (dir, normal, eta_ratio);
    todo!()
}

//! Robust origins for secondary rays (TODO(geometry helper)).

use glam::Vec3;

/// Origin for a ray leaving the surface point `point` (with unit geometric normal `normal`) in
/// direction `dir`: `point` pushed off the surface, to the side `dir` points to, by a distance
/// that scales with the floating-point error of `point`, so that the new ray never re-hits the
/// surface it starts on.
#[inline]
pub fn spawn_origin(point: Vec3, normal: Vec3, dir: Vec3) -> Vec3 {
    let _ = (point, normal, dir);
    todo!()
}

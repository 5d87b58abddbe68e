//! A camera ray's Mueller matrix through the lens at every wavelength lane: `trace::CameraPath`
//! for the transmitted branch (no ghosts, branch probability 1), row by row, operation for
//! operation ([`super::vec3`]): P ← P·Rot·E at each interface from the sensor end, the rotation
//! into each interface's s frame and, at the end, into the scene-side frame.

use glam::DVec3;
use wide::f64x8;

use super::surface::ElementLanes;
use super::vec3::{and_not, lane_set, Mask, V3};
use crate::lens::fresnel_stack::camera_stokes_x;
use crate::lens::trace::MAX_LANES;

/// Below this squared length n × f is taken as zero (`fresnel_stack::PARALLEL_SQUARED`).
const PARALLEL_SQUARED: f64 = 1e-28;

/// The rows of a path's Mueller matrix carried so far at every lane, and the x axis of the
/// frame the light leaves the last interface met in.
pub(super) struct PathLanes {
    /// Row r, column k.
    rows: [[f64x8; 4]; 4],
    /// The rows carried: 4, or 1 (row 0, unpolarised light).
    count: usize,
    previous_x: V3,
}

impl PathLanes {
    /// The path of camera rays leaving the sensor along `dir` (every lane), with the camera's
    /// `up`; `rows` 4 (the whole matrix) or 1 (row 0).
    pub fn start(dir: DVec3, up: DVec3, rows: usize) -> Self {
        Self::with_x(V3::splat(camera_stokes_x(dir, up)), rows)
    }

    /// [`Self::start`] with each lane's own direction `dir`, for the lanes of `live`.
    pub fn start_lanes(dir: V3, up: DVec3, rows: usize, live: Mask) -> Self {
        Self::with_x(camera_stokes_x_lanes(dir, up, live), rows)
    }

    fn with_x(previous_x: V3, rows: usize) -> Self {
        let identity = std::array::from_fn(|row| {
            std::array::from_fn(|col| if row == col { f64x8::ONE } else { f64x8::ZERO })
        });
        Self { rows: identity, count: rows, previous_x }
    }

    /// Adds an interface of unit normal `normal` that the camera rays met along `dir_in` and
    /// left along `dir_out`, transmitting with `element`: `CameraPath::visit`.
    #[inline(always)]
    pub fn visit(&mut self, normal: V3, dir_in: V3, dir_out: V3, element: &ElementLanes) {
        // The light goes the other way.
        let light_in = dir_out.neg();
        let light_out = dir_in.neg();
        // fresnel_stack::s_axis.
        let s = normal.cross(light_in);
        let length_squared = s.dot(s);
        let tilted = length_squared.simd_gt(f64x8::splat(PARALLEL_SQUARED));
        let s = V3::select(tilted, s.scaled(f64x8::ONE / length_squared.sqrt()), self.previous_x);
        let (cos_2, sin_2) = rotation_angle(light_out, s, self.previous_x);
        let ElementLanes { a, b, w_re, w_im } = *element;
        let (minus_sin_2, minus_w_im) = (-sin_2, -w_im);
        // fresnel_stack::rotate_then_element.
        for row in &mut self.rows[..self.count] {
            let [r0, r1, r2, r3] = *row;
            let (q0, q1, q2, q3) = (r0, r1 * cos_2 + r2 * minus_sin_2, r1 * sin_2 + r2 * cos_2, r3);
            *row = [q0 * a + q1 * b, q0 * b + q1 * a, q2 * w_re + q3 * minus_w_im, q2 * w_im + q3 * w_re];
        }
        self.previous_x = s;
    }

    /// The rows after the rotation into the scene-side frame of rays leaving along `exit_dir`
    /// (`CameraPath::finish` without ghosts; `rotate` false: without Fresnel weights, where the
    /// path is the identity), for the lanes of `live`; rows not carried are 0.
    pub fn finish(mut self, exit_dir: V3, up: DVec3, live: Mask, rotate: bool) -> [[[f64; 4]; 4]; MAX_LANES] {
        if rotate {
            let scene_x = camera_stokes_x_lanes(exit_dir, up, live);
            let (cos_2, sin_2) = rotation_angle(exit_dir.neg(), scene_x, self.previous_x);
            let minus_sin_2 = -sin_2;
            // fresnel_stack::rotate_row.
            for row in &mut self.rows[..self.count] {
                let [r0, r1, r2, r3] = *row;
                *row = [r0, r1 * cos_2 + r2 * minus_sin_2, r1 * sin_2 + r2 * cos_2, r3];
            }
        }
        let mut out = [[[0.0; 4]; 4]; MAX_LANES];
        for (r, row) in self.rows[..self.count].iter().enumerate() {
            for (k, entry) in row.iter().enumerate() {
                for (lane, value) in entry.to_array().into_iter().enumerate() {
                    out[lane][r][k] = value;
                }
            }
        }
        out
    }
}

/// `fresnel_stack::camera_stokes_x` per lane: normalize(`dir` × `up`), else (`dir` ∥ `up`, lane
/// by lane with the scalar function) a perpendicular of `dir`, for the lanes of `live`.
#[inline]
fn camera_stokes_x_lanes(dir: V3, up: DVec3, live: Mask) -> V3 {
    let x = dir.cross(V3::splat(up));
    let length_squared = x.dot(x);
    let scene_x = x.divided(length_squared.sqrt());
    let parallel = and_not(live, length_squared.simd_gt(f64x8::splat(PARALLEL_SQUARED)));
    if !parallel.any() {
        return scene_x;
    }
    let mut lanes = scene_x.lanes();
    for (lane, dir) in dir.lanes().iter().enumerate() {
        if lane_set(parallel, lane) {
            lanes[lane] = camera_stokes_x(*dir, up);
        }
    }
    V3::from_lanes(&lanes)
}

/// `fresnel_stack::rotation_angle`: cos 2θ and sin 2θ of the Stokes rotation from x axis
/// `from` to `to` for light along `forward` (1 and 0 where it is the identity).
#[inline(always)]
fn rotation_angle(forward: V3, from: V3, to: V3) -> (f64x8, f64x8) {
    let cos_theta = from.dot(to);
    let sin_theta = forward.dot(from.cross(to));
    let norm = cos_theta * cos_theta + sin_theta * sin_theta;
    let degenerate = norm.simd_le(f64x8::ZERO);
    let inverse = f64x8::ONE / norm;
    let cos_2 = (cos_theta * cos_theta - sin_theta * sin_theta) * inverse;
    let sin_2 = f64x8::splat(2.0) * sin_theta * cos_theta * inverse;
    (degenerate.select(f64x8::ONE, cos_2), degenerate.select(f64x8::ZERO, sin_2))
}

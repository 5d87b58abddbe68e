//! One lens surface at every wavelength lane: the media's indices, where the lanes' rays meet
//! the surface and its normal there, and the Mueller element of the transmitted beam, each the
//! scalar code's arithmetic operation for operation ([`super::vec3`]): the indices are
//! [`crate::optics::dispersion::DispersionFormula::n_at_nm`], the hit
//! [`crate::lens::surface_geometry::intersect`] of a sphere, plane or conic, the element
//! [`crate::lens::fresnel_stack::interface_fresnel`]'s real path through
//! `DiagonalElement::transmission`. What the vector code does not take (an even asphere's
//! Newton iteration, a coated surface's stack, a power-series glass) is computed lane by lane
//! with the scalar functions themselves.

use glam::DVec3;
use wide::f64x8;

use super::vec3::{and_not, lane_set, Mask, V3};
use crate::lens::fresnel_stack::{coated_interface_fresnel, DiagonalElement};
use crate::lens::surface_geometry::intersect;
use crate::lens::trace::{MAX_LANES, T_MIN_MM};
use crate::lens::{Coating, Medium, Surface};
use crate::optics::dispersion::DispersionFormula;

/// The refractive index of `medium` at every lane's wavelength `lambda_nm` (nm; the same
/// numbers as an array in `lambdas_nm`): [`Medium::n_at_nm`] per lane, to the bit.
pub(super) fn index_lanes(medium: &Medium, lambda_nm: f64x8, lambdas_nm: &[f64; MAX_LANES]) -> f64x8 {
    let formula = match medium {
        Medium::Air => return f64x8::ONE,
        Medium::Glass { formula, .. } => formula,
    };
    let lambda_um = lambda_nm * f64x8::splat(1e-3);
    let lambda_um2 = lambda_um * lambda_um;
    match formula {
        DispersionFormula::Sellmeier { b, c_um2 } => {
            // `Iterator::sum` of f64 folds from −0.0.
            let mut sum = f64x8::splat(-0.0);
            for (b_i, c_i) in b.iter().zip(c_um2) {
                sum += f64x8::splat(*b_i) * lambda_um2 / (lambda_um2 - f64x8::splat(*c_i));
            }
            (f64x8::ONE + sum).sqrt()
        }
        DispersionFormula::Cauchy { a, b_um2, c_um4 } => {
            f64x8::splat(*a)
                + f64x8::splat(*b_um2) / lambda_um2
                + f64x8::splat(*c_um4) / (lambda_um2 * lambda_um2)
        }
        DispersionFormula::PowerSeries { .. } => f64x8::from(lambdas_nm.map(|l| formula.n_at_nm(l))),
    }
}

/// Where the lanes' rays meet a surface: the point (mm, lens coordinates), the unit normal
/// toward +z, and the lanes that meet it (on its vertex patch, with a finite normal).
pub(super) struct HitLanes {
    pub point: V3,
    pub normal: V3,
    pub hit: Mask,
}

/// The lanes' rays `origin + t·dir` (unit `dir`) meeting `surface`, whose vertex is at z =
/// `vertex_z_mm`: [`intersect`] with `T_MIN_MM` per lane, for the lanes of `live` (the others'
/// numbers are meaningless).
#[inline(always)]
pub(super) fn hit_lanes(surface: &Surface, vertex_z_mm: f64, origin: V3, dir: V3, live: Mask) -> HitLanes {
    if !surface.aspheric_mm.is_empty() {
        return hit_lanes_scalar(surface, vertex_z_mm, origin, dir, live);
    }
    let splat = f64x8::splat;
    let (zero, one) = (f64x8::ZERO, f64x8::ONE);
    let c = surface.curvature_per_mm();
    let k1 = 1.0 + surface.conic;
    let (vc, vk1, t_min) = (splat(c), splat(k1), splat(T_MIN_MM));
    // local = origin − (0, 0, vertex_z), as DVec3's subtraction.
    let local = V3 { x: origin.x - zero, y: origin.y - zero, z: origin.z - splat(vertex_z_mm) };
    // surface_geometry::intersect_conic.
    let a = vc * (dir.x * dir.x + dir.y * dir.y + vk1 * dir.z * dir.z);
    let b = dir.z - vc * (local.x * dir.x + local.y * dir.y + vk1 * local.z * dir.z);
    let cc = vc * (local.x * local.x + local.y * local.y + vk1 * local.z * local.z) - splat(2.0) * local.z;
    let discriminant = b * b - a * cc;
    let negative = discriminant.simd_lt(zero);
    let root = discriminant.sqrt();
    let q = b + b.simd_lt(zero).select(-root, root);
    let nan = splat(f64::NAN);
    let near = q.simd_ne(zero).select(cc / q, nan);
    let far = a.simd_ne(zero).select(q / a, nan);
    let c_k1 = vc * vk1;
    let on_patch =
        |t: f64x8| t.is_finite() & t.simd_gt(t_min) & (one - c_k1 * (local.z + t * dir.z)).simd_gt(zero);
    let (near_ok, far_ok) = (on_patch(near), on_patch(far));
    // The smaller of the roots on the patch (the first of equals, as `min_by`).
    let both = near_ok & far_ok;
    let t = both.select(far.simd_lt(near).select(far, near), near_ok.select(near, far));
    let mut hit = and_not(near_ok | far_ok, negative);
    // surface_geometry::normal_local of a sphere or plane, else of a conic.
    let point_local = V3 { x: local.x + t * dir.x, y: local.y + t * dir.y, z: local.z + t * dir.z };
    let minus_c = -vc;
    let normal = if surface.conic == 0.0 || c == 0.0 {
        V3 { x: minus_c * point_local.x, y: minus_c * point_local.y, z: one - vc * point_local.z }
    } else {
        let gradient =
            V3 { x: minus_c * point_local.x, y: minus_c * point_local.y, z: one - c_k1 * point_local.z };
        gradient.normalize()
    };
    hit &= normal.is_finite();
    let point =
        V3 { x: point_local.x + zero, y: point_local.y + zero, z: point_local.z + splat(vertex_z_mm) };
    HitLanes { point, normal, hit: hit & live }
}

/// [`hit_lanes`] lane by lane with [`intersect`] (an even asphere's Newton iteration).
#[inline(never)]
fn hit_lanes_scalar(surface: &Surface, vertex_z_mm: f64, origin: V3, dir: V3, live: Mask) -> HitLanes {
    let (origins, dirs) = (origin.lanes(), dir.lanes());
    let mut points = [DVec3::ZERO; MAX_LANES];
    let mut normals = [DVec3::Z; MAX_LANES];
    let mut hit = [0.0; MAX_LANES];
    for lane in 0..MAX_LANES {
        if !lane_set(live, lane) {
            continue;
        }
        if let Some(found) = intersect(surface, vertex_z_mm, origins[lane], dirs[lane], T_MIN_MM) {
            points[lane] = found.point;
            normals[lane] = found.normal;
            hit[lane] = 1.0;
        }
    }
    HitLanes {
        point: V3::from_lanes(&points),
        normal: V3::from_lanes(&normals),
        hit: f64x8::from(hit).simd_eq(f64x8::ONE),
    }
}

/// The lanes' rays refracted by a surface: where they meet it, its normal there (toward +z), the
/// unsigned cosine of incidence, the refracted direction, and the lanes still live.
pub(super) struct Crossing {
    pub point: V3,
    pub normal: V3,
    pub cos_i: f64x8,
    pub dir_out: V3,
    pub live: Mask,
}

/// The lanes of `live` with rays `origin + t·dir` (unit `dir`) meeting `surface` (vertex at z =
/// `vertex_z_mm`) and refracted into it with `eta` = n_incident / n_transmitted: the hit
/// ([`hit_lanes`]), the clear aperture (`surface_geometry::within_aperture`, its slack
/// included), the normal facing the ray and Snell's law (`trace::refract`), total internal
/// reflection blocking, as `trace::LensTracer::meet` and `reverse::LensTracer::step_back` do
/// them.
#[inline(always)]
pub(super) fn cross_lanes(
    surface: &Surface,
    vertex_z_mm: f64,
    origin: V3,
    dir: V3,
    eta: f64x8,
    live: Mask,
) -> Crossing {
    let one = f64x8::ONE;
    let hit = hit_lanes(surface, vertex_z_mm, origin, dir, live);
    let semi_squared = surface.semi_diameter_mm * surface.semi_diameter_mm;
    let rim = f64x8::splat(semi_squared * (1.0 + 1e-12));
    let mut live = hit.hit & (hit.point.x * hit.point.x + hit.point.y * hit.point.y).simd_le(rim);
    let normal = hit.normal;
    let cos_signed = normal.dot(dir);
    let facing = V3::select(cos_signed.simd_lt(f64x8::ZERO), normal, normal.neg());
    // |cos|.min(1).
    let cos_abs = cos_signed.abs();
    let cos_i = cos_abs.simd_gt(one).select(one, cos_abs);
    let cos_t_sqr = one - eta * eta * (one - cos_i * cos_i);
    live = and_not(live, cos_t_sqr.simd_lt(f64x8::ZERO));
    let along_normal = eta * cos_i - cos_t_sqr.sqrt();
    let dir_out = dir.scaled(eta).plus(facing.scaled(along_normal)).normalize();
    Crossing { point: hit.point, normal, cos_i, dir_out, live }
}

/// The Mueller element of the transmitted beam, [[a, b, 0, 0], [b, a, 0, 0], [0, 0, w_re,
/// w_im], [0, 0, −w_im, w_re]] per lane (`DiagonalElement`'s numbers).
#[derive(Clone, Copy)]
pub(super) struct ElementLanes {
    pub a: f64x8,
    pub b: f64x8,
    pub w_re: f64x8,
    pub w_im: f64x8,
}

/// The transmitted beam's element at every lane for incidence at the unsigned cosine `cos_i`
/// from index `n_in` to `n_other`: `DiagonalElement::transmission(&interface_fresnel(..))` to
/// the bit for a bare surface (its real path; the identity where the indices match or a
/// denominator vanishes, 0 under total internal reflection, as the complex path gives them);
/// for a coated one, [`coated_interface_fresnel`] lane by lane (toward the object, as the camera
/// ray crosses it), for the lanes of `live`.
#[inline(always)]
pub(super) fn transmission_lanes(
    surface: &Surface,
    cos_i: f64x8,
    n_in: f64x8,
    n_other: f64x8,
    lambdas_nm: &[f64; MAX_LANES],
    live: Mask,
) -> ElementLanes {
    if let Some(coating) = &surface.coating {
        return coated_transmission_lanes(coating, cos_i, n_in, n_other, lambdas_nm, live);
    }
    let splat = f64x8::splat;
    let (zero, one) = (f64x8::ZERO, f64x8::ONE);
    // fresnel_stack::interface_fresnel (cos_i is already in [0, 1]).
    let eta_it = n_other / n_in;
    let sin_t_sqr = (one - cos_i * cos_i) / (eta_it * eta_it);
    let cos_t_sqr = one - sin_t_sqr;
    let total_internal_reflection = cos_t_sqr.simd_lt(zero);
    let matched = n_in.simd_eq(n_other);
    // real_interface_fresnel.
    let cos_t = cos_t_sqr.sqrt();
    let denominator_s = cos_i + eta_it * cos_t;
    let denominator_p = eta_it * cos_i + cos_t;
    let vanishing = denominator_s.simd_eq(zero) | denominator_p.simd_eq(zero);
    let (inverse_s, inverse_p) = (one / denominator_s, one / denominator_p);
    let two_cos_i = splat(2.0) * cos_i;
    let t_s = two_cos_i * inverse_s;
    let t_p = two_cos_i * inverse_p;
    let flux = splat(4.0) * cos_i * eta_it * cos_t;
    let transmittance_s = flux * inverse_s * inverse_s;
    // DiagonalElement::transmission and of_jones, with the Complex64 arithmetic of real
    // amplitudes written out: |t|² = t·t + 0·0, t_s·conj(t_p) = (t_s·t_p − 0·(−0), t_s·(−0) + 0·t_p).
    let t_s_sqr = t_s * t_s + zero * zero;
    let flux_factor = t_s_sqr.simd_gt(zero).select(transmittance_s / t_s_sqr, zero);
    let power_x = t_s_sqr * flux_factor;
    let power_y = (t_p * t_p + zero * zero) * flux_factor;
    let minus_zero = splat(-0.0);
    let w_re = (t_s * t_p - zero * minus_zero) * flux_factor;
    let w_im = (t_s * minus_zero + zero * t_p) * flux_factor;
    let half = splat(0.5);
    let real = ElementLanes { a: half * (power_x + power_y), b: half * (power_x - power_y), w_re, w_im };
    // The complex path's cases: total internal reflection (0; never with matched indices),
    // else no interface (the identity) where the indices match or a denominator vanishes.
    let identity = matched | vanishing;
    let pick = |of_real: f64x8, of_identity: f64x8| {
        total_internal_reflection.select(zero, identity.select(of_identity, of_real))
    };
    ElementLanes {
        a: pick(real.a, one),
        b: pick(real.b, zero),
        w_re: pick(real.w_re, one),
        w_im: pick(real.w_im, zero),
    }
}

/// [`transmission_lanes`] of a coated surface, lane by lane with [`coated_interface_fresnel`].
#[inline(never)]
fn coated_transmission_lanes(
    coating: &Coating,
    cos_i: f64x8,
    n_in: f64x8,
    n_other: f64x8,
    lambdas_nm: &[f64; MAX_LANES],
    live: Mask,
) -> ElementLanes {
    let (cos_i, n_in, n_other) = (cos_i.to_array(), n_in.to_array(), n_other.to_array());
    let mut parts = [[0.0; MAX_LANES]; 4];
    for lane in 0..MAX_LANES {
        if !lane_set(live, lane) {
            continue;
        }
        let fresnel = coated_interface_fresnel(
            cos_i[lane],
            n_in[lane],
            n_other[lane],
            coating,
            false,
            lambdas_nm[lane],
        );
        let element = DiagonalElement::transmission(&fresnel);
        for (part, value) in parts.iter_mut().zip([element.a, element.b, element.w_re, element.w_im]) {
            part[lane] = value;
        }
    }
    let [a, b, w_re, w_im] = parts.map(f64x8::from);
    ElementLanes { a, b, w_re, w_im }
}

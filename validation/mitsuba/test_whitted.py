#!/usr/bin/env python3
"""Checks of the Whitted integrator (whitted.py) against answers computed without it.

1. A Lambertian plane (albedo ρ) under a point light of intensity I: L = I·ρ/π·cos θ/d² at every
   point of the plane, with a glass sphere's shadow black (glass blocks shadow rays) and pixels
   that miss the plane showing the background, which does not light the plane.
2. The same plane under a square area light of radiance L_e: L = ρ/π·∫ L_e cos θ cos θ'/r² dA,
   the integral computed here by a 100×100 midpoint rule.
3. Depth: a mirror seen by the camera shows R·L_background with max_depth = 1 and black with
   max_depth = 0 (prisma counts specular bounces).
4. The spectral variant: the plane of check 1 in XYZ, Y = I·ρ/π·cos θ/d² for a constant
   spectrum of value 1 (Y of an equal-energy spectrum of 1 is 1).
5. Polarised (llvm_ad_mono_polarized, inside Mitsuba's `stokes`): the plane of check 1 seen
   directly is unpolarised (S1 = S2 = S3 = 0 exactly: the diffuse BSDF depolarises) with S0 as
   in check 1.
6. Polarised: a Lambertian ceiling lit by a point light, seen in a glass floor (n = 1.5) by a
   camera looking at Brewster's angle. Per ray, S0 = ½(Rs + Rp)·L, and (S1, S2) =
   ½(Rs − Rp)·L·(cos 2ψ, sin 2ψ), L the Lambertian radiance of the ceiling point the reflected ray
   meets and ψ the angle of the s direction (normal × d) in the Stokes frame of `stokes`
   (x = d × camera up, y = (−d) × x); S3 = 0. The plane of incidence turns across the image, so
   this checks the Mueller product and every frame rotation, on the direct-light path.

The expected radiance of a pixel is the mean of the analytic radiance over 16×16 points of the
pixel, found on the plane through Mitsuba's camera rays (the camera is not under test). Mono
renders have no wavelength noise, so a point light gives the pixel mean to within the noise of
pixel jittering only.

Run: validation/.venv/bin/python validation/mitsuba/test_whitted.py   (exit code 0 when all pass)
"""

import importlib
import pathlib
import sys

import drjit as dr
import mitsuba as mi
import numpy as np

WIDTH, HEIGHT = 48, 32
SPP = 4096
PASSES = 64
SUBPIXELS = 16

ALBEDO = 0.6
INTENSITY = 5.0
POINT_LIGHT = np.array([0.7, 2.0, -0.4])
BACKGROUND = 0.25
SPHERE_CENTER = np.array([0.4, 1.0, -0.2])
SPHERE_RADIUS = 0.3
AREA_RADIANCE = 3.0
AREA_CENTER = np.array([-0.5, 1.5, 0.5])
AREA_HALF = 0.4
MIRROR_REFLECTANCE = 0.8


def camera():
    return {
        "type": "perspective", "fov_axis": "y", "fov": 70.0,
        "to_world": mi.ScalarTransform4f().look_at(origin=[0.0, 3.0, -2.0], target=[0.0, 0.0, 0.0],
                                                    up=[0.0, 1.0, 0.0]),
        "film": {"type": "hdrfilm", "width": WIDTH, "height": HEIGHT, "rfilter": {"type": "box"},
                 "pixel_format": "luminance" if mi.is_monochromatic else "xyz",
                 "component_format": "float32"},
        "sampler": {"type": "independent", "sample_count": SPP},
    }


def stokes_render(scene_dict, sensor, max_depth=4):
    """(S image (H, W, 4), its per-pixel standard error, the scene) from whitted in `stokes`."""
    scene = mi.load_dict(dict(scene_dict, type="scene", sensor=sensor,
                              integrator={"type": "stokes", "integrator": {"type": "whitted", "max_depth": max_depth}}))
    passes = []
    for k in range(PASSES):
        image = np.array(mi.render(scene, spp=SPP // PASSES, seed=100 + k), dtype=np.float64)
        bitmap = scene.sensors()[0].film().bitmap()
        names = [bitmap.struct_()[i].name for i in range(image.shape[-1])]
        passes.append(np.stack([image[..., names.index(f"S{i}.R")] for i in range(4)], axis=-1))
    passes = np.stack(passes)
    return passes.mean(axis=0), passes.std(axis=0, ddof=1) / np.sqrt(PASSES), scene


def sub_rays(scene, subpixels):
    """Origins and directions (H, W, S, 3) of subpixels² rays per pixel, and the camera's up."""
    sensor = scene.sensors()[0]
    s = (np.arange(subpixels) + 0.5) / subpixels
    py, px, sy, sx = np.meshgrid(np.arange(HEIGHT), np.arange(WIDTH), s, s, indexing="ij")
    u = ((px + sx) / WIDTH).ravel()
    v = ((py + sy) / HEIGHT).ravel()
    rays, _ = sensor.sample_ray(0.0, 0.5, mi.Point2f(u, v), mi.Point2f(0.5, 0.5))
    shape = (HEIGHT, WIDTH, subpixels * subpixels, 3)
    m = np.array(sensor.world_transform().matrix, dtype=np.float64).reshape(4, 4, -1)[..., 0]
    return np.array(rays.o).T.reshape(shape), np.array(rays.d).T.reshape(shape), m[:3, 1] / np.linalg.norm(m[:3, 1])


def fresnel_rs_rp(cos_i, n):
    """Rs, Rp of a dielectric of index n seen from outside (numpy, float64)."""
    cos_t = np.sqrt(1.0 - (1.0 - cos_i**2) / n**2)
    rs = ((cos_i - n * cos_t) / (cos_i + n * cos_t)) ** 2
    rp = ((n * cos_i - cos_t) / (n * cos_i + cos_t)) ** 2
    return rs, rp


def plane(half_size=3.0):
    """The plane y = 0, normal +y, a square of side 2·half_size."""
    return {"type": "rectangle",
            "to_world": mi.ScalarTransform4f().rotate([1, 0, 0], -90).scale([half_size, half_size, 1]),
            "bsdf": {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": {"type": "uniform", "value": ALBEDO}}}}


def render(scene_dict, max_depth=4):
    """(Y image, its per-pixel standard error from PASSES independent passes, the scene)."""
    scene_dict = dict(scene_dict, type="scene", sensor=camera(),
                      integrator={"type": "whitted", "max_depth": max_depth})
    scene = mi.load_dict(scene_dict)
    passes = np.stack([np.array(mi.render(scene, spp=SPP // PASSES, seed=100 + k), dtype=np.float64)
                       for k in range(PASSES)])
    # Y is the only channel in mono and the second of XYZ.
    passes = passes[..., 0] if passes.shape[-1] == 1 else passes[..., 1]
    return passes.mean(axis=0), passes.std(axis=0, ddof=1) / np.sqrt(PASSES), scene


def plane_points(scene, subpixels=SUBPIXELS):
    """Points of y = 0 seen through subpixels² positions of every pixel: array (H, W, S, 3), NaN
    where the ray misses the plane's square or goes upward."""
    sensor = scene.sensors()[0]
    s = (np.arange(subpixels) + 0.5) / subpixels
    py, px, sy, sx = np.meshgrid(np.arange(HEIGHT), np.arange(WIDTH), s, s, indexing="ij")
    u = ((px + sx) / WIDTH).ravel()
    v = ((py + sy) / HEIGHT).ravel()
    rays, _ = sensor.sample_ray(0.0, 0.5, mi.Point2f(u, v), mi.Point2f(0.5, 0.5))
    o = np.array(rays.o).T
    d = np.array(rays.d).T
    t = -o[:, 1] / d[:, 1]
    p = o + t[:, None] * d
    miss = (t <= 0) | (np.abs(p[:, 0]) > 3.0) | (np.abs(p[:, 2]) > 3.0)
    p[miss] = np.nan
    return p.reshape(HEIGHT, WIDTH, subpixels * subpixels, 3)


def shadowed_by_sphere(points, light):
    """True where the segment from a point to the light crosses the sphere."""
    to_light = light - points
    dist = np.linalg.norm(to_light, axis=-1, keepdims=True)
    d = to_light / dist
    oc = points - SPHERE_CENTER
    b = np.sum(oc * d, axis=-1)
    c = np.sum(oc * oc, axis=-1) - SPHERE_RADIUS**2
    disc = b * b - c
    t = -b - np.sqrt(np.maximum(disc, 0.0))
    return (disc > 0) & (t > 0) & (t < dist[..., 0])


def point_light_expected(points, sphere=True):
    to_light = POINT_LIGHT - points
    d2 = np.sum(to_light**2, axis=-1)
    cos_theta = to_light[..., 1] / np.sqrt(d2)
    radiance = INTENSITY * ALBEDO / np.pi * cos_theta / d2
    if not sphere:
        return radiance
    return np.where(shadowed_by_sphere(points, POINT_LIGHT), 0.0, radiance)


def area_light_expected(points):
    """ρ/π·∫ L_e cos θ cos θ'/r² dA over the square light (normal -y) by a midpoint rule."""
    n = 100
    g = (np.arange(n) + 0.5) / n * 2 * AREA_HALF - AREA_HALF
    gx, gz = np.meshgrid(g, g, indexing="ij")
    light_points = np.stack([AREA_CENTER[0] + gx.ravel(), np.full(n * n, AREA_CENTER[1]),
                             AREA_CENTER[2] + gz.ravel()], axis=-1)
    da = (2 * AREA_HALF / n) ** 2
    flat = points.reshape(-1, 3)
    out = np.full(flat.shape[0], np.nan)
    ok = ~np.isnan(flat[:, 0])
    for i in np.flatnonzero(ok):
        r = light_points - flat[i]
        r2 = np.sum(r * r, axis=-1)
        cos_both = (r[:, 1] / np.sqrt(r2)) ** 2  # cos θ at the plane = cos θ' at the light (parallel)
        out[i] = AREA_RADIANCE * ALBEDO / np.pi * np.sum(cos_both / r2) * da
    return out.reshape(points.shape[:-1])


def pixel_mean(per_point):
    """Mean over the pixel's sub-points; NaN when some miss (mixed pixels are not compared)."""
    return per_point.mean(axis=-1)


def report(name, rendered, stderr, expected, rel_tol):
    # Only pixels whose neighbours are all comparable: an edge (of the plane, a shadow, an
    # occluder) can cross the border strip of a pixel that the 16×16 sub-points do not reach.
    mask = ~np.isnan(expected)
    mask[1:, :] &= mask[:-1, :].copy()
    mask[:-1, :] &= ~np.isnan(expected[1:, :])
    mask[:, 1:] &= ~np.isnan(expected[:, :-1])
    mask[:, :-1] &= ~np.isnan(expected[:, 1:])
    lit = mask & (expected > 0)
    # Allowed: 5 standard errors of the render plus rel_tol of the value (quadrature, float32).
    error = np.abs(rendered[lit] - expected[lit])
    z = error / np.maximum(stderr[lit], 1e-30)
    ok = bool(np.all(error <= 5.0 * stderr[lit] + rel_tol * expected[lit]))
    within = np.mean(z <= 3.0)
    print(f"{'PASS' if ok else 'FAIL'} {name}: {lit.sum()} lit pixels, max |rel diff| "
          f"{(error / expected[lit]).max():.2e}, {100 * within:.1f}% within 3σ, "
          f"mean rendered/expected {rendered[lit].sum() / expected[lit].sum():.5f}")
    return ok


def main():
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
    results = []

    mi.set_variant("llvm_ad_mono")
    import whitted  # noqa: F401  registers "whitted" for this variant

    # 1. Point light, glass sphere shadow, background not a light.
    glass = {"type": "sphere", "center": SPHERE_CENTER.tolist(), "radius": SPHERE_RADIUS,
             "bsdf": {"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0}}
    scene_dict = {"plane": plane(), "glass": glass,
                  "light": {"type": "point", "position": POINT_LIGHT.tolist(),
                            "intensity": {"type": "uniform", "value": INTENSITY}},
                  "background": {"type": "constant", "radiance": {"type": "uniform", "value": BACKGROUND}}}
    rendered, stderr, scene = render(scene_dict)
    points = plane_points(scene)
    per_point = point_light_expected(points)
    expected = pixel_mean(per_point)
    # The sphere hides parts of the plane from the camera: compare only pixels whose rays miss it,
    # and leave out the penumbra pixels, part shadowed and part lit (a binary noisy estimate).
    sensor_rays_hit_sphere = shadowed_by_sphere(points, np.array([0.0, 3.0, -2.0])).any(axis=-1)
    penumbra = np.any(per_point == 0.0, axis=-1) & np.any(per_point > 0.0, axis=-1)
    expected[sensor_rays_hit_sphere | penumbra] = np.nan
    results.append(report("point light on a Lambertian plane (I·ρ/π·cos θ/d²)", rendered, stderr, expected, 1e-4))
    umbra = ~np.isnan(expected) & np.all(per_point == 0.0, axis=-1)
    umbra_ok = umbra.sum() > 0 and np.all(rendered[umbra] == 0.0)
    print(f"{'PASS' if umbra_ok else 'FAIL'} glass sphere shadow is black: {umbra.sum()} pixels, "
          f"max {rendered[umbra].max() if umbra.any() else float('nan'):.3g}")
    results.append(umbra_ok)
    missed = np.all(np.isnan(points[..., 0]), axis=-1) & ~sensor_rays_hit_sphere
    bg_ok = missed.sum() > 0 and np.allclose(rendered[missed], BACKGROUND, rtol=1e-3)
    print(f"{'PASS' if bg_ok else 'FAIL'} escaping rays see the background: {missed.sum()} pixels, "
          f"mean {rendered[missed].mean() if missed.any() else float('nan'):.5f} (expected {BACKGROUND})")
    results.append(bg_ok)

    # 2. Square area light facing down (rectangle emits toward local +z, here rotated to -y).
    area = {"type": "rectangle",
            "to_world": mi.ScalarTransform4f().translate(AREA_CENTER.tolist()).rotate([1, 0, 0], 90)
            .scale([AREA_HALF, AREA_HALF, 1]),
            "bsdf": {"type": "diffuse", "reflectance": {"type": "uniform", "value": 0.0}},
            "emitter": {"type": "area", "radiance": {"type": "uniform", "value": AREA_RADIANCE}}}
    rendered, stderr, scene = render({"plane": plane(), "area": area})
    points = plane_points(scene, subpixels=8)  # the quadrature is costly; the answer is smooth
    expected = pixel_mean(area_light_expected(points))
    # Leave out the pixels where the light hides part of the plane from the camera.
    eye = np.array([0.0, 3.0, -2.0])
    t = (AREA_CENTER[1] - eye[1]) / (points[..., 1] - eye[1])
    crossing = eye + t[..., None] * (points - eye)
    hidden = (np.abs(crossing[..., 0] - AREA_CENTER[0]) <= AREA_HALF) & \
             (np.abs(crossing[..., 2] - AREA_CENTER[2]) <= AREA_HALF)
    expected[hidden.any(axis=-1)] = np.nan
    results.append(report("square area light on a Lambertian plane (quadrature)", rendered, stderr, expected, 1e-4))

    # 3. Depth semantics: a mirror reflecting the background.
    mirror = {"type": "rectangle",
              "to_world": mi.ScalarTransform4f().rotate([1, 0, 0], -90).scale([3.0, 3.0, 1]),
              "bsdf": {"type": "conductor", "material": "none",
                       "specular_reflectance": {"type": "uniform", "value": MIRROR_REFLECTANCE}}}
    bg = {"type": "constant", "radiance": {"type": "uniform", "value": BACKGROUND}}
    for depth, value in [(0, 0.0), (1, MIRROR_REFLECTANCE * BACKGROUND)]:
        rendered, stderr, scene = render({"mirror": mirror, "background": bg}, max_depth=depth)
        on_mirror = ~np.all(np.isnan(plane_points(scene)[..., 0]), axis=-1)
        inner = on_mirror & ~np.isnan(plane_points(scene)[..., 0]).any(axis=-1)
        ok = np.allclose(rendered[inner], value, atol=1e-6)
        print(f"{'PASS' if ok else 'FAIL'} mirror with max_depth = {depth} shows {value:.3f}: "
              f"mean {rendered[inner].mean():.6f} over {inner.sum()} pixels")
        results.append(ok)

    # 4. Spectral variant, XYZ film.
    mi.set_variant("llvm_ad_spectral")
    importlib.reload(whitted)  # define and register the integrator for this variant too
    flat = lambda v: {"type": "regular", "wavelength_min": 360, "wavelength_max": 830,  # noqa: E731
                      "values": ",".join([repr(float(v))] * 471)}
    scene_dict = {"plane": plane(),
                  "light": {"type": "point", "position": POINT_LIGHT.tolist(), "intensity": flat(INTENSITY)}}
    scene_dict["plane"]["bsdf"]["bsdf"]["reflectance"] = flat(ALBEDO)
    rendered, stderr, scene = render(scene_dict)
    expected = pixel_mean(point_light_expected(plane_points(scene), sphere=False))
    results.append(report("spectral: Y of the same plane (equal-energy spectra)", rendered, stderr, expected, 1e-4))

    # 5. Polarised: a diffuse plane seen directly is unpolarised.
    mi.set_variant("llvm_ad_mono_polarized")
    importlib.reload(whitted)
    scene_dict = {"plane": plane(),
                  "light": {"type": "point", "position": POINT_LIGHT.tolist(),
                            "intensity": {"type": "uniform", "value": INTENSITY}}}
    S, S_err, scene = stokes_render(scene_dict, camera())
    expected = pixel_mean(point_light_expected(plane_points(scene), sphere=False))
    results.append(report("polarised: S0 of the plane of check 1", S[..., 0], S_err[..., 0], expected, 1e-4))
    ok = bool(np.all(S[..., 1:] == 0.0))
    print(f"{'PASS' if ok else 'FAIL'} polarised: the diffuse plane is unpolarised, max |S1,S2,S3| = "
          f"{np.abs(S[..., 1:]).max():.1e}")
    results.append(ok)

    # 6. Polarised: a lit Lambertian ceiling (y = 2) seen in a glass floor (y = 0) at Brewster.
    n_glass = 1.5
    theta_b = np.arctan(n_glass)
    eye = np.array([0.0, 1.0, -1.0 / np.cos(theta_b) * np.sin(theta_b)])
    lamp = np.array([0.3, 1.5, 2.5])
    sensor = dict(camera(), to_world=mi.ScalarTransform4f().look_at(origin=eye.tolist(), target=[0.0, 0.0, 0.0],
                                                                    up=[0.0, 1.0, 0.0]))
    sensor["fov"] = 40.0
    glass_floor = {"type": "rectangle",
                   "to_world": mi.ScalarTransform4f().rotate([1, 0, 0], -90).scale([40.0, 40.0, 1]),
                   "bsdf": {"type": "dielectric", "int_ior": n_glass, "ext_ior": 1.0}}
    ceiling = {"type": "rectangle",
               "to_world": mi.ScalarTransform4f().translate([0, 2.0, 0]).rotate([1, 0, 0], 90).scale([40.0, 40.0, 1]),
               "bsdf": {"type": "twosided", "bsdf": {"type": "diffuse", "reflectance": {"type": "uniform", "value": ALBEDO}}}}
    scene_dict = {"floor": glass_floor, "ceiling": ceiling,
                  "light": {"type": "point", "position": lamp.tolist(),
                            "intensity": {"type": "uniform", "value": INTENSITY}}}
    S, S_err, scene = stokes_render(scene_dict, sensor)
    o, d, up = sub_rays(scene, 8)
    t = -o[..., 1] / d[..., 1]
    cos_i = -d[..., 1]
    rs, rp = fresnel_rs_rp(cos_i, n_glass)
    r = d * np.array([1.0, -1.0, 1.0])
    hit = o + t[..., None] * d
    q = hit + ((2.0 - hit[..., 1]) / r[..., 1])[..., None] * r
    to_lamp = lamp - q
    dist2 = np.sum(to_lamp**2, axis=-1)
    radiance = INTENSITY * ALBEDO / np.pi * (-to_lamp[..., 1] / np.sqrt(dist2)) / dist2
    x = np.cross(d, up)
    x /= np.linalg.norm(x, axis=-1, keepdims=True)
    y = np.cross(-d, x)
    s_dir = np.cross(d, [0.0, 1.0, 0.0])
    psi = np.arctan2(np.sum(s_dir * y, -1), np.sum(s_dir * x, -1))
    expected = np.stack([0.5 * (rs + rp) * radiance, 0.5 * (rs - rp) * radiance * np.cos(2 * psi),
                         0.5 * (rs - rp) * radiance * np.sin(2 * psi), 0.0 * radiance], axis=-1).mean(axis=2)
    for i in range(3):
        error = np.abs(S[..., i] - expected[..., i])
        ok = bool(np.all(error <= 5.0 * S_err[..., i] + 1e-4 * expected[..., 0]))
        print(f"{'PASS' if ok else 'FAIL'} polarised: S{i} of a lit ceiling seen in glass at Brewster's angle: "
              f"{error.size} pixels, max |diff|/S0 {(error / expected[..., 0]).max():.2e}, "
              f"{100 * np.mean(error <= 3.0 * S_err[..., i]):.1f}% within 3σ")
        results.append(ok)
    ok = bool(np.all(np.abs(S[..., 3]) <= 1e-6 * S[..., 0]))
    print(f"{'PASS' if ok else 'FAIL'} polarised: S3 of that reflection is 0: max |S3|/S0 = "
          f"{np.max(np.abs(S[..., 3]) / np.maximum(S[..., 0], 1e-30)):.1e}")
    results.append(ok)
    c = (HEIGHT // 2, WIDTH // 2)
    print(f"      centre pixel: S/S0 = {np.round(S[c] / S[c][0], 4)}, expected {np.round(expected[c] / expected[c][0], 4)}")

    print("all checks passed" if all(results) else "SOME CHECKS FAILED")
    return 0 if all(results) else 1


if __name__ == "__main__":
    sys.exit(main())

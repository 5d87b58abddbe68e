#!/usr/bin/env python3
"""prisma against Mitsuba 3 on this machine, in one run: ray throughput and time to equal error.

Measures, with the same inputs for both renderers:

1. Raw ray throughput on one procedural mesh (a displaced sphere of ~1M triangles): prisma's BVH
   (`prisma bench-rays`) against Mitsuba's `ray_intersect` / `ray_test` (Embree) in the
   llvm_ad_spectral variant, for coherent camera rays and incoherent random rays; prisma in
   packets of 16 consecutive rays (as Mitsuba calls Embree) and one by one. The best of 15
   passes each, in three alternating rounds of five; Mitsuba's JIT-compiling passes are excluded.
2. Rendering: render time, samples per second and time to equal error on (a) a specular-only
   glass scene, where Mitsuba's path tracer computes exactly Whitted, and (b) the TP6 mirror + glass
   scene, where Mitsuba runs the Whitted integrator of validation/mitsuba/whitted.py; each twice,
   like with like: unpolarised (prisma --unpolarized against Mitsuba's llvm_ad_spectral and
   scalar_spectral) and polarised (prisma's default against llvm_ad_spectral_polarized and
   scalar_spectral_polarized). Mitsuba runs its independent, ldsampler and multijitter samplers (the
   comparison is against the fastest of them). Both renderers' images go through prisma's colour
   pipeline (Mitsuba's specfilm with prisma's CIE table, translate.prisma_rgb), as the references
   do: the error is the relative MSE against the converged reference of that mode (the mean of the
   two committed `<case>_prisma_cmf` or `<case>_polarized` Mitsuba references, rendered with the
   same translation) minus the reference's own noise. Stratified samplers converge faster than 1/N, so no single efficiency constant describes
   them: the time to reach each target error is interpolated log-log between sample counts, and the
   speed ratio at equal error is t_mitsuba / t_prisma at that error.

Run from the repository root after validation/setup.sh and `cargo build --release`:
  export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
  validation/.venv/bin/python validation/bench/bench.py            # writes validation/bench/RESULTS.md
  validation/.venv/bin/python validation/bench/bench.py --quick    # smaller, for a smoke test
  ... bench.py --skip-rays --modes polarised                          # part of it
"""

import argparse
import datetime
import json
import os
import pathlib
import platform
import subprocess
import sys
import tempfile
import time

import numpy as np

REPO = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "validation" / "mitsuba"))

import drjit as dr  # noqa: E402
import mitsuba as mi  # noqa: E402

import translate  # noqa: E402

# (renderer, sampler, sample counts): Mitsuba runs its default independent sampler and its two
# stratified ones, so that the comparison is against its best configuration, not its default.
# Sample counts a factor of 2 apart, so that the log-log interpolation between them follows the
# error curves closely (stratified samplers' errors fall faster than 1/N and not as a power law).
# "llvm" and "scalar" stand for the mode's variants (MODES).
RENDERERS = [
    ("prisma", "sobol-owen", [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024]),
    ("llvm", "independent", [4, 16, 64, 256, 1024, 4096]),
    # ldsampler rounds its sample count up to a power of 4 (8 renders 16 samples), and
    # multijitter stratifies best on perfect squares (it rounds 32 up to 5 × 7 = 35, which
    # converges worse than 64): powers of 4 for both, their best counts.
    ("llvm", "ldsampler", [4, 16, 64, 256, 1024, 4096]),
    ("llvm", "multijitter", [4, 16, 64, 256, 1024, 4096]),
    ("scalar", "independent", [4, 16]),
]
# mode: (prisma flag, Mitsuba's llvm and scalar variants, suffix of the references' case name)
MODES = {
    "unpolarised": ("--unpolarized", "llvm_ad_spectral", "scalar_spectral", "_prisma_cmf"),
    "polarised": ("--polarized", "llvm_ad_spectral_polarized", "scalar_spectral_polarized", "_polarized"),
}
# Error levels (relMSE beyond the reference's noise) at which the times are compared: a preview
# (1e-3), a clean image (1e-4) and a converged one (1e-5; both references' noise is below 2.2e-6).
TARGETS = [1e-3, 1e-4, 1e-5]

CASES = [
    ("specular glass (path = Whitted)", "specular_spheres", "path"),
    ("TP6 mirror + glass (Whitted)", "tp6_point", "whitted"),
]


def prisma_commit():
    """The commit of the working tree (with "+changes" when it differs), or "unknown"."""
    try:
        head = subprocess.run(["git", "-C", str(REPO), "rev-parse", "--short", "HEAD"], check=True,
                              capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(REPO), "status", "--porcelain", "--untracked-files=no"],
                               check=True, capture_output=True, text=True).stdout.strip()
        return head + ("+changes" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def machine():
    model = "unknown CPU"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return f"{model}, {os.cpu_count()} logical cores, {platform.system()} {platform.release()}"


def displaced_sphere(path, rings):
    """A closed, bumpy UV sphere with about 2·rings² triangles, written as OBJ."""
    theta = np.linspace(0.0, np.pi, rings + 1)[1:-1]
    phi = np.linspace(0.0, 2.0 * np.pi, rings, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    radius = 1.0 + 0.05 * np.sin(7 * t) * np.cos(9 * p) + 0.02 * np.sin(31 * t + 17 * p)
    xyz = np.stack([radius * np.sin(t) * np.cos(p), radius * np.cos(t), radius * np.sin(t) * np.sin(p)], -1)
    vertices = np.concatenate([[[0.0, 1.0, 0.0]], xyz.reshape(-1, 3), [[0.0, -1.0, 0.0]]])
    n_rings, n = len(theta), rings
    idx = lambda r, s: 1 + r * n + (s % n)  # noqa: E731
    faces = []
    for s in range(n):
        faces.append((0, idx(0, s + 1), idx(0, s)))
        faces.append((len(vertices) - 1, idx(n_rings - 1, s), idx(n_rings - 1, s + 1)))
    r = np.arange(n_rings - 1)[:, None]
    s = np.arange(n)[None, :]
    a, b, c, d = idx(r, s), idx(r, s + 1), idx(r + 1, s), idx(r + 1, s + 1)
    quads = np.stack([np.stack([a, b, c], -1), np.stack([b, d, c], -1)], -2).reshape(-1, 3)
    faces = np.concatenate([np.array(faces), quads])
    with open(path, "w") as f:
        f.write("".join(f"v {x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in vertices))
        f.write("".join(f"f {i + 1} {j + 1} {k + 1}\n" for i, j, k in faces))
    return len(faces)


def ray_sets(count, rng):
    """Coherent (a pinhole camera's grid aimed at the mesh) and incoherent rays, float32 (N, 6)."""
    side = int(round(count ** 0.5))
    u, v = np.meshgrid(np.linspace(-0.6, 0.6, side), np.linspace(-0.6, 0.6, side))
    d = np.stack([u.ravel(), v.ravel(), np.ones(side * side)], -1)
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    coherent = np.concatenate([np.tile([0.0, 0.0, -3.0], (side * side, 1)), d], 1)
    origins = rng.normal(size=(count, 3))
    origins *= 2.5 / np.linalg.norm(origins, axis=1, keepdims=True)
    targets = rng.uniform(-1.0, 1.0, size=(count, 3))
    d = targets - origins
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    incoherent = np.concatenate([origins, d], 1)
    return {"coherent": coherent.astype(np.float32), "incoherent": incoherent.astype(np.float32)}


def mitsuba_rays(obj, rays, repeat=5):
    scene = mi.load_dict({"type": "scene", "mesh": {"type": "obj", "filename": str(obj)}})
    r = rays.astype(np.float32)
    ray = mi.Ray3f(mi.Point3f(r[:, 0], r[:, 1], r[:, 2]), mi.Vector3f(r[:, 3], r[:, 4], r[:, 5]))
    best = {}
    for name, fn in [("closest", lambda: scene.ray_intersect(ray, ray_flags=mi.RayFlags.Minimal, coherent=False).t),
                     ("any", lambda: scene.ray_test(ray))]:
        dr.eval(fn())  # JIT compile
        times = []
        for _ in range(repeat):
            start = time.perf_counter()
            out = fn()
            dr.eval(out)
            dr.sync_thread()
            times.append(time.perf_counter() - start)
        best[name] = len(r) / min(times) * 1e-6
    t = np.array(scene.ray_intersect(ray).t)
    hits = np.isfinite(t)
    best["hits"] = int(hits.sum())
    best["mean_t"] = float(t[hits].mean()) if hits.any() else float("nan")
    return best


def prisma_rays(prisma, obj, ray_file, repeat=5):
    out = subprocess.run([prisma, "bench-rays", "--obj", str(obj), "--rays", str(ray_file), "--threads",
                          str(os.cpu_count()), "--repeat", str(repeat)], check=True, capture_output=True,
                         text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def best_of_rounds(prisma, obj, ray_file, rays, rounds=3):
    """prisma's and Mitsuba's best throughput over `rounds` alternating rounds (each round takes
    the best of 5 passes per renderer), so that a slow spell of this shared machine does not fall on
    one renderer only."""
    best_p, best_m = None, None
    for _ in range(rounds):
        p = prisma_rays(prisma, obj, ray_file)
        m = mitsuba_rays(obj, rays)
        if best_p is None:
            best_p, best_m = p, m
        else:
            for key in ("closest_mrays_s", "any_mrays_s", "single_closest_mrays_s", "single_any_mrays_s"):
                best_p[key] = max(best_p[key], p[key])
            for key in ("closest", "any"):
                best_m[key] = max(best_m[key], m[key])
    return best_p, best_m


def rel_mse(image, reference):
    return float(np.mean((image - reference) ** 2 / (reference ** 2 + 1e-2)))


def reference_noise(first, second):
    """The relMSE that the noise of the reference (the mean of two independent renders) adds to
    every measurement: E[(mean − truth)²] = E[(first − second)²] / 4 per pixel."""
    reference = 0.5 * (first + second)
    return float(np.mean((first - second) ** 2 / 4.0 / (reference ** 2 + 1e-2)))


def read_exr(path, channels):
    bitmap = mi.Bitmap(str(path))
    names = [bitmap.struct_()[i].name for i in range(bitmap.channel_count())]
    data = np.array(bitmap, dtype=np.float64)
    return np.stack([data[..., names.index(c)] for c in channels], -1)


def timing_repeats(spp):
    """Timed renders per measurement: the best of three for the short ones, whose single times
    this shared machine's noise moves by ±20 %; one for the long ones."""
    return 3 if spp <= 256 else 1


def prisma_render(prisma, scene, spp, out_dir, mode_flag):
    """(render seconds, process wall seconds, image): the render time excludes loading the scene
    and writing the images, as Mitsuba's does (its scene is loaded before the clock starts). The
    best of `timing_repeats` runs; the image is the same every run (same seed)."""
    out = out_dir / f"prisma_{scene.stem}_{spp}{mode_flag}.exr"
    stats = out_dir / f"prisma_{scene.stem}_{spp}{mode_flag}.json"
    best = (float("inf"), float("inf"))
    # Dr.Jit's worker threads keep a core busy for 0.1-0.2 s after Mitsuba's last render or image
    # read in this process; a prisma render started meanwhile shares the cores with them (see
    # SETTLE_SECONDS in caustics_bench.py). The repeats follow one another without Dr.Jit work.
    time.sleep(0.5)
    for _ in range(timing_repeats(spp)):
        start = time.perf_counter()
        subprocess.run([prisma, "render", str(scene), "--spp", str(spp), "-o", str(out), "--quiet", "--seed",
                        "7", "--stats", str(stats), mode_flag], check=True)
        wall = time.perf_counter() - start
        best = min(best, (json.loads(stats.read_text())["render_seconds"], wall))
    return best[0], best[1], read_exr(out, ["R", "G", "B"])


def mitsuba_render(variant, sampler, prisma, scene_path, integrator_kind, spp, export_dir):
    mi.set_variant(variant)
    scene = translate.PrismaScene.load(scene_path, export_dir, prisma)
    integrator = (translate.whitted_integrator if integrator_kind == "whitted" else translate.path_integrator)(
        scene.max_depth)
    # The references' translation: graded planes, prisma's colour pipeline.
    translator = translate.Translator(scene, None, False, plane_half_size="graded")
    mitsuba_scene = mi.load_dict(translator.scene_dict(integrator, spp, sampler=sampler, film="prisma_xyz"))
    # The sample count the sampler really takes (ldsampler rounds up to a power of 4).
    actual_spp = int(mitsuba_scene.sensors()[0].sampler().sample_count())
    timings, images = [], []
    for k in range(1 + timing_repeats(actual_spp)):  # the first llvm render includes JIT compilation
        start = time.perf_counter()
        images.append(np.array(mi.render(mitsuba_scene, spp=actual_spp, seed=11 + k), dtype=np.float64))
        timings.append(time.perf_counter() - start)
    film = mitsuba_scene.sensors()[0].film()
    channels = [film.bitmap().struct_()[i].name for i in range(images[1].shape[-1])]
    # prisma's matrix on the XYZ film (not timed: prisma's own conversion is a per-pixel step too).
    rgb, names = translate.prisma_rgb(images[1], channels)
    return actual_spp, min(timings[1:]), np.stack([rgb[..., names.index(c)] for c in "RGB"], -1)


def time_to_error(points, target):
    """Seconds to reach relMSE `target`, interpolated log-log between the measured (seconds, error)
    points, or extrapolated along the last two (marked) when the target lies beyond them."""
    # The fastest way to each error: points that a faster point already matches are dropped
    # (timing noise can make a larger sample count finish sooner), so the curve falls strictly.
    frontier = []
    for t, e in sorted((t, e) for t, e in points if e > 0):
        if not frontier or e < frontier[-1][1]:
            frontier.append((t, e))
    points = frontier
    if len(points) < 2:
        return float("nan"), True
    for (t0, e0), (t1, e1) in zip(points, points[1:]):
        if e1 <= target <= e0:
            f = np.log(target / e0) / np.log(e1 / e0) if e1 != e0 else 0.0
            return float(np.exp(np.log(t0) + f * np.log(t1 / t0))), False
    (t0, e0), (t1, e1) = (points[0], points[1]) if target > points[0][1] else (points[-2], points[-1])
    slope = np.log(t1 / t0) / np.log(e1 / e0)
    return float(t1 * (target / e1) ** slope), True


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small mesh, few sample counts")
    parser.add_argument("--out", type=pathlib.Path, default=REPO / "validation" / "bench" / "RESULTS.md")
    parser.add_argument("--skip-rays", action="store_true", help="skip the ray-throughput part")
    parser.add_argument("--modes", nargs="+", choices=list(MODES), default=list(MODES))
    args = parser.parse_args()
    prisma = translate.find_prisma()
    rng = np.random.default_rng(1)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        mi.set_variant("llvm_ad_spectral")
        ray_rows, triangles = [], 0
        if not args.skip_rays:
            obj = tmp / "mesh.obj"
            triangles = displaced_sphere(obj, 120 if args.quick else 708)
            for kind, rays in ray_sets(200_000 if args.quick else 1_000_000, rng).items():
                ray_file = tmp / f"{kind}.bin"
                rays.tofile(ray_file)
                p, m = best_of_rounds(prisma, obj, ray_file, rays)
                ray_rows.append((kind, len(rays), p, m))
                print(f"rays {kind}: prisma packets {p['closest_mrays_s']:.2f} / {p['any_mrays_s']:.2f} Mrays/s, "
                      f"single rays {p['single_closest_mrays_s']:.2f} / {p['single_any_mrays_s']:.2f}, "
                      f"Mitsuba {m['closest']:.2f} / {m['any']:.2f} Mrays/s (closest / any); "
                      f"hits {p['hits']} (packets {p['packet_hits']}) vs {m['hits']}", flush=True)

        for mode in args.modes:
            flag, llvm_variant, scalar_variant, suffix = MODES[mode]
            for title, case, kind in CASES:
                scene_path = REPO / "validation" / "scenes" / f"{case}.toml"
                references = [read_exr(REPO / "validation" / "references" / f"{case}{suffix}_seed{k}.exr",
                                       ["R", "G", "B"]) for k in (1, 2)]
                reference = 0.5 * (references[0] + references[1])
                floor = reference_noise(*references)
                pixels = reference.shape[0] * reference.shape[1]
                # (renderer, sampler) -> [(spp, render seconds, process wall seconds or None, relMSE)]
                result = {}
                for renderer, sampler, levels in RENDERERS:
                    variant = {"llvm": llvm_variant, "scalar": scalar_variant}.get(renderer, renderer)
                    if renderer == "scalar" and kind == "whitted":
                        continue  # Python integrators do not run in scalar variants
                    levels = [spp for spp in levels if not args.quick or spp <= 16]
                    for spp in levels:
                        if renderer == "prisma":
                            seconds, wall, image = prisma_render(prisma, scene_path, spp, tmp, flag)
                        else:
                            spp, seconds, image = mitsuba_render(variant, sampler, prisma, scene_path, kind, spp,
                                                                 tmp / f"export_{case}")
                            wall = None
                        error = rel_mse(image, reference)
                        result.setdefault((variant, sampler), []).append((spp, seconds, wall, error))
                        print(f"{mode} {case} {variant} {sampler} spp {spp}: {seconds:.3f} s, relMSE {error:.3e}",
                              flush=True)
                rows.append((mode, title, case, suffix, pixels, floor, result))

    lines = [
        "# prisma vs Mitsuba 3: benchmark results",
        "",
        f"Date: {datetime.date.today().isoformat()}. Machine: {machine()}.",
        f"Mitsuba {mi.__version__}; prisma `{prisma}` (commit {prisma_commit()}). Command: "
        f"`validation/.venv/bin/python validation/bench/bench.py{' ' if sys.argv[1:] else ''}{' '.join(sys.argv[1:])}`.",
        "",
        "Where the time goes and what the next factor would come from: [PROFILE.md](PROFILE.md).",
        "",
    ]
    if ray_rows:
        lines += [
            f"## Ray throughput on a {triangles:,}-triangle mesh (Mrays/s, all cores, best of 15 passes in 3 "
            f"alternating rounds)",
            "",
            "prisma traces the rays in packets of 16 consecutive rays (`Geometry::intersect_packet` and "
            "`occluded_packet`, as Mitsuba hands Embree 16 rays at a time) and, for comparison, one by one "
            "(`intersect`, `occluded`); the ratio is that of the packets to Embree.",
            "",
            "| rays | count | query | prisma, 16-ray packets | prisma, single rays | Mitsuba (Embree) | ratio | "
            "hits prisma / Mitsuba |",
            "|---|---|---|---|---|---|---|---|",
        ]
        for kind, count, p, m in ray_rows:
            for query, name, hits in (("closest", "closest hit", "packet_hits"), ("any", "any hit", "packet_occluded")):
                lines.append(f"| {kind} | {count:,} | {name} | {p[f'{query}_mrays_s']:.2f} | "
                             f"{p[f'single_{query}_mrays_s']:.2f} | {m[query]:.2f} | "
                             f"{p[f'{query}_mrays_s'] / m[query]:.2f} | {p[hits]} / {m['hits']} |")
        built = ray_rows[0][2]
        lines += ["", f"prisma BVH build: {built['build_s']:.2f} s for {triangles:,} triangles (2 threads); memory "
                      f"{built['bvh_bytes_per_triangle']:.1f} bytes per triangle for the nodes, "
                      f"{built['total_bytes_per_triangle']:.1f} with the leaf packets that copy the vertices.", ""]
    for mode, title, case, suffix, pixels, floor, result in rows:
        lines += [f"## {title}, {mode} (`validation/scenes/{case}.toml`)", "",
                  f"prisma `{MODES[mode][0]}` against Mitsuba's `{MODES[mode][1]}` (and `{MODES[mode][2]}` where "
                  f"it runs). relMSE against the converged reference (the mean of the two committed "
                  f"`{case}{suffix}` Mitsuba renders, same translation, prisma's colour pipeline on both sides), "
                  f"minus that reference's own noise ({floor:.2e}, estimated from the difference of the two). "
                  f"Render time excludes scene loading and image writing for both renderers (and Mitsuba's JIT "
                  f"compilation: its first render is not timed); it is the best of three renders up to 256 spp, "
                  f"of one above. prisma's process wall time is also shown.", "",
                  "| renderer | sampler | spp | render time (s) | process wall (s) | samples/s | relMSE |",
                  "|---|---|---|---|---|---|---|"]
        for (renderer, sampler), points in result.items():
            for spp, seconds, wall, error in points:
                wall_text = f"{wall:.2f}" if wall is not None else "–"
                lines.append(f"| {renderer} | {sampler} | {spp} | {seconds:.3f} | {wall_text} | "
                             f"{pixels * spp / seconds:,.0f} | {max(error - floor, 0.0):.3e} |")
        lines += ["", "Time to reach equal error (seconds, interpolated log-log between the measured points; "
                  "* extrapolated beyond them):", "",
                  "| renderer | sampler | " + " | ".join(f"relMSE {t:.0e}" for t in TARGETS) + " |",
                  "|---|---|" + "---|" * len(TARGETS)]
        times = {}
        for key, points in result.items():
            cells = []
            for target in TARGETS:
                t, extrapolated = time_to_error([(s, e - floor) for _, s, _, e in points], target)
                times[key, target] = t
                cells.append(f"{t:.3g}{'*' if extrapolated else ''}")
            lines.append(f"| {key[0]} | {key[1]} | " + " | ".join(cells) + " |")
        lines.append("")
        prisma_key = next(k for k in result if k[0] == "prisma")
        for target in TARGETS:
            llvm = {k: times[k, target] for k in result
                    if k[0] == MODES[mode][1] and np.isfinite(times[k, target])}
            if llvm:
                best = min(llvm, key=llvm.get)
                lines.append(f"- relMSE {target:.0e}: prisma is **{llvm[best] / times[prisma_key, target]:.2f}×** "
                             f"as fast as Mitsuba's fastest configuration (`{best[0]}`, `{best[1]}` sampler).")
        lines.append("")
    args.out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()

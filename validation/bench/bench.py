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
  ... bench.py --transport      # full transport only (below); its section of RESULTS.md is replaced
  ... bench.py --transport-scene room room_point   # the rooms (room_bench.py); their sections replaced

3. --transport: full light transport, TP6 with its quad light (validation/scenes/tp6_quad_path.toml,
   scenes/tp6_quad.toml's scene at 150×100 with `integrator = "path"`, max_depth 64): prisma's
   `path` integrator against Mitsuba's `path` (max_depth 65, its default Russian roulette;
   translate.full_transport_integrator, as the references), unpolarised (prisma --unpolarized
   against llvm_ad_spectral) and polarised (prisma's default against llvm_ad_spectral_polarized);
   the scene has no Fresnel interface and unpolarised lights, so both modes compute the same S0
   and are measured against the same reference. The reference is the mean of the two committed
   `tp6_quad_path_prisma_cmf` renders, each weighed with one more render of the same case from
   validation/bench/transport_reference.py (when present) by their sample counts; its own noise
   is estimated from the difference of the two halves and subtracted, as above. Mitsuba's JIT
   compilation does not depend on the sample count (measured: a first render at a new count
   takes as long as the second), so each sampler is warmed up once, at 4 spp; its three samplers
   run to 1024 spp, and multijitter again with the background left out of its light sampling
   (TRANSPORT_RENDERERS), and the fastest of the four to 4096. Also prisma's 1 → 2 thread scaling and peak
   memory (/usr/bin/time -v), and the load average at the start and end of the run. Each render's
   CPU time is recorded beside its wall time (prisma's whole process from getrusage, Mitsuba's
   render calls from this process's CPU clock, all threads), and the times to equal error are
   given in both: on a machine whose cores other processes share, CPU time is the steadier
   measure. --samplers and --max-spp run part of the race (some of Mitsuba's configurations, no
   count above a cap: the long run is skipped when it is above it).
4. --transport-scene room room_point: the same race on two rooms (validation/bench/room_bench.py,
   the scenes in transport_scenes.py, the references from transport_reference.py --scene): the
   glass-and-mirror room (validation/scenes/stokes_room_path.toml, spectral) against Mitsuba's
   `path` in both modes, and the point-light room (transport_room_point.toml) against Mitsuba's
   `ptracer` on the pixels where it is complete; each room writes its own section and headline
   row of RESULTS.md. Mitsuba's renders are cached in validation/bench/mitsuba_cache.json (and
   mitsuba_cache/), so a re-run with a new prisma renders prisma only (--refresh-mitsuba: all).
"""

import argparse
import datetime
import json
import os
import pathlib
import platform
import re
import resource
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


def prisma_render(prisma, scene, spp, out_dir, mode_flag, extra_args=(), with_stats=False):
    """(render seconds, process wall seconds, image): the render time excludes loading the scene
    and writing the images, as Mitsuba's does (its scene is loaded before the clock starts). The
    best of `timing_repeats` runs; the image is the same every run (same seed). `extra_args` are
    passed to `prisma render`; with_stats adds the best run's stats JSON (rays, samples)."""
    out = out_dir / f"prisma_{scene.stem}_{spp}{mode_flag}.exr"
    stats = out_dir / f"prisma_{scene.stem}_{spp}{mode_flag}.json"
    best = (float("inf"), float("inf"), None)
    # Dr.Jit's worker threads keep a core busy for 0.1-0.2 s after Mitsuba's last render or image
    # read in this process; a prisma render started meanwhile shares the cores with them (see
    # SETTLE_SECONDS in caustics_bench.py). The repeats follow one another without Dr.Jit work.
    time.sleep(0.5)
    for _ in range(timing_repeats(spp)):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        subprocess.run([prisma, "render", str(scene), "--spp", str(spp), "-o", str(out), "--quiet", "--seed",
                        "7", "--stats", str(stats), mode_flag, *extra_args], check=True)
        wall = time.perf_counter() - start
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        figures = json.loads(stats.read_text())
        # CPU time of the render alone, all threads (`render_cpu_seconds`: the span of
        # `render_seconds`, as Mitsuba's is its `mi.render` call's); the whole process's (loading
        # and writing included) from a binary that does not report it.
        process_cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        figures["cpu_seconds"] = figures.get("render_cpu_seconds") or process_cpu
        if (figures["render_seconds"], wall) < best[:2]:
            best = (figures["render_seconds"], wall, figures)
    image = read_exr(out, ["R", "G", "B"])
    return (best[0], best[1], image, best[2]) if with_stats else (best[0], best[1], image)


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


# Full transport (--transport): TP6 with its quad light, prisma's `path` against Mitsuba's `path`.
TRANSPORT_SCENE = "tp6_quad_path"
TRANSPORT_REFERENCE = "tp6_quad_path_prisma_cmf"
# prisma: doubling sample counts up to 1024 (relMSE 1e-4 needs about 500 spp). Mitsuba: powers
# of 4 (ldsampler's and multijitter's best counts, as above) up to 1024 for each sampler, and
# TRANSPORT_LONG_SPP for the sampler fastest at 1024 spp only (a 4096-spp render takes over a
# minute on two cores: all three would not fit the quiet spell of a shared machine).
#
# Mitsuba picks the light of each next-event estimate among the scene's emitters with
# probability proportional to their `sampling_weight` (1 by default: measured with
# Scene.sample_emitter, the quad and the background 1/2 each), and the background lights this
# closed room along no direction of positive measure: half its estimates are wasted. The last
# entry is Mitsuba tuned for the scene, the background's sampling_weight 0 (still a light, met by
# BSDF sampling with full weight: unbiased), so that the race is against its best configuration.
QUAD_ONLY = "multijitter, quad-only NEE"
TRANSPORT_RENDERERS = [
    ("prisma", "sobol-owen", [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024]),
    ("llvm", "independent", [4, 16, 64, 256, 1024]),
    ("llvm", "ldsampler", [4, 16, 64, 256, 1024]),
    ("llvm", "multijitter", [4, 16, 64, 256, 1024]),
    ("llvm", QUAD_ONLY, [4, 16, 64, 256, 1024]),
]
TRANSPORT_LONG_SPP = 4096
TRANSPORT_TARGETS = [1e-3, 1e-4]
# prisma's 1 → 2 thread scaling and peak memory: this many samples per pixel, best of this many
# alternating rounds.
SCALING_SPP, SCALING_ROUNDS = 256, 3
TRANSPORT_BEGIN = "<!-- bench.py --transport: begin -->"
TRANSPORT_END = "<!-- bench.py --transport: end -->"


def transport_reference():
    """(reference, its own noise, description): the two committed `tp6_quad_path_prisma_cmf`
    references, each weighed by sample count with the render of validation/bench/references of
    the same parity (seed 3 with 1, 4 with 2) when those exist; the noise from the two halves."""
    committed_dir = REPO / "validation" / "references"
    extra_dir = REPO / "validation" / "bench" / "references"
    committed_spp = json.loads((committed_dir / f"{TRANSPORT_REFERENCE}.json").read_text())["spp"]
    halves = [read_exr(committed_dir / f"{TRANSPORT_REFERENCE}_seed{k}.exr", ["R", "G", "B"]) for k in (1, 2)]
    text = (f"the mean of the two committed `{TRANSPORT_REFERENCE}` Mitsuba references "
            f"({committed_spp} spp each, `independent` sampler)")
    extra_json = extra_dir / f"{TRANSPORT_REFERENCE}.json"
    if extra_json.exists():
        extra = json.loads(extra_json.read_text())
        extra_spp = extra["spp_per_pass"] * extra["passes"]
        extras = [read_exr(extra_dir / render["file"], ["R", "G", "B"]) for render in extra["renders"]]
        # The new renders must estimate what the committed ones do: the relMSE between the two
        # means is the sum of their noises if neither is biased.
        between = rel_mse(0.5 * (halves[0] + halves[1]), 0.5 * (extras[0] + extras[1]))
        expected = reference_noise(*halves) + reference_noise(*extras)
        halves = [(committed_spp * c + extra_spp * e) / (committed_spp + extra_spp) for c, e in zip(halves, extras)]
        text += (f", each weighed with one more render of the same translation and settings at another seed "
                 f"(`validation/bench/transport_reference.py`, {extra_spp} spp each): two halves of "
                 f"{committed_spp + extra_spp} spp (the committed and the new means differ by relMSE "
                 f"{between:.3e}, their noises predict {expected:.3e})")
    return 0.5 * (halves[0] + halves[1]), reference_noise(*halves), text


def mitsuba_transport_renders(variant, sampler, prisma, scene_path, levels, export_dir):
    """[(spp, render seconds, image, CPU seconds)] of Mitsuba's full-transport path tracer at each sample count,
    the scene loaded once and compiled by a first 4-spp render (not timed: the kernels do not
    depend on the sample count). `sampler` is a Mitsuba sampler's name or QUAD_ONLY. Each
    count's time is the best of `timing_repeats` renders at seeds 11, 12, …; its image is the
    first's."""
    mi.set_variant(variant)
    scene = translate.PrismaScene.load(scene_path, export_dir, prisma)
    translator = translate.Translator(scene, None, False, plane_half_size="graded")
    integrator = translate.full_transport_integrator(scene.max_depth)
    description = translator.scene_dict(integrator, 4, sampler=sampler.split(",")[0], film="prisma_xyz")
    if sampler == QUAD_ONLY:
        description["background"]["sampling_weight"] = 0.0
    mitsuba_scene = mi.load_dict(description)
    sampler_object = mitsuba_scene.sensors()[0].sampler()
    mi.render(mitsuba_scene, spp=4, seed=10)
    film = mitsuba_scene.sensors()[0].film()
    out = []
    for spp in levels:
        timings, cpu, first = [], [], None
        for k in range(timing_repeats(spp)):
            start, start_cpu = time.perf_counter(), time.process_time()
            image = mi.render(mitsuba_scene, spp=spp, seed=11 + k)
            dr.eval(image)
            dr.sync_thread()
            timings.append(time.perf_counter() - start)
            # CPU time of this process's threads (Dr.Jit's workers render).
            cpu.append(time.process_time() - start_cpu)
            if first is None:
                first = np.array(image, dtype=np.float64)
        actual = int(sampler_object.sample_count())
        channels = [film.bitmap().struct_()[i].name for i in range(first.shape[-1])]
        rgb, names = translate.prisma_rgb(first, channels)
        out.append((actual, min(timings), np.stack([rgb[..., names.index(c)] for c in "RGB"], -1), min(cpu)))
        print(f"transport {variant} {sampler} spp {actual}: {min(timings):.3f} s", flush=True)
    return out


def prisma_process(prisma, scene, spp, threads, mode_flag, out_dir):
    """One `prisma render` under /usr/bin/time -v: (render seconds, process wall seconds, peak
    resident memory in MiB, stats)."""
    out = out_dir / f"scaling_{threads}{mode_flag}.exr"
    stats = out_dir / f"scaling_{threads}{mode_flag}.json"
    time.sleep(0.5)  # Dr.Jit's idle worker threads (prisma_render)
    start = time.perf_counter()
    run = subprocess.run(["/usr/bin/time", "-v", prisma, "render", str(scene), "--integrator", "path", "--spp",
                          str(spp), "--threads", str(threads), "-o", str(out), "--quiet", "--seed", "7", "--stats",
                          str(stats), mode_flag], check=True, capture_output=True, text=True)
    wall = time.perf_counter() - start
    peak = re.search(r"Maximum resident set size \(kbytes\): (\d+)", run.stderr)
    figures = json.loads(stats.read_text())
    return figures["render_seconds"], wall, int(peak.group(1)) / 1024.0 if peak else float("nan"), figures


def load_text():
    """`uptime`'s load averages (1, 5, 15 minutes) and the UTC time."""
    one, five, fifteen = os.getloadavg()
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC")
    return f"{now}, load average {one:.2f}, {five:.2f}, {fifteen:.2f}"


def transport(args, prisma):
    """The full-transport race (see the module's docstring, 3.): its RESULTS.md section's lines
    and a summary for the headline."""
    scene_path = REPO / "validation" / "scenes" / f"{TRANSPORT_SCENE}.toml"
    reference, floor, reference_text = transport_reference()
    pixels = reference.shape[0] * reference.shape[1]
    started = load_text()
    print(f"transport: reference noise {floor:.3e}; start {started}", flush=True)
    cap = 16 if args.quick else (args.max_spp or float("inf"))
    quick = lambda levels: [spp for spp in levels if spp <= cap]  # noqa: E731
    renderers = [r for r in TRANSPORT_RENDERERS if r[0] == "prisma" or args.samplers is None or r[1] in args.samplers]
    results = {}
    cpu = {}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        for mode in args.modes:
            flag, llvm_variant, _, _ = MODES[mode]
            # (renderer, sampler) -> [(spp, render seconds, process wall or None, relMSE, stats or None)]
            result = {}
            for renderer, sampler, levels in renderers:
                if renderer == "prisma":
                    for spp in quick(levels):
                        seconds, wall, image, figures = prisma_render(prisma, scene_path, spp, tmp, flag,
                                                                      ("--integrator", "path"), with_stats=True)
                        error = rel_mse(image, reference) - floor
                        result.setdefault(("prisma", sampler), []).append((spp, seconds, wall, error, figures))
                        cpu[mode, ("prisma", sampler), spp] = figures["cpu_seconds"]
                        print(f"transport {mode} prisma spp {spp}: {seconds:.3f} s, relMSE {error:.3e}", flush=True)
                else:
                    for spp, seconds, image, cpu_seconds in mitsuba_transport_renders(
                            llvm_variant, sampler, prisma, scene_path, quick(levels), tmp / "export"):
                        error = rel_mse(image, reference) - floor
                        result.setdefault((llvm_variant, sampler), []).append((spp, seconds, None, error, None))
                        cpu[mode, (llvm_variant, sampler), spp] = cpu_seconds
                        print(f"transport {mode} {llvm_variant} {sampler} spp {spp}: relMSE {error:.3e}", flush=True)
            # The sampler that reaches the last common error soonest goes on to TRANSPORT_LONG_SPP.
            mitsuba_keys = [k for k in result if k[0] == llvm_variant]
            last = max(min(e for _, _, _, e, _ in result[k]) for k in mitsuba_keys)
            fastest = min(mitsuba_keys, key=lambda k: time_to_error([(p[1], p[3]) for p in result[k]], last)[0])
            long_spp = 64 if args.quick else TRANSPORT_LONG_SPP
            for spp, seconds, image, cpu_seconds in mitsuba_transport_renders(
                    llvm_variant, fastest[1], prisma, scene_path, quick([long_spp]), tmp / "export"):
                error = rel_mse(image, reference) - floor
                result[fastest].append((spp, seconds, None, error, None))
                cpu[mode, fastest, spp] = cpu_seconds
                print(f"transport {mode} {llvm_variant} {fastest[1]} spp {spp}: relMSE {error:.3e}", flush=True)
            results[mode] = result
        # prisma's thread scaling and peak memory, in alternating rounds.
        scaling_spp = 16 if args.quick else SCALING_SPP
        scaling = {}
        for mode in args.modes:
            for _ in range(1 if args.quick else SCALING_ROUNDS):
                for threads in (1, 2):
                    run = prisma_process(prisma, scene_path, scaling_spp, threads, MODES[mode][0], tmp)
                    best = scaling.get((mode, threads))
                    scaling[mode, threads] = run if best is None or run[0] < best[0] else best
                    print(f"transport {mode} prisma {threads} thread(s) {scaling_spp} spp: {run[0]:.3f} s, "
                          f"peak {run[2]:.1f} MiB", flush=True)
    finished = load_text()
    mitsuba_peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0

    command = (f"validation/.venv/bin/python validation/bench/bench.py{' ' if sys.argv[1:] else ''}"
               f"{' '.join(sys.argv[1:])}")
    lines = [TRANSPORT_BEGIN,
             f"## Full transport: TP6 with its quad light, prisma `path` against Mitsuba `path` "
             f"(`validation/scenes/{TRANSPORT_SCENE}.toml`)", "",
             f"Run: {started} → {finished}. Machine: {machine()}. Mitsuba {mi.__version__}; prisma `{prisma}` "
             f"(commit {prisma_commit()}). Command: `{command}` (this section written by it).", "",
             f"The scene is `scenes/tp6_quad.toml` (diffuse walls and spheres, the D65 quad light, the grey "
             f"background a light too) at 150×100 with `integrator = \"path\"` and `max_depth = 64` bounces; "
             f"prisma renders it with `--integrator path`, Mitsuba with its `path` integrator (max_depth 65, which "
             f"counts vertices; Russian roulette from its default depth 5), the translation of the references "
             f"(graded planes, specfilm with prisma's CIE table, prisma's matrix). relMSE = mean (x − r)²/(r² + 0.01) "
             f"over the R, G, B pixels against the converged reference: {reference_text}, minus that reference's "
             f"own noise ({floor:.2e}, from the difference of the halves). The scene has no Fresnel interface and "
             f"its lights are unpolarised, so the polarised renders' S0 is the unpolarised radiance: both modes "
             f"are measured against the same reference. Render time excludes loading and writing for both "
             f"(and Mitsuba's JIT compilation, done once per sampler by a 4-spp render: its kernels do not depend "
             f"on the sample count); the best of three renders up to 256 spp, of one above (prisma renders "
             f"the same seed each time, Mitsuba seeds 11, 12, 13: the error is the first's). Mitsuba runs its "
             f"three samplers to 1024 spp, and `multijitter` once more with the background's `sampling_weight` 0 "
             f"(`{QUAD_ONLY}`: by default Mitsuba's next-event estimation picks the quad or the background with "
             f"probability 1/2 each, and the background lights this room along no direction of positive measure; "
             f"still a light, met by BSDF sampling), and the one of these four fastest at 1024 spp to "
             f"{TRANSPORT_LONG_SPP}.", ""]
    summary = {}
    for mode, result in results.items():
        flag, llvm_variant, _, _ = MODES[mode]
        lines += [f"### {mode}: prisma `{flag}` against `{llvm_variant}`", "",
                  "| renderer | sampler | spp | render time (s) | process wall (s) | CPU time (s) | samples/s | Mrays/s | "
                  "rays/sample | relMSE | relMSE × spp |",
                  "|---|---|---|---|---|---|---|---|---|---|---|"]
        for (renderer, sampler), points in result.items():
            for spp, seconds, wall, error, figures in sorted(points, key=lambda p: p[0]):
                rays = (f"{figures['rays'] / seconds * 1e-6:.2f} | {figures['rays'] / figures['samples']:.2f}"
                        if figures else "– | –")
                lines.append(f"| {renderer} | {sampler} | {spp} | {seconds:.3f} | "
                             f"{f'{wall:.2f}' if wall is not None else '–'} | {cpu[mode, (renderer, sampler), spp]:.2f} | "
                             f"{pixels * spp / seconds:,.0f} | "
                             f"{rays} | {error:.3e} | {error * spp:.3g} |")
        lines += ["", "Time to reach equal error (seconds, interpolated log-log between the measured points; "
                  "* extrapolated beyond them):", "",
                  "| renderer | sampler | " + " | ".join(f"relMSE {t:.0e}" for t in TRANSPORT_TARGETS) + " |",
                  "|---|---|" + "---|" * len(TRANSPORT_TARGETS)]
        times = {}
        for key, points in result.items():
            cells = []
            for target in TRANSPORT_TARGETS:
                t, extrapolated = time_to_error([(p[1], p[3]) for p in points], target)
                times[key, target] = (t, extrapolated)
                cells.append(f"{t:.3g}{'*' if extrapolated else ''}")
            lines.append(f"| {key[0]} | {key[1]} | " + " | ".join(cells) + " |")
        lines.append("")
        prisma_key = next(k for k in result if k[0] == "prisma")
        for target in TRANSPORT_TARGETS:
            mitsuba = {k: times[k, target] for k in result if k[0] == llvm_variant and np.isfinite(times[k, target][0])}
            if mitsuba and np.isfinite(times[prisma_key, target][0]):
                best = min(mitsuba, key=lambda k: mitsuba[k][0])
                ratio = mitsuba[best][0] / times[prisma_key, target][0]
                marked = mitsuba[best][1] or times[prisma_key, target][1]
                summary[mode, target] = (ratio, times[prisma_key, target][0], mitsuba[best][0], best[1], marked)
                lines.append(f"- relMSE {target:.0e}: prisma {times[prisma_key, target][0]:.3g} s, Mitsuba "
                             f"{mitsuba[best][0]:.3g} s (`{best[1]}`){' (extrapolated)' if marked else ''}: prisma "
                             f"is **{ratio:.2f}×** as fast as Mitsuba's fastest configuration.")
        # The same race in CPU time (all threads; prisma's render, Mitsuba's render calls):
        # less sensitive than wall time to other processes sharing the cores.
        lines += ["", "In CPU time (prisma's render, `render_cpu_seconds` of its stats: loading and writing excluded; Mitsuba's render calls; all "
                  "threads; interpolated as above):", "",
                  "| renderer | sampler | " + " | ".join(f"relMSE {t:.0e}" for t in TRANSPORT_TARGETS) + " |",
                  "|---|---|" + "---|" * len(TRANSPORT_TARGETS)]
        cpu_times = {}
        for key, points in result.items():
            cells = []
            for target in TRANSPORT_TARGETS:
                t, extrapolated = time_to_error([(cpu[mode, key, p[0]], p[3]) for p in points], target)
                cpu_times[key, target] = (t, extrapolated)
                cells.append(f"{t:.3g}{'*' if extrapolated else ''}")
            lines.append(f"| {key[0]} | {key[1]} | " + " | ".join(cells) + " |")
        lines.append("")
        for target in TRANSPORT_TARGETS:
            mitsuba = {k: cpu_times[k, target] for k in result
                       if k[0] == llvm_variant and np.isfinite(cpu_times[k, target][0])}
            if mitsuba and np.isfinite(cpu_times[prisma_key, target][0]):
                best = min(mitsuba, key=lambda k: mitsuba[k][0])
                ratio = mitsuba[best][0] / cpu_times[prisma_key, target][0]
                marked = mitsuba[best][1] or cpu_times[prisma_key, target][1]
                summary[mode, target, "cpu"] = (ratio, cpu_times[prisma_key, target][0], mitsuba[best][0], best[1],
                                                marked)
                lines.append(f"- relMSE {target:.0e}, CPU time: prisma {cpu_times[prisma_key, target][0]:.3g} s, "
                             f"Mitsuba {mitsuba[best][0]:.3g} s (`{best[1]}`){' (extrapolated)' if marked else ''}: "
                             f"prisma is **{ratio:.2f}×** as fast as Mitsuba's fastest configuration.")
        # Where the ratio comes from: time per sample and error per sample, at the largest sample
        # counts both ran (errors there are furthest above the reference's noise).
        prisma_points = sorted(result[prisma_key])
        p_spp, p_seconds, _, p_error, _ = prisma_points[-1]
        mitsuba_best = min((k for k in result if k[0] == llvm_variant),
                           key=lambda k: np.nan_to_num(times[k, TRANSPORT_TARGETS[-1]][0], nan=np.inf))
        m_spp, m_seconds, _, m_error, _ = sorted(result[mitsuba_best])[-1]
        per_sample = (m_seconds / m_spp) / (p_seconds / p_spp)
        per_error = (m_error * m_spp) / (p_error * p_spp)
        lines += ["", f"Decomposed at the largest counts (prisma {p_spp} spp, Mitsuba `{mitsuba_best[1]}` {m_spp} spp): "
                  f"a sample costs Mitsuba {per_sample:.2f}× prisma's time, and leaves {per_error:.2f}× prisma's "
                  f"error (relMSE × spp); their product, {per_sample * per_error:.1f}, is the ratio at equal error "
                  f"where both errors fall as 1/spp.", ""]
    lines += [f"### prisma's thread scaling and peak memory ({scaling_spp} spp, best of "
              f"{1 if args.quick else SCALING_ROUNDS} alternating rounds, `/usr/bin/time -v`)", "",
              "| mode | threads | render time (s) | process wall (s) | speed-up | peak resident memory (MiB) | Mrays/s |",
              "|---|---|---|---|---|---|---|"]
    for mode in args.modes:
        one = scaling[mode, 1][0]
        for threads in (1, 2):
            seconds, wall, peak, figures = scaling[mode, threads]
            lines.append(f"| {mode} | {threads} | {seconds:.3f} | {wall:.2f} | {one / seconds:.2f}× | {peak:.1f} | "
                         f"{figures['rays'] / seconds * 1e-6:.2f} |")
    lines += ["", f"(This Python process's peak resident memory, Mitsuba's renders included: {mitsuba_peak:,.0f} MiB.)",
              "", TRANSPORT_END]
    return lines, summary


def replace_section(text, begin, end, block, insert):
    """`text` with what lies between the markers `begin` and `end` (both included) replaced by
    `block`, or, where they are absent, with `block` put in by `insert(text, block)`. Notes
    written by hand belong outside the markers: a run replaces everything between them."""
    if begin in text and end in text:
        head, rest = text.split(begin, 1)
        return head + block + rest.split(end, 1)[1]
    return insert(text, block)


def write_transport_section(out, lines):
    """Replaces the --transport section of `out` (between its markers), or inserts it before the
    first `## ` section after the headline table."""
    text = out.read_text() if out.exists() else "# prisma vs Mitsuba 3: benchmark results\n"

    def before_equal_error(text, block):
        anchor = text.find("\n## Rendering at equal error")
        if anchor < 0:
            return text.rstrip("\n") + "\n\n" + block + "\n"
        return text[:anchor + 1] + block + "\n\n" + text[anchor + 1:]

    out.write_text(replace_section(text, TRANSPORT_BEGIN, TRANSPORT_END, "\n".join(lines), before_equal_error))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small mesh, few sample counts")
    parser.add_argument("--out", type=pathlib.Path, default=REPO / "validation" / "bench" / "RESULTS.md")
    parser.add_argument("--skip-rays", action="store_true", help="skip the ray-throughput part")
    parser.add_argument("--modes", nargs="+", choices=list(MODES), default=list(MODES))
    parser.add_argument("--transport", action="store_true",
                        help="full transport only (TP6's quad light, prisma path vs Mitsuba path); replaces "
                             "that section of --out and leaves the rest of it")
    parser.add_argument("--samplers", nargs="+", choices=[r[1] for r in TRANSPORT_RENDERERS if r[0] != "prisma"],
                        help="--transport: only these of Mitsuba's configurations (all by default)")
    parser.add_argument("--max-spp", type=int,
                        help="--transport: no sample count above this, for either renderer (none by default)")
    parser.add_argument("--transport-scene", nargs="+", choices=["room", "room_point"],
                        help="full transport on the rooms of transport_scenes.py (room_bench.py): the glass-and-mirror "
                             "room against Mitsuba's path, the point-light room against its ptracer; replaces their "
                             "sections and headline rows of --out and leaves the rest of it")
    parser.add_argument("--refresh-mitsuba", action="store_true",
                        help="--transport-scene: render Mitsuba again instead of reading mitsuba_cache.json")
    args = parser.parse_args()
    prisma = translate.find_prisma()
    if args.transport_scene:
        import room_bench

        room_bench.main(args, prisma)
        return
    if args.transport:
        lines, summary = transport(args, prisma)
        write_transport_section(args.out, lines)
        print("\n".join(lines))
        for (mode, target, *cpu), (ratio, p, m, sampler, marked) in summary.items():
            print(f"headline: {mode} relMSE {target:.0e}{' CPU' if cpu else ''}: {ratio:.2f}x (prisma {p:.3g} s, Mitsuba {sampler} {m:.3g} s"
                  f"{', extrapolated' if marked else ''})")
        return
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

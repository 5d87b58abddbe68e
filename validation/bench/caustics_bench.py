#!/usr/bin/env python3
"""Caustics speed: time for prisma (Whitted + light tracer) and Mitsuba 3.9.1's `ptracer`
(`llvm_ad_mono`, the same wavelength, the same scene, its floor the `receiver` BSDF of
validation/mitsuba/caustics.py) to reach relMSE 1e-3 and 1e-4 against the converged reference
(the two committed 50 M-path references of `caustic_sphere_550`), in one run.

relMSE is bench.py's, mean (p − m)²/(m² + 0.01), over the pixels that see the floor directly
(both references non-zero, eroded by one pixel), less the part the reference's own noise explains.
With --spectral, the same race on caustic_sphere_spectral (a D65 spot, a ball of constant index
1.5) with every wavelength at once: prisma's spectral render (8 wavelengths per sample and light
path, unpolarised) against `ptracer` in `llvm_ad_spectral`, relMSE over linear sRGB against that
case's references.

Each renderer renders at doubling effort; the time at a target error is interpolated in log-log
between the two renders that bracket it. prisma's time is its render time (stats JSON, without
loading and writing); Mitsuba's is the wall time of mi.render after a warm-up render of the same
size (JIT compilation excluded). Each effort is rendered 5 times (--repeat N), with a seed per
run: its time is the best of the runs, its error the mean of theirs. The runs are taken in
rounds: each round renders all of prisma's efforts, then all of Mitsuba's, so that both sides
share the load of a shared machine. Each prisma render starts after a pause that lets
Dr.Jit's worker threads go idle (SETTLE_SECONDS, below).
CPU time is reported beside wall time (all threads; prisma's whole process, so with loading and
writing; Mitsuba's process during mi.render): on a machine shared with other work it varies less
than wall time, which is what the target is stated in.

  export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
  validation/.venv/bin/python validation/bench/caustics_bench.py            # ball lens vs ptracer
  validation/.venv/bin/python validation/bench/caustics_bench.py --newton   # and the Newton prism
  validation/.venv/bin/python validation/bench/caustics_bench.py --spectral # and all wavelengths at once
  validation/.venv/bin/python validation/bench/caustics_bench.py --sampler ldsampler  # ptracer's sampler
  validation/.venv/bin/python validation/bench/caustics_bench.py --no-light-guide     # prisma unguided
  validation/.venv/bin/python validation/bench/caustics_bench.py --light-paths 0      # the scene's split
  validation/.venv/bin/python validation/bench/caustics_bench.py --edge-samples 1    # no edge refinement

The prisma binary is $PRISMA, else target/release/prisma of this repository (translate.find_prisma).
Mitsuba's sampler is `independent` (ptracer's usual one, and the references') unless --sampler
names another.
"""

import json
import math
import resource
import pathlib
import subprocess
import sys
import tempfile
import time
import tomllib

import mitsuba as mi
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "validation" / "mitsuba"))
import translate  # noqa: E402

SCENE = ROOT / "validation" / "scenes" / "caustic_sphere.toml"
WAVELENGTH = 550.0
# Each effort is rendered this many times, with a seed each, its best time and mean error kept
# (--repeat N): the machine is shared, and one seed's error is noisy.
REPEATS = int(sys.argv[sys.argv.index("--repeat") + 1]) if "--repeat" in sys.argv else 5
# Pause before each prisma render. After any Dr.Jit work in this process (a Mitsuba render, or
# mi.Bitmap reading the previous render's EXR) one of its worker threads keeps a core busy for
# 0.1-0.2 s (measured: the system 52 %, then 35 % busy in the next two 100 ms windows); a
# prisma render started meanwhile shares the 2 cores with it and took 1.4-1.7x its time (4 spp:
# 0.027-0.045 s against 0.017-0.022 s after a pause). Mitsuba's own renders follow its own work
# and are not paused.
SETTLE_SECONDS = 0.5
# prisma's flags passed through from this script's command line.
PRISMA_FLAGS = [flag for flag in ("--no-light-guide",) if flag in sys.argv]
# Camera samples per pass at edge pixels (src/edges.rs; --edge-samples N): prisma's default is 1
# (off), the races use 4, which leaves one pass a tenth of the camera side's error on the ball.
PRISMA_FLAGS += ["--edge-samples", sys.argv[sys.argv.index("--edge-samples") + 1] if "--edge-samples" in sys.argv else "4"]
# Light paths per pass of prisma's renders in the races (--light-paths N; 0: the scene's, one per
# pixel). prisma splits a render between camera samples and light paths, Mitsuba's ptracer
# traces light paths only. With edge refinement (src/edges.rs) one pass leaves the camera side
# little error (2.1e-4 relMSE on the ball at 1 spp), so the light paths decide and a pass can
# hold many: two per pixel per pass is the best split of the ball lens at 550 nm (best of 3, six
# runs each on 2026-12-04 18:01-18:19 UTC, the time to relMSE 1e-3 / 1e-4: 12,288 paths 7.4-9.1 /
# 33-37 ms (three runs), 16,384 7.3-10.7 / 30.5-34.1 ms, 24,576 7.4-9.3 / 27.6-35.7 ms).
LIGHT_PATHS = int(sys.argv[sys.argv.index("--light-paths") + 1]) if "--light-paths" in sys.argv else 24576


def load(path):
    image = np.array(mi.Bitmap(str(path)), dtype=np.float64)
    return image[..., 0] if image.ndim == 3 else image


def erode(mask):
    out = mask.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            out &= np.roll(np.roll(mask, dy, axis=0), dx, axis=1)
    return out


def rgb(path):
    """The R, G, B channels of a prisma EXR."""
    bitmap = mi.Bitmap(str(path))
    names = [bitmap.struct_()[i].name for i in range(bitmap.channel_count())]
    image = np.array(bitmap, dtype=np.float64)
    return image[..., [names.index(c) for c in ("R", "G", "B")]]


def children_cpu():
    """User + system CPU seconds of the finished child processes so far."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def rel_mse(image, reference, mask):
    return float(np.mean(((image - reference) ** 2 / (reference ** 2 + 1e-2))[mask]))


def describe(effort):
    """An effort as printed: Mitsuba's spp, or prisma's passes with their light paths."""
    if isinstance(effort, tuple):
        spp, paths = effort
        return f"{spp} spp" + (f" x {paths} light paths" if paths else "")
    return f"{effort} spp"


def time_at(points, target):
    """log-log interpolation of (seconds, error) points at `target` error."""
    points = sorted(points)
    for (t0, e0), (t1, e1) in zip(points, points[1:]):
        if e0 >= target >= e1 and e0 > 0 and e1 > 0:
            f = math.log(target / e0) / math.log(e1 / e0)
            return math.exp(math.log(t0) + f * (math.log(t1) - math.log(t0)))
    return None


class Case:
    """One race: a scene, its two Mitsuba references (seeds 1 and 2), and how each side renders it."""

    def __init__(self, name, scene, wavelength, variant):
        self.name, self.scene, self.wavelength, self.variant = name, scene, wavelength, variant
        self.references = [ROOT / "validation" / "references" / f"{name}_seed{s}.exr" for s in (1, 2)]

    def image(self, path):
        """A render as the references hold it: Y (monochromatic) or linear sRGB."""
        return load(path) if self.wavelength is not None else rgb(path)


# The ball lens of the issue: one wavelength, Mitsuba in a mono variant.
MONO = Case("caustic_sphere_550", SCENE, WAVELENGTH, "llvm_ad_mono")
# The same ball of constant index 1.5 (Mitsuba cannot disperse) lit by D65, every wavelength at
# once: prisma as users run it (8 wavelengths per camera sample and light path), Mitsuba in
# llvm_ad_spectral (4 wavelengths per path, as it is built).
SPECTRAL = Case("caustic_sphere_spectral", ROOT / "validation" / "scenes" / "caustic_sphere_spectral.toml", None,
                "llvm_ad_spectral")


def race(case, prisma, out, sampler):
    """Times prisma and Mitsuba's ptracer on `case` at doubling effort: the results dict."""
    mi.set_variant("scalar_rgb")
    first, second = (case.image(p) for p in case.references)
    reference = 0.5 * (first + second)
    positive = (first > 0) & (second > 0)
    mask = erode(positive if positive.ndim == 2 else positive.all(axis=-1))
    noise = float(np.mean(((first - second) ** 2 / 4.0 / (reference ** 2 + 1e-2))[mask]))
    results = {"case": case.name, "reference_noise_relmse": noise, "pixels": int(mask.sum()), "repeats": REPEATS}
    mode = ["--wavelength", str(case.wavelength)] if case.wavelength is not None else []
    results["prisma_light_paths_per_pass"] = LIGHT_PATHS or "the scene's"

    def render_prisma(effort, round_):
        """One prisma render of `effort` = (passes, light paths per pass or None for the scene's),
        with round `round_`'s seed: (render seconds, CPU seconds of the process, relMSE)."""
        spp, paths = effort
        exr, stats = out / f"{case.name}_prisma_{spp}_{paths}.exr", out / f"{case.name}_prisma_{spp}_{paths}.json"
        time.sleep(SETTLE_SECONDS)
        before = children_cpu()
        light_paths = ["--light-paths", str(paths)] if paths else []
        # Unpolarised, as Mitsuba's plain variants and the references.
        subprocess.run([prisma, "render", str(case.scene), *mode, "--spp", str(spp), "--unpolarized", "--seed",
                        str(17 + round_), "-o", str(exr), "--quiet", "--stats", str(stats), *PRISMA_FLAGS, *light_paths], check=True)
        cpu = children_cpu() - before
        seconds = json.loads(stats.read_text())["render_seconds"]
        return seconds, cpu, rel_mse(case.image(exr), reference, mask) - noise

    mi.set_variant(case.variant)
    import caustics
    caustics.register_receiver()
    # Mitsuba's spectral film needs the references' correction of its Y normalisation.
    fix = caustics.y_normalisation_fix()[0] if mi.is_spectral else 1.0
    scene = translate.PrismaScene.load(case.scene, out / f"{case.name}_export", prisma)
    translator = caustics.CausticTranslator(scene, case.wavelength)
    results["mitsuba_sampler"] = sampler
    results["mitsuba_variant"] = case.variant
    mitsuba_scenes = {}

    def render_mitsuba(spp, round_):
        """One Mitsuba render with round `round_`'s seed (the scene loaded and compiled by a
        warm-up render the first time): (wall seconds of mi.render, CPU seconds of this process
        meanwhile, relMSE). The seeds (2, 3, ...) are none of the references' passes' (1000-1063,
        2000-2063)."""
        if spp not in mitsuba_scenes:
            mitsuba_scenes[spp] = mi.load_dict(translator.scene_dict(caustics.PTRACER, spp, sampler=sampler))
            mi.render(mitsuba_scenes[spp], spp=spp, seed=1)  # warm-up: compile
        start, start_cpu = time.perf_counter(), time.process_time()
        image = np.array(mi.render(mitsuba_scenes[spp], spp=spp, seed=2 + round_), dtype=np.float64)
        seconds, cpu = time.perf_counter() - start, time.process_time() - start_cpu
        image = (image[..., 0] if image.ndim == 3 else image) if case.wavelength is not None else image[..., :3]
        return seconds, cpu, rel_mse(fix * image, reference, mask) - noise

    # The first round finds each side's renders (doubling effort until relMSE < 5e-5; Mitsuba from
    # 4 spp, so that its time at relMSE 1e-3 is bracketed too). Every round times all of prisma's
    # renders, then all of Mitsuba's, so that both sides meet the same load of this shared machine
    # within seconds of each other; each round renders with seeds of its own, each effort keeps
    # its best time over the rounds and the mean of their errors: the error of one seed varies
    # by 10-20 % at a few passes (prisma's one-pass renders of the ball, 24 seeds), enough to
    # move a time interpolated between two efforts as much as a real change would.
    # prisma's efforts: one pass with an eighth, a quarter and half of its light paths (the eighth
    # brackets 1e-3 in the spectral race, whose quarter is below it; a pass has at least
    # one camera sample per pixel, so below one pass only the light paths shrink), then doubling
    # passes.
    per_pass = LIGHT_PATHS or None
    below_one_pass = [(1, LIGHT_PATHS // d) for d in (8, 4, 2)] if LIGHT_PATHS >= 8 else []
    sides = {"prisma": (render_prisma, below_one_pass + [(spp, per_pass) for spp in (1, 2, 4, 8, 16, 32, 64, 128, 256)]),
             "mitsuba": (render_mitsuba, [4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096])}
    best = {name: {} for name in sides}
    for round_ in range(REPEATS):
        for name, (render, efforts) in sides.items():
            for effort in efforts:
                if round_ > 0 and effort not in best[name]:
                    break
                seconds, cpu, error = render(effort, round_)
                previous = best[name].get(effort, (math.inf, math.inf, []))
                best[name][effort] = (min(previous[0], seconds), min(previous[1], cpu), previous[2] + [error])
                if round_ == 0:
                    print(f"{case.name}: {name} {describe(effort)}: relMSE {error:.3e}", flush=True)
                    if error < 5e-5:
                        break
    for name in sides:
        best[name] = {effort: (seconds, cpu, float(np.mean(errors)))
                      for effort, (seconds, cpu, errors) in best[name].items()}
        for effort, (seconds, cpu, error) in best[name].items():
            print(f"{case.name}: {name} {describe(effort)}: {seconds:.3f} s ({cpu:.3f} CPU s), relMSE {error:.3e}")
        results[name] = [(seconds, error) for seconds, _, error in best[name].values()]
        results[f"{name}_cpu"] = [(cpu, error) for _, cpu, error in best[name].values()]
    for target in (1e-3, 1e-4):
        tp, tm = time_at(results["prisma"], target), time_at(results["mitsuba"], target)
        cp, cm = time_at(results["prisma_cpu"], target), time_at(results["mitsuba_cpu"], target)
        ratio = f"{tm / tp:.1f}x" if tp and tm else "n/a"
        cpu_ratio = f"{cm / cp:.1f}x" if cp and cm else "n/a"
        print(f"{case.name}: relMSE {target:g}: prisma {tp} s, Mitsuba {tm} s, prisma faster by {ratio}; "
              f"CPU time: prisma {cp} s, Mitsuba {cm} s, {cpu_ratio}")
        results[f"time_at_{target:g}"] = {"prisma_s": tp, "mitsuba_s": tm, "prisma_cpu_s": cp,
                                          "mitsuba_cpu_s": cm}
    return results


def main():
    prisma = translate.find_prisma()
    out = pathlib.Path(tempfile.mkdtemp(prefix="caustics_bench_"))
    sampler = sys.argv[sys.argv.index("--sampler") + 1] if "--sampler" in sys.argv else "independent"
    results = race(MONO, prisma, out, sampler)
    if "--spectral" in sys.argv:
        results["spectral"] = race(SPECTRAL, prisma, out, sampler)
    if "--newton" in sys.argv:
        results["newton"] = newton(prisma, out)
        print(f"newton: relMSE 1e-3 after {results['newton']['time_at_1e-3']} s, "
              f"1e-4 after {results['newton']['time_at_1e-4']} s")
    (out / "results.json").write_text(json.dumps(results, indent=2))
    print(f"results in {out / 'results.json'}")


def newton(prisma, out):
    """scenes/newton_prism.toml at 800×450: time to relMSE 1e-3 and 1e-4 (linear sRGB, bench.py's
    definition) against a long prisma render (16 spp with 4× the scene's light paths per pass,
    64× the 1-spp render's light paths), whose own noise is not subtracted (it adds about 1/64
    of the 1-spp render's relMSE). The efforts: one pass with 1/16, 1/8, 1/4, 1/2 and all of the
    scene's light paths, then 2, 4 and 8 passes (a pass cannot have less than one camera sample
    per pixel, so below one pass only the light paths shrink)."""
    scene = ROOT / "scenes" / "newton_prism.toml"
    with open(scene, "rb") as f:
        light_paths = tomllib.load(f)["render"]["light_paths"]
    long_exr = out / "newton_long.exr"
    subprocess.run([prisma, "render", str(scene), "--spp", "16", "--light-paths", str(4 * light_paths),
                    "--seed", "99", "-o", str(long_exr), "--quiet"], check=True)
    mi.set_variant("scalar_rgb")
    reference = rgb(long_exr)
    points = []
    efforts = [(1, light_paths // d) for d in (16, 8, 4, 2)] + [(spp, light_paths) for spp in (1, 2, 4, 8)]
    for spp, paths in efforts:
        exr, stats = out / f"newton_{spp}_{paths}.exr", out / f"newton_{spp}_{paths}.json"
        time.sleep(SETTLE_SECONDS)
        subprocess.run([prisma, "render", str(scene), "--spp", str(spp), "--light-paths", str(paths),
                        "--seed", "5", "-o", str(exr), "--quiet", "--stats", str(stats)], check=True)
        image = rgb(exr)
        seconds = json.loads(stats.read_text())["render_seconds"]
        error = float(np.mean((image - reference) ** 2 / (reference ** 2 + 1e-2)))
        points.append((seconds, error))
        print(f"newton {spp} spp, {paths} light paths per pass: {seconds:.2f} s, relMSE {error:.3e}", flush=True)
        if error < 5e-5:
            break
    return {"points": points, "time_at_1e-3": time_at(points, 1e-3), "time_at_1e-4": time_at(points, 1e-4)}


if __name__ == "__main__":
    main()

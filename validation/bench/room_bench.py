"""bench.py --transport-scene room | room_point: the full-transport race on the two rooms of
transport_scenes.py, prisma's `path` integrator against Mitsuba 3's `path` (the glass-and-mirror
room, spectral, unpolarised and polarised) or `ptracer` (the point-light room, spectral, on the
pixels where ptracer is complete), time to relMSE 1e-3 and 1e-4 against the converged references
of transport_reference.py --scene, in render time and in CPU time; prisma's 1 → 2 thread scaling
and peak memory. Writes its own section of RESULTS.md (between its markers) and its own row of
the headline table, and leaves the rest of the file alone.

Mitsuba's measured renders are cached (MITSUBA_CACHE, a JSON index, and the images under
MITSUBA_CACHE_DIR), keyed by scene (with its resolution and the scene file's SHA-256), variant,
sampler, sample count, seed and Mitsuba version: a re-run with a new prisma binary renders only
prisma and recomputes every error against the references (--refresh-mitsuba renders Mitsuba
again). A cached row keeps the times, the date and the load of the run that measured it.
"""

import datetime
import hashlib
import json
import os
import pathlib
import resource
import sys
import tempfile
import time

import numpy as np

import bench
import transport_scenes

dr, mi, translate = bench.dr, bench.mi, bench.translate
REPO = bench.REPO
MITSUBA_CACHE = REPO / "validation" / "bench" / "mitsuba_cache.json"
MITSUBA_CACHE_DIR = REPO / "validation" / "bench" / "mitsuba_cache"
# Seed of a Mitsuba render's k-th timed repeat (its image is the first's): none of the
# references' pass seeds (1000 and up).
MITSUBA_SEED = 11
TARGETS = [1e-3, 1e-4]
# (renderer, sampler, sample counts). prisma doubles; Mitsuba runs powers of 4 (ldsampler's and
# multijitter's best counts) to 1024 with each sampler, and the sampler that reaches the last
# common error soonest once more at LONG_SPP. The particle tracer runs `independent` (its usual
# sampler, the references') and `multijitter`.
RENDERERS = {
    # prisma's error on both rooms is still 2-2.6e-4 at 1024 spp: 2048 and 4096 bracket 1e-4
    # instead of extrapolating to it.
    "path": [
        ("prisma", "sobol-owen", [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096]),
        ("llvm", "independent", [4, 16, 64, 256, 1024]),
        ("llvm", "ldsampler", [4, 16, 64, 256, 1024]),
        ("llvm", "multijitter", [4, 16, 64, 256, 1024]),
    ],
    "ptracer": [
        ("prisma", "sobol-owen", [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048, 4096]),
        ("llvm", "independent", [4, 16, 64, 256, 1024]),
        ("llvm", "multijitter", [4, 16, 64, 256, 1024]),
    ],
}
# Mitsuba's long renders, for the sampler fastest at 1024 spp: the particle tracer's relMSE is
# still 1.3e-4 at 4096 spp on the point-light room, so 9216 (96², a count multijitter takes as
# it is) brackets 1e-4 there.
LONG_SPP = {"path": [4096], "ptracer": [4096, 9216]}
SCALING_SPP, SCALING_ROUNDS = 64, 3


def begin_marker(bench_scene):
    return f"<!-- bench.py --transport-scene {bench_scene.key}: begin -->"


def end_marker(bench_scene):
    return f"<!-- bench.py --transport-scene {bench_scene.key}: end -->"


def headline_prefix(bench_scene):
    """The start of this scene's row of the headline table (found and replaced by it)."""
    return f"| full transport, {bench_scene.title} (`--transport-scene {bench_scene.key}`)"


def scene_id(bench_scene):
    digest = hashlib.sha256(bench_scene.scene.read_bytes()).hexdigest()[:12]
    return f"{bench_scene.key} {bench_scene.width}x{bench_scene.height} scene-sha256:{digest}"


def cache_key(bench_scene, variant, sampler, spp, seed):
    return (f"{scene_id(bench_scene)} | {variant} | {sampler} | spp {spp} | seed {seed} | "
            f"mitsuba {mi.__version__}")


def load_cache():
    if MITSUBA_CACHE.exists():
        return json.loads(MITSUBA_CACHE.read_text())
    return {"about": "Mitsuba's measured renders of bench.py --transport-scene (validation/bench/room_bench.py): "
                     "render seconds (best of the repeats, JIT compilation excluded), CPU seconds of the render "
                     "calls (all threads), and the first repeat's image (linear sRGB, transport_scenes.to_rgb) "
                     "under mitsuba_cache/", "entries": {}}


def save_cache(cache):
    cache["entries"] = dict(sorted(cache["entries"].items()))
    MITSUBA_CACHE.write_text(json.dumps(cache, indent=1) + "\n")


def mitsuba_renders(bench_scene, variant, sampler, levels, prisma, export_dir, cache, refresh):
    """[(spp, render seconds, CPU seconds, image, cached)] of Mitsuba at each sample count, from
    the cache where it holds them; the others rendered (the scene loaded once and compiled by a
    4-spp render, not timed), timed as bench.mitsuba_transport_renders does, and cached."""
    out, scene = [], None
    for spp in levels:
        key = cache_key(bench_scene, variant, sampler, spp, MITSUBA_SEED)
        entry = cache["entries"].get(key)
        if entry is None or refresh:
            if scene is None:
                mi.set_variant(variant)
                prisma_scene = transport_scenes.load(bench_scene, export_dir, prisma)
                scene = mi.load_dict(transport_scenes.mitsuba_description(bench_scene, prisma_scene, 4, sampler))
                mi.render(scene, spp=4, seed=10)
                film = scene.sensors()[0].film()
            timings, cpu, first = [], [], None
            repeats = bench.timing_repeats(spp)
            for k in range(repeats):
                start, start_cpu = time.perf_counter(), time.process_time()
                image = mi.render(scene, spp=spp, seed=MITSUBA_SEED + k)
                dr.eval(image)
                dr.sync_thread()
                timings.append(time.perf_counter() - start)
                cpu.append(time.process_time() - start_cpu)
                if first is None:
                    first = np.array(image, dtype=np.float64)
            # The sample count the sampler really took (multijitter rounds up to a product of two
            # near-equal factors): the row shows it, the cache keeps it under the count asked for.
            actual = int(scene.sensors()[0].sampler().sample_count())
            channels = [film.bitmap().struct_()[i].name for i in range(first.shape[-1])]
            rgb = transport_scenes.to_rgb(bench_scene, first, channels)
            name = f"{bench_scene.key}_{variant}_{sampler}_{spp}spp_seed{MITSUBA_SEED}.exr"
            MITSUBA_CACHE_DIR.mkdir(parents=True, exist_ok=True)
            translate.write_exr(MITSUBA_CACHE_DIR / name, rgb, ["R", "G", "B"])
            entry = {"spp": actual, "render_seconds": min(timings), "cpu_seconds": min(cpu), "repeats": repeats,
                     "repeat_seeds": [MITSUBA_SEED + k for k in range(repeats)],
                     "image": f"{MITSUBA_CACHE_DIR.name}/{name}", "image_seed": MITSUBA_SEED,
                     "measured": bench.load_text(), "drjit": dr.__version__}
            cache["entries"][key] = entry
            save_cache(cache)
            cached = False
        else:
            cached = True
        image = bench.read_exr(MITSUBA_CACHE.parent / entry["image"], ["R", "G", "B"])
        out.append((entry.get("spp", spp), entry["render_seconds"], entry["cpu_seconds"], image, cached))
        print(f"{bench_scene.key} {variant} {sampler} spp {spp}: {entry['render_seconds']:.3f} s, CPU "
              f"{entry['cpu_seconds']:.3f} s{' (cached)' if cached else ''}", flush=True)
    return out


def reference(bench_scene, mode):
    """(reference, mask, its own noise over the mask, description) of `bench_scene` in `mode`."""
    case = bench_scene.references[mode]
    directory = transport_scenes.REFERENCES
    while not (directory / f"{case}.json").exists():
        print(f"waiting for the reference {directory / case}.json (transport_reference.py --scene "
              f"{bench_scene.key})", flush=True)
        time.sleep(30)
    provenance = json.loads((directory / f"{case}.json").read_text())
    halves = [bench.read_exr(directory / render["file"], ["R", "G", "B"]) for render in provenance["renders"]]
    mask = transport_scenes.mask(bench_scene, halves)
    noise = bench.reference_noise(halves[0][mask], halves[1][mask])
    text = (f"`validation/bench/references/{case}` (Mitsuba {provenance['mitsuba_version']}, "
            f"`{provenance['variant']}`, `{provenance['integrator']['type']}`, `{provenance['sampler']}` sampler, two "
            f"halves of {provenance['renders'][0]['spp']} spp at seeds "
            f"{', '.join(str(r['seed']) for r in provenance['renders'])}, {bench_scene.width}×{bench_scene.height}; "
            f"`{provenance['command']}`)")
    return 0.5 * (halves[0] + halves[1]), mask, noise, text


def prisma_process(prisma, bench_scene, spp, threads, mode_flag, out_dir):
    """One `prisma render` under /usr/bin/time -v (bench.prisma_process with this scene's
    arguments): (render seconds, process wall seconds, peak resident memory in MiB, stats)."""
    import re
    import subprocess

    out, stats = out_dir / f"scaling_{threads}{mode_flag}.exr", out_dir / f"scaling_{threads}{mode_flag}.json"
    time.sleep(0.5)
    start = time.perf_counter()
    run = subprocess.run(["/usr/bin/time", "-v", prisma, "render", str(bench_scene.scene), *bench_scene.prisma_args(),
                          "--spp", str(spp), "--threads", str(threads), "-o", str(out), "--quiet", "--seed", "7",
                          "--stats", str(stats), mode_flag], check=True, capture_output=True, text=True)
    wall = time.perf_counter() - start
    peak = re.search(r"Maximum resident set size \(kbytes\): (\d+)", run.stderr)
    return (json.loads(stats.read_text())["render_seconds"], wall,
            int(peak.group(1)) / 1024.0 if peak else float("nan"), json.loads(stats.read_text()))


def race(args, prisma, bench_scene):
    """The race on `bench_scene`: (its RESULTS.md section's lines, its headline row)."""
    cache = load_cache()
    started = bench.load_text()
    modes = [m for m in args.modes if m in bench_scene.references]
    cap = 16 if args.quick else (args.max_spp or float("inf"))
    capped = lambda levels: [spp for spp in levels if spp <= cap]  # noqa: E731
    renderers = [r for r in RENDERERS[bench_scene.mitsuba]
                 if r[0] == "prisma" or args.samplers is None or r[1] in args.samplers]
    results, references = {}, {}
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        for mode in modes:
            flag = bench.MODES[mode][0]
            variant = transport_scenes.VARIANTS[mode]
            # (renderer, sampler) -> [(spp, render s, process wall s or None, CPU s, image, stats, cached)];
            # the errors are computed once the reference is there (it may still be rendering).
            result = {}
            for renderer, sampler, levels in renderers:
                if renderer == "prisma":
                    for spp in capped(levels):
                        seconds, wall, image, figures = bench.prisma_render(
                            prisma, bench_scene.scene, spp, tmp, flag, bench_scene.prisma_args(), with_stats=True)
                        result.setdefault(("prisma", sampler), []).append(
                            (spp, seconds, wall, figures["cpu_seconds"], image, figures, False))
                        print(f"{bench_scene.key} {mode} prisma spp {spp}: {seconds:.3f} s, CPU "
                              f"{figures['cpu_seconds']:.2f} s", flush=True)
                else:
                    for spp, seconds, cpu, image, cached in mitsuba_renders(
                            bench_scene, variant, sampler, capped(levels), prisma, tmp / "export", cache,
                            args.refresh_mitsuba):
                        result.setdefault((variant, sampler), []).append((spp, seconds, None, cpu, image, None, cached))
            ref, mask, floor, ref_text = reference(bench_scene, mode)
            references[mode] = (floor, ref_text, int(mask.sum()), mask.size)
            error = lambda image: bench.rel_mse(image[mask], ref[mask]) - floor  # noqa: E731
            result = {key: [(*p[:4], error(p[4]), *p[5:]) for p in points] for key, points in result.items()}
            for key, points in result.items():
                for p in points:
                    print(f"{bench_scene.key} {mode} {key[0]} {key[1]} spp {p[0]}: relMSE {p[4]:.3e}", flush=True)
            # The sampler that reaches the last common error soonest (CPU time) goes on to LONG_SPP.
            keys = [k for k in result if k[0] == variant]
            long_levels = capped(LONG_SPP[bench_scene.mitsuba])
            if keys and long_levels:
                last = max(min(p[4] for p in result[k]) for k in keys)
                fastest = min(keys, key=lambda k: bench.time_to_error([(p[3], p[4]) for p in result[k]], last)[0])
                for spp, seconds, cpu, image, cached in mitsuba_renders(
                        bench_scene, variant, fastest[1], long_levels, prisma, tmp / "export", cache,
                        args.refresh_mitsuba):
                    result[fastest].append((spp, seconds, None, cpu, error(image), None, cached))
                    print(f"{bench_scene.key} {mode} {variant} {fastest[1]} spp {spp}: relMSE "
                          f"{result[fastest][-1][4]:.3e}", flush=True)
            results[mode] = result
        scaling_spp = 16 if args.quick else SCALING_SPP
        scaling = {}
        for mode in modes:
            for _ in range(1 if args.quick else SCALING_ROUNDS):
                for threads in (1, 2):
                    run = prisma_process(prisma, bench_scene, scaling_spp, threads, bench.MODES[mode][0], tmp)
                    best = scaling.get((mode, threads))
                    scaling[mode, threads] = run if best is None or run[0] < best[0] else best
                    print(f"{bench_scene.key} {mode} prisma {threads} thread(s) {scaling_spp} spp: {run[0]:.3f} s, "
                          f"peak {run[2]:.1f} MiB", flush=True)
    finished = bench.load_text()
    return write_up(args, prisma, bench_scene, results, references, scaling, scaling_spp, started, finished)


def write_up(args, prisma, bench_scene, results, references, scaling, scaling_spp, started, finished):
    command = (f"validation/.venv/bin/python validation/bench/bench.py{' ' if sys.argv[1:] else ''}"
               f"{' '.join(sys.argv[1:])}")
    pixels = bench_scene.width * bench_scene.height
    lines = [begin_marker(bench_scene),
             f"## Full transport: {bench_scene.title}, prisma `path` against Mitsuba `{bench_scene.mitsuba}` "
             f"(`{bench_scene.scene.relative_to(REPO)}`, {bench_scene.width}×{bench_scene.height})", "",
             f"Run: {started} → {finished}. Machine: {bench.machine()}. Mitsuba {mi.__version__}; prisma `{prisma}` "
             f"(commit {bench.prisma_commit()}). Command: `{command}` (this section written by it; "
             f"`validation/bench/room_bench.py`, the scenes in `validation/bench/transport_scenes.py`).", ""]
    if bench_scene.mitsuba == "path":
        lines += [
            "The validation case's room (`stokes_room_path`: a glass sphere of constant index 1.5 and a mirror sphere, "
            "a quad light and the grey sky through the open top) rendered with every wavelength instead of its case's "
            f"550 nm: prisma `--integrator path {' '.join(bench_scene.tuning)}` (max_depth 64 bounces; the light "
            "tracer on for the quad light's caustics and the light they throw onward, its light paths per pass as "
            "given: transport_scenes.py says why) against Mitsuba's `path` (max_depth 65 "
            "vertices, its default Russian roulette), both through prisma's colour pipeline (Mitsuba's specfilm with "
            "prisma's CIE table, then prisma's matrix). The glass does not disperse, so Mitsuba's one-index dielectric "
            "renders the same scene; the mirror is Mitsuba's perfect conductor (translate.py). At 75×50, a quarter of "
            "the case's pixels (same camera), so that the references converge in the time there was. Every pixel "
            "counts.",
            ""]
    else:
        lines += [
            "The validation case's closed room with a floating glass sphere and a D65 point light "
            f"(`transport_room_point`): prisma `--integrator path {' '.join(bench_scene.tuning)}` with its light "
            "tracer (the scene's `caustics = true`; its light paths per pass as given, the scene's default being one "
            "per pixel: transport_scenes.py says why) against Mitsuba's particle tracer `ptracer` (max_depth "
            "257 vertices, default Russian roulette, twosided diffuse walls), Mitsuba through its hdrfilm times its "
            "luminance normalisation fix, as the validation case. Compared only on the pixels whose camera ray first "
            "meets a diffuse surface, where ptracer holds every path of light: both halves of the reference positive "
            "(ptracer leaves the glass black), eroded by one pixel. At 75×50, a quarter of the case's pixels (same "
            "camera). Unpolarised only (the issue asks for at least spectral; Mitsuba's `stokes` does not wrap "
            "ptracer).", ""]
    lines += [
        "relMSE = mean (x − r)²/(r² + 0.01) over the R, G, B values of the compared pixels, minus the reference's "
        "own noise (from the difference of its two halves). Render time excludes loading and writing for both (and "
        "Mitsuba's JIT compilation, done once per sampler by a 4-spp render); the best of three renders up to 256 spp, "
        "of one above (prisma renders seed 7 each time, Mitsuba seeds 11, 12, 13: the error is the first's). CPU time: "
        "prisma's whole process (loading and writing included), Mitsuba's render calls, all threads; the machine is "
        "shared, so CPU time is the measure to read. Mitsuba runs each sampler to 1024 spp and the one fastest there "
        "on to the longer counts of LONG_SPP (room_bench.py). Mitsuba's rows marked † come from "
        "`validation/bench/mitsuba_cache.json` (measured in an earlier run of this command, same scene, variant, "
        "sampler, spp, seed and Mitsuba version; its date and load are in the cache); their errors are recomputed "
        "against the reference.", ""]
    headline, ratios = [], []
    for mode, result in results.items():
        flag = bench.MODES[mode][0]
        variant = transport_scenes.VARIANTS[mode]
        floor, ref_text, compared, total = references[mode]
        lines += [f"### {mode}: prisma `{flag}` against `{variant}`", "",
                  f"Reference: {ref_text}; its own noise {floor:.2e}; {compared:,} of {total:,} pixels compared.", "",
                  "| renderer | sampler | spp | render time (s) | process wall (s) | CPU time (s) | samples/s | "
                  "rays/sample | relMSE | relMSE × spp |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        for (renderer, sampler), points in result.items():
            for spp, seconds, wall, cpu, error, figures, cached in sorted(points, key=lambda p: p[0]):
                rays = f"{figures['rays'] / figures['samples']:.2f}" if figures else "–"
                lines.append(f"| {renderer} | {sampler}{' †' if cached else ''} | {spp} | {seconds:.3f} | "
                             f"{f'{wall:.2f}' if wall is not None else '–'} | {cpu:.2f} | "
                             f"{pixels * spp / seconds:,.0f} | {rays} | {error:.3e} | {error * spp:.3g} |")
        for label, column in (("render time", 1), ("CPU time", 3)):
            lines += ["", f"Time to equal error, {label} (seconds, interpolated log-log between the measured points; "
                      "* extrapolated beyond them):", "",
                      "| renderer | sampler | " + " | ".join(f"relMSE {t:.0e}" for t in TARGETS) + " |",
                      "|---|---|" + "---|" * len(TARGETS)]
            times = {}
            for key, points in result.items():
                cells = []
                for target in TARGETS:
                    t = bench.time_to_error([(p[column], p[4]) for p in points], target)
                    times[key, target] = t
                    cells.append(f"{t[0]:.3g}{'*' if t[1] else ''}")
                lines.append(f"| {key[0]} | {key[1]} | " + " | ".join(cells) + " |")
            lines.append("")
            prisma_key = next(k for k in result if k[0] == "prisma")
            for target in TARGETS:
                mitsuba = {k: times[k, target] for k in result if k[0] == variant and np.isfinite(times[k, target][0])}
                mine = times[prisma_key, target]
                if not mitsuba or not np.isfinite(mine[0]):
                    lines.append(f"- relMSE {target:.0e}, {label}: not reached by both.")
                    continue
                best = min(mitsuba, key=lambda k: mitsuba[k][0])
                ratio = mitsuba[best][0] / mine[0]
                marked = mitsuba[best][1] or mine[1]
                lines.append(f"- relMSE {target:.0e}, {label}: prisma {mine[0]:.3g} s, Mitsuba "
                             f"{mitsuba[best][0]:.3g} s (`{best[1]}`){' (extrapolated)' if marked else ''}: "
                             f"prisma is **{ratio:.2f}×** as fast as Mitsuba's fastest sampler.")
                if label == "CPU time":
                    ratios.append(ratio)
                    headline.append(f"{mode} {target:.0e}: **{ratio:.2f}×**{'*' if marked else ''} "
                                    f"({mine[0]:.3g} vs {mitsuba[best][0]:.3g} s, `{best[1]}`)")
        # Where the ratio comes from: CPU time per sample and error per sample at the largest
        # count both rendered (the errors there are furthest above the reference's noise).
        prisma_key = next(k for k in result if k[0] == "prisma")
        mitsuba_keys = [k for k in result if k[0] == variant]
        if mitsuba_keys:
            common = max(p[0] for p in result[prisma_key])
            long_key = max(mitsuba_keys, key=lambda k: max(p[0] for p in result[k]))
            m_spp = min(max(p[0] for p in result[long_key]), common)
            p_point = next(p for p in result[prisma_key] if p[0] == m_spp)
            m_point = next((p for p in result[long_key] if p[0] == m_spp), None)
            if m_point is not None:
                per_sample = (m_point[3] / m_spp) / (p_point[3] / m_spp)
                per_error = m_point[4] / p_point[4]
                lines += [f"Decomposed at {m_spp} spp (Mitsuba `{long_key[1]}`), in CPU time: a sample costs Mitsuba "
                          f"{per_sample:.2f}× prisma's time and leaves {per_error:.2f}× prisma's error; their product, "
                          f"{per_sample * per_error:.2f}, is the ratio at equal error where both errors fall as 1/spp.",
                          ""]
        lines.append("")
    lines += [f"### prisma's thread scaling and peak memory ({scaling_spp} spp, best of "
              f"{1 if args.quick else SCALING_ROUNDS} alternating rounds, `/usr/bin/time -v`)", "",
              "| mode | threads | render time (s) | process wall (s) | speed-up | peak resident memory (MiB) |",
              "|---|---|---|---|---|---|"]
    scaling_text = []
    for mode in results:
        one = scaling[mode, 1][0]
        for threads in (1, 2):
            seconds, wall, peak, _ = scaling[mode, threads]
            lines.append(f"| {mode} | {threads} | {seconds:.3f} | {wall:.2f} | {one / seconds:.2f}× | {peak:.1f} |")
        scaling_text.append(f"{mode} 1 → 2 threads {one / scaling[mode, 2][0]:.2f}×, peak RSS "
                            f"{max(scaling[mode, t][2] for t in (1, 2)):.0f} MiB")
    lines += ["", f"(This Python process's peak resident memory, Mitsuba's renders included: "
              f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0:,.0f} MiB.)", "", end_marker(bench_scene)]
    extrapolated = any(h.split("**")[-1].startswith("*") for h in headline)
    row = (f"{headline_prefix(bench_scene)}, {bench_scene.width}×{bench_scene.height}, prisma `path` vs Mitsuba 3.9.1 "
           f"`{bench_scene.mitsuba}`, time to equal relMSE | CPU time, against Mitsuba's fastest sampler: "
           f"{'; '.join(headline)}{' (* extrapolated)' if extrapolated else ''}; "
           f"the issue's 3× "
           f"{'holds on each' if ratios and min(ratios) >= 3 else 'does **not** hold on each'}; "
           f"{'; '.join(scaling_text)} | `{command}` (see its section) | {started} → {finished} |")
    return lines, row


def write(out, bench_scene, lines, row):
    """Replaces this scene's section (between its markers) and headline row of `out`, or adds
    them: the section after the last `bench.py` section, the row at the end of the headline table."""
    text = out.read_text() if out.exists() else "# prisma vs Mitsuba 3: benchmark results\n"

    def after_the_last_section(text, block):
        anchor = text.rfind("end -->")
        if anchor < 0:
            return text.rstrip("\n") + "\n\n" + block + "\n"
        anchor = text.index("\n", anchor) + 1
        return text[:anchor] + "\n" + block + "\n" + text[anchor:]

    text = bench.replace_section(text, begin_marker(bench_scene), end_marker(bench_scene), "\n".join(lines),
                                 after_the_last_section)
    rows = text.split("\n")
    existing = [i for i, line in enumerate(rows) if line.startswith(headline_prefix(bench_scene))]
    if existing:
        rows[existing[0]] = row
    else:
        start = next((i for i, line in enumerate(rows) if line.startswith("## Headline numbers")), None)
        if start is None:
            rows[1:1] = ["", "## Headline numbers", "", "| what | result | command | date, load |", "|---|---|---|---|",
                         row]
        else:
            i = start + 1
            while i < len(rows) and not rows[i].startswith("|"):
                i += 1
            while i < len(rows) and rows[i].startswith("|"):
                i += 1
            rows.insert(i, row)
    out.write_text("\n".join(rows))


def main(args, prisma):
    for key in args.transport_scene:
        bench_scene = transport_scenes.SCENES[key]
        lines, row = race(args, prisma, bench_scene)
        write(args.out, bench_scene, lines, row)
        print("\n".join(lines))
        print(row)

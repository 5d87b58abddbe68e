#!/usr/bin/env python3
"""More samples for the converged reference of bench.py --transport (TP6's quad light in full
transport, `tp6_quad_path_prisma_cmf`).

The committed references (validation/references/tp6_quad_path_prisma_cmf_seed1.exr, _seed2.exr,
4096 spp each) leave a reference noise of 5.6e-5 relMSE in their mean: half of the 1e-4 that the
race measures. This script renders two more Mitsuba references of the same case with exactly
render_references.py's settings (llvm_ad_spectral, `path` with max_depth 65 and Mitsuba's default
Russian roulette, the graded planes, specfilm with prisma's CIE table, then prisma's matrix;
sampler `independent`), at seeds 3 and 4 (pass k of seed s: mi.render(seed = s·1000 + k), none
of them a seed of the committed references or of bench.py's own Mitsuba renders, 11 and up), into
validation/bench/references/tp6_quad_path_prisma_cmf_seed3.exr and _seed4.exr, with the
per-pixel variance (_var.exr) and provenance (tp6_quad_path_prisma_cmf.json).

bench.py --transport weighs each committed reference with the new one of the same parity by
their sample counts (seed 1 with seed 3, seed 2 with seed 4): two independent halves, whose
difference gives the reference's own noise as for the other cases.

  export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
  validation/.venv/bin/python validation/bench/transport_reference.py             # 8,192 spp per seed
  validation/.venv/bin/python validation/bench/transport_reference.py --passes 4  # a quick check, into /tmp

--scene room | room_point: the converged references of bench.py --transport-scene (the rooms of
validation/bench/transport_scenes.py, at their benchmark resolution), into
validation/bench/references/<case>_seed1.exr and _seed2.exr (independent halves, seeds 1 and 2:
pass k of seed s at mi.render(seed = s·1000 + k), none of bench.py's Mitsuba seeds, 10 and up),
with their variance and provenance (<case>.json), one case per mode of the scene (--modes):
  room        Mitsuba `path` (translate.full_transport_integrator), `multijitter` sampler (256 spp
              per pass, a perfect square; unbiased in every pass, passes independent), specfilm
              with prisma's CIE table then prisma's matrix; llvm_ad_spectral and
              llvm_ad_spectral_polarized
  room_point  Mitsuba `ptracer` (caustics.full_transport_ptracer), `independent` sampler, 256 spp
              per pass (caustics.py: passes above 512 spp lose float32 precision in a focus),
              hdrfilm times the luminance normalisation fix; llvm_ad_spectral
  ... transport_reference.py --scene room --passes 64   # 2 × 16,384 spp per mode
"""

import argparse
import datetime
import json
import os
import pathlib
import platform
import sys
import tempfile
import time

import drjit as dr
import mitsuba as mi
import numpy as np

REPO = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "validation" / "mitsuba"))
sys.path.insert(0, str(REPO / "validation" / "bench"))
import translate  # noqa: E402
import transport_scenes  # noqa: E402

CASE = "tp6_quad_path_prisma_cmf"
SCENE = REPO / "validation" / "scenes" / "tp6_quad_path.toml"
SEEDS = (3, 4)
SPP_PER_PASS = 128


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--passes", type=int, default=64, help=f"passes of {SPP_PER_PASS} spp per seed")
    parser.add_argument("--out", type=pathlib.Path, help="output directory (default: validation/bench/references, "
                        "or a temporary one with fewer than 64 passes)")
    parser.add_argument("--scene", choices=["tp6_quad", *transport_scenes.SCENES], default="tp6_quad",
                        help="which benchmark's reference (default: TP6's quad light)")
    parser.add_argument("--modes", nargs="+", choices=list(transport_scenes.VARIANTS),
                        help="--scene room / room_point: only these modes (default: the scene's all)")
    args = parser.parse_args()
    if args.scene != "tp6_quad":
        return room_references(transport_scenes.SCENES[args.scene], args)
    out_dir = args.out or (REPO / "validation" / "bench" / "references" if args.passes >= 64
                           else pathlib.Path(tempfile.mkdtemp(prefix="transport_reference_")))
    out_dir.mkdir(parents=True, exist_ok=True)
    prisma = translate.find_prisma()
    mi.set_variant("llvm_ad_spectral")
    export_dir = pathlib.Path(tempfile.mkdtemp(prefix="prisma_export_transport_"))
    scene = translate.PrismaScene.load(SCENE, export_dir, prisma)
    if scene.integrator != "path":
        raise SystemExit(f"{SCENE}: the scene's integrator is {scene.integrator!r}, the case is for \"path\"")
    integrator = translate.full_transport_integrator(scene.max_depth)
    translator = translate.Translator(scene, None, False, "graded")
    mitsuba_scene = mi.load_dict(translator.scene_dict(integrator, SPP_PER_PASS, film="prisma_xyz"))
    renders = []
    for seed in SEEDS:
        start, cpu_start = time.perf_counter(), time.process_time()
        mean, variance, channels = translate.render(mitsuba_scene, SPP_PER_PASS, seed, args.passes,
                                                    translate.prisma_rgb)
        seconds, cpu_seconds = time.perf_counter() - start, time.process_time() - cpu_start
        keep = [i for i, c in enumerate(channels) if not c.startswith("XYZ.")]
        mean, variance, channels = mean[..., keep], variance[..., keep], [channels[i] for i in keep]
        path, var_path = out_dir / f"{CASE}_seed{seed}.exr", out_dir / f"{CASE}_seed{seed}_var.exr"
        translate.write_exr(path, mean, channels)
        translate.write_exr(var_path, variance, channels)
        renders.append({"file": path.name, "variance_file": var_path.name, "seed": seed,
                        "spp": SPP_PER_PASS * args.passes, "wall_time_s": round(seconds, 2),
                        "cpu_time_s": round(cpu_seconds, 2),
                        "channel_means": {c: float(mean[..., i].mean()) for i, c in enumerate(channels)}})
        print(f"{CASE} seed {seed}: {SPP_PER_PASS * args.passes} spp in {seconds:.1f} s (CPU {cpu_seconds:.1f} s), "
              f"means {renders[-1]['channel_means']}", flush=True)
    provenance = {
        "case": CASE,
        "purpose": "extra samples for bench.py --transport's converged reference (validation/bench/RESULTS.md)",
        "same_as": "validation/references/tp6_quad_path_prisma_cmf.json except the seeds and sample counts",
        "scene": str(SCENE.relative_to(REPO)),
        "mitsuba_version": mi.__version__,
        "drjit_version": dr.__version__,
        "variant": "llvm_ad_spectral",
        "integrator": integrator,
        "sampler": "independent",
        "spp_per_pass": SPP_PER_PASS,
        "passes": args.passes,
        "pass_seed_rule": f"pass k of seed s uses mi.render(seed = s*{translate.PASS_SEED_STRIDE} + k)",
        "film": "specfilm with prisma's CIE table, then prisma's matrix (translate.prisma_rgb)",
        "plane_half_size": "graded",
        "renders": renders,
        "prisma_binary": str(prisma),
        "command": " ".join([pathlib.Path(sys.executable).name, os.path.relpath(sys.argv[0], REPO), *sys.argv[1:]]),
        "platform": platform.platform(),
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
    }
    (out_dir / f"{CASE}.json").write_text(json.dumps(provenance, indent=2) + "\n")
    print(f"written to {out_dir}")


ROOM_SEEDS = (1, 2)
ROOM_SPP_PER_PASS = 256


def room_references(bench, args):
    """The converged references of one room of transport_scenes (see the module's docstring)."""
    out_dir = args.out or (REPO / "validation" / "bench" / "references" if args.passes >= 16
                           else pathlib.Path(tempfile.mkdtemp(prefix="transport_reference_")))
    out_dir.mkdir(parents=True, exist_ok=True)
    prisma = translate.find_prisma()
    sampler = "multijitter" if bench.mitsuba == "path" else "independent"
    for mode in args.modes or list(bench.references):
        case, variant = bench.references[mode], transport_scenes.VARIANTS[mode]
        mi.set_variant(variant)
        export_dir = pathlib.Path(tempfile.mkdtemp(prefix=f"prisma_export_{bench.key}_"))
        scene = transport_scenes.load(bench, export_dir, prisma)
        mitsuba_scene = mi.load_dict(transport_scenes.mitsuba_description(bench, scene, ROOM_SPP_PER_PASS, sampler))
        renders = []
        for seed in ROOM_SEEDS:
            start, cpu_start = time.perf_counter(), time.process_time()
            mean, variance, channels = translate.render(
                mitsuba_scene, ROOM_SPP_PER_PASS, seed, args.passes,
                lambda image, names: (transport_scenes.to_rgb(bench, image, names), ["R", "G", "B"]))
            seconds, cpu_seconds = time.perf_counter() - start, time.process_time() - cpu_start
            path, var_path = out_dir / f"{case}_seed{seed}.exr", out_dir / f"{case}_seed{seed}_var.exr"
            translate.write_exr(path, mean, channels)
            translate.write_exr(var_path, variance, channels)
            renders.append({"file": path.name, "variance_file": var_path.name, "seed": seed,
                            "spp": ROOM_SPP_PER_PASS * args.passes, "wall_time_s": round(seconds, 2),
                            "cpu_time_s": round(cpu_seconds, 2),
                            "channel_means": {c: float(mean[..., i].mean()) for i, c in enumerate(channels)}})
            print(f"{case} seed {seed}: {ROOM_SPP_PER_PASS * args.passes} spp in {seconds:.1f} s "
                  f"(CPU {cpu_seconds:.1f} s), means {renders[-1]['channel_means']}", flush=True)
        provenance = {
            "case": case,
            "purpose": f"converged reference of bench.py --transport-scene {bench.key}, {mode} "
                       "(validation/bench/RESULTS.md)",
            "scene": str(bench.scene.relative_to(REPO)),
            "resolution": [bench.width, bench.height],
            "resolution_note": "the benchmark's, a quarter of the scene file's pixels (same camera)",
            "mitsuba_version": mi.__version__,
            "drjit_version": dr.__version__,
            "variant": variant,
            "integrator": transport_scenes.mitsuba_integrator(bench, scene),
            "sampler": sampler,
            "spp_per_pass": ROOM_SPP_PER_PASS,
            "passes": args.passes,
            "pass_seed_rule": f"pass k of seed s uses mi.render(seed = s*{translate.PASS_SEED_STRIDE} + k)",
            "film": ("specfilm with prisma's CIE table, then prisma's matrix (translate.prisma_rgb)"
                     if bench.mitsuba == "path" else
                     "hdrfilm (linear sRGB) times Mitsuba's luminance normalisation fix "
                     "(caustics.y_normalisation_fix)"),
            "plane_half_size": "graded",
            "variance_files": "per pixel and channel, the variance of the seed's mean over its passes",
            "renders": renders,
            "prisma_binary": str(prisma),
            "command": " ".join([pathlib.Path(sys.executable).name, os.path.relpath(sys.argv[0], REPO),
                                 *sys.argv[1:]]),
            "platform": platform.platform(),
            "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        }
        (out_dir / f"{case}.json").write_text(json.dumps(provenance, indent=2) + "\n")
        print(f"written to {out_dir}")


if __name__ == "__main__":
    main()

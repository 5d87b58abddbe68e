#!/usr/bin/env python3
"""Renders the Mitsuba 3 reference images of validation/cases.toml, with provenance.

For every case: two references at independent seeds (references/<case>_seed1.exr, _seed2.exr,
float32, the channels named in cases.toml), the standard error of each per pixel estimated from
its independent passes (references/<case>_seed<s>_stderr.exr), and references/<case>.json:
versions, variant, integrator and parameters, samples and seeds, resolution, wall time of each
render, the command line, the date, the prisma commit whose `prisma export` fed the translation,
and why prisma and Mitsuba compute the same quantity in this case.

The Mitsuba side of each case (variant, integrator, samples) is in MITSUBA_SETTINGS below;
cases.toml holds what the Rust side reads. Spectral references are divided by Mitsuba's
luminance normalisation error (see `y_normalisation_fix` and validation/README.md).

Run from the repository root after validation/setup.sh and `cargo build --release`:
  export DRJIT_LIBLLVM_PATH=...          # printed by validation/setup.sh
  validation/.venv/bin/python validation/mitsuba/render_references.py            # all cases
  validation/.venv/bin/python validation/mitsuba/render_references.py tp6_quad   # one case
  ... --quick    (1/16 of the samples, into /tmp, for trying changes)
"""

import argparse
import datetime
import hashlib
import json
import os
import pathlib
import platform
import shlex
import subprocess
import sys
import tempfile
import time
import tomllib

import drjit as dr
import mitsuba as mi
import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import translate  # noqa: E402

VALIDATION = pathlib.Path(__file__).resolve().parents[1]
SEEDS = (1, 2)

# The Mitsuba side of each case. spp = spp_per_pass × passes per reference; passes bound the
# memory of a wavefront and give the per-pixel standard error. Sample counts are set so that each
# render takes at most about three minutes on two cores.
MITSUBA_SETTINGS = {
    "specular_spheres": dict(variant="llvm_ad_spectral", integrator="path", spp_per_pass=1024, passes=64),
    "specular_prism": dict(variant="llvm_ad_spectral", integrator="path", spp_per_pass=1024, passes=64),
    "tp6_point": dict(variant="llvm_ad_spectral", integrator="whitted", spp_per_pass=1024, passes=64),
    "tp6_quad": dict(variant="llvm_ad_spectral", integrator="whitted", spp_per_pass=1024, passes=64),
    "dispersion_450": dict(variant="llvm_ad_mono", integrator="path", spp_per_pass=1024, passes=64),
    "dispersion_550": dict(variant="llvm_ad_mono", integrator="path", spp_per_pass=1024, passes=64),
    "dispersion_650": dict(variant="llvm_ad_mono", integrator="path", spp_per_pass=1024, passes=64),
    "color_emitters": dict(variant="llvm_ad_spectral", integrator="path", spp_per_pass=2048, passes=48),
    "color_upsampling": dict(variant="llvm_ad_spectral", integrator="path", spp_per_pass=2048, passes=48,
                             mitsuba_rgb_emitters=True),
}


def y_normalisation_fix():
    """The factor that makes Mitsuba's spectral film follow Y = ∫L·ȳ / ∫ȳ.

    Mitsuba 3.9.1 scales its colour-matching functions by MI_CIE_Y_NORMALIZATION = 1/106.7503
    ("so that a unit-valued spectrum integrates to a luminance of 1"), but the tables it
    interpolates (5 nm, 360–830 nm) integrate to ∫ȳ = 106.8570: an equal-energy radiance of 1
    renders to Y = 1.0010. Multiplying a spectral render by 1/(MI_CIE_Y_NORMALIZATION·∫ȳ) gives
    ∫L·cmf/∫ȳ, prisma's convention. The integral is the trapezoid rule on a 1 nm grid, exact for
    the piecewise-linear interpolant of a 5 nm table.
    """
    grid = np.arange(translate.LAMBDA_MIN_NM, translate.LAMBDA_MAX_NM + 0.5, 1.0)
    y_bar = np.array(mi.cie1931_y(mi.Float(grid)), dtype=np.float64)
    integral = float(np.sum(0.5 * (y_bar[1:] + y_bar[:-1]) * np.diff(grid)))
    return 1.0 / (float(mi.MI_CIE_Y_NORMALIZATION) * integral), integral


def git_commit():
    try:
        head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=VALIDATION, check=True, capture_output=True,
                              text=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--", "src", "Cargo.lock"], cwd=VALIDATION,
                               check=True, capture_output=True, text=True).stdout.strip()
        return head + ("+dirty-src" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def sha256(path):
    return hashlib.sha256(pathlib.Path(path).read_bytes()).hexdigest()


def render_case(case, settings, out_dir, prisma, quick, command):
    name = case["name"]
    mi.set_variant(settings["variant"])
    spp_per_pass = settings["spp_per_pass"] // (16 if quick else 1)
    passes = settings["passes"]
    wavelength = case.get("wavelength_nm")
    export_dir = pathlib.Path(tempfile.mkdtemp(prefix=f"prisma_export_{name}_"))
    scene = translate.PrismaScene.load(VALIDATION / case["scene"], export_dir, prisma)
    translator = translate.Translator(scene, wavelength, settings.get("mitsuba_rgb_emitters", False))
    if settings["integrator"] == "path":
        if scene.has_diffuse():
            raise SystemExit(f"{name}: Mitsuba's path tracer is Whitted only without diffuse surfaces")
        integrator = translate.path_integrator(scene.max_depth)
    else:
        integrator = translate.whitted_integrator(scene.max_depth)
    mitsuba_scene = mi.load_dict(translator.scene_dict(integrator, spp_per_pass))

    fix, y_integral = y_normalisation_fix() if mi.is_spectral else (1.0, None)
    renders = []
    for seed in SEEDS:
        start = time.perf_counter()
        mean, stack, channels = translate.render(mitsuba_scene, spp_per_pass, seed, passes)
        seconds = time.perf_counter() - start
        if channels != case["channels"]:
            raise SystemExit(f"{name}: Mitsuba wrote channels {channels}, cases.toml compares {case['channels']}")
        mean *= fix
        stderr = fix * stack.std(axis=0, ddof=1) / np.sqrt(passes)
        path = out_dir / f"{name}_seed{seed}.exr"
        translate.write_exr(path, mean, channels)
        translate.write_exr(out_dir / f"{name}_seed{seed}_stderr.exr", stderr, channels)
        renders.append({
            "file": f"references/{path.name}",
            "stderr_file": f"references/{name}_seed{seed}_stderr.exr",
            "seed": seed,
            "pass_seeds": [translate.pass_seed(seed, k) for k in range(passes)],
            "wall_time_s": round(seconds, 2),
            "channel_means": {c: float(mean[..., i].mean()) for i, c in enumerate(channels)},
        })
        print(f"{name} seed {seed}: {spp_per_pass * passes} spp in {seconds:.1f} s, "
              f"means {[round(float(mean[..., i].mean()), 5) for i in range(len(channels))]}")

    integrator_params = {k: v for k, v in integrator.items()}
    provenance = {
        "case": name,
        "why": case["why"],
        "scene": case["scene"],
        "scene_sha256": sha256(VALIDATION / case["scene"]),
        "wavelength_nm": wavelength,
        "mitsuba_version": mi.__version__,
        "drjit_version": dr.__version__,
        "numpy_version": np.__version__,
        "python_version": platform.python_version(),
        "variant": settings["variant"],
        "integrator": integrator_params,
        "integrator_source": ("validation/mitsuba/whitted.py" if settings["integrator"] == "whitted"
                              else "Mitsuba's built-in path tracer"),
        "sampler": "independent",
        "spp": spp_per_pass * passes,
        "spp_per_pass": spp_per_pass,
        "passes": passes,
        "seeds": list(SEEDS),
        "pass_seed_rule": f"pass k of seed s uses mi.render(seed = s*{translate.PASS_SEED_STRIDE} + k)",
        "resolution": [int(scene.camera["width"]), int(scene.camera["height"])],
        "channels": case["channels"],
        "film": "hdrfilm, box filter, float32, pixel_format "
                + ("luminance" if mi.is_monochromatic else "rgb (linear sRGB)"),
        "spectra": ("Mitsuba's own RGB upsampling (rgb spectrum, srgb_d65) for emitters given as rgb; "
                    "prisma export tables for the rest" if settings.get("mitsuba_rgb_emitters")
                    else "prisma export tables (regular spectra, 1 nm, 360-830 nm)" if mi.is_spectral
                    else f"prisma export tables evaluated at {wavelength} nm (uniform spectra)"),
        "y_normalisation_fix": {
            "factor_applied": fix,
            "reason": ("Mitsuba's MI_CIE_Y_NORMALIZATION is 1/106.7503 but its CIE tables integrate to "
                       f"{y_integral}; the image is multiplied by 1/(MI_CIE_Y_NORMALIZATION*that) so that "
                       "Y = integral(L*ybar)/integral(ybar)") if y_integral else
                      "none: a mono render involves no colour-matching functions",
        },
        "renders": renders,
        "prisma_commit": git_commit(),
        "command": command,
        "environment": {"DRJIT_LIBLLVM_PATH": os.environ.get("DRJIT_LIBLLVM_PATH"),
                        "platform": platform.platform(), "cpu_count": os.cpu_count()},
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "quick": quick,
    }
    (out_dir / f"{name}.json").write_text(json.dumps(provenance, indent=2) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", help="case names (default: all of cases.toml)")
    parser.add_argument("--quick", action="store_true", help="1/16 of the samples, written to --out")
    parser.add_argument("--out", type=pathlib.Path, help="output directory (default: validation/references, "
                                                         "or a temporary one with --quick)")
    parser.add_argument("--prisma", help="prisma binary (default: $PRISMA or target/release/prisma)")
    args = parser.parse_args()

    with open(VALIDATION / "cases.toml", "rb") as f:
        cases = tomllib.load(f)["case"]
    names = [c["name"] for c in cases]
    if set(names) != set(MITSUBA_SETTINGS):
        raise SystemExit(f"cases.toml and MITSUBA_SETTINGS disagree: {sorted(set(names) ^ set(MITSUBA_SETTINGS))}")
    if args.cases:
        unknown = set(args.cases) - set(names)
        if unknown:
            raise SystemExit(f"unknown cases: {sorted(unknown)}")
        cases = [c for c in cases if c["name"] in args.cases]
    out_dir = args.out or (pathlib.Path(tempfile.mkdtemp(prefix="references_quick_")) if args.quick
                           else VALIDATION / "references")
    out_dir.mkdir(parents=True, exist_ok=True)
    prisma = args.prisma or translate.find_prisma()
    command = " ".join(shlex.quote(a) for a in [f"{pathlib.Path(sys.executable).name}",
                                                 *[os.path.relpath(sys.argv[0], VALIDATION.parent)],
                                                 *sys.argv[1:]])
    for case in cases:
        for key in ("name", "scene", "references", "channels", "why"):
            if key not in case:
                raise SystemExit(f"cases.toml: case {case.get('name')} lacks {key}")
        expected = [f"references/{case['name']}_seed{s}.exr" for s in SEEDS]
        if case["references"] != expected:
            raise SystemExit(f"{case['name']}: cases.toml references should be {expected}")
        render_case(case, MITSUBA_SETTINGS[case["name"]], out_dir, prisma, args.quick, command)
    print(f"references in {out_dir}")


if __name__ == "__main__":
    main()

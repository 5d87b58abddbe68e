#!/usr/bin/env python3
"""Renders the Mitsuba 3 reference images of validation/cases.toml, of
validation/polarised_cases.toml, of validation/colour_cases.toml and of the `path` cases of
validation/transport_cases.toml (its `ptracer` cases are caustics.py's), with provenance.

For every case: two references at independent seeds (references/<case>_seed1.exr, _seed2.exr,
float32, the channels Mitsuba's film writes, which include those the case compares), the
per-pixel variance of each (references/<case>_seed<s>_var.exr, see below), and
references/<case>.json: versions, variant, integrator and parameters, samples and seeds,
resolution, wall time and CPU time of each render, the command line, the date, the scene's
SHA-256, the prisma commit whose `prisma export` fed the translation, the translation's settings
(plane size, polarised or not) and why prisma and Mitsuba compute the same quantity in this case.

The variance file. Each reference is the mean of P independent passes (pass k of seed s uses
mi.render(seed = s·1000 + k)); <case>_seed<s>_var.exr holds, per pixel and channel, the variance
of that mean estimated from the passes, Σ_k (x_k − x̄)²/(P(P − 1)) (an unbiased estimate with
P − 1 degrees of freedom), in the units of the reference squared (the luminance factor below
applied squared). Same channels, size and pixel order as the reference.

The Mitsuba side of each case (variant, integrator, samples, whether `stokes` wraps the
integrator, the plane size) is in MITSUBA_SETTINGS below; the case files hold what the Rust side
reads. Spectral references are divided by Mitsuba's luminance normalisation error (see
`y_normalisation_fix` and validation/README.md).

Run from the repository root after validation/setup.sh and `cargo build --release`:
  export DRJIT_LIBLLVM_PATH=...          # printed by validation/setup.sh
  validation/.venv/bin/python validation/mitsuba/render_references.py            # all cases, into out/references
  validation/.venv/bin/python validation/mitsuba/render_references.py tp6_quad   # one case
  ... --out validation/references   (replace the committed references)
  ... --quick    (1/16 of the samples, into /tmp, for trying changes)
  ... --polarised (the cases of polarised_cases.toml only)
  ... --variance-only CASE ...  (repeat committed references for their variance files only)
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
CASE_FILES = [VALIDATION / "cases.toml", VALIDATION / "polarised_cases.toml",
              VALIDATION / "colour_cases.toml", VALIDATION / "mitsuba" / "mitsuba_pipeline_cases.toml",
              VALIDATION / "transport_cases.toml"]
SEEDS = (1, 2)

# Infinite planes: the references of cases.toml were rendered with 1000-unit rectangles; the
# polarised ones with the graded mesh, which leaves neither the escaping rays of a finite
# rectangle nor its float32 imprecision at large sizes (plane_size_study.py).
PLANE_HALF_SIZE_POLARISED = "graded"

# The Mitsuba side of each case. spp = spp_per_pass × passes per reference; passes bound the
# memory of a wavefront and give the per-pixel variance. stokes: wrap the integrator in Mitsuba's
# `stokes` (polarised variants), which adds the S0.R … S3.B channels. The unpolarised sample
# counts were set so that each render takes at most about three minutes on two cores; the
# polarised ones so that all of them fit in about two CPU-hours on this machine.
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
for _settings in MITSUBA_SETTINGS.values():
    _settings.setdefault("plane_half_size", 1000.0)

# Spectral polarised references go through prisma's colour pipeline (Mitsuba's specfilm with
# prisma's CIE table, then prisma's XYZ → sRGB matrix; tolerance_study.py shows why), S0 only:
# Mitsuba's `stokes` takes its Stokes channels to sRGB with its own tables and assumes the
# hdrfilm's wavelength sampling. The mono ones keep `stokes` (no colour pipeline at one λ).
_POLARISED_GLASS = dict(spp_per_pass=256, passes=64, plane_half_size=PLANE_HALF_SIZE_POLARISED)
_SPECTRAL = dict(variant="llvm_ad_spectral_polarized", film="prisma_xyz")
_MONO = dict(variant="llvm_ad_mono_polarized", stokes=True)
_STOKES = dict(variant="llvm_ad_mono_polarized", integrator="path", spp_per_pass=256, passes=64, stokes=True,
               plane_half_size=PLANE_HALF_SIZE_POLARISED)
# The glass plane is seen in reflection only with probability R ≈ 0.07 per sample (Mitsuba picks
# reflection or refraction by the Fresnel reflectance): twice the samples.
_BREWSTER = dict(_STOKES, spp_per_pass=512)
MITSUBA_SETTINGS.update({
    "specular_spheres_polarized": dict(_POLARISED_GLASS, **_SPECTRAL, integrator="path"),
    "specular_prism_polarized": dict(_POLARISED_GLASS, **_SPECTRAL, integrator="path"),
    "tp6_point_polarized": dict(_POLARISED_GLASS, **_SPECTRAL, integrator="whitted"),
    "tp6_quad_polarized": dict(_POLARISED_GLASS, **_SPECTRAL, integrator="whitted"),
    "dispersion_450_polarized": dict(_POLARISED_GLASS, **_MONO, integrator="path"),
    "dispersion_550_polarized": dict(_POLARISED_GLASS, **_MONO, integrator="path"),
    "dispersion_650_polarized": dict(_POLARISED_GLASS, **_MONO, integrator="path"),
    "stokes_brewster": dict(_BREWSTER),
    "stokes_rolled_30": dict(_BREWSTER),
    "stokes_rolled_45": dict(_BREWSTER),
    "stokes_glass_sphere": dict(_STOKES),
    "stokes_two_mirrors_skew": dict(_STOKES),
    "stokes_gold_pair": dict(_STOKES),
    "stokes_tir_prism": dict(_STOKES),
    "stokes_polarizers": dict(_STOKES),
})
# Unpolarised, through prisma's colour pipeline (colour_cases.toml).
_PRISMA_CMF = dict(variant="llvm_ad_spectral", film="prisma_xyz", spp_per_pass=256, passes=64,
                   plane_half_size=PLANE_HALF_SIZE_POLARISED)
MITSUBA_SETTINGS.update({
    "specular_spheres_prisma_cmf": dict(_PRISMA_CMF, integrator="path"),
    "specular_prism_prisma_cmf": dict(_PRISMA_CMF, integrator="path"),
    "tp6_point_prisma_cmf": dict(_PRISMA_CMF, integrator="whitted"),
    "tp6_quad_prisma_cmf": dict(_PRISMA_CMF, integrator="whitted"),
    "color_emitters_prisma_cmf": dict(_PRISMA_CMF, integrator="path"),
})
# Full transport (transport_cases.toml, mitsuba_integrator = "path"): integrator "full" is
# Mitsuba's path tracer on scenes with diffuse surfaces (translate.full_transport_integrator:
# max_depth = prisma's + 1, Mitsuba's default Russian roulette), for scenes whose own integrator
# is "path". Sample counts were cut to what a machine of two cores shared with compiles could give
# within about 50 minutes of wall time (the first reference, 4096 spp, took 11 minutes there
# instead of the 3.5 it takes alone): 4096 spp for the spectral TP6, 512 for the mono TP6 (32
# passes, 31 degrees of freedom of the variance), 2048 for the Stokes room (64 passes).
_FULL = dict(integrator="full", plane_half_size=PLANE_HALF_SIZE_POLARISED)
MITSUBA_SETTINGS.update({
    "tp6_quad_path_prisma_cmf": dict(_FULL, variant="llvm_ad_spectral", film="prisma_xyz", spp_per_pass=64,
                                     passes=64),
    **{f"tp6_quad_path_{nm}": dict(_FULL, variant="llvm_ad_mono", spp_per_pass=16, passes=32)
       for nm in (450, 550, 650)},
    "stokes_room_path": dict(_FULL, variant="llvm_ad_mono_polarized", stokes=True, spp_per_pass=32, passes=64),
    # Depth of field through Mitsuba's `thinlens` sensor (translate.py), 4096 spp (about a minute
    # per reference here).
    "thin_lens_dof_550": dict(_FULL, variant="llvm_ad_mono", spp_per_pass=64, passes=64),
})


def load_cases():
    """[(case, the file it comes from)] of every case file (without the `ptracer` cases of
    transport_cases.toml, which caustics.py renders, and without the cases that compare with
    another case's references, such as stokes_room_path_caustics)."""
    cases = []
    for path in CASE_FILES:
        with open(path, "rb") as f:
            cases += [(case, path) for case in tomllib.load(f)["case"]
                      if case.get("mitsuba_integrator", "path") != "ptracer"
                      and case["references"][0].startswith(f"references/{case['name']}_seed")]
    return cases


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
        # Pathspecs from the repository's root (":/"): git reads plain ones relative to cwd.
        dirty = subprocess.run(["git", "status", "--porcelain", "--", ":/src", ":/Cargo.lock"], cwd=VALIDATION,
                               check=True, capture_output=True, text=True).stdout.strip()
        return head + ("+dirty-src" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def sha256(path):
    return hashlib.sha256(pathlib.Path(path).read_bytes()).hexdigest()


def prisma_identity(prisma):
    """Version string and SHA-256 of the prisma binary that ran `prisma export`."""
    try:
        version = subprocess.run([prisma, "--version"], check=True, capture_output=True, text=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        version = "unknown"
    return {"path": str(prisma), "version": version, "sha256": sha256(prisma)}


def read_exr(path):
    bitmap = mi.Bitmap(str(path))
    data = np.array(bitmap, dtype=np.float64)
    if data.ndim == 2:
        data = data[..., None]
    return data, [bitmap.struct_()[i].name for i in range(data.shape[-1])]


def stored_channels(channels):
    """The channels a reference keeps: a mono film's S<k>.G and S<k>.B repeat S<k>.R (Mitsuba's
    `stokes` copies the one value into R, G and B) and the prisma_xyz film's XYZ.* are not
    compared, so they are left out to keep the files small."""
    return [c for c in channels if not c.startswith("XYZ.")
            and not (mi.is_monochromatic and c.startswith("S") and c[-2:] in (".G", ".B"))]


def render_case(case, case_file, settings, out_dir, prisma, quick, command, variance_only=False):
    """Renders one case (both seeds) into out_dir. variance_only: render exactly as before, keep
    the committed reference EXRs, write only the variance files and <case>_var.json, after
    checking that the new mean reproduces the committed one (to float rounding: the LLVM
    backend's accumulation order across threads is not fixed)."""
    name = case["name"]
    mi.set_variant(settings["variant"])
    spp_per_pass = settings["spp_per_pass"] // (16 if quick else 1)
    passes = settings["passes"]
    wavelength = case.get("wavelength_nm")
    export_dir = pathlib.Path(tempfile.mkdtemp(prefix=f"prisma_export_{name}_"))
    scene = translate.PrismaScene.load(VALIDATION / case["scene"], export_dir, prisma)
    translator = translate.Translator(scene, wavelength, settings.get("mitsuba_rgb_emitters", False),
                                      settings["plane_half_size"])
    if settings["integrator"] == "full":
        if scene.integrator != "path" or case.get("integrator", scene.integrator) != "path":
            raise SystemExit(f"{name}: a full-transport reference is for prisma's integrator \"path\"")
        integrator = translate.full_transport_integrator(scene.max_depth)
    elif settings["integrator"] == "path":
        if scene.has_diffuse():
            raise SystemExit(f"{name}: Mitsuba's path tracer is Whitted only without diffuse surfaces")
        integrator = translate.path_integrator(scene.max_depth)
    else:
        integrator = translate.whitted_integrator(scene.max_depth)
    if settings.get("stokes"):
        integrator = translate.stokes_integrator(integrator)
    film = settings.get("film", "hdrfilm")
    mitsuba_scene = mi.load_dict(translator.scene_dict(integrator, spp_per_pass, film=film))
    transform = translate.prisma_rgb if film == "prisma_xyz" else None

    fix, y_integral = y_normalisation_fix() if mi.is_spectral and film == "hdrfilm" else (1.0, None)
    renders = []
    for seed in SEEDS:
        start, cpu_start = time.perf_counter(), time.process_time()
        mean, variance, channels = translate.render(mitsuba_scene, spp_per_pass, seed, passes, transform)
        seconds, cpu_seconds = time.perf_counter() - start, time.process_time() - cpu_start
        missing = [c for c in case["channels"] if c not in channels]
        if missing:
            raise SystemExit(f"{name}: Mitsuba wrote channels {channels}, the case compares {case['channels']}")
        mean *= fix
        variance *= fix * fix
        if not variance_only:
            keep = [channels.index(c) for c in stored_channels(channels)]
            mean, variance, channels = mean[..., keep], variance[..., keep], [channels[i] for i in keep]
        path = out_dir / f"{name}_seed{seed}.exr"
        var_path = out_dir / f"{name}_seed{seed}_var.exr"
        agreement = None
        if variance_only:
            committed, committed_channels = read_exr(path)
            if committed_channels != channels or committed.shape != mean.shape:
                raise SystemExit(f"{name}: {path} has channels {committed_channels}, the render {channels}")
            difference = np.abs(mean.astype(np.float32) - committed)
            sigma = np.sqrt(variance)
            agreement = {"max_abs_difference": float(difference.max()),
                         "max_relative_difference": float((difference / np.maximum(np.abs(committed), 1e-6)).max()),
                         "max_difference_over_sigma": float((difference / np.maximum(sigma, 1e-12)).max())}
            print(f"{name} seed {seed}: the new mean against {path.name}: {agreement}")
        else:
            translate.write_exr(path, mean, channels)
        translate.write_exr(var_path, variance, channels)
        renders.append({
            "file": f"references/{path.name}",
            "variance_file": f"references/{var_path.name}",
            "seed": seed,
            "pass_seeds": [translate.pass_seed(seed, k) for k in range(passes)],
            "wall_time_s": round(seconds, 2),
            "cpu_time_s": round(cpu_seconds, 2),
            "channel_means": {c: float(mean[..., i].mean()) for i, c in enumerate(channels)},
            "channel_mean_stderr": {c: float(np.sqrt(variance[..., i].sum()) / variance[..., i].size)
                                    for i, c in enumerate(channels)},
        })
        if agreement is not None:
            renders[-1]["committed_mean_reproduced"] = agreement
        print(f"{name} seed {seed}: {spp_per_pass * passes} spp in {seconds:.1f} s (CPU {cpu_seconds:.1f} s), "
              f"means {dict((c, round(float(mean[..., i].mean()), 5)) for i, c in enumerate(channels) if c in case['channels'])}")

    provenance = {
        "case": name,
        "case_file": str(case_file.relative_to(VALIDATION.parent)),
        "why": case["why"],
        "scene": case["scene"],
        "scene_sha256": sha256(VALIDATION / case["scene"]),
        "wavelength_nm": wavelength,
        "prisma_integrator": scene.integrator,
        "prisma_max_depth": scene.max_depth,
        "mitsuba_version": mi.__version__,
        "drjit_version": dr.__version__,
        "numpy_version": np.__version__,
        "python_version": platform.python_version(),
        "variant": settings["variant"],
        "polarized": bool(mi.is_polarized),
        "integrator": integrator,
        "integrator_source": ("validation/mitsuba/whitted.py" if settings["integrator"] == "whitted"
                              else "Mitsuba's built-in path tracer in full transport (diffuse surfaces, "
                                   "Russian roulette from Mitsuba's default rr_depth 5), for prisma's "
                                   "integrator \"path\" with max_depth " + str(scene.max_depth)
                              if settings["integrator"] == "full"
                              else "Mitsuba's built-in path tracer")
                             + (", inside Mitsuba's stokes integrator" if settings.get("stokes") else ""),
        "sampler": "independent",
        "spp": spp_per_pass * passes,
        "spp_per_pass": spp_per_pass,
        "passes": passes,
        "seeds": list(SEEDS),
        "pass_seed_rule": f"pass k of seed s uses mi.render(seed = s*{translate.PASS_SEED_STRIDE} + k)",
        "resolution": [int(scene.camera["width"]), int(scene.camera["height"])],
        "channels": channels,
        "compared_channels": case["channels"],
        "stored_channels_rule": ("a mono film's S<k>.G, S<k>.B (copies of S<k>.R) and the XYZ.* of the prisma_xyz "
                                 "film are not stored"),
        "variance_files": "per pixel and channel, the variance of the reference (a mean of `passes` passes): "
                          "sum_k (x_k - mean)^2 / (passes*(passes - 1)), from the passes, times the square "
                          "of the factor applied to the image",
        "film": ("specfilm, box filter, float32, with prisma's CIE 1931 table (data/cie1931_2deg.csv, 1 nm) as "
                 "its three response functions (each channel = integral of L*cmf); R, G, B and XYZ.X/Y/Z then "
                 "follow prisma's pipeline: XYZ = that / integral(ybar) (trapezoid on the 1 nm table), "
                 "linear sRGB = prisma's matrix from the sRGB primaries and D65 (translate.prisma_rgb)"
                 if film == "prisma_xyz" else
                 "hdrfilm, box filter, float32, pixel_format "
                 + ("luminance" if mi.is_monochromatic else "rgb (linear sRGB)")
                 + ("; stokes adds S0.R..S3.B in Mitsuba's stokes frame (x = normalize(d x camera up), "
                    "S3 = +1 clockwise as seen by the camera)" if settings.get("stokes") else "")),
        "spectra": ("Mitsuba's own RGB upsampling (rgb spectrum, srgb_d65) for emitters given as rgb; "
                    "prisma export tables for the rest" if settings.get("mitsuba_rgb_emitters")
                    else "prisma export tables (regular spectra, 1 nm, 360-830 nm)" if mi.is_spectral
                    else f"prisma export tables evaluated at {wavelength} nm (uniform spectra)"),
        "translation": {
            "plane_half_size": settings["plane_half_size"],
            "ideal_mirror": ("conductor eta = 0, k = %g (perfect electric conductor)" % translate.PEC_K
                             if mi.is_polarized else "conductor material 'none'"),
            "retarder": "validation/mitsuba/ideal_retarder.py (plugin ideal_retarder)",
            "polarizer": "Mitsuba's polarizer, theta = 0, local U along the transmission axis",
        },
        "y_normalisation_fix": {
            "factor_applied": fix,
            "reason": ("Mitsuba's MI_CIE_Y_NORMALIZATION is 1/106.7503 but its CIE tables integrate to "
                       f"{y_integral}; the image is multiplied by 1/(MI_CIE_Y_NORMALIZATION*that) so that "
                       "Y = integral(L*ybar)/integral(ybar)") if y_integral else
                      ("none: a mono render involves no colour-matching functions" if mi.is_monochromatic else
             "none: prisma's own colour-matching table and normalisation (specfilm)"),
        },
        "background": ("a constant emitter of the scene's background radiance (prisma export's table): "
                       "a light in full transport" if any(v != 0.0 for v in scene.spectra["background"])
                       else "none (black)"),
        "renders": renders,
        "prisma_commit": git_commit(),
        "prisma_binary": prisma_identity(prisma),
        "command": command,
        "environment": {"DRJIT_LIBLLVM_PATH": os.environ.get("DRJIT_LIBLLVM_PATH"),
                        "platform": platform.platform(), "cpu_count": os.cpu_count()},
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "quick": quick,
    }
    if variance_only:
        provenance["variance_only"] = ("the reference EXRs are the committed ones (see <case>.json); this render "
                                       "repeated them with the same settings and seeds for the variance files only")
    (out_dir / f"{name}{'_var' if variance_only else ''}.json").write_text(json.dumps(provenance, indent=2) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", help="case names (default: every case of the case files)")
    parser.add_argument("--polarised", action="store_true", help="only the cases of polarised_cases.toml")
    parser.add_argument("--quick", action="store_true", help="1/16 of the samples, written to --out")
    parser.add_argument("--variance-only", action="store_true",
                        help="keep the committed references, add their variance files (and <case>_var.json)")
    parser.add_argument("--out", type=pathlib.Path, help="output directory (default: out/references, "
                        "ignored by git, or a temporary one with --quick; --out validation/references "
                        "replaces the committed references)")
    parser.add_argument("--prisma", help="prisma binary (default: $PRISMA or target/release/prisma)")
    args = parser.parse_args()

    cases = load_cases()
    names = [c["name"] for c, _ in cases]
    if len(set(names)) != len(names) or set(names) != set(MITSUBA_SETTINGS):
        raise SystemExit(f"the case files and MITSUBA_SETTINGS disagree: {sorted(set(names) ^ set(MITSUBA_SETTINGS))}")
    if args.polarised:
        cases = [(c, f) for c, f in cases if f == CASE_FILES[1]]
    if args.cases:
        unknown = set(args.cases) - set(names)
        if unknown:
            raise SystemExit(f"unknown cases: {sorted(unknown)}")
        cases = [(c, f) for c, f in cases if c["name"] in args.cases]
    out_dir = args.out or (pathlib.Path(tempfile.mkdtemp(prefix="references_quick_")) if args.quick
                           else VALIDATION.parent / "out" / "references")
    out_dir.mkdir(parents=True, exist_ok=True)
    prisma = args.prisma or translate.find_prisma()
    command = " ".join(shlex.quote(a) for a in [f"{pathlib.Path(sys.executable).name}",
                                                 *[os.path.relpath(sys.argv[0], VALIDATION.parent)],
                                                 *sys.argv[1:]])
    for case, case_file in cases:
        for key in ("name", "scene", "references", "channels", "why"):
            if key not in case:
                raise SystemExit(f"{case_file.name}: case {case.get('name')} lacks {key}")
        expected = [f"references/{case['name']}_seed{s}.exr" for s in SEEDS]
        if case["references"] != expected:
            raise SystemExit(f"{case['name']}: {case_file.name} references should be {expected}")
        render_case(case, case_file, MITSUBA_SETTINGS[case["name"]], out_dir, prisma, args.quick, command,
                    args.variance_only)
    print(f"references in {out_dir}")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Renders the Mitsuba 3 references of validation/caustic_cases.toml and of the `ptracer` cases of
validation/transport_cases.toml: Mitsuba's particle tracer `ptracer` on prisma's caustic scenes,
with provenance (as render_references.py does for cases.toml, whose settings and checks it
reuses by import).

Full transport (transport_cases.toml, mitsuba_integrator = "ptracer", scenes whose integrator is
"path"): diffuse materials stay translate.py's twosided diffuse (light continues past them, so
ptracer sums every path of light), max_depth = prisma's + 1 and Russian roulette as Mitsuba's
default (rr_depth 5, unbiased); the film is the hdrfilm (Mitsuba 3.9.1's ptracer does not splat
correctly into a specfilm: a test render came out about 60× too dark), with the luminance
normalisation fix of render_references.py. Mitsuba's `stokes` wraps only sampling integrators,
so these references are unpolarised S0.

Mitsuba's side: `ptracer` (max_depth = -1: unlimited, Russian roulette from depth 64, unbiased),
unpolarised variants, as the cases are (caustic_cases.toml says why): `llvm_ad_mono` with every
spectrum and n(λ) taken at the case's wavelength, or `llvm_ad_spectral` for the non-dispersive
spectral case. Each reference is the mean of 64 independent passes, and <case>_seed<s>_var.exr
holds the per-pixel variance of that mean from the passes (as render_references.py's variance
files), which `prisma validate` uses as the reference's noise. The translation is
translate.py's, plus the lights it does not know:

  beam light   rectangle with a black diffuse BSDF and a `directionalarea` emitter whose
               `radiance` is prisma's irradiance (W·m⁻²·nm⁻¹ across the beam: ptracer gives a
               path from it the weight radiance × area); local +z on the emitting side, as for
               quad lights
  spot light   `spot` with to_world = look_at(position, look_at), cutoff_angle and beam_width in
               degrees (the same linear falloff in angle)

Run from the repository root after `cargo build --release`:
  export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so
  validation/.venv/bin/python validation/mitsuba/caustics.py                    # every case, into out/references
  ... --out validation/references   (replace the committed references)
  validation/.venv/bin/python validation/mitsuba/caustics.py caustic_prism_550  # one case
  ... --quick    (1/16 of the samples, into a temporary directory)
"""

import argparse
import copy
import datetime
import json
import os
import pathlib
import platform
import shlex
import sys
import tempfile
import time
import tomllib

import drjit as dr
import mitsuba as mi
import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import translate  # noqa: E402
from render_references import git_commit, prisma_identity, sha256, y_normalisation_fix  # noqa: E402

VALIDATION = pathlib.Path(__file__).resolve().parents[1]
SEEDS = (1, 2)
CASES_FILE = "caustic_cases.toml"
# transport_cases.toml also lists `path` cases, which render_references.py renders.
TRANSPORT_CASES_FILE = "transport_cases.toml"

# Light paths: ptracer traces spp × width × height paths per render: 4096 spp × 12 288 pixels =
# 50 M paths per reference, 30–50× what prisma traces per render in CI, in 64 passes of 64 spp
# (the per-pixel variance of the mean has 63 degrees of freedom). Passes must stay small for the
# ball: ptracer adds its splats into a float32 image block, and where millions of splats of nearly
# equal value land in one pixel (the ball's focus) the rounding of those additions no longer
# averages out: one pass of 4096 spp left the 9 focus pixels 1 % low (measured against prisma's
# f64 sums and against passes of 256 spp); passes of 512 spp and fewer agree.
PTRACER = {"type": "ptracer", "max_depth": -1, "rr_depth": 64, "hide_emitters": False}
MITSUBA_SETTINGS = {
    **{f"caustic_sphere_{nm}": dict(variant="llvm_ad_mono", spp_per_pass=64, passes=64)
       for nm in (450, 550, 650)},
    **{f"caustic_prism_{nm}": dict(variant="llvm_ad_mono", spp_per_pass=64, passes=64)
       for nm in (450, 550, 650)},
    "caustic_sphere_spectral": dict(variant="llvm_ad_spectral", spp_per_pass=64, passes=64),
    # Full transport in a closed room: 512 spp × 15 000 pixels = 7.7 M light paths per reference
    # (about a minute each on this machine's two cores alone), in 32 passes.
    "transport_room_point": dict(variant="llvm_ad_spectral", spp_per_pass=16, passes=32, full_transport=True),
    "transport_room_spot": dict(variant="llvm_ad_spectral", spp_per_pass=16, passes=32, full_transport=True),
}


def full_transport_ptracer(prisma_max_depth):
    """ptracer for prisma's integrator "path": max_depth counts vertices (prisma's bounces + 1),
    Mitsuba's default Russian roulette (rr_depth 5, unbiased)."""
    return {"type": "ptracer", "max_depth": prisma_max_depth + 1, "hide_emitters": False}

BLACK = {"type": "diffuse", "reflectance": {"type": "uniform", "value": 0.0}}


def register_receiver():
    """Registers `receiver`: Lambertian (ρ/π) toward the sensor, but a light path ends there.

    ptracer connects every vertex to the sensor with `eval` and continues with `sample`; this
    BSDF evaluates as a two-sided Lambertian of reflectance ρ and samples nothing, so Mitsuba's
    particle tracer sums exactly L S* D E, the paths prisma's Whitted + light tracer decomposition
    counts, and leaves out L S* D S* D E (light a diffuse receiver sends back through or off the
    glass onto itself: 2-3 % of the caustic below a ball lens, measured), which prisma does not
    trace.
    """

    class ReceiverBSDF(mi.BSDF):
        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            self.reflectance = props.get("reflectance", 0.5)
            self.m_flags = mi.BSDFFlags.DiffuseReflection | mi.BSDFFlags.FrontSide | mi.BSDFFlags.BackSide
            self.m_components = [self.m_flags]

        def sample(self, ctx, si, sample1, sample2, active=True):
            width = dr.width(sample1)
            return dr.zeros(mi.BSDFSample3f, width), dr.zeros(mi.Spectrum, width)

        def eval(self, ctx, si, wo, active=True):
            cos_i, cos_o = mi.Frame3f.cos_theta(si.wi), mi.Frame3f.cos_theta(wo)
            same_side = cos_i * cos_o > 0.0
            value = self.reflectance * dr.inv_pi * dr.abs(cos_o)
            return mi.Spectrum(dr.select(active & same_side, value, 0.0))

        def pdf(self, ctx, si, wo, active=True):
            return dr.zeros(mi.Float, dr.width(wo))

        def eval_pdf(self, ctx, si, wo, active=True):
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def to_string(self):
            return f"Receiver[reflectance={self.reflectance}]"

    mi.register_bsdf("receiver", lambda props: ReceiverBSDF(props))


class CausticTranslator(translate.Translator):
    """translate.Translator with prisma's beam and spot lights, and diffuse materials as
    `receiver` BSDFs (constant albedo only), or with receiver = False as translate.py's twosided
    diffuse (full transport: light continues past diffuse vertices)."""

    def __init__(self, scene, wavelength_nm=None, receiver=True, **kwargs):
        super().__init__(scene, wavelength_nm, **kwargs)
        self.receiver = receiver

    def bsdf(self, name):
        desc = self.scene.desc["materials"][name]
        if desc["type"] != "diffuse" or not self.receiver:
            return super().bsdf(name)
        values = np.asarray(self.scene.spectra["materials"][name]["albedo"], dtype=np.float64)
        if self.mono:
            albedo = float(np.interp(self.wavelength_nm, self.scene.grid, values))
        elif np.ptp(values) == 0.0:
            albedo = float(values[0])
        else:
            raise translate.TranslationError(f"material {name!r}: the receiver takes a constant albedo")
        return {"type": "receiver", "reflectance": albedo}

    def scene_dict(self, integrator, spp, pixel_format=None, sampler="independent", film="hdrfilm"):
        scene = self.scene
        lights = scene.desc.get("lights", [])
        extra = [(i, light) for i, light in enumerate(lights) if light["type"] in ("beam", "spot")]
        # translate.py translates the point and quad lights; the others are added here.
        plain = copy.copy(scene)
        plain.desc = dict(scene.desc, lights=[l for l in lights if l["type"] not in ("beam", "spot")])
        plain.spectra = dict(scene.spectra, lights=[s for l, s in zip(lights, scene.spectra["lights"])
                                                     if l["type"] not in ("beam", "spot")])
        self.scene = plain
        try:
            out = super().scene_dict(integrator, spp, pixel_format, sampler, film)
        finally:
            self.scene = scene
        for i, light in extra:
            resolved = scene.spectra["lights"][i]
            if light["type"] == "beam":
                emit = light.get("emit", "edge1_cross_edge2")
                out[f"beam_{i}"] = {
                    "type": "rectangle",
                    "to_world": self.quad_transform(light["corner"], light["edge1"], light["edge2"],
                                                    swap=(emit == "edge2_cross_edge1")),
                    "bsdf": BLACK,
                    "emitter": {"type": "directionalarea", "radiance": self.spectrum(resolved["irradiance"])},
                }
            else:
                position = [float(c) for c in light["position"]]
                target = [float(c) for c in light["look_at"]]
                axis = np.subtract(target, position)
                up = [0.0, 1.0, 0.0] if abs(axis[1]) < 0.9 * np.linalg.norm(axis) else [1.0, 0.0, 0.0]
                cutoff = float(light["cutoff_deg"])
                out[f"spot_{i}"] = {
                    "type": "spot",
                    "to_world": mi.ScalarTransform4f().look_at(origin=position, target=target, up=up),
                    "intensity": self.spectrum(resolved["intensity"]),
                    "cutoff_angle": cutoff,
                    "beam_width": float(light.get("beam_width_deg", 0.75 * cutoff)),
                }
        return out


def render_case(case, settings, out_dir, prisma, quick, command, case_file=CASES_FILE):
    name = case["name"]
    mi.set_variant(settings["variant"])
    register_receiver()
    spp_per_pass = settings["spp_per_pass"] // (16 if quick else 1)
    passes = settings["passes"]
    wavelength = case.get("wavelength_nm")
    export_dir = pathlib.Path(tempfile.mkdtemp(prefix=f"prisma_export_{name}_"))
    scene = translate.PrismaScene.load(VALIDATION / case["scene"], export_dir, prisma)
    full = settings.get("full_transport", False)
    if full:
        if scene.integrator != "path" or case.get("integrator", scene.integrator) != "path":
            raise SystemExit(f"{name}: a full-transport reference is for prisma's integrator \"path\"")
        integrator = full_transport_ptracer(scene.max_depth)
    else:
        integrator = PTRACER
    translator = CausticTranslator(scene, wavelength, receiver=not full)
    mitsuba_scene = mi.load_dict(translator.scene_dict(integrator, spp_per_pass))
    fix, y_integral = y_normalisation_fix() if mi.is_spectral else (1.0, None)
    renders = []
    for seed in SEEDS:
        start, cpu_start = time.perf_counter(), time.process_time()
        mean, variance, channels = translate.render(mitsuba_scene, spp_per_pass, seed, passes)
        seconds, cpu_seconds = time.perf_counter() - start, time.process_time() - cpu_start
        if channels != case["channels"]:
            raise SystemExit(f"{name}: Mitsuba wrote channels {channels}, {case_file} compares {case['channels']}")
        mean *= fix
        # The variance of the mean from the passes, in the units of the reference squared.
        variance *= fix * fix
        if not np.all(np.isfinite(variance)):
            raise SystemExit(f"{name}: the variance needs at least two passes")
        path = out_dir / f"{name}_seed{seed}.exr"
        var_path = out_dir / f"{name}_seed{seed}_var.exr"
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
        print(f"{name} seed {seed}: {spp_per_pass * passes} spp in {seconds:.1f} s, "
              f"means {[round(float(mean[..., i].mean()), 5) for i in range(len(channels))]}", flush=True)
    width, height = int(scene.camera["width"]), int(scene.camera["height"])
    provenance = {
        "case": name,
        "case_file": f"validation/{case_file}",
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
        "integrator": integrator,
        "integrator_source": "Mitsuba's built-in particle tracer (ptracer)"
                             + (", full transport: twosided diffuse BSDFs, default Russian roulette" if full
                                else ", diffuse surfaces as `receiver` BSDFs (paths end there)"),
        "sampler": "independent",
        "spp": spp_per_pass * passes,
        "spp_per_pass": spp_per_pass,
        "passes": passes,
        "light_paths_per_render": spp_per_pass * passes * width * height,
        "variance_files": "per pixel and channel, the variance of the reference (a mean of `passes` passes): "
                          "sum_k (x_k - mean)^2 / (passes (passes - 1))",
        "seeds": list(SEEDS),
        "pass_seed_rule": f"pass k of seed s uses mi.render(seed = s*{translate.PASS_SEED_STRIDE} + k)",
        "resolution": [width, height],
        "channels": case["channels"],
        "film": "hdrfilm, box filter, float32, pixel_format "
                + ("luminance" if mi.is_monochromatic else "rgb (linear sRGB)"),
        "spectra": ("prisma export tables (regular spectra, 1 nm, 360-830 nm)" if mi.is_spectral
                    else f"prisma export tables evaluated at {wavelength} nm (uniform spectra)"),
        "lights": "beam -> rectangle + directionalarea (radiance = irradiance), black BSDF; "
                  "spot -> spot (cutoff_angle, beam_width)",
        "y_normalisation_fix": {
            "factor_applied": fix,
            "reason": ("Mitsuba's MI_CIE_Y_NORMALIZATION is 1/106.7503 but its CIE tables integrate to "
                       f"{y_integral}; the image is multiplied by 1/(MI_CIE_Y_NORMALIZATION*that)")
                      if y_integral else "none: a mono render involves no colour-matching functions",
        },
        "renders": renders,
        "prisma_commit": git_commit(),
        "prisma_binary": prisma_identity(prisma),
        "command": command,
        "environment": {"DRJIT_LIBLLVM_PATH": os.environ.get("DRJIT_LIBLLVM_PATH"),
                        "platform": platform.platform(), "cpu_count": os.cpu_count()},
        "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "quick": quick,
    }
    (out_dir / f"{name}.json").write_text(json.dumps(provenance, indent=2) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", help=f"case names (default: all of {CASES_FILE})")
    parser.add_argument("--quick", action="store_true", help="1/16 of the samples, written to --out")
    parser.add_argument("--out", type=pathlib.Path, help="output directory (default: out/references, "
                        "ignored by git, or a temporary one with --quick; --out validation/references "
                        "replaces the committed references)")
    parser.add_argument("--prisma", help="prisma binary (default: $PRISMA or target/release/prisma)")
    args = parser.parse_args()
    with open(VALIDATION / CASES_FILE, "rb") as f:
        cases = [(c, CASES_FILE) for c in tomllib.load(f)["case"]]
    with open(VALIDATION / TRANSPORT_CASES_FILE, "rb") as f:
        cases += [(c, TRANSPORT_CASES_FILE) for c in tomllib.load(f)["case"]
                  if c.get("mitsuba_integrator") == "ptracer"]
    names = [c["name"] for c, _ in cases]
    if set(names) != set(MITSUBA_SETTINGS):
        raise SystemExit(f"{CASES_FILE} and MITSUBA_SETTINGS disagree: {sorted(set(names) ^ set(MITSUBA_SETTINGS))}")
    if args.cases:
        unknown = set(args.cases) - set(names)
        if unknown:
            raise SystemExit(f"unknown cases: {sorted(unknown)}")
        cases = [(c, f) for c, f in cases if c["name"] in args.cases]
    out_dir = args.out or (pathlib.Path(tempfile.mkdtemp(prefix="caustics_quick_")) if args.quick
                           else VALIDATION.parent / "out" / "references")
    out_dir.mkdir(parents=True, exist_ok=True)
    prisma = args.prisma or translate.find_prisma()
    command = " ".join(shlex.quote(a) for a in [pathlib.Path(sys.executable).name,
                                                 os.path.relpath(sys.argv[0], VALIDATION.parent), *sys.argv[1:]])
    for case, case_file in cases:
        expected = [f"references/{case['name']}_seed{s}.exr" for s in SEEDS]
        if case["references"] != expected:
            raise SystemExit(f"{case['name']}: {case_file} references should be {expected}")
        render_case(case, MITSUBA_SETTINGS[case["name"]], out_dir, prisma, args.quick, command, case_file)
    print(f"references in {out_dir}")


if __name__ == "__main__":
    main()

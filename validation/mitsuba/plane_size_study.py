#!/usr/bin/env python3
"""How large must the rectangles be that stand in for prisma's infinite planes on the Mitsuba
side? Renders the plane scenes (tp6_point, tp6_quad, stokes_brewster) with rectangles of several
half-sizes, every other setting and the seed unchanged, and reports what the size changes.

With the same seed Mitsuba draws the same samples, so two renders that differ only in the
rectangles' size differ, beyond float rounding, exactly on the pixels where a path meets (or
misses) a rectangle because of its size. Per size it prints
  - the pixels that differ by more than 1e-3 (relative) from the render with BASELINE (1000,
    the size of the references of cases.toml; float rounding changes every pixel a little), and
    the largest difference in units of the per-pixel standard error of the render (from its
    passes);
  - the image mean against BASELINE's, relative;
  - the same image against prisma (`prisma render --wavelength`, several seeds): the image-mean
    difference in standard errors of the difference, and the fraction of pixels beyond 5σ;
  - the pixels that change most between BASELINE and the graded mesh, at every size, with
    prisma's value.
Where a path that prisma continues through an infinite plane leaves a finite rectangle, Mitsuba
sees the background instead (in TP6 the open rear of the box: rays leaving toward -z within the
tube of the four walls escape beyond z = -L); the affected solid angle shrinks as 1/L².

Run from the repository root (about 10 CPU-minutes):
  validation/.venv/bin/python validation/mitsuba/plane_size_study.py [--spp-per-pass 256 --passes 16]
Writes nothing; prints the table the choice of translate.PLANE_HALF_SIZE rests on.
"""

import argparse
import pathlib
import subprocess
import sys
import tempfile

import mitsuba as mi
import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import translate  # noqa: E402

VALIDATION = pathlib.Path(__file__).resolve().parents[1]
SIZES = [1e2, 3e2, 1e3, 3e3, 1e4, 1e5, 1e6, 1e7, "graded"]
BASELINE = 1e3  # the size of the references of cases.toml
WAVELENGTH_NM = 550.0
CASES = [("tp6_point", "whitted", False), ("tp6_quad", "whitted", False), ("stokes_brewster", "path", True)]


read_exr = translate.read_exr


def s0_channel(image):
    """prisma's S0 (spectral radiance with --wavelength): R in the unpolarised layout, S0.R or the
    spectral-layout S0.<λ>nm channel in the polarised ones."""
    for name in ("S0.R", "R"):
        if name in image:
            return image[name]
    return next(v for k, v in image.items() if k.startswith("S0."))


def prisma_renders(scene_path, spp, seeds, out_dir, prisma, polarised):
    """`seeds` prisma renders at WAVELENGTH_NM, polarised or not (--unpolarized when the binary
    knows the flag; older binaries are unpolarised)."""
    help_text = subprocess.run([prisma, "render", "--help"], check=True, capture_output=True, text=True).stdout
    mode = [] if polarised or "--unpolarized" not in help_text else ["--unpolarized"]
    images = []
    for k in range(seeds):
        out = pathlib.Path(out_dir) / f"prisma_{k}.exr"
        subprocess.run([prisma, "render", str(scene_path), "--wavelength", str(WAVELENGTH_NM), "--spp", str(spp),
                        "--seed", str(7000 + k), "-o", str(out), "--quiet", *mode], check=True)
        images.append(s0_channel(read_exr(out)))
    return np.stack(images)


def study(name, integrator_kind, polarised, args, prisma):
    mi.set_variant("llvm_ad_mono_polarized" if polarised else "llvm_ad_mono")  # prisma likewise
    scene = translate.PrismaScene.load(VALIDATION / "scenes" / f"{name}.toml", prisma=prisma)
    integrator = (translate.whitted_integrator if integrator_kind == "whitted" else translate.path_integrator)(
        scene.max_depth)
    renders = {}
    for size in SIZES:
        translator = translate.Translator(scene, WAVELENGTH_NM, plane_half_size=size)
        mitsuba_scene = mi.load_dict(translator.scene_dict(integrator, args.spp_per_pass))
        mean, variance, _ = translate.render(mitsuba_scene, args.spp_per_pass, seed=11, passes=args.passes)
        renders[size] = (mean[..., 0], variance[..., 0])
    with tempfile.TemporaryDirectory() as tmp:
        prisma_stack = prisma_renders(VALIDATION / "scenes" / f"{name}.toml", args.prisma_spp, args.prisma_seeds, tmp,
                                      prisma, polarised)
    p_mean = prisma_stack.mean(axis=0)
    p_var = prisma_stack.var(axis=0, ddof=1) / prisma_stack.shape[0]
    baseline = renders[BASELINE][0]
    print(f"\n== {name} ({mi.variant()}, {integrator_kind}, {WAVELENGTH_NM:g} nm, "
          f"{args.spp_per_pass * args.passes} spp, seed 11; prisma {args.prisma_seeds} × {args.prisma_spp} spp)")
    print(f"{'half-size':>10} {'pixels Δ>1e-3':>13} {'max |Δ|/σ':>10} {'mean/mean(1e3) - 1':>19} "
          f"{'mean/prisma - 1':>16} {'± (1σ)':>9} {'z':>8} {'pixels |z|>5':>13}")
    for size in SIZES:
        mean, variance = renders[size]
        sigma = np.sqrt(variance)
        diff = mean - baseline
        changed = np.abs(diff) > 1e-3 * np.abs(baseline) + 1e-6
        worst = np.max(np.abs(diff[changed]) / np.maximum(sigma[changed], 1e-12)) if changed.any() else 0.0
        rel = mean.mean() / baseline.mean() - 1.0
        d = mean - p_mean
        se_mean = np.sqrt(variance.sum() + p_var.sum()) / mean.size
        floor = 1e-4 + 1e-3 * np.abs(mean)
        z = d / np.sqrt(variance + p_var + floor**2)
        where = ""
        if changed.any():
            ys, xs = np.nonzero(changed)
            where = f"  (rows {ys.min()}–{ys.max()}, columns {xs.min()}–{xs.max()})"
        label = size if isinstance(size, str) else f"{size:.0e}"
        print(f"{label:>10} {int(changed.sum()):>13d} {worst:>10.1f} {rel:>19.2e} {d.mean() / p_mean.mean():>16.2e} "
              f"{se_mean / p_mean.mean():>9.1e} {d.mean() / se_mean:>8.2f} {np.mean(np.abs(z) > 5):>13.4f}{where}")
    print("the pixels that change most between 1e3 and the graded mesh (value at each size):")
    escape_pixels(renders, p_mean)


def escape_pixels(renders, p_mean, count=3):
    """The pixels that change most between BASELINE and the graded mesh: their value at every
    size and prisma's (where a ray escapes past a finite rectangle, Mitsuba sees the background)."""
    if "graded" not in renders:
        return
    change = np.abs(renders[BASELINE][0] - renders["graded"][0])
    for i in np.argsort(change.ravel())[::-1][:count]:
        y, x = divmod(int(i), change.shape[1])
        values = ", ".join(f"{size if isinstance(size, str) else f'{size:.0e}'} {renders[size][0][y, x]:.5f}"
                           for size in SIZES)
        print(f"  pixel (row {y}, column {x}): {values}; prisma {p_mean[y, x]:.5f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--spp-per-pass", type=int, default=256)
    parser.add_argument("--passes", type=int, default=16)
    parser.add_argument("--prisma-spp", type=int, default=1024)
    parser.add_argument("--prisma-seeds", type=int, default=4)
    parser.add_argument("--cases", nargs="*", default=[c[0] for c in CASES])
    parser.add_argument("--prisma", help="prisma binary (default: $PRISMA or target/release/prisma)")
    args = parser.parse_args()
    prisma = args.prisma or translate.find_prisma()
    for name, kind, polarised in CASES:
        if name in args.cases:
            study(name, kind, polarised, args, prisma)


if __name__ == "__main__":
    main()

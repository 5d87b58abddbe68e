#!/usr/bin/env python3
"""Cross-check of prisma against the committed Mitsuba references, case by case (a diagnostic
for whoever renders the references; `prisma validate` is the project's real comparison).

For every case of validation/cases.toml it renders the scene with prisma at K seeds (same
resolution, `--wavelength` for monochromatic cases), then prints, per compared channel:
  - the ratio of image means prisma / Mitsuba, and Mitsuba seed 1 / seed 2 (the noise floor);
  - per-pixel relative differences (median and 95th percentile over pixels brighter than 1% of
    the channel's mean);
  - the fraction of pixels whose difference is within 3σ, σ² = σ²_prisma + σ²_Mitsuba, σ_prisma
    from the spread of the K prisma renders and σ_Mitsuba from the references' *_var.exr
    (estimated by render_references.py and caustics.py from their passes).
and writes a side-by-side PNG (Mitsuba | prisma | |difference| × 4) per case.

Run: validation/.venv/bin/python validation/mitsuba/compare.py [CASE ...] [--spp 256] [--seeds 8]
"""

import argparse
import pathlib
import subprocess
import sys
import tempfile
import tomllib

import mitsuba as mi
import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import translate  # noqa: E402

VALIDATION = pathlib.Path(__file__).resolve().parents[1]


read_exr = translate.read_exr


def prisma_renders(case, spp, seeds, out_dir, prisma):
    """K prisma renders of the case at distinct seeds; list of channel dicts."""
    renders = []
    for k in range(seeds):
        out = out_dir / f"{case['name']}_prisma_{k}.exr"
        cmd = [prisma, "render", str(VALIDATION / case["scene"]), "--spp", str(spp), "--seed", str(1000 + k),
               "-o", str(out), "--quiet"]
        if "wavelength_nm" in case:
            cmd += ["--wavelength", str(case["wavelength_nm"])]
        subprocess.run(cmd, check=True)
        renders.append(read_exr(out))
    return renders


def prisma_channel(mitsuba_channel):
    """prisma's channel for a Mitsuba channel: R, G, B alike; a mono `Y` is every prisma channel
    (prisma --wavelength writes the spectral radiance to all of them), so take R."""
    return "R" if mitsuba_channel == "Y" else mitsuba_channel


def srgb_preview(image):
    x = np.clip(image, 0.0, 1.0)
    x = np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)
    return (x * 255 + 0.5).astype(np.uint8)


def compare_case(case, spp, seeds, out_dir, prisma, references=None):
    """references: a directory holding the reference files instead of validation/references."""
    ref_paths = [references / pathlib.Path(r).name if references else VALIDATION / r for r in case["references"]]
    refs = [read_exr(p) for p in ref_paths]
    variance_paths = [p.with_name(p.stem + "_var.exr") for p in ref_paths]
    variances = [read_exr(p) if p.exists() else None for p in variance_paths]
    renders = prisma_renders(case, spp, seeds, out_dir, prisma)
    print(f"== {case['name']} ({spp} spp × {seeds} prisma seeds)")
    rows = []
    panels = {"mitsuba": [], "prisma": [], "diff": []}
    for channel in case["channels"]:
        ref = 0.5 * (refs[0][channel] + refs[1][channel])
        stack = np.stack([r[prisma_channel(channel)] for r in renders])
        ours = stack.mean(axis=0)
        sigma_ours = stack.std(axis=0, ddof=1) / np.sqrt(seeds)
        if all(v is not None for v in variances):
            sigma_ref = 0.5 * np.sqrt(variances[0][channel] + variances[1][channel])
        else:  # two seeds only: |s1 - s2|/2 is a one-degree-of-freedom estimate
            sigma_ref = 0.5 * np.abs(refs[0][channel] - refs[1][channel])
        sigma = np.sqrt(sigma_ours**2 + sigma_ref**2)
        diff = ours - ref
        # 1e-4 of the value: float32 accumulation in both renderers (Mitsuba sums passes of many samples).
        tolerance = 3.0 * sigma + 1e-4 * np.abs(ref)
        within = np.mean(np.abs(diff) <= tolerance)
        bright = ref > 0.01 * max(ref.mean(), 1e-12)
        rel = np.abs(diff[bright]) / ref[bright]
        rows.append((channel, ours.mean() / ref.mean(), refs[0][channel].mean() / refs[1][channel].mean(),
                     np.median(rel), np.percentile(rel, 95), within,
                     np.mean(np.abs(diff) / np.maximum(sigma + 1e-4 / 3 * np.abs(ref), 1e-12))))
        panels["mitsuba"].append(ref)
        panels["prisma"].append(ours)
        panels["diff"].append(4.0 * np.abs(diff))
    print(f"  {'ch':>3} {'prisma/mi':>10} {'mi s1/s2':>9} {'med|rel|':>9} {'p95|rel|':>9} {'≤3σ':>7} {'mean|z|':>8}")
    for channel, ratio, noise, med, p95, within, mean_z in rows:
        print(f"  {channel:>3} {ratio:10.5f} {noise:9.5f} {med:9.4f} {p95:9.4f} {100 * within:6.2f}% {mean_z:8.3f}")
    tiles = []
    for key in ("mitsuba", "prisma", "diff"):
        img = np.stack(panels[key], axis=-1)
        if img.shape[-1] == 1:
            img = np.repeat(img, 3, axis=-1)
        tiles += [srgb_preview(img), np.full((img.shape[0], 3, 3), 255, np.uint8)]
    preview = np.concatenate(tiles[:-1], axis=1)
    path = out_dir / f"{case['name']}_compare.png"
    mi.util.write_bitmap(str(path), preview)
    print(f"  preview: {path}")
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", help="case names (default: all)")
    parser.add_argument("--spp", type=int, default=256, help="prisma samples per pixel per seed")
    parser.add_argument("--seeds", type=int, default=8, help="prisma renders at distinct seeds")
    parser.add_argument("--out", type=pathlib.Path, help="working directory (default: temporary)")
    parser.add_argument("--references", type=pathlib.Path,
                        help="directory of the references (default: validation/references)")
    parser.add_argument("--prisma", help="prisma binary (default: $PRISMA or target/release/prisma)")
    args = parser.parse_args()
    mi.set_variant("scalar_rgb")
    prisma = args.prisma or translate.find_prisma()
    with open(VALIDATION / "cases.toml", "rb") as f:
        cases = tomllib.load(f)["case"]
    if args.cases:
        unknown = set(args.cases) - {c["name"] for c in cases}
        if unknown:
            sys.exit(f"unknown cases: {sorted(unknown)}")
        cases = [c for c in cases if c["name"] in args.cases]
    out_dir = args.out or pathlib.Path(tempfile.mkdtemp(prefix="prisma_compare_"))
    out_dir.mkdir(parents=True, exist_ok=True)
    for case in cases:
        compare_case(case, args.spp, args.seeds, out_dir, prisma, args.references)


if __name__ == "__main__":
    main()

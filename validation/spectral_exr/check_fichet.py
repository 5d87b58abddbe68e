#!/usr/bin/env python3
"""Reads prisma's spectral EXR back with colour-science and checks it (not part of CI).

prisma writes spectral radiance in the OpenEXR layout of Fichet, Pacanowski and Wilkie (JCGT
10(3), 2021): channels `S<k>.<λ>nm` (comma decimal), one per band and Stokes component, each the
mean spectral radiance over its band, with the attributes `spectralLayoutVersion`,
`emissiveUnits` and, when polarised, `polarisationHandedness`. This script renders a small scene
three times with the prisma binary:

  polarised      render --spectral-bands 16             (S0-S3 x 16 bands, plus RGB, XYZ, S0-S3 RGB)
  unpolarised    render --spectral-bands 16 --unpolarized   (S0 x 16 bands)
  monochromatic  render --wavelength 550                (S0-S3 at 550 nm only, attribute wavelengthNm)

and for each file checks
  1. every spectral channel name against the reference regex of the layout (the one the task
     quotes, which is colour-science's PATTERN_FICHET2021 anchored and with the S0-S3/T prefix);
  2. that colour-science's `read_spectral_image_Fichet2021` (through OpenImageIO) finds the
     expected components and wavelengths (the band centres, MIN + (i + 1/2)(MAX - MIN)/N);
  3. that the values it returns equal the same channels read directly with the `OpenEXR`
     package (an independent reader), bit for bit;
  4. the attributes (as colour-science reports them and as OpenEXR reads them);
  5. physics: |S1|, |S2|, |S3| <= S0 per band and pixel, and the image-mean CIE Y computed from
     the S0 bands with colour-science's CIE 1931 table agrees with prisma's XYZ.Y within 2 %.

Run from the repository root (Python 3.11+; PyPI reached through pip):

  cargo build --release
  python3 -m venv validation/spectral_exr/.venv
  validation/spectral_exr/.venv/bin/pip install -r validation/spectral_exr/requirements.txt
  validation/spectral_exr/.venv/bin/python validation/spectral_exr/check_fichet.py

It prints one line per check and exits 1 if any failed. Results: RESULT.md beside this file.
"""

from __future__ import annotations

import argparse
import platform
import re
import subprocess
import sys
import tempfile
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]

# The layout's channel-name grammar, as the task states it.
REFERENCE = re.compile(
    r"^((S([0-3]))|T)\.(\d*,?\d*([Ee][+-]?\d+)?)(Y|Z|E|P|T|G|M|k|h|da|d|c|m|u|n|p)?(m|Hz)$"
)
BANDS = 16
RANGE_NM = (360.0, 830.0)
MONO_NM = 550.0


@dataclass
class Report:
    """Check results, printed as they come."""

    failures: list[str] = field(default_factory=list)
    count: int = 0

    def check(self, name: str, ok: bool, detail: str = "") -> None:
        self.count += 1
        print(f"{'PASS' if ok else 'FAIL'}  {name}{': ' + detail if detail else ''}")
        if not ok:
            self.failures.append(name)


def render(prisma: Path, scene: Path, out: Path, *flags: str) -> Path:
    command = [str(prisma), "render", str(scene), "-o", str(out), "--width", "60", "--spp", "4", "--quiet", *flags]
    subprocess.run(command, check=True)
    return out


def direct_channels(path: Path) -> tuple[dict[str, np.ndarray], dict]:
    """Every channel and the header, read with the OpenEXR package."""
    import OpenEXR

    with OpenEXR.File(str(path), separate_channels=True) as exr:
        channels = {name: np.array(channel.pixels) for name, channel in exr.channels().items()}
        return channels, dict(exr.header())


def wavelength_nm(name: str) -> float:
    """`S0.374,687500nm` -> 374.6875."""
    match = REFERENCE.match(name)
    assert match and match.group(6) == "n" and match.group(7) == "m", name
    return float(match.group(4).replace(",", "."))


def check_file(
    report: Report,
    label: str,
    path: Path,
    components: list[str],
    centres: np.ndarray,
    polarised: bool,
    monochromatic: bool,
) -> None:
    from colour.io import read_spectral_image_Fichet2021

    channels, header = direct_channels(path)
    spectral = sorted(n for n in channels if n.startswith(("S0.", "S1.", "S2.", "S3.", "T.")) and n.endswith("m"))
    bad = [n for n in spectral if not REFERENCE.match(n)]
    report.check(f"{label}: {len(spectral)} spectral channel names match the reference regex", not bad, ", ".join(bad))
    expected_count = len(components) * len(centres)
    report.check(f"{label}: {expected_count} spectral channels expected", len(spectral) == expected_count, str(len(spectral)))

    read, specification = read_spectral_image_Fichet2021(str(path), additional_data=True)
    report.check(
        f"{label}: colour-science finds components {components}",
        sorted(read) == components,
        f"got {sorted(read)}",
    )
    report.check(
        f"{label}: emissive, polarised = {polarised}",
        specification.is_emissive and specification.is_polarised == polarised and not specification.is_bispectral,
        f"is_emissive {specification.is_emissive}, is_polarised {specification.is_polarised}",
    )
    height, width = next(iter(channels.values())).shape
    for component in components:
        if component not in read:
            continue
        wavelengths, values = read[component]
        order = np.argsort(wavelengths)
        wavelengths, values = wavelengths[order], values[:, :, order]
        report.check(
            f"{label}: {component} wavelengths are the band centres",
            wavelengths.shape == centres.shape and np.allclose(wavelengths, centres, rtol=0, atol=1e-9),
            f"{wavelengths[:3]}... vs {centres[:3]}...",
        )
        direct = {wavelength_nm(n): channels[n] for n in spectral if n.startswith(component + ".")}
        direct_stack = np.stack([direct[w] for w in sorted(direct)], axis=-1)
        same = values.shape == (height, width, len(centres)) and np.array_equal(values, direct_stack)
        report.check(
            f"{label}: {component} values equal the channels read directly with OpenEXR ({height}x{width}x{len(centres)})",
            same,
            f"shape {values.shape}, max |diff| {np.nanmax(np.abs(values - direct_stack)) if values.shape == direct_stack.shape else 'n/a'}",
        )

    attributes = {a.name: a.value for a in specification.attributes}
    expected = {"spectralLayoutVersion": "1.0", "emissiveUnits": "W.m^-2.sr^-1"}
    if polarised:
        expected["polarisationHandedness"] = "right"
    for name, value in expected.items():
        report.check(
            f"{label}: attribute {name} = {value!r} (colour-science and OpenEXR)",
            attributes.get(name) == value and header.get(name) == value,
            f"colour-science {attributes.get(name)!r}, OpenEXR {header.get(name)!r}",
        )
    if not polarised:
        report.check(f"{label}: no polarisationHandedness when unpolarised", "polarisationHandedness" not in header)
    if monochromatic:
        report.check(
            f"{label}: wavelengthNm = {MONO_NM}, no RGB channels",
            header.get("wavelengthNm") == MONO_NM and not any(n in channels for n in ("R", "S0.R", "XYZ.Y")),
            f"wavelengthNm {header.get('wavelengthNm')!r}",
        )
    else:
        report.check(f"{label}: chromaticities and RGB beside the bands", "chromaticities" in header and "R" in channels)

    if polarised and all(c in read for c in components):
        s0 = read["S0"][1]
        worst = max(float(np.max(np.abs(read[c][1]) - s0)) for c in ("S1", "S2", "S3"))
        report.check(f"{label}: |S1|, |S2|, |S3| <= S0 in every band and pixel", worst <= 1e-6 * max(1.0, float(s0.max())), f"largest excess {worst:.3g}")

    if not monochromatic and "XYZ.Y" in channels:
        import colour

        cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
        grid = np.arange(RANGE_NM[0], RANGE_NM[1] + 1.0)
        ybar = np.interp(grid, cmfs.wavelengths, cmfs.values[:, 1])
        width_nm = (RANGE_NM[1] - RANGE_NM[0]) / len(centres)
        # Y = ∫ L ȳ dλ / ∫ ȳ dλ; with band means L_b: Σ_b L_b ∫_band ȳ dλ / ∫ ȳ dλ.
        band_of = np.minimum(((grid - RANGE_NM[0]) / width_nm).astype(int), len(centres) - 1)
        ybar_per_band = np.bincount(band_of, weights=ybar, minlength=len(centres))
        waves, s0 = read["S0"]
        s0 = s0[:, :, np.argsort(waves)]
        y_bands = float((s0.mean(axis=(0, 1)) * ybar_per_band).sum() / ybar.sum())
        y_film = float(channels["XYZ.Y"].mean())
        ratio = y_bands / y_film
        report.check(
            f"{label}: image-mean Y from the S0 bands (colour's CIE 1931 ȳ) matches XYZ.Y within 2 %",
            abs(ratio - 1.0) < 0.02,
            f"{y_bands:.5f} vs {y_film:.5f} (ratio {ratio:.4f})",
        )


def versions(prisma: Path) -> str:
    import colour
    import OpenEXR
    import OpenImageIO

    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    prisma_version = subprocess.run([str(prisma), "--version"], capture_output=True, text=True).stdout.strip()
    return (
        f"Python {platform.python_version()}, colour-science {colour.__version__}, OpenImageIO {OpenImageIO.__version__}, "
        f"OpenEXR {getattr(OpenEXR, '__version__', '?')}, numpy {np.__version__}; {prisma_version} at {commit}"
    )


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--prisma", type=Path, default=ROOT / "target" / "release" / "prisma")
    parser.add_argument("--scene", type=Path, default=ROOT / "scenes" / "tp6_mirror_glass.toml")
    parser.add_argument("--keep", type=Path, help="write the EXR files here instead of a temporary directory")
    args = parser.parse_args()
    warnings.filterwarnings("ignore", message=".*related API features are not available.*")

    print(versions(args.prisma))
    centres = RANGE_NM[0] + (np.arange(BANDS) + 0.5) * (RANGE_NM[1] - RANGE_NM[0]) / BANDS
    report = Report()
    with tempfile.TemporaryDirectory() as temporary:
        out = args.keep or Path(temporary)
        out.mkdir(parents=True, exist_ok=True)
        bands = str(BANDS)
        polarised = render(args.prisma, args.scene, out / "polarised.exr", "--spectral-bands", bands)
        unpolarised = render(args.prisma, args.scene, out / "unpolarised.exr", "--spectral-bands", bands, "--unpolarized")
        mono = render(args.prisma, args.scene, out / "mono550.exr", "--wavelength", str(MONO_NM))
        stokes = ["S0", "S1", "S2", "S3"]
        check_file(report, "polarised", polarised, stokes, centres, polarised=True, monochromatic=False)
        check_file(report, "unpolarised", unpolarised, ["S0"], centres, polarised=False, monochromatic=False)
        check_file(report, "550 nm", mono, stokes, np.array([MONO_NM]), polarised=True, monochromatic=True)
    print(f"{report.count - len(report.failures)} passed, {len(report.failures)} failed")
    return 1 if report.failures else 0


if __name__ == "__main__":
    sys.exit(main())

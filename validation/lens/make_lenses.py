"""Writes the lens files of data/lenses/ (pbrt-v4 .dat with a glass column, and Zemax .zmx) from
the prescriptions below, with the last thickness (last vertex to image plane) at the paraxial
focus for the d line (587.5618 nm, object at infinity), computed here by a paraxial y-nu trace
in double precision with the Sellmeier coefficients of data/glasses.toml.

dgauss50_pbrt.dat is pbrt-v4's file as it is and is not written by this script.

Usage (from the repository root):
    validation/lens/.venv/bin/python validation/lens/make_lenses.py
"""

import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
LENSES = ROOT / "data" / "lenses"
LAMBDA_D_NM = 587.5618


def catalogue():
    with open(ROOT / "data" / "glasses.toml", "rb") as f:
        data = tomllib.load(f)
    out = {}
    for g in data["glass"]:
        if "sellmeier" in g:
            s = g["sellmeier"]
            c = s.get("c_um2") or [r * r for r in s["resonance_um"]]
            out[g["name"]] = (s["b"], c)
    return out


GLASSES = catalogue()


def index(glass, lam_nm):
    if glass == "air":
        return 1.0
    b, c = GLASSES[glass]
    l2 = (lam_nm * 1e-3) ** 2
    return (1.0 + sum(bi * l2 / (l2 - ci) for bi, ci in zip(b, c))) ** 0.5


# Each surface: (radius_mm, thickness_mm or None for the image distance, glass behind or "air",
# semi-diameter_mm, is_stop, pbrt eta column). Object side first.
PRESCRIPTIONS = {
    "singlet_nbk7": {
        "title": "N-BK7 equiconvex singlet, f = 100 mm, 1 inch, stop 5 mm in front, f/8",
        "surfaces": [
            (0.0, 5.0, "air", 6.25, True, 0.0),
            (102.4, 3.6, "N-BK7", 12.7, False, 1.5168),
            (-102.4, None, "air", 12.7, False, 1.0),
        ],
    },
    "achromat": {
        "title": "Thorlabs AC254-100-A cemented achromat (N-BK7/SF5), f = 100 mm, stop at the front vertex",
        "surfaces": [
            (0.0, 0.0, "air", 11.43, True, 0.0),
            (62.75, 4.0, "N-BK7", 12.7, False, 1.5168),
            (-45.71, 2.5, "SF5", 12.7, False, 1.6727),
            (-128.23, None, "air", 12.7, False, 1.0),
        ],
    },
    "dgauss50": {
        "title": "Double Gauss F/2 50 mm (pbrt-v4 dgauss.50mm.dat, Tronnier US 2,673,491) with real glasses",
        "surfaces": [
            (29.475, 3.76, "N-BAF10", 12.6, False, 1.67),
            (84.83, 0.12, "air", 12.6, False, 1.0),
            (19.275, 4.025, "N-BAF10", 11.5, False, 1.67),
            (40.77, 3.275, "N-SF15", 11.5, False, 1.699),
            (12.75, 5.705, "air", 9.0, False, 1.0),
            (0.0, 4.5, "air", 8.55, True, 0.0),
            (-14.495, 1.18, "F5", 8.5, False, 1.603),
            (40.77, 6.065, "N-SSK5", 10.0, False, 1.658),
            (-20.385, 0.19, "air", 10.0, False, 1.0),
            (437.065, 3.22, "S-LAM3", 10.0, False, 1.717),
            (-39.73, None, "air", 10.0, False, 1.0),
        ],
    },
}


def paraxial_image_distance(surfaces, lam_nm):
    """Last vertex to the paraxial focus of a ray parallel to the axis (y-nu trace)."""
    y, nu, n = 1.0, 0.0, 1.0
    for i, (r, t, glass, *_rest) in enumerate(surfaces):
        n2 = index(glass, lam_nm)
        c = 0.0 if r == 0.0 else 1.0 / r
        nu = nu - y * (n2 - n) * c
        n = n2
        if i + 1 < len(surfaces):
            y = y + t * nu / n
    return -y * n / nu


def fmt(x):
    return repr(float(x))


def write_pbrt(name, spec, image_mm):
    lines = [
        f"# {spec['title']}",
        "# prisma lens file: pbrt-v4's format with an optional 5th column, the glass behind the",
        "# surface (a catalogue name of data/glasses.toml, or air). Object side first; mm.",
        f"# Last thickness: the paraxial focus at the d line ({LAMBDA_D_NM} nm), object at infinity.",
        "# Written by validation/lens/make_lenses.py; see data/lenses/README.md.",
        "# radius thickness eta aperture_diameter glass",
    ]
    for r, t, glass, sd, _stop, eta in spec["surfaces"]:
        t = image_mm if t is None else t
        lines.append(f"{fmt(r)} {fmt(t)} {fmt(eta)} {fmt(2.0 * sd)} {glass}")
    (LENSES / f"{name}.dat").write_text("\n".join(lines) + "\n")


def write_zmx(name, spec, image_mm):
    # WAVM: the F, d, C lines (µm; rayoptics needs wavelengths to load a file and takes the
    # middle one, d, as its reference). They describe the analysis, not the lens. GCAT: the
    # catalogues to look glass names up in, in order (F5 is also a CDGM name).
    lines = ["UNIT MM", "WAVM 1 0.4861327 1", "WAVM 2 0.5875618 1", "WAVM 3 0.6562725 1",
             "GCAT SCHOTT OHARA", "SURF 0", "  TYPE STANDARD", "  CURV 0", "  DISZ INFINITY"]
    for i, (r, t, glass, sd, stop, _eta) in enumerate(spec["surfaces"], start=1):
        t = image_mm if t is None else t
        lines.append(f"SURF {i}")
        if stop:
            lines.append("  STOP")
        lines.append("  TYPE STANDARD")
        lines.append(f"  CURV {fmt(0.0 if r == 0.0 else 1.0 / r)}")
        lines.append(f"  DISZ {fmt(t)}")
        if glass != "air":
            lines.append(f"  GLAS {glass}")
        lines.append(f"  DIAM {fmt(sd)} 1")
    lines += [f"SURF {len(spec['surfaces']) + 1}", "  TYPE STANDARD", "  CURV 0", "  DISZ 0"]
    (LENSES / f"{name}.zmx").write_text("\n".join(lines) + "\n")


def main():
    for name, spec in PRESCRIPTIONS.items():
        image_mm = paraxial_image_distance(spec["surfaces"], LAMBDA_D_NM)
        print(f"{name}: paraxial image distance at d = {image_mm!r} mm")
        write_pbrt(name, spec, image_mm)
        write_zmx(name, spec, image_mm)


if __name__ == "__main__":
    main()

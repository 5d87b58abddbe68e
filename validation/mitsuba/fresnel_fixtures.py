#!/usr/bin/env python3
"""Mitsuba 3 reference values of the Fresnel equations, for tests/fresnel_fixtures.rs.

Writes three CSV files into tests/fixtures/ (each opening with '#' provenance lines):

  fresnel_dielectric.csv  mi.fresnel(cos_theta_i, eta)
      cos_theta_i,eta,reflectance,cos_theta_t,eta_it,eta_ti
  fresnel_polarized.csv   mi.fresnel_polarized(cos_theta_i, eta), amplitudes split into real and
                          imaginary parts (complex under total internal reflection)
      cos_theta_i,eta,a_s_re,a_s_im,a_p_re,a_p_im,cos_theta_t,eta_it,eta_ti
  fresnel_conductor.csv   mi.fresnel_conductor(cos_theta_i, eta_re + i eta_im)
      cos_theta_i,eta_re,eta_im,reflectance

Inputs are float32 values (Mitsuba's scalar variants compute in float32) written in their
shortest round-trip form, so that the Rust test feeds prisma exactly the same numbers. The grid
of cos_theta_i holds -1, 0 and 1 exactly, every relative index's critical angle and Brewster
angle, and their float32 neighbours. -0.0 is left out: Mitsuba treats it as incidence from the
exterior but signs cos_theta_t as for the interior, where prisma is consistent (exterior).

Run from the repository root, in the pinned environment of validation/requirements.txt:
  python3 -m venv validation/.venv
  validation/.venv/bin/pip install -r validation/requirements.txt
  validation/.venv/bin/python validation/mitsuba/fresnel_fixtures.py
"""

import argparse
import datetime
import math
import pathlib
import sys

import drjit as dr
import mitsuba as mi
import numpy as np

VARIANT = "scalar_rgb"

# Relative indices n_interior / n_exterior: rarer interiors (< 1, total internal reflection from
# the exterior), index-matched and near-matched, water, crown glass, diamond.
DIELECTRIC_ETAS = [0.5, 0.75, 1.0 / 1.5, 1.0, 1.0001, 1.33, 1.5, 2.4]

# Complex relative indices n + ik: metal-like values near Johnson & Christy's silver (550 nm),
# gold and copper (650 nm) and Rakic's aluminium (550 nm); a lossy dielectric; k = 0 denser and
# rarer than the exterior (the latter with total internal reflection).
CONDUCTOR_ETAS = [
    (0.05, 4.2),  # silver-like
    (0.17, 3.15),  # gold-like
    (0.21, 3.6),  # copper-like
    (1.0, 6.7),  # aluminium-like
    (2.0, 1.0),  # lossy dielectric
    (1.5, 0.0),
    (0.5, 0.0),
]

# cos_theta_i from -1 to 1 in steps of 1/128 (exact in float32, so -1, 0 and 1 are included).
GRID_POINTS = 257


def f32(x):
    return np.float32(x)


def text(x):
    """Shortest decimal that reads back as the same float32."""
    return str(f32(x))


def neighbours(x, count=2):
    """x and its `count` float32 neighbours on each side."""
    values = [f32(x)]
    up = down = f32(x)
    for _ in range(count):
        up = np.nextafter(up, f32(np.inf))
        down = np.nextafter(down, f32(-np.inf))
        values += [up, down]
    return values


def dielectric_cosines(eta):
    """The base grid plus the critical and Brewster angles of this eta, from both sides."""
    cosines = {f32(c) for c in np.linspace(-1.0, 1.0, GRID_POINTS, dtype=np.float64)}
    # Total internal reflection starts where sin(theta_i) = min(eta, 1/eta): from the exterior
    # when eta < 1, from the interior when eta > 1.
    sin_critical = min(eta, 1.0 / eta)
    cos_critical = math.sqrt(max(0.0, 1.0 - sin_critical * sin_critical))
    sign = 1.0 if eta < 1.0 else -1.0
    cosines.update(neighbours(sign * cos_critical))
    # Brewster: tan(theta_B) = eta_it, eta from the exterior and 1/eta from the interior.
    cosines.update(neighbours(math.cos(math.atan(eta)), 1))
    cosines.update(neighbours(-math.cos(math.atan(1.0 / eta)), 1))
    # No -0.0 (see the module docstring); keep cosines within [-1, 1].
    return sorted(c for c in cosines if -1.0 <= c <= 1.0 and not (c == 0.0 and math.copysign(1.0, c) < 0.0))


def conductor_cosines():
    cosines = {f32(c) for c in np.linspace(0.0, 1.0, 129, dtype=np.float64)}
    cosines.update(f32(c) for c in (1e-6, 1e-4, 1e-3, 0.999, 0.9999))
    return sorted(cosines)


def header(lines, title, columns, command):
    lines += [
        f"# {title}",
        f"# mitsuba {mi.__version__}, drjit {dr.__version__}, numpy {np.__version__}, "
        f"variant {VARIANT} (float32 arithmetic)",
        f"# generated {datetime.date.today().isoformat()} by: {command}",
        "# inputs are float32 values in shortest round-trip form; outputs likewise",
        columns,
    ]


def dielectric_rows(command):
    lines = []
    header(lines, "Mitsuba 3 mi.fresnel(cos_theta_i, eta): unpolarised dielectric Fresnel reflectance",
           "cos_theta_i,eta,reflectance,cos_theta_t,eta_it,eta_ti", command)
    for eta in map(f32, DIELECTRIC_ETAS):
        for cos_theta_i in dielectric_cosines(float(eta)):
            r, cos_theta_t, eta_it, eta_ti = mi.fresnel(float(cos_theta_i), float(eta))
            lines.append(",".join(text(v) for v in (cos_theta_i, eta, r, cos_theta_t, eta_it, eta_ti)))
    return lines


def polarized_rows(command):
    lines = []
    header(lines, "Mitsuba 3 mi.fresnel_polarized(cos_theta_i, eta + 0i): complex amplitudes a_s, a_p "
                  "(Verdet convention)",
           "cos_theta_i,eta,a_s_re,a_s_im,a_p_re,a_p_im,cos_theta_t,eta_it,eta_ti", command)
    for eta in map(f32, DIELECTRIC_ETAS):
        for cos_theta_i in dielectric_cosines(float(eta)):
            # Python binds only the complex-eta overload; a real eta has zero imaginary part, and
            # so do the eta_it, eta_ti it returns.
            a_s, a_p, cos_theta_t, eta_it, eta_ti = mi.fresnel_polarized(
                float(cos_theta_i), mi.Complex2f(float(eta), 0.0))
            assert dr.imag(eta_it) == 0.0 and dr.imag(eta_ti) == 0.0
            values = (cos_theta_i, eta, dr.real(a_s), dr.imag(a_s), dr.real(a_p), dr.imag(a_p),
                      cos_theta_t, dr.real(eta_it), dr.real(eta_ti))
            lines.append(",".join(text(v) for v in values))
    return lines


def conductor_rows(command):
    lines = []
    header(lines, "Mitsuba 3 mi.fresnel_conductor(cos_theta_i, eta): unpolarised reflectance of a "
                  "conductor of relative complex index eta_re + i eta_im",
           "cos_theta_i,eta_re,eta_im,reflectance", command)
    for eta_re, eta_im in CONDUCTOR_ETAS:
        eta = mi.Complex2f(float(f32(eta_re)), float(f32(eta_im)))
        for cos_theta_i in conductor_cosines():
            r = mi.fresnel_conductor(float(cos_theta_i), eta)
            lines.append(",".join(text(v) for v in (cos_theta_i, eta_re, eta_im, r)))
    return lines


def main():
    root = pathlib.Path(__file__).resolve().parents[2]
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=pathlib.Path, default=root / "tests" / "fixtures",
                        help="output directory (default: tests/fixtures)")
    args = parser.parse_args()
    mi.set_variant(VARIANT)
    command = "python " + " ".join([pathlib.Path(sys.argv[0]).as_posix()] + sys.argv[1:])
    args.out.mkdir(parents=True, exist_ok=True)
    for name, rows in [("fresnel_dielectric.csv", dielectric_rows),
                       ("fresnel_polarized.csv", polarized_rows),
                       ("fresnel_conductor.csv", conductor_rows)]:
        lines = rows(command)
        path = args.out / name
        path.write_text("\n".join(lines) + "\n")
        print(f"{path}: {sum(1 for line in lines if not line.startswith('#')) - 1} rows")


if __name__ == "__main__":
    main()

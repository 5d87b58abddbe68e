#!/usr/bin/env python3
"""Mitsuba 3 reference values of its Mueller-matrix functions, for Rust tests of prisma's
polarisation code against Mitsuba's own.

Writes plain CSV files into tests/fixtures/ (first line = column names, no comment lines; the
provenance is this docstring and the `generated_by` note below). Every number is a float32
value (Mitsuba's scalar variants compute in float32) in its shortest round-trip form, inputs
included, so that a Rust test feeds prisma exactly Mitsuba's inputs. A Mueller matrix is written
row-major as m00, m01, …, m33 (m_ij = row i, column j; it maps a Stokes column vector,
S_out = M·S_in).

  mueller_reflection.csv      mi.mueller.specular_reflection(cos_theta_i, eta_re + i eta_im)
      cos_theta_i,eta_re,eta_im,m00,...,m33
    - real eta (eta_im = 0): 1.5, 1/1.5, 1.33, 1.9, each at 40 regular angles (20 incident from
      outside, cos > 0, and 20 from inside, cos < 0), cos = 1, 0, −1, the Brewster angle from
      both sides, the critical angle (incidence from the denser side) and its float32
      neighbours, and angles of total internal reflection (where the matrix carries the phase
      shift);
    - complex eta, a conductor seen from outside (cos > 0): gold-like 0.35 + 2.7i,
      aluminium-like 1.0 + 6.6i, and 0 + 1e14i, the parameterisation translate.py uses for an
      ideal mirror (a perfect electric conductor: diag(1, 1, −1, −1) to 1.2e-7,
      polarisation_conventions.py). Convention: eta_im is written as handed to Mitsuba, the
      graphics convention n + ik with k ≥ 0; Mitsuba's fresnel_polarized conjugates it to
      n − ik internally ("kappa negative", Verdet convention for a_p), so a test that feeds
      prisma n + ik compares like with like.
  mueller_transmission.csv    mi.mueller.specular_transmission(cos_theta_i, eta), real eta
      cos_theta_i,eta,m00,...,m33
    on the same real-eta angles. It is the Fresnel transmittance matrix only (η_it·cos θt/cos θi
    times the squared amplitudes): Mitsuba's dielectric BSDF multiplies it by
    (1/η_it)² separately for radiance; zero under total internal reflection.
  fresnel_conductor_amplitudes.csv   mi.fresnel_polarized(cos_theta_i, eta_re + i eta_im)
      cos_theta_i,eta_re,eta_im,a_s_re,a_s_im,a_p_re,a_p_im,cos_theta_t,eta_it_re,eta_it_im,eta_ti_re,eta_ti_im
    for the complex etas above, cos_theta_i in (0, 1]. Mitsuba returns no transmission
    amplitude (a conductor transmits nothing); eta_it, eta_ti come back conjugated (n − ik).
  mueller_rotator.csv         mi.mueller.rotator(theta)
      theta_rad,m00,...,m33
  mueller_rotations.csv       mi.mueller.rotate_stokes_basis(forward, basis_current, basis_target)
      forward_x,forward_y,forward_z,current_x,current_y,current_z,target_x,target_y,target_z,m00,...,m33
    for (forward, current, target) triples with current and target orthogonal to forward:
    axis-aligned and skew forwards, target at ±30°, ±45°, ±90°, 180° and arbitrary angles from
    current (the sign of the angle is set by forward · (current × target)).
  mueller_elements.csv        mi.mueller.rotated_element(theta, element(parameter))
      element,parameter,theta_rad,m00,...,m33
    element "linear_polarizer" (parameter = value, the transmittance factor: Mitsuba's matrix is
    value/2·[[1,1,0,0],[1,1,0,0],0,0]) or "linear_retarder" (parameter = phase in radians,
    fast axis along the Stokes x axis, polarisation_conventions.py); theta_rad = 0 gives the
    element itself.

Run from the repository root after validation/setup.sh:
  validation/.venv/bin/python validation/mitsuba/mueller_fixtures.py [--out DIR]
"""

import argparse
import math
import pathlib

import drjit as dr
import mitsuba as mi
import numpy as np

VARIANT = "scalar_rgb"

REAL_ETAS = [1.5, 1.0 / 1.5, 1.33, 1.9]
# (n, k) with k ≥ 0, as handed to Mitsuba (see the module docstring).
COMPLEX_ETAS = [(0.35, 2.7), (1.0, 6.6), (0.0, 1e14)]
REGULAR_ANGLES = 20  # per side

ROTATOR_THETAS = [0.0, 0.1, math.pi / 12, math.pi / 8, math.pi / 6, math.pi / 4, 1.0, math.pi / 3,
                  math.pi / 2, 2.0, 3 * math.pi / 4, math.pi, -0.1, -math.pi / 6, -math.pi / 4, -math.pi / 2]


def f32(x):
    return np.float32(x)


def text(x):
    """Shortest decimal that reads back as the same float32."""
    return str(f32(x))


def matrix_entries(m):
    return [m[i, j] for i in range(4) for j in range(4)]


MATRIX_COLUMNS = [f"m{i}{j}" for i in range(4) for j in range(4)]


def neighbours(x):
    up = np.nextafter(f32(x), f32(np.inf))
    down = np.nextafter(f32(x), f32(-np.inf))
    return [f32(x), up, down]


def real_eta_cosines(eta):
    """40 regular angles (20 per side), the exact ends, Brewster from both sides, the critical
    angle with its float32 neighbours and angles of total internal reflection."""
    cosines = set()
    theta = (np.arange(REGULAR_ANGLES) + 0.5) / REGULAR_ANGLES * (math.pi / 2)
    cosines.update(f32(math.cos(t)) for t in theta)
    cosines.update(f32(-math.cos(t)) for t in theta)
    cosines.update([f32(1.0), f32(0.0), f32(-1.0)])
    cosines.add(f32(math.cos(math.atan(eta))))  # Brewster, from outside
    cosines.add(f32(-math.cos(math.atan(1.0 / eta))))  # Brewster, from inside
    # Critical angle: from outside when eta < 1 (cos > 0), from inside when eta > 1 (cos < 0).
    sign = 1.0 if eta < 1.0 else -1.0
    sin_c = min(eta, 1.0 / eta)
    cos_c = math.sqrt(1.0 - sin_c * sin_c)
    cosines.update(f32(sign * c) for c in neighbours(cos_c))
    # Deep in total internal reflection: angles between critical and grazing.
    theta_c = math.asin(sin_c)
    for frac in (0.25, 0.5, 0.75):
        cosines.add(f32(sign * math.cos(theta_c + frac * (math.pi / 2 - theta_c))))
    return sorted(c for c in cosines if -1.0 <= c <= 1.0)


def complex_eta_cosines():
    theta = (np.arange(36) + 0.5) / 36 * (math.pi / 2)
    cosines = {f32(math.cos(t)) for t in theta}
    cosines.update(f32(c) for c in (1.0, 1e-3, 0.01, 0.1))
    return sorted(cosines)


def reflection_rows():
    rows = [["cos_theta_i", "eta_re", "eta_im"] + MATRIX_COLUMNS]
    for eta in map(f32, REAL_ETAS):
        for c in real_eta_cosines(float(eta)):
            m = mi.mueller.specular_reflection(float(c), mi.Complex2f(float(eta), 0.0))
            rows.append([text(v) for v in [c, eta, 0.0] + matrix_entries(m)])
    for n, k in COMPLEX_ETAS:
        n, k = f32(n), f32(k)
        for c in complex_eta_cosines():
            m = mi.mueller.specular_reflection(float(c), mi.Complex2f(float(n), float(k)))
            rows.append([text(v) for v in [c, n, k] + matrix_entries(m)])
    return rows


def transmission_rows():
    rows = [["cos_theta_i", "eta"] + MATRIX_COLUMNS]
    for eta in map(f32, REAL_ETAS):
        for c in real_eta_cosines(float(eta)):
            m = mi.mueller.specular_transmission(float(c), float(eta))
            rows.append([text(v) for v in [c, eta] + matrix_entries(m)])
    return rows


def amplitude_rows():
    rows = [["cos_theta_i", "eta_re", "eta_im", "a_s_re", "a_s_im", "a_p_re", "a_p_im", "cos_theta_t",
             "eta_it_re", "eta_it_im", "eta_ti_re", "eta_ti_im"]]
    for n, k in COMPLEX_ETAS:
        n, k = f32(n), f32(k)
        for c in complex_eta_cosines():
            a_s, a_p, cos_t, eta_it, eta_ti = mi.fresnel_polarized(float(c), mi.Complex2f(float(n), float(k)))
            rows.append([text(v) for v in (c, n, k, dr.real(a_s), dr.imag(a_s), dr.real(a_p), dr.imag(a_p), cos_t,
                                           dr.real(eta_it), dr.imag(eta_it), dr.real(eta_ti), dr.imag(eta_ti))])
    return rows


def rotator_rows():
    rows = [["theta_rad"] + MATRIX_COLUMNS]
    for theta in map(f32, ROTATOR_THETAS):
        rows.append([text(v) for v in [theta] + matrix_entries(mi.mueller.rotator(float(theta)))])
    return rows


def rotation_triples():
    """(forward, current, target), float32 unit vectors, current and target ⟂ forward."""
    def unit(v):
        v = np.asarray(v, dtype=np.float64)
        return v / np.linalg.norm(v)

    triples = []
    forwards = [unit([0, 0, 1]), unit([0, 0, -1]), unit([1, 0, 0]), unit([0, -1, 0]), unit([1, 2, 3]),
                unit([-0.3, 0.8, -0.5])]
    for forward in forwards:
        helper = np.array([1.0, 0, 0]) if abs(forward[0]) < 0.9 else np.array([0, 1.0, 0])
        current = unit(np.cross(helper, forward))
        bitangent = np.cross(forward, current)
        for degrees in (0.0, 30.0, -30.0, 45.0, -45.0, 90.0, -90.0, 180.0, 117.0, -71.0):
            a = math.radians(degrees)
            target = unit(math.cos(a) * current + math.sin(a) * bitangent)
            triples.append((forward, current, target))
    return [tuple(np.array([f32(x) for x in v]) for v in triple) for triple in triples]


def rotations_rows():
    names = [f"{v}_{a}" for v in ("forward", "current", "target") for a in "xyz"]
    rows = [names + MATRIX_COLUMNS]
    for forward, current, target in rotation_triples():
        m = mi.mueller.rotate_stokes_basis(mi.Vector3f(*map(float, forward)), mi.Vector3f(*map(float, current)),
                                           mi.Vector3f(*map(float, target)))
        rows.append([text(v) for v in list(forward) + list(current) + list(target) + matrix_entries(m)])
    return rows


def elements_rows():
    rows = [["element", "parameter", "theta_rad"] + MATRIX_COLUMNS]
    thetas = [0.0, 0.3, math.pi / 8, math.pi / 4, math.pi / 3, math.pi / 2, -0.7, 2.5]
    elements = [("linear_polarizer", v, mi.mueller.linear_polarizer) for v in (1.0, 0.8)] + \
               [("linear_retarder", p, mi.mueller.linear_retarder) for p in (math.pi / 2, math.pi, 0.4, -math.pi / 2)]
    for name, parameter, make in elements:
        parameter = f32(parameter)
        for theta in map(f32, thetas):
            m = mi.mueller.rotated_element(float(theta), make(float(parameter)))
            rows.append([name] + [text(v) for v in [parameter, theta] + matrix_entries(m)])
    return rows


def main():
    root = pathlib.Path(__file__).resolve().parents[2]
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=pathlib.Path, default=root / "tests" / "fixtures",
                        help="output directory (default: tests/fixtures)")
    args = parser.parse_args()
    mi.set_variant(VARIANT)
    args.out.mkdir(parents=True, exist_ok=True)
    print(f"mitsuba {mi.__version__}, drjit {dr.__version__}, numpy {np.__version__}, variant {VARIANT}")
    for name, make in [("mueller_reflection.csv", reflection_rows),
                       ("mueller_transmission.csv", transmission_rows),
                       ("fresnel_conductor_amplitudes.csv", amplitude_rows),
                       ("mueller_rotator.csv", rotator_rows),
                       ("mueller_rotations.csv", rotations_rows),
                       ("mueller_elements.csv", elements_rows)]:
        rows = make()
        path = args.out / name
        path.write_text("\n".join(",".join(row) for row in rows) + "\n")
        print(f"{path}: {len(rows) - 1} rows")


if __name__ == "__main__":
    main()

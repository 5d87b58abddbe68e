"""Thin-film fixtures for tests/thin_film_fixtures.rs, computed by the `tmm` package (Byrnes,
arXiv:1603.02720), pinned in requirements.txt.

    python3 -m venv validation/thinfilm/.venv
    validation/thinfilm/.venv/bin/pip install -r validation/thinfilm/requirements.txt
    validation/thinfilm/.venv/bin/python validation/thinfilm/make_fixtures.py

writes tests/fixtures/thin_film_<case>.csv, one file per case, every value in shortest
round-trip form (repr), so that the files add no rounding of their own.

Conventions (the mapping from tmm's to prisma's, see src/optics/thin_film.rs):
- tmm writes fields E e^{i(kz - wt)} and absorbing indices n + ik (k > 0); prisma writes
  E e^{i(wt - kz)} and n - ik. The same physical wave has conjugate complex amplitudes in the
  two, so prisma's r_s, r_p, t_s, t_p are the complex conjugates of tmm's. A user gives an index
  as n + ik in both (prisma conjugates it internally), so the indices below are passed as they
  are.
- tmm's interface_r/interface_t for p are Hecht's r_par, t_par, the signs prisma's Fresnel
  functions use (r_p = -r_s at normal incidence): no sign change.
- Ellipsometry: prisma defines tan(psi) e^{i Delta} = r_p / r_s in its own conventions, Delta in
  (-180, 180] degrees, so that a bare dielectric below Brewster's angle has Delta = 180.
  tmm.ellips returns psi = arctan|r_p/r_s| (the same) and Delta_tmm = angle(-r_p/r_s) in tmm's
  conventions; hence Delta = 180 - Delta_tmm (conjugation flips the sign, the minus sign adds
  180), wrapped to (-180, 180].
- R and T are tmm's (T with Byrnes' factor Re(n_s conj(cos th_s)) / Re(n_0 conj(cos th_0)) for
  p, Re(n_s cos th_s) / Re(n_0 cos th_0) for s): the power entering the substrate, absorbing
  substrates (gold) included.
"""

import datetime
import importlib.metadata
import math
import os
import sys

import numpy as np
import tmm

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.normpath(os.path.join(HERE, "..", "..", "tests", "fixtures"))

DESIGN_NM = 550.0
AIR = 1.0
MGF2 = 1.38
N_BK7 = 1.5168  # N-BK7 at the d line (587.6 nm), constant across the spectrum here
ZRO2 = 2.05
TIO2 = 2.4
SIO2 = 1.46
WATER = 1.333
GOLD = 0.18 + 3.43j  # gold near 650 nm, n + ik, constant across the spectrum here


def quarter_wave(n):
    return DESIGN_NM / (4.0 * n)


# name: (ambient index, [(layer index, thickness nm), ...] from the ambient side, substrate index,
# description for the header)
CASES = {
    "mgf2_on_bk7": (
        AIR,
        [(MGF2, quarter_wave(MGF2))],
        N_BK7,
        "air | MgF2 1.38, quarter wave at 550 nm | N-BK7 1.5168",
    ),
    "ar4_on_bk7": (
        AIR,
        [(MGF2, 99.64), (ZRO2, 134.15), (MGF2, 30.0), (ZRO2, 15.0)],
        N_BK7,
        "air | MgF2 1.38 99.64 nm (quarter wave at 550) | ZrO2 2.05 134.15 nm (half wave) | "
        "MgF2 30 nm | ZrO2 15 nm | N-BK7 1.5168: four-layer AR, inner thicknesses from a 2.5 nm "
        "grid search for the lowest mean R over 420-680 nm at normal incidence (0.18 %)",
    ),
    "mirror_tio2_sio2": (
        AIR,
        [(TIO2, quarter_wave(TIO2)), (SIO2, quarter_wave(SIO2))] * 8,
        N_BK7,
        "air | (TiO2 2.4 | SiO2 1.46) x 8, quarter waves at 550 nm | N-BK7 1.5168",
    ),
    "sio2_on_gold": (
        AIR,
        [(SIO2, 100.0)],
        GOLD,
        "air | SiO2 1.46 100 nm | gold 0.18 + 3.43i (n + ik)",
    ),
    "soap_film": (
        AIR,
        [(WATER, 500.0)],
        AIR,
        "air | water 1.333 500 nm | air (free-standing soap film)",
    ),
}

WAVELENGTHS_NM = sorted(set(list(range(360, 821, 20)) + [550, 830]))
ANGLES_DEG = list(range(0, 86, 5)) + [89]

COLUMNS = [
    "wavelength_nm", "theta_deg", "R_s", "R_p", "T_s", "T_p", "psi_deg", "delta_deg",
    "r_s_re", "r_s_im", "r_p_re", "r_p_im", "t_s_re", "t_s_im", "t_p_re", "t_p_im",
]


def wrap_degrees(angle):
    """Wraps to (-180, 180]."""
    wrapped = math.fmod(angle, 360.0)
    if wrapped > 180.0:
        wrapped -= 360.0
    if wrapped <= -180.0:
        wrapped += 360.0
    return wrapped


def cx(index):
    """An index n + ik as "n k", shortest round-trip form."""
    index = complex(index)
    return f"{index.real!r} {index.imag!r}"


def row(ambient, layers, substrate, wavelength, theta_deg):
    n_list = [ambient] + [n for n, _ in layers] + [substrate]
    d_list = [np.inf] + [d for _, d in layers] + [np.inf]
    theta = math.radians(theta_deg)
    s = tmm.coh_tmm("s", n_list, d_list, theta, wavelength)
    p = tmm.coh_tmm("p", n_list, d_list, theta, wavelength)
    ellips = tmm.ellips(n_list, d_list, theta, wavelength)
    psi_deg = math.degrees(float(ellips["psi"]))
    delta_deg = wrap_degrees(180.0 - math.degrees(float(ellips["Delta"])))
    # prisma's amplitudes are the conjugates of tmm's (time convention, see the docstring).
    r_s, r_p = np.conj(complex(s["r"])), np.conj(complex(p["r"]))
    t_s, t_p = np.conj(complex(s["t"])), np.conj(complex(p["t"]))
    values = [
        float(wavelength), float(theta_deg),
        float(s["R"]), float(p["R"]), float(np.real(s["T"])), float(np.real(p["T"])),
        psi_deg, delta_deg,
        r_s.real, r_s.imag, r_p.real, r_p.imag, t_s.real, t_s.imag, t_p.real, t_p.imag,
    ]
    return ",".join(repr(float(v)) for v in values)


def main():
    date = datetime.date.today().isoformat()
    python = ".".join(str(v) for v in sys.version_info[:3])
    for name, (ambient, layers, substrate, description) in CASES.items():
        path = os.path.join(OUT, f"thin_film_{name}.csv")
        with open(path, "w", newline="\n") as f:
            f.write(f"# thin film '{name}': {description}\n")
            # Machine-readable stack, read by tests/thin_film_fixtures.rs: "re im" indices
            # (n + ik), layers as "re im thickness_nm" from the ambient side, ";"-separated.
            f.write(f"# ambient: {cx(ambient)}\n")
            f.write("# layers: " + "; ".join(f"{cx(n)} {d!r}" for n, d in layers) + "\n")
            f.write(f"# substrate: {cx(substrate)}\n")
            f.write(f"# tmm {importlib.metadata.version('tmm')}, "
                    f"numpy {np.__version__}, Python {python}; coh_tmm and ellips in float64\n")
            f.write(f"# generated {date} by: validation/thinfilm/.venv/bin/python "
                    f"validation/thinfilm/make_fixtures.py\n")
            f.write("# prisma's conventions (e^{i(wt - kz)}, Hecht's r_p): amplitudes are conj(tmm's), "
                    "delta_deg = 180 - Delta_tmm wrapped to (-180, 180]; psi, R, T are tmm's\n")
            f.write(",".join(COLUMNS) + "\n")
            for wavelength in WAVELENGTHS_NM:
                for theta_deg in ANGLES_DEG:
                    f.write(row(ambient, layers, substrate, float(wavelength), theta_deg) + "\n")
        print(f"wrote {path}")


if __name__ == "__main__":
    main()

"""Normal-incidence reflectances of every surface of the coated double Gauss
(data/lenses/dgauss50_coated.dat), computed by the `tmm` package (Byrnes, arXiv:1603.02720),
pinned in requirements.txt, for tests/lens_coating.rs.

    python3 -m venv validation/thinfilm/.venv
    validation/thinfilm/.venv/bin/pip install -r validation/thinfilm/requirements.txt
    validation/thinfilm/.venv/bin/python validation/thinfilm/make_lens_fixture.py

writes tests/fixtures/thin_film_dgauss50_coated.csv: one row per wavelength and surface with
the indices on both sides, whether the surface is coated, and R at normal incidence (tmm's
coh_tmm, s polarisation, equal to p at normal incidence), every value in shortest round-trip
form.

The lens is described here independently of prisma's reader: the glass behind each surface is
the 5th column of data/lenses/dgauss50.dat (the uncoated lens), its index from the Sellmeier
coefficients of data/glasses.toml (n^2 = 1 + sum B_i l^2 / (l^2 - C_i), l in um; the published
SCHOTT/OHARA coefficients), and every surface between air and a glass carries one layer of MgF2
of index 1.38 and thickness 550 / (4 * 1.38) nm (a quarter wave at 550 nm), the definition of
dgauss50_coated.dat. Cemented surfaces (glass | glass) and the stop (air | air) are bare.
"""

import datetime
import importlib.metadata
import math
import os
import sys
import tomllib

import numpy as np
import tmm

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
OUT = os.path.join(ROOT, "tests", "fixtures", "thin_film_dgauss50_coated.csv")

MGF2 = 1.38
DESIGN_NM = 550.0
WAVELENGTHS_NM = [400.0, 486.1327, 550.0, 587.5618, 656.2725, 750.0]


def glasses():
    with open(os.path.join(ROOT, "data", "glasses.toml"), "rb") as f:
        catalogue = tomllib.load(f)
    return {g["name"]: g["sellmeier"] for g in catalogue["glass"] if "sellmeier" in g}


def index(sellmeier, wavelength_nm):
    l2 = (wavelength_nm * 1e-3) ** 2
    c = sellmeier.get("c_um2") or [r * r for r in sellmeier["resonance_um"]]
    return math.sqrt(1.0 + sum(b * l2 / (l2 - ci) for b, ci in zip(sellmeier["b"], c)))


def media():
    """The glass name behind each surface of dgauss50.dat ("air" for air)."""
    names = []
    with open(os.path.join(ROOT, "data", "lenses", "dgauss50.dat")) as f:
        for line in f:
            content = line.split("#")[0].split()
            if content:
                names.append(content[4])
    return names


def main():
    catalogue = glasses()
    names = media()
    date = datetime.date.today().isoformat()
    python = ".".join(str(v) for v in sys.version_info[:3])
    thickness = DESIGN_NM / (4.0 * MGF2)
    with open(OUT, "w", newline="\n") as f:
        f.write("# normal-incidence R of each surface of data/lenses/dgauss50_coated.dat: the glasses of "
                "dgauss50.dat (Sellmeier, data/glasses.toml), air | glass surfaces with MgF2 1.38 "
                f"{thickness!r} nm (quarter wave at 550 nm), glass | glass and air | air bare\n")
        f.write(f"# tmm {importlib.metadata.version('tmm')}, numpy {np.__version__}, Python {python}; "
                "coh_tmm('s', ..., th_0 = 0) in float64\n")
        f.write(f"# generated {date} by: validation/thinfilm/.venv/bin/python "
                "validation/thinfilm/make_lens_fixture.py\n")
        f.write("wavelength_nm,surface,n_before,n_after,coated,R\n")
        for wavelength in WAVELENGTHS_NM:
            n = [1.0] + [1.0 if name == "air" else index(catalogue[name], wavelength) for name in names]
            for surface in range(1, len(names) + 1):
                n_before, n_after = n[surface - 1], n[surface]
                coated = (names[surface - 2] == "air" if surface > 1 else True) != (names[surface - 1] == "air")
                layers = [MGF2] if coated else []
                d_list = [np.inf] + [thickness] * len(layers) + [np.inf]
                result = tmm.coh_tmm("s", [n_before] + layers + [n_after], d_list, 0.0, wavelength)
                f.write(f"{wavelength!r},{surface},{n_before!r},{n_after!r},{int(coated)},{float(result['R'])!r}\n")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()

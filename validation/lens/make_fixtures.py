"""Reference numbers for the lenses of data/lenses/, from rayoptics (an optical design code),
written as validation/lens/fixtures/NAME.json (schema and conventions: validation/lens/README.md).

For each lens's .zmx, opened with rayoptics' open_model:
- paraxial first-order data at six wavelengths (EFL, BFL, FFL, pupils, f-number, focus and
  the longitudinal chromatic focal shift), each also recomputed here by an independent 2x2
  paraxial matrix trace with the Sellmeier formulas of data/glasses.toml (residuals stored);
- real rays (object at infinity) given as a start point on the plane z = Z_START_MM and a unit
  direction, traced by rayoptics to the image plane: intercepts and exit direction cosines;
- RMS spot radii over a stated pupil grid, vignetting by every clear aperture applied.

Usage (from the repository root):
    validation/lens/.venv/bin/python validation/lens/make_fixtures.py
"""

import datetime
import json
import math
import platform
import sys
import tempfile
import tomllib
from importlib.metadata import version
from pathlib import Path

import numpy as np
from rayoptics.environment import open_model
from rayoptics.raytr import raytrace as rt

ROOT = Path(__file__).resolve().parents[2]
OUT = ROOT / "validation" / "lens" / "fixtures"
COMMAND = "validation/lens/.venv/bin/python validation/lens/make_fixtures.py"

LAMBDA_D_NM = 587.5618
# F, d, C lines first, then three more across the visible.
WAVELENGTHS_NM = [486.1327, 587.5618, 656.2725, 450.0, 550.0, 650.0]
FIELD_FRACTIONS = [0.0, 0.7, 1.0]
# Real rays start on the plane 10 mm in front of the first surface's vertex.
Z_START_MM = -10.0
# Pupil points (px, py) of the listed real rays, in units of the entrance pupil radius.
RAY_PUPILS = [
    ("chief", 0.0, 0.0),
    ("marginal +y", 0.0, 1.0),
    ("marginal -y", 0.0, -1.0),
    ("half +y", 0.0, 0.5),
    ("sagittal +x", 1.0, 0.0),
    ("skew", 0.5, 0.5),
    ("skew", -0.6, 0.3),
    ("skew", 0.7071067811865476, -0.7071067811865476),
]
GRID_N = 32

LENSES = {
    # name: maximum field angle in degrees (object at infinity, field along +y)
    "singlet_nbk7": 5.0,
    "achromat": 5.0,
    "dgauss50": 20.0,
    "dgauss50_pbrt": 20.0,
}


# ----------------------------------------------------------------------------------------
# Independent paraxial check: 2x2 matrices on (y, n·u), Sellmeier from data/glasses.toml.

def catalogue():
    with open(ROOT / "data" / "glasses.toml", "rb") as f:
        data = tomllib.load(f)
    out = {}
    for g in data["glass"]:
        if "sellmeier" in g:
            s = g["sellmeier"]
            c = s.get("c_um2") or [r * r for r in s["resonance_um"]]
            out[g["name"]] = (list(s["b"]), list(c))
    return out


GLASSES = catalogue()


def sellmeier(glass, lam_nm):
    if glass == "air":
        return 1.0
    if glass.startswith("n="):  # one index at every wavelength (pbrt's own lens files)
        return float(glass[2:])
    b, c = GLASSES[glass]
    l2 = (lam_nm * 1e-3) ** 2
    return math.sqrt(1.0 + sum(bi * l2 / (l2 - ci) for bi, ci in zip(b, c)))


def refraction(c, n, n2):
    return np.array([[1.0, 0.0], [-(n2 - n) * c, 1.0]])


def transfer(t, n):
    return np.array([[1.0, t / n], [0.0, 1.0]])


def paraxial_check(surfaces, stop, lam_nm):
    """First-order data of `surfaces` [(curvature, thickness, glass, sd)] at lam_nm, this
    project's conventions (z toward the image, positions relative to first/last vertex)."""
    n = [1.0] + [sellmeier(s[2], lam_nm) for s in surfaces]
    # matrix from the first vertex plane (object space) to just after surface j
    def system(upto):
        m = np.eye(2)
        for j in range(upto + 1):
            if j > 0:
                m = transfer(surfaces[j - 1][1], n[j]) @ m
            m = refraction(surfaces[j][0], n[j], n[j + 1]) @ m
        return m

    k = len(surfaces) - 1
    (a, b), (c, d) = system(k)
    efl = -1.0 / c
    bfl = -a / c
    ffl = d / c
    # entrance pupil: the chief ray (0, 1) just after the stop, back to object space
    m_stop = system(stop)
    y0, nu0 = np.linalg.solve(m_stop, np.array([0.0, 1.0]))
    enp_z = -y0 / nu0
    # marginal ray parallel at height 1: its height at the stop scales the stop to the pupil
    y_stop = (m_stop @ np.array([1.0, 0.0]))[0]
    enp_radius = surfaces[stop][3] / abs(y_stop)
    # exit pupil: chief ray from the stop centre forward to image space
    m_after = np.linalg.solve(m_stop.T, system(k).T).T  # system(k) @ inv(m_stop)
    yk, nuk = m_after @ np.array([0.0, 1.0])
    exp_z = -yk / nuk
    ym, num = system(k) @ np.array([enp_radius, 0.0])
    exp_radius = abs(ym + num * exp_z)
    return {
        "efl_mm": efl, "bfl_mm": bfl, "ffl_mm": ffl,
        "entrance_pupil_z_mm": enp_z, "entrance_pupil_diameter_mm": 2 * enp_radius,
        "exit_pupil_z_from_last_mm": exp_z, "exit_pupil_diameter_mm": 2 * exp_radius,
        "f_number": efl / (2 * enp_radius),
    }


def own_real_trace(surfaces, start, direction, lam_nm):
    """Independent real-ray trace (vector Snell's law, sphere intersection nearest the
    vertex) from `start` on the start plane to the image plane: (x, y) at the image and the
    direction after the last surface."""
    p = np.array(start, dtype=float)
    d = np.array(direction, dtype=float)
    n1 = 1.0
    z_vertex = 0.0
    for c, t, glass, _sd in surfaces:
        q = p - np.array([0.0, 0.0, z_vertex])
        b = c * q.dot(d) - d[2]
        cc = c * q.dot(q) - 2.0 * q[2]
        s = cc / (-b + math.sqrt(b * b - c * cc))
        q = q + s * d
        normal = np.array([-c * q[0], -c * q[1], 1.0 - c * q[2]])
        n2 = sellmeier(glass, lam_nm)
        mu = n1 / n2
        cos_i = d.dot(normal)
        d = mu * d + (math.sqrt(1.0 - mu * mu * (1.0 - cos_i * cos_i)) - mu * cos_i) * normal
        p = q + np.array([0.0, 0.0, z_vertex])
        n1 = n2
        z_vertex += t
    s = (z_vertex - p[2]) / d[2]
    p = p + s * d
    return p[:2], d


def normal_incidence_transmission(surfaces, lam_nm):
    """Closed form Π(1 − R), R = ((n1 − n2)/(n1 + n2))², over every surface at normal
    incidence (uncoated, no absorption, no multiple reflections)."""
    t, n1 = 1.0, 1.0
    for _c, _t, glass, _sd in surfaces:
        n2 = sellmeier(glass, lam_nm)
        t *= 1.0 - ((n1 - n2) / (n1 + n2)) ** 2
        n1 = n2
    return t


def thick_lens_efl(r1, r2, t, n):
    """1/f = (n−1)[1/R1 − 1/R2 + (n−1)t/(n R1 R2)] (thick lens in air)."""
    return 1.0 / ((n - 1.0) * (1.0 / r1 - 1.0 / r2 + (n - 1.0) * t / (n * r1 * r2)))


# ----------------------------------------------------------------------------------------
# pbrt-v4's own double Gauss (one index per element): traced as pbrt sees it, with the image
# plane at its paraxial focus (the same at every wavelength), through a .zmx written here.

PBRT_DAT = {"dgauss50_pbrt": ROOT / "data" / "lenses" / "dgauss50_pbrt.dat"}
PBRT_ZMX = {}


def pbrt_rows(path):
    rows = []
    for line in path.read_text().splitlines():
        line = line.split("#", 1)[0].split()
        if line:
            rows.append([float(v) for v in line[:4]])
    return rows


def write_pbrt_zmx(name, tmpdir):
    rows = pbrt_rows(PBRT_DAT[name])
    glass = ["air" if eta in (0.0, 1.0) else f"n={eta!r}" for _r, _t, eta, _a in rows]
    surfaces = [(0.0 if r == 0 else 1.0 / r, t, g, a / 2) for (r, t, _e, a), g in zip(rows, glass)]
    n = [1.0] + [sellmeier(g, LAMBDA_D_NM) for g in glass]
    m = np.eye(2)
    for j, (c, th, _g, _sd) in enumerate(surfaces):
        if j > 0:
            m = transfer(surfaces[j - 1][1], n[j]) @ m
        m = refraction(c, n[j], n[j + 1]) @ m
    image = float(-m[0, 0] / m[1, 0])
    lines = ["UNIT MM", "WAVM 1 0.4861327 1", "WAVM 2 0.5875618 1", "WAVM 3 0.6562725 1",
             "SURF 0", "  TYPE STANDARD", "  CURV 0", "  DISZ INFINITY"]
    for i, ((r, th, eta, ap), g) in enumerate(zip(rows, glass), start=1):
        th = image if i == len(rows) else th
        lines += [f"SURF {i}"] + (["  STOP"] if r == 0.0 and eta == 0.0 else []) + [
            "  TYPE STANDARD", f"  CURV {0.0 if r == 0 else 1.0 / r!r}", f"  DISZ {th!r}"]
        if g != "air":
            lines.append(f"  GLAS ___BLANK 1 0 {eta!r} 0")  # V_d = 0: a constant index
        lines.append(f"  DIAM {ap / 2!r} 1")
    lines += [f"SURF {len(rows) + 1}", "  TYPE STANDARD", "  CURV 0", "  DISZ 0"]
    path = Path(tmpdir) / f"{name}.zmx"
    path.write_text("\n".join(lines) + "\n")
    PBRT_ZMX[name] = path


# ----------------------------------------------------------------------------------------
# rayoptics

def zmx_path(name):
    return PBRT_ZMX.get(name, ROOT / "data" / "lenses" / f"{name}.zmx")


def load(name, finite_object_mm=None):
    opm, info = open_model(zmx_path(name), info=True)
    track, not_found = info
    assert not not_found and track.get("glass substituted", 0) == 0 and \
        track.get("glass not found", 0) == 0, (name, info)
    sm, osp = opm["seq_model"], opm["optical_spec"]
    # rayoptics leaves the stop unset when STOP is on surface 1 (set_stop needs > 2 surfaces).
    stops = [i for i, line in enumerate(_surface_blocks(name), start=1) if "STOP" in line]
    assert len(stops) == 1
    sm.stop_surface = stops[0]
    osp["wvls"].set_from_list([(w, 1.0) for w in WAVELENGTHS_NM])
    osp["wvls"].reference_wvl = WAVELENGTHS_NM.index(LAMBDA_D_NM)
    if finite_object_mm is not None:
        sm.gaps[0].thi = finite_object_mm
    opm.update_model()
    return opm


def _surface_blocks(name):
    text = zmx_path(name).read_text()
    blocks = text.split("SURF ")[2:-1]  # skip header+object, drop the image
    return blocks


def dat_vs_zmx(name, surfaces, stop_index):
    """Largest relative difference between the .dat file's numbers and the .zmx's as rayoptics
    read them (radius against 1/CURV, thickness, semi-diameter); glasses and stop must agree."""
    rows = []
    dat = PBRT_DAT.get(name, ROOT / "data" / "lenses" / f"{name}.dat")
    for line in dat.read_text().splitlines():
        line = line.split("#", 1)[0].split()
        if line:
            rows.append(line)
    assert len(rows) == len(surfaces), (name, len(rows), len(surfaces))
    worst = 0.0
    for i, (row, (cv, t, glass, sd)) in enumerate(zip(rows, surfaces)):
        r, th, eta, ap = float(row[0]), float(row[1]), float(row[2]), float(row[3])
        if len(row) > 4:
            g = row[4]
        else:  # pbrt's own file: eta 0 or 1 is air, otherwise one index at every wavelength
            g = "air" if eta in (0.0, 1.0) else f"n={eta!r}"
            if i == len(rows) - 1:
                th = t  # pbrt leaves the image distance to its focusing (0 in the file)
        assert g == glass, (name, i, g, glass)
        assert (r == 0.0) == (i == stop_index or cv == 0.0)
        r_zmx = 0.0 if cv == 0.0 else 1.0 / cv
        for a, b in ((r, r_zmx), (th, t), (ap / 2.0, sd)):
            if a != b:
                worst = max(worst, abs(a - b) / abs(b))
    return worst


def surfaces_of(opm):
    """[(curvature, thickness, glass, semi-diameter)] of the lens (object and image dropped),
    with the glasses checked against data/glasses.toml, coefficient for coefficient."""
    sm = opm["seq_model"]
    out = []
    for i in range(1, len(sm.ifcs) - 1):
        ifc, gap = sm.ifcs[i], sm.gaps[i]
        med = gap.medium
        kind = type(med).__name__
        if kind == "Air":
            glass = "air"
        elif kind == "ConstantIndex":
            glass = f"n={med.n!r}"
        else:
            glass = med.name().replace(" ", "")
        if glass != "air" and kind != "ConstantIndex":
            b, c = GLASSES[glass]
            assert list(med.coefs[0:3]) == b and list(med.coefs[3:6]) == c, (glass, med.coefs)
        out.append((ifc.profile.cv, gap.thi, glass, ifc.max_aperture))
    return out


def stop_limited_pupils(opm, lam_nm, stop_sd):
    """rayoptics' first-order data at lam_nm, with the pupils scaled so that the paraxial
    marginal ray fills the stop at this wavelength."""
    osp = opm["optical_spec"]
    osp["wvls"].reference_wvl = WAVELENGTHS_NM.index(lam_nm)
    opm.update_model()
    pd = opm["analysis_results"]["parax_data"]
    fod = pd.fod
    stop = opm["seq_model"].stop_surface
    y_stop = pd.ax_ray[stop][0]
    scale = stop_sd / abs(y_stop)
    return fod, scale


def trace_ray(opm_finite, start, direction, lam_nm):
    sm = opm_finite["seq_model"]
    pt0 = np.array([start[0], start[1], 0.0])  # on the object plane, Z_START_MM in lens coords
    ray, _opd, _w = rt.trace(sm, pt0, np.array(direction), lam_nm)
    return ray


def aim_chief(opm_finite, direction, lam_nm, stop):
    """Start height on the start plane of the ray (direction given) through the stop centre,
    by the secant method on rayoptics' trace."""
    def y_at_stop(y0):
        return trace_ray(opm_finite, (0.0, y0), direction, lam_nm)[stop][0][1]

    tan = direction[1] / direction[2]
    y_a, y_b = -tan * 10.0, -tan * 10.0 + 0.1
    f_a, f_b = y_at_stop(y_a), y_at_stop(y_b)
    for _ in range(50):
        if f_b == f_a:
            break
        y_a, f_a, y_b = y_b, f_b, y_b - f_b * (y_b - y_a) / (f_b - f_a)
        f_b = y_at_stop(y_b)
        if abs(f_b) < 1e-14:
            break
    return y_b, f_b


def ray_record(ray, sds, last_thickness):
    """Image intercept, exit direction and aperture clearance of a traced ray."""
    # ray[i] = [pt, after_dir, after_dst, normal] in interface i's local frame (no tilts)
    img_pt = ray[-1][0]
    exit_dir = ray[-2][1]
    margins = []
    for i, sd in enumerate(sds, start=1):
        r = math.hypot(ray[i][0][0], ray[i][0][1])
        margins.append(sd - r)
    worst = int(np.argmin(margins))
    return {
        "image_mm": [float(img_pt[0]), float(img_pt[1])],
        "image_z_residual_mm": float(img_pt[2]),
        "exit_direction": [float(v) for v in exit_dir],
        "passes_apertures": bool(min(margins) >= 0.0),
        "min_aperture_margin_mm": float(min(margins)),
        "min_margin_surface": worst,
    }


def grid_points(n):
    """Cell-centred n×n grid on [−1, 1]², kept where px² + py² ≤ 1, row-major in (py, px)."""
    pts = []
    for j in range(n):
        py = -1.0 + (j + 0.5) * 2.0 / n
        for i in range(n):
            px = -1.0 + (i + 0.5) * 2.0 / n
            if px * px + py * py <= 1.0:
                pts.append((px, py))
    return pts


def fixture(name, max_field_deg):
    opm = load(name)
    opm_finite = load(name, finite_object_mm=-Z_START_MM)
    sm = opm["seq_model"]
    surfaces = surfaces_of(opm)
    stop = sm.stop_surface  # 1-based among the lens surfaces (rayoptics' object is 0)
    stop_sd = surfaces[stop - 1][3]
    sds = [s[3] for s in surfaces]
    last_thickness = surfaces[-1][1]

    checks = {"dat_matches_zmx_max_rel_diff": dat_vs_zmx(name, surfaces, stop - 1)}
    paraxial = []
    bfl_d = None
    for lam in WAVELENGTHS_NM:
        fod, scale = stop_limited_pupils(opm, lam, stop_sd)
        enp_radius = fod.enp_radius * scale
        entry = {
            "wavelength_nm": lam,
            "efl_mm": float(fod.efl),
            "bfl_mm": float(fod.bfl),
            "ffl_mm": float(fod.ffl),
            "entrance_pupil_z_mm": float(fod.enp_dist),
            "entrance_pupil_diameter_mm": float(2 * enp_radius),
            # rayoptics' exp_dist adds its paraxial image distance at this wavelength where the
            # image plane's distance belongs (they differ by the focal shift away from d).
            "exit_pupil_z_from_last_mm": float(fod.exp_dist - fod.img_dist + last_thickness),
            "exit_pupil_diameter_mm": float(2 * fod.exp_radius * scale),
            "f_number": float(fod.efl / (2 * enp_radius)),
            "paraxial_image_distance_mm": float(fod.bfl),
        }
        if lam == LAMBDA_D_NM:
            bfl_d = entry["bfl_mm"]
        paraxial.append(entry)
        own = paraxial_check([(s[0], s[1], s[2], s[3]) for s in surfaces], stop - 1, lam)
        for key, value in own.items():
            rel = (entry[key] - value) / max(abs(value), 1e-300)
            checks.setdefault(f"paraxial_{key}_max_rel_residual", 0.0)
            checks[f"paraxial_{key}_max_rel_residual"] = max(
                checks[f"paraxial_{key}_max_rel_residual"], abs(rel))
    for entry in paraxial:
        entry["focal_shift_mm"] = entry["paraxial_image_distance_mm"] - bfl_d
    transmission = [
        {"wavelength_nm": lam,
         "normal_incidence_transmission": normal_incidence_transmission(surfaces, lam)}
        for lam in WAVELENGTHS_NM]
    checks["image_plane_minus_paraxial_focus_d_mm"] = last_thickness - bfl_d

    # ---- real rays
    rays = []
    spots = []
    enp_radius_d = next(p for p in paraxial if p["wavelength_nm"] == LAMBDA_D_NM)[
        "entrance_pupil_diameter_mm"] / 2
    grid = grid_points(GRID_N)
    for frac in FIELD_FRACTIONS:
        theta = math.radians(frac * max_field_deg)
        direction = (0.0, math.sin(theta), math.cos(theta))
        for lam in WAVELENGTHS_NM:
            y_c, stop_residual = aim_chief(opm_finite, direction, lam, stop)
            for label, px, py in RAY_PUPILS:
                start = (px * enp_radius_d, y_c + py * enp_radius_d, Z_START_MM)
                ray = trace_ray(opm_finite, start, direction, lam)
                rec = {
                    "kind": label, "wavelength_nm": lam, "field_fraction": frac,
                    "field_angle_deg": frac * max_field_deg, "pupil": [px, py],
                    "start_mm": [start[0], start[1], start[2]],
                    "direction": list(direction),
                }
                rec.update(ray_record(ray, sds, last_thickness))
                own_xy, own_dir = own_real_trace(surfaces, start, direction, lam)
                for key, diff in (
                        ("real_ray_image_max_abs_diff_mm",
                         np.max(np.abs(own_xy - np.array(rec["image_mm"])))),
                        ("real_ray_exit_direction_max_abs_diff",
                         np.max(np.abs(own_dir - np.array(rec["exit_direction"]))))):
                    checks[key] = max(checks.get(key, 0.0), float(diff))
                if label == "chief":
                    rec["stop_intercept_y_mm"] = float(stop_residual)
                rays.append(rec)
            # spot
            pts = []
            chief_img = None
            blocked = 0
            closest = math.inf
            for px, py in grid:
                start = (px * enp_radius_d, y_c + py * enp_radius_d, Z_START_MM)
                ray = trace_ray(opm_finite, start, direction, lam)
                rec = ray_record(ray, sds, last_thickness)
                closest = min(closest, abs(rec["min_aperture_margin_mm"]))
                if rec["passes_apertures"]:
                    pts.append(rec["image_mm"])
                else:
                    blocked += 1
            chief_img = next(r["image_mm"] for r in rays if r["kind"] == "chief"
                             and r["wavelength_nm"] == lam and r["field_fraction"] == frac)
            p = np.array(pts)
            centroid = p.mean(axis=0)
            rms = math.sqrt(np.mean(np.sum((p - centroid) ** 2, axis=1)))
            rms_chief = math.sqrt(np.mean(np.sum((p - np.array(chief_img)) ** 2, axis=1)))
            spots.append({
                "wavelength_nm": lam, "field_fraction": frac,
                "field_angle_deg": frac * max_field_deg,
                "chief_start_y_mm": y_c,
                "rays_in_pupil": len(grid), "rays_passing": len(pts), "rays_vignetted": blocked,
                "closest_aperture_margin_mm": closest,
                "centroid_mm": [float(centroid[0]), float(centroid[1])],
                "rms_radius_mm": rms,
                "rms_radius_about_chief_mm": rms_chief,
            })

    lens_surfaces = []
    for i, (cv, t, glass, sd) in enumerate(surfaces):
        lens_surfaces.append({
            "curvature_per_mm": cv, "radius_mm": 0.0 if cv == 0 else 1.0 / cv,
            "thickness_mm": t, "glass": glass, "semi_diameter_mm": sd,
            "is_stop": i + 1 == stop,
        })
    return {
        "lens": name,
        "files": ({"dat": f"data/lenses/{name}.dat",
                   "note": "no .zmx: make_fixtures.py writes a temporary one from the .dat, with "
                           "GLAS ___BLANK (constant index) and the image plane at the paraxial "
                           "d-line focus (pbrt's file has 0 there)"}
                  if name in PBRT_DAT else
                  {"zmx": f"data/lenses/{name}.zmx", "dat": f"data/lenses/{name}.dat"}),
        "provenance": {
            "tool": "rayoptics", "rayoptics_version": version("rayoptics"),
            "opticalglass_version": version("opticalglass"), "numpy_version": version("numpy"),
            "python_version": platform.python_version(), "command": COMMAND,
            "date_utc": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
        },
        "conventions": (
            "mm and nm; +z from object toward image; z = 0 at the first surface's vertex; "
            "radius > 0 when the centre of curvature is on the image side; object at infinity; "
            "air n = 1; see validation/lens/README.md"),
        "surfaces": lens_surfaces,
        "stop_index": stop - 1,
        "image_distance_mm": last_thickness,
        "max_field_deg": max_field_deg,
        "wavelengths_nm": WAVELENGTHS_NM,
        "reference_wavelength_nm": LAMBDA_D_NM,
        "paraxial": paraxial,
        "closed_form": {
            "description": (
                "not from rayoptics: on-axis transmission of the uncoated lens, product over "
                "surfaces of 1 - ((n1 - n2)/(n1 + n2))^2 at normal incidence, Sellmeier indices "
                "of data/glasses.toml, no absorption, no ghost (multiply reflected) light"),
            "list": transmission,
        },
        "rays": {
            "start_plane_z_mm": Z_START_MM,
            "entrance_pupil_radius_mm": enp_radius_d,
            "list": rays,
        },
        "spots": {
            "grid": {
                "n": GRID_N,
                "description": (
                    "pupil points px = -1 + (i + 0.5) * 2 / n, py = -1 + (j + 0.5) * 2 / n for "
                    "i, j in 0..n, kept where px^2 + py^2 <= 1; each ray starts at (px * R, "
                    "chief_start_y_mm + py * R, start_plane_z_mm) with R = "
                    "rays.entrance_pupil_radius_mm and the field's direction (0, sin θ, cos θ); "
                    "rays outside any surface's clear semi-diameter (stop included) are dropped; "
                    "rms_radius_mm is about the centroid of the remaining image intercepts, "
                    "unweighted"),
            },
            "list": spots,
        },
        "checks": checks,
    }


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    tmpdir = tempfile.mkdtemp(prefix="prisma-lens-")
    for name in PBRT_DAT:
        write_pbrt_zmx(name, tmpdir)
    for name, max_field in LENSES.items():
        data = fixture(name, max_field)
        path = OUT / f"{name}.json"
        path.write_text(json.dumps(data, indent=1) + "\n")
        print(f"{name}: wrote {path.relative_to(ROOT)}")
        for key, value in data["checks"].items():
            print(f"  check {key} = {value:.3e}")
        d = next(p for p in data["paraxial"] if p["wavelength_nm"] == LAMBDA_D_NM)
        print(f"  d line: EFL {d['efl_mm']!r}, BFL {d['bfl_mm']!r}, f/{d['f_number']!r}")
        for p in data["paraxial"]:
            print(f"  {p['wavelength_nm']:9.4f} nm: focus {p['paraxial_image_distance_mm']:.6f}"
                  f"  shift {p['focal_shift_mm']:+.6f} mm")
        for tr in data["closed_form"]["list"]:
            print(f"  T(normal) {tr['wavelength_nm']}: {tr['normal_incidence_transmission']:.6f}")
        for s in data["spots"]["list"]:
            print(f"  spot {s['wavelength_nm']:9.4f} nm field {s['field_fraction']}: rms "
                  f"{s['rms_radius_mm']*1e3:8.3f} µm, {s['rays_passing']}/{s['rays_in_pupil']} pass,"
                  f" closest margin {s['closest_aperture_margin_mm']:.2e} mm")
        if name == "singlet_nbk7":
            surf = data["surfaces"]
            for p in data["paraxial"]:
                n = sellmeier("N-BK7", p["wavelength_nm"])
                f = thick_lens_efl(surf[1]["radius_mm"], surf[2]["radius_mm"],
                                   surf[1]["thickness_mm"], n)
                print(f"  thick-lens formula at {p['wavelength_nm']} nm: f = {f!r}, rayoptics "
                      f"{p['efl_mm']!r}, relative residual {(p['efl_mm'] - f) / f:.3e}")


if __name__ == "__main__":
    sys.exit(main())

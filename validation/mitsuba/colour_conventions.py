#!/usr/bin/env python3
"""Evidence for the colour conventions of validation/README.md: what Mitsuba 3.9.1 and prisma
each compute from a spectrum, measured and by quadrature.

1. Mitsuba's luminance normalisation: an equal-energy radiance of 1 seen directly, rendered in
   llvm_ad_spectral to an XYZ film (expected Y = 1 under the convention ∫L·ȳ/∫ȳ), beside
   1/MI_CIE_Y_NORMALIZATION and the integral of Mitsuba's own ȳ.
2. The colour-matching tables: Mitsuba's cie1931_xyz (a 5 nm table, interpolated) against
   prisma's data/cie1931_2deg.csv (1 nm); and the XYZ → linear sRGB matrices (Mitsuba's
   xyz_to_srgb against the one derived from the sRGB primaries and D65 white, as prisma does).
3. For each emitter of scenes/color_emitters.toml: XYZ and linear sRGB by quadrature of prisma's
   exported table with prisma's pipeline and with Mitsuba's (tables and matrix), i.e. the ratio
   prisma/Mitsuba the color_emitters case should show; and Mitsuba's own upsampling of the RGB
   colour (srgb_d65), i.e. what the color_upsampling case should show on that quad.
4. Mitsuba's mono variant: a luminance film has one channel named Y holding the radiance.

Run: validation/.venv/bin/python validation/mitsuba/colour_conventions.py
"""

import json
import pathlib
import sys
import tempfile

import mitsuba as mi
import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import translate  # noqa: E402

REPO = pathlib.Path(__file__).resolve().parents[2]
FINE_STEP_NM = 0.05  # quadrature step: products of piecewise-linear tables need sub-nm steps


def prisma_cmf():
    rows = [line.split(",") for line in (REPO / "data" / "cie1931_2deg.csv").read_text().splitlines()
            if line[:1].isdigit()]
    table = np.array([[float(v) for v in row[:4]] for row in rows])
    return table[:, 0], table[:, 1:4]


def srgb_matrix_from_primaries():
    """XYZ → linear sRGB from the Rec. 709 primaries and the D65 white point (x, y)."""
    primaries = np.array([[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]])
    white = np.array([0.3127, 0.3290])

    def xyz(xy):
        return np.array([xy[0] / xy[1], 1.0, (1.0 - xy[0] - xy[1]) / xy[1]])

    columns = np.stack([xyz(p) for p in primaries], axis=1)
    gains = np.linalg.solve(columns, xyz(white))
    return np.linalg.inv(columns * gains)


def integrate(values_nm, values, cmf_nm, cmf):
    fine = np.arange(translate.LAMBDA_MIN_NM, translate.LAMBDA_MAX_NM + FINE_STEP_NM / 2, FINE_STEP_NM)
    f = np.interp(fine, values_nm, values)
    c = np.stack([np.interp(fine, cmf_nm, cmf[:, i]) for i in range(3)], axis=-1)
    y_bar_integral = np.trapezoid(c[:, 1], fine)
    return np.trapezoid(f[:, None] * c, fine, axis=0) / y_bar_integral


def main():
    # 1. Normalisation, measured.
    mi.set_variant("llvm_ad_spectral")
    flat = {"type": "regular", "wavelength_min": 360, "wavelength_max": 830, "values": ",".join(["1.0"] * 471)}
    scene = mi.load_dict({
        "type": "scene", "integrator": {"type": "path", "max_depth": 1},
        "sensor": {"type": "perspective", "fov": 20,
                   "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0, 5], target=[0, 0, 0], up=[0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": 64, "height": 64, "rfilter": {"type": "box"},
                            "pixel_format": "xyz", "component_format": "float32"},
                   "sampler": {"type": "independent", "sample_count": 1024}},
        "wall": {"type": "rectangle", "to_world": mi.ScalarTransform4f().scale([10, 10, 1]),
                 "emitter": {"type": "area", "radiance": flat}},
    })
    means = np.array([np.array(mi.render(scene, seed=s)).reshape(-1, 3).mean(axis=0) for s in range(32)])
    xyz_e = means.mean(axis=0)
    err = means.std(axis=0, ddof=1) / np.sqrt(len(means))
    grid = np.arange(360.0, 830.5, 1.0)
    y_bar_m = np.array(mi.cie1931_y(mi.Float(grid)), dtype=np.float64)
    print("1. Mitsuba spectral film, equal-energy radiance 1 (32 × 1024 spp, 64×64 px):")
    print(f"   XYZ = {xyz_e.round(6)} ± {err.round(6)}")
    print(f"   1/MI_CIE_Y_NORMALIZATION = {1 / mi.MI_CIE_Y_NORMALIZATION:.6f}, ∫ȳ of Mitsuba's table = "
          f"{np.trapezoid(y_bar_m, grid):.6f}, ratio {np.trapezoid(y_bar_m, grid) * mi.MI_CIE_Y_NORMALIZATION:.6f}")

    # 2. Tables and matrices.
    cmf_nm, cmf_p = prisma_cmf()
    cmf_m = np.array([list(mi.cie1931_xyz(mi.Float(cmf_nm)))], dtype=np.float64)[0].T
    print("2. CMF tables, max |Mitsuba − prisma| at the 1 nm points (x̄, ȳ, z̄):",
          np.abs(cmf_m - cmf_p).max(axis=0).round(5), "; ∫ȳ prisma", round(np.trapezoid(cmf_p[:, 1], cmf_nm), 6))
    m_prisma = srgb_matrix_from_primaries()
    m_mitsuba = np.array([list(mi.xyz_to_srgb(mi.Color3f(*map(float, e)))) for e in np.identity(3)]).T
    print("   XYZ→sRGB, max |Mitsuba − from primaries| =", f"{np.abs(m_mitsuba - m_prisma).max():.2e}")

    # 3. The emitters of color_emitters.toml.
    export_dir = pathlib.Path(tempfile.mkdtemp(prefix="colour_conventions_"))
    scene_path = REPO / "validation" / "scenes" / "color_emitters.toml"
    translate.export(scene_path, export_dir)
    spectra = json.loads((export_dir / "spectra.json").read_text())
    names = ["equal energy", "D65", "540-560 nm band", "rgb (0.8, 0.3, 0.1)"]
    print("3. color_emitters by quadrature (prisma's table; pipelines: prisma = 1 nm CMF + primaries "
          "matrix, Mitsuba = its CMF + its matrix, Y normalised to ∫ȳ):")
    for name, light in zip(names, spectra["lights"]):
        xyz_p = integrate(grid, light["radiance"], cmf_nm, cmf_p)
        xyz_m = integrate(grid, light["radiance"], cmf_nm, cmf_m)
        rgb_p, rgb_m = m_prisma @ xyz_p, m_mitsuba @ xyz_m
        print(f"   {name:22s} XYZ prisma {xyz_p.round(5)}  RGB prisma {rgb_p.round(5)}  RGB Mitsuba {rgb_m.round(5)}"
              f"  ratio {(rgb_p / rgb_m).round(4)}")
    mi.set_variant("scalar_spectral")
    # Mitsuba 3.9 names the RGB-emitter spectrum plugin "d65" (older releases: "srgb_d65").
    upsampled = mi.load_dict({"type": "d65", "color": [0.8, 0.3, 0.1]})
    si = mi.SurfaceInteraction3f()
    values = []
    for lam in grid:
        si.wavelengths = mi.Spectrum(float(lam))
        values.append(float(upsampled.eval(si)[0]))
    xyz_up = integrate(grid, values, cmf_nm, cmf_m)
    rgb_up = m_mitsuba @ xyz_up
    rgb_p = m_prisma @ integrate(grid, spectra["lights"][3]["radiance"], cmf_nm, cmf_p)
    print(f"   Mitsuba's own srgb_d65 of (0.8, 0.3, 0.1): RGB {rgb_up.round(5)}; prisma's table in prisma's "
          f"pipeline {rgb_p.round(5)}; ratio prisma/Mitsuba {(rgb_p / rgb_up).round(4)}")
    rel = np.abs(np.array(values) - np.array(spectra["lights"][3]["radiance"])) / np.max(values)
    print(f"   the two spectra differ by up to {100 * rel.max():.1f}% of the peak")

    # 4. Mono film channel.
    mi.set_variant("llvm_ad_mono")
    scene = mi.load_dict({
        "type": "scene", "integrator": {"type": "path", "max_depth": 1},
        "sensor": {"type": "perspective", "fov": 20,
                   "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0, 5], target=[0, 0, 0], up=[0, 1, 0]),
                   "film": {"type": "hdrfilm", "width": 8, "height": 8, "rfilter": {"type": "box"},
                            "pixel_format": "luminance", "component_format": "float32"},
                   "sampler": {"type": "independent", "sample_count": 64}},
        "wall": {"type": "rectangle", "to_world": mi.ScalarTransform4f().scale([10, 10, 1]),
                 "emitter": {"type": "area", "radiance": {"type": "uniform", "value": 0.7}}},
    })
    mi.render(scene)
    bitmap = scene.sensors()[0].film().bitmap()
    channels = [bitmap.struct_()[i].name for i in range(bitmap.channel_count())]
    print(f"4. llvm_ad_mono luminance film: channels {channels}, value {np.array(bitmap).mean():.6f} "
          "for a uniform radiance 0.7")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Translate a prisma scene file into a Mitsuba 3 scene (a `mi.load_dict` dictionary).

Geometry comes from the scene's TOML (read with `tomllib`) and from the meshes `prisma export`
writes; every spectrum and index of refraction comes from the `spectra.json` of `prisma export`
(tabulated at 1 nm over 360–830 nm exactly as prisma evaluates it), so that a difference in RGB
upsampling, illuminant tables or glass formulas can neither cause nor hide a validation failure.

The mapping, prisma → Mitsuba 3.9.1:

  camera            perspective, fov_axis "y", fov = fov_y_deg, to_world = look_at(position,
                    look_at, up); hdrfilm with a box filter, float32, width/height of the file
                    (both renderers use the same handedness: +x on the image's left looking down +z)
  camera with lens  (aperture_radius > 0) thinlens, the same fov and to_world, aperture_radius and
                    focus_distance as given: both put the lens at the camera position, focus on the
                    plane at depth focus_distance along the view, sample the lens uniformly
                    (concentric map) and weigh every ray 1
  sphere            sphere (outward normals)
  plane             rectangle of half-size PLANE_HALF_SIZE centred on `point`, local +z = normal;
                    or (plane_half_size = "graded") a triangle mesh of the plane to 1e6 units with
                    fine cells around the scene (`graded_plane_obj`)
  quad              rectangle mapping local (±1, ±1) to the corners: centre corner + (e1 + e2)/2,
                    local x = e1/2, local y = e2/2, local z = unit(e1 × e2)
  mesh, prism       obj (the mesh_<k>.obj of prisma export, scene space) with face normals
  diffuse           twosided(diffuse), reflectance = albedo (prisma shades both sides)
  mirror            unpolarised variants: conductor, material "none" (reflectance 1 at every
                    angle), specular_reflectance = reflectance.
                    polarised variants: conductor with eta = 0, k = PEC_K (1e14), a perfect
                    electric conductor: Mueller diag(1, 1, −1, −1) to 1.2e-7 at every angle
                    (polarisation_conventions.py), times reflectance. Mitsuba's "none" is η = i,
                    whose s and p phases differ with the angle: not prisma's ideal mirror.
  mirror + metal    conductor, eta and k = the n, k of data/metals/<metal>.csv (the table prisma
                    embeds), interpolated linearly in λ, constant beyond its ends (as prisma does),
                    specular_reflectance = reflectance
  mirror + complex_ior = [n, k]   conductor, eta = n, k = k (constant), times reflectance
  dielectric        dielectric, int_ior = n, ext_ior = 1 (constant n only; a dispersive glass is
                    rendered band by band in a mono variant with n(λ))
  polarizer         Mitsuba's polarizer (theta = 0, transmittance), on a flat shape whose local V
                    (the absorbing axis) is normal × axis and local U the transmission axis
                    (axis projected onto the sheet): a plane becomes a rectangle with local x
                    along that axis; a quad becomes a two-triangle OBJ whose texture coordinates
                    (u, v) = (p·axis, p·(normal × axis)) make dp/du point along it (a rectangle's
                    U follows its first edge, which need not be the axis). Mitsuba's `theta`
                    stays 0: its sign depends on the side the light arrives from.
                    At oblique incidence both follow Korger et al. (2013).
  retarder          ideal_retarder.py's plugin (delta = retardance_deg) on the same kind of shape,
                    local U = the fast axis: Mitsuba's retarder at normal incidence, where
                    polarisation_conventions.py measured that the field component along U leads,
                    with the fast axis projected onto the wavefront off normal incidence and no
                    cos θ falloff of the retardance, as prisma's. (Mitsuba's own `retarder`,
                    retarder_plugin="retarder", turns its axis by about the tilt angle off normal
                    incidence: see ideal_retarder.py.)
  point light       point, intensity (W·sr⁻¹·nm⁻¹ in both renderers)
  quad light        rectangle with a black diffuse BSDF (prisma's quad lights reflect nothing) and
                    an area emitter; Mitsuba emits toward local +z, so for emit =
                    "edge2_cross_edge1" the roles of e1 and e2 are swapped to keep the frame
                    right-handed with +z on the emitting side
  background        constant emitter (left out when the background is black)
  [render] polarized   true (prisma's default) or false: which Mitsuba variants compare with it
                    (`polarized_variant`); the translation itself follows the current variant
  max_depth         prisma counts bounces (Whitted: specular ones; "path": every kind), Mitsuba's
                    `path` and `ptracer` count path vertices: Mitsuba max_depth = prisma max_depth
                    + 1 (see `path_integrator`, `full_transport_integrator`)
  [render] integrator = "path"   Mitsuba's `path` with diffuse surfaces and its default Russian
                    roulette (`full_transport_integrator`); the background is a `constant` emitter
                    in both integrators, which lights diffuse surfaces in full transport as prisma's
                    "path" does (prisma's Whitted counts it only along specular paths)

Spectra become `regular` spectra over 360–830 nm in spectral variants, and the value at the
chosen wavelength in mono variants. Optionally, emitters whose file gives an `rgb` colour can be
handed to Mitsuba as that RGB colour instead, so that Mitsuba upsamples it its own way (the
`color_upsampling` validation case).

Not translated (a TranslationError says so): Oren–Nayar roughness, Beer–Lambert absorption,
dispersive glass in a spectral variant.

Scenes with the polarisation keys (polarizer, retarder, complex_ior, [render] polarized) are
exported through a copy without them (`exportable_copy`: a polariser becomes a diffuse material
whose albedo is its transmittance, so that `prisma export` tabulates that spectrum; a retarder a
white diffuse one; complex_ior and `polarized` are dropped; mesh paths made absolute), so that a
prisma binary from before these keys existed exports them too. The translation reads the
polarisation keys from the scene file itself.

In polarised variants, wrap the integrator in `stokes_integrator(...)` to get the Stokes channels
S0.R … S3.B (Mitsuba's frame: x = normalize(d × camera up), S3 = +1 when the field turns clockwise
as seen by the camera, which is prisma's convention; polarisation_conventions.py).

As a command, renders a scene with Mitsuba for a quick look (polarised variants by default when
the scene is polarised, which is prisma's default; `--stokes` adds the Stokes channels):
  validation/.venv/bin/python validation/mitsuba/translate.py validation/scenes/tp6_quad.toml \\
      --spp 256 -o /tmp/tp6_quad_mitsuba.exr
  validation/.venv/bin/python validation/mitsuba/translate.py validation/scenes/stokes_brewster.toml \\
      --wavelength 550 --stokes --spp 256 -o /tmp/brewster.exr
Set DRJIT_LIBLLVM_PATH for the llvm variants (validation/setup.sh prints the value).
"""

import argparse
import importlib
import json
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import tomllib

import mitsuba as mi
import numpy as np

REPO_ROOT = pathlib.Path(__file__).resolve().parents[2]

# prisma's spectral range and the export grid step; spectra.json must hold exactly this grid.
LAMBDA_MIN_NM = 360.0
LAMBDA_MAX_NM = 830.0

# Half-size of the rectangle standing in for an infinite plane. Rays of the validation scenes
# that travel farther than this before meeting a plane carry negligible radiance (a point light
# at distance d lights the plane with I/d²), and Mitsuba's float32 intersection of a rectangle is
# accurate at this scale.
PLANE_HALF_SIZE = 1000.0

# The graded alternative (plane_half_size = "graded", used by the polarised references): a
# triangle mesh of the plane out to GRADED_PLANE_HALF_SIZE whose cells are small where the scene
# is and double in size outward. A single rectangle trades two errors: rays leaving the scene
# parallel to planes escape past its edge (a solid angle ∝ 1/L²), and its hit points are only as
# precise as float32 at the scale of its corners (∝ L); the mesh's hits near the scene are as
# precise as the scene's own coordinates and its edge is 1e6 away (plane_size_study.py).
GRADED_PLANE_HALF_SIZE = 1.0e6

# k of the conductor (eta = 0) standing in for prisma's ideal mirror in polarised variants: its
# Mueller matrix is diag(1, 1, −1, −1) to 1.2e-7 in float32 down to cos θ = 1e-6, where k = 1e6
# is off by 1 at grazing incidence (polarisation_conventions.py, check "pec").
PEC_K = 1e14


def prisma_observer():
    """prisma's colour pipeline, for Mitsuba's `specfilm`: (λ nm, the CIE 1931 x̄, ȳ, z̄ of
    data/cie1931_2deg.csv at 1 nm (N × 3), ∫ȳ by the trapezoid rule on that table, the XYZ →
    linear sRGB matrix from the sRGB primaries and the D65 white point (x, y) = (0.3127, 0.3290)),
    each as src/spectrum/cie.rs and src/spectrum/color.rs define them."""
    rows = [line.split(",") for line in (REPO_ROOT / "data" / "cie1931_2deg.csv").read_text().splitlines()
            if line[:1].isdigit()]
    table = np.array([[float(v) for v in row[:4]] for row in rows], dtype=np.float64)
    nm, cmf = table[:, 0], table[:, 1:4]
    y_integral = float(np.sum(0.5 * (cmf[1:, 1] + cmf[:-1, 1]) * np.diff(nm)))

    def xyz_of(xy):
        return np.array([xy[0] / xy[1], 1.0, (1.0 - xy[0] - xy[1]) / xy[1]])

    primaries = np.stack([xyz_of(p) for p in ([0.64, 0.33], [0.30, 0.60], [0.15, 0.06])], axis=1)
    gains = np.linalg.solve(primaries, xyz_of([0.3127, 0.3290]))
    return nm, cmf, y_integral, np.linalg.inv(primaries * gains)


# Channel names of the `prisma_xyz` film (specfilm sorts its channels alphabetically).
PRISMA_XYZ_CHANNELS = ["cie_x", "cie_y", "cie_z"]


def prisma_rgb(image, channels):
    """A `prisma_xyz` film image (∫L·x̄, ∫L·ȳ, ∫L·z̄ with prisma's table) → linear sRGB and XYZ
    under prisma's normalisation XYZ = ∫L·cmf / ∫ȳ: returns (image, ["R", "G", "B", "XYZ.X",
    "XYZ.Y", "XYZ.Z"])."""
    _, _, y_integral, matrix = prisma_observer()
    idx = [channels.index(c) for c in PRISMA_XYZ_CHANNELS]
    xyz = image[..., idx] / y_integral
    rgb = xyz @ matrix.T
    return np.concatenate([rgb, xyz], axis=-1), ["R", "G", "B", "XYZ.X", "XYZ.Y", "XYZ.Z"]


class TranslationError(Exception):
    """A prisma feature that the translation cannot express in Mitsuba."""


def read_exr(path):
    """{channel name: float64 array (H, W)} of an EXR (multi-layer names kept, e.g. "XYZ.Y")."""
    bitmap = mi.Bitmap(str(path))
    data = np.array(bitmap, dtype=np.float64)
    if data.ndim == 2:
        data = data[..., None]
    names = [bitmap.struct_()[i].name for i in range(data.shape[-1])]
    return {name: data[..., i] for i, name in enumerate(names)}


def find_prisma():
    """The prisma binary: $PRISMA, else target/release/prisma of the repository, else PATH."""
    if os.environ.get("PRISMA"):
        return os.environ["PRISMA"]
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", REPO_ROOT / "target"))
    candidate = target / "release" / "prisma"
    if candidate.exists():
        return str(candidate)
    found = shutil.which("prisma")
    if found:
        return found
    raise FileNotFoundError("prisma binary not found: build it (cargo build --release) or set PRISMA")


# Polarisation-only keys: a scene using them is exported through `exportable_copy`.
SHEET_MATERIALS = ("polarizer", "retarder")


def uses_polarisation_keys(desc):
    materials = desc.get("materials", {}).values()
    return ("polarized" in desc.get("render", {})
            or any(m.get("type") in SHEET_MATERIALS or "complex_ior" in m for m in materials))


def toml_value(value):
    """A value as TOML text (inline tables for dictionaries)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)  # a JSON string is a valid TOML basic string
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{k} = {toml_value(v)}" for k, v in value.items()) + " }"
    raise TypeError(f"cannot write {value!r} as TOML")


def toml_document(desc):
    """A prisma scene description (as tomllib read it) written back as TOML: top-level keys,
    then [camera], [render], [materials.NAME], [[shapes]], [[lights]]."""
    tables = ("camera", "render", "materials")

    def table_array(value):
        return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)

    lines = [f"{k} = {toml_value(v)}" for k, v in desc.items() if k not in tables and not table_array(v)]
    for key, value in desc.items():
        if key == "materials":
            for name, material in value.items():
                lines += ["", f"[materials.{name}]"] + [f"{k} = {toml_value(v)}" for k, v in material.items()]
        elif key in tables:
            lines += ["", f"[{key}]"] + [f"{k} = {toml_value(v)}" for k, v in value.items()]
        elif table_array(value):
            for item in value:
                lines += ["", f"[[{key}]]"] + [f"{k} = {toml_value(v)}" for k, v in item.items()]
    return "\n".join(lines) + "\n"


def exportable_copy(desc, scene_dir):
    """The scene without the polarisation keys, for `prisma export` (see the module docstring):
    the shapes, lights and every spectrum stay as they are."""
    desc = json.loads(json.dumps(desc))  # deep copy
    desc.get("render", {}).pop("polarized", None)
    for material in desc.get("materials", {}).values():
        material.pop("complex_ior", None)
        if material.get("type") == "polarizer":
            albedo = material.get("transmittance", 1.0)
            material.clear()
            material.update(type="diffuse", albedo=albedo)
        elif material.get("type") == "retarder":
            material.clear()
            material.update(type="diffuse", albedo=1.0)
    for shape in desc.get("shapes", []):
        if shape.get("type") == "mesh":
            shape["file"] = str((pathlib.Path(scene_dir) / shape["file"]).resolve())
    return desc


def export(scene_path, out_dir, prisma=None):
    """Runs `prisma export SCENE -o OUT_DIR` (1 nm grid) and returns OUT_DIR; a scene with the
    polarisation keys goes through `exportable_copy`, written into OUT_DIR."""
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    with open(scene_path, "rb") as f:
        desc = tomllib.load(f)
    if uses_polarisation_keys(desc):
        copy = out_dir / "exportable_scene.toml"
        copy.write_text(toml_document(exportable_copy(desc, pathlib.Path(scene_path).parent)))
        scene_path = copy
    cmd = [prisma or find_prisma(), "export", str(scene_path), "-o", str(out_dir), "--step-nm", "1"]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return out_dir


def metal_table(name):
    """(λ nm, n, k) of a metal of data/metals/ by name or chemical symbol, as prisma reads it."""
    names = {"silver": "ag", "ag": "ag", "aluminium": "al", "aluminum": "al", "al": "al", "gold": "au",
             "au": "au", "copper": "cu", "cu": "cu"}
    key = names.get(name.lower())
    if key is None:
        raise TranslationError(f"unknown metal {name!r}")
    rows = []
    header_seen = False
    for line in (REPO_ROOT / "data" / "metals" / f"{key}.csv").read_text().splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        if not header_seen:
            if line != "wavelength_nm,n,k":
                raise TranslationError(f"data/metals/{key}.csv: unexpected header {line!r}")
            header_seen = True
            continue
        rows.append([float(v) for v in line.split(",")])
    table = np.array(rows, dtype=np.float64)
    return table[:, 0], table[:, 1], table[:, 2]


class PrismaScene:
    """A prisma scene file with the tables and meshes `prisma export` wrote for it."""

    def __init__(self, scene_path, export_dir):
        self.path = pathlib.Path(scene_path)
        self.export_dir = pathlib.Path(export_dir)
        with open(self.path, "rb") as f:
            self.desc = tomllib.load(f)
        with open(self.export_dir / "spectra.json") as f:
            self.spectra = json.load(f)
        grid = np.asarray(self.spectra["wavelengths_nm"], dtype=np.float64)
        expected = np.arange(LAMBDA_MIN_NM, LAMBDA_MAX_NM + 0.5, 1.0)
        if grid.shape != expected.shape or np.any(grid != expected):
            raise TranslationError("spectra.json must be tabulated at 1 nm over 360–830 nm")
        self.grid = grid

    @classmethod
    def load(cls, scene_path, export_dir=None, prisma=None):
        """Exports the scene (into `export_dir`, else a temporary directory) and loads it."""
        if export_dir is None:
            export_dir = tempfile.mkdtemp(prefix="prisma_export_")
        export(scene_path, export_dir, prisma)
        return cls(scene_path, export_dir)

    @property
    def camera(self):
        return self.desc["camera"]

    @property
    def render_settings(self):
        return self.desc.get("render", {})

    @property
    def integrator(self):
        """prisma's `[render] integrator`: "whitted" (the default) or "path" (full transport)."""
        return str(self.render_settings.get("integrator", "whitted"))

    @property
    def max_depth(self):
        """prisma's `max_depth`: specular bounces for Whitted (default 16), bounces of every kind
        for "path" (default 256)."""
        return int(self.render_settings.get("max_depth", 256 if self.integrator == "path" else 16))

    @property
    def polarized(self):
        """prisma's `[render] polarized` (default true)."""
        return bool(self.render_settings.get("polarized", True))

    def has_diffuse(self):
        return any(m["type"] == "diffuse" for m in self.desc.get("materials", {}).values())


class Translator:
    """Builds the Mitsuba dictionary of a PrismaScene for the current Mitsuba variant.

    wavelength_nm: for mono variants, the wavelength at which every spectrum and IOR is taken.
    mitsuba_rgb_emitters: emitters whose file gives `{ rgb = [...] }` get Mitsuba's own RGB
      upsampling (an `rgb` spectrum, which Mitsuba multiplies by its D65) instead of prisma's table.
    plane_half_size: half-size of the rectangles standing in for infinite planes, or "graded"
      for the graded mesh (see GRADED_PLANE_HALF_SIZE).
    retarder_plugin: "ideal_retarder" (ideal_retarder.py, prisma's retarder) or Mitsuba's "retarder".
    Polarised variants (mi.is_polarized) get the polarised translation of mirrors.
    """

    def __init__(self, scene, wavelength_nm=None, mitsuba_rgb_emitters=False, plane_half_size=PLANE_HALF_SIZE,
                 retarder_plugin="ideal_retarder"):
        self.scene = scene
        self.mono = mi.is_monochromatic
        self.spectral = mi.is_spectral
        self.polarized = mi.is_polarized
        self.plane_half_size = plane_half_size if plane_half_size == "graded" else float(plane_half_size)
        if retarder_plugin not in ("ideal_retarder", "retarder"):
            raise TranslationError(f"unknown retarder plugin {retarder_plugin!r}")
        self.retarder_plugin = retarder_plugin
        if not (self.mono or self.spectral):
            raise TranslationError(f"variant {mi.variant()}: use a spectral or a mono variant "
                                   "(an RGB variant would re-upsample prisma's spectra)")
        if self.mono and wavelength_nm is None:
            raise TranslationError("a mono variant needs wavelength_nm")
        if self.spectral and wavelength_nm is not None:
            raise TranslationError("wavelength_nm is for mono variants only")
        if wavelength_nm is not None and not LAMBDA_MIN_NM <= wavelength_nm <= LAMBDA_MAX_NM:
            raise TranslationError(f"wavelength {wavelength_nm} nm outside 360–830 nm")
        self.wavelength_nm = wavelength_nm
        self.mitsuba_rgb_emitters = mitsuba_rgb_emitters

    # Spectra -------------------------------------------------------------------------------

    def spectrum(self, table):
        """A spectrum from a 1 nm table of spectra.json: `regular` (spectral) or its value at
        the chosen wavelength (mono)."""
        values = np.asarray(table, dtype=np.float64)
        if self.mono:
            return {"type": "uniform", "value": float(np.interp(self.wavelength_nm, self.scene.grid, values))}
        return {
            "type": "regular",
            "wavelength_min": LAMBDA_MIN_NM,
            "wavelength_max": LAMBDA_MAX_NM,
            # repr of a Python float round-trips, so Mitsuba parses exactly prisma's values.
            "values": ",".join(repr(float(v)) for v in values),
        }

    def emitter_spectrum(self, desc_value, table):
        """An emitter's spectrum; Mitsuba's own RGB upsampling when asked for and the file gives
        an RGB colour."""
        if self.mitsuba_rgb_emitters and isinstance(desc_value, dict) and "rgb" in desc_value:
            scale = float(desc_value.get("scale", 1.0))
            return {"type": "rgb", "value": [scale * float(c) for c in desc_value["rgb"]]}
        return self.spectrum(table)

    def ior(self, table, name):
        values = np.asarray(table, dtype=np.float64)
        if self.mono:
            return float(np.interp(self.wavelength_nm, self.scene.grid, values))
        if np.ptp(values) > 0.0:
            raise TranslationError(f"material {name!r}: Mitsuba's dielectric takes one IOR; render a "
                                   "dispersive glass wavelength by wavelength in a mono variant")
        return float(values[0])

    # Materials ------------------------------------------------------------------------------

    def bsdf(self, name):
        desc = self.scene.desc["materials"][name]
        resolved = self.scene.spectra["materials"][name]
        kind = desc["type"]
        if kind == "diffuse":
            if float(desc.get("roughness_deg", 0.0)) != 0.0:
                raise TranslationError(f"material {name!r}: Oren–Nayar roughness has no Mitsuba 3 plugin")
            return {"type": "twosided",
                    "bsdf": {"type": "diffuse", "reflectance": self.spectrum(resolved["albedo"])}}
        if kind == "mirror":
            reflectance = self.spectrum(resolved["reflectance"])
            if desc.get("metal") is not None and desc.get("complex_ior") is not None:
                raise TranslationError(f"material {name!r}: give either metal or complex_ior, not both")
            if desc.get("metal") is not None:
                lambda_nm, n, k = metal_table(desc["metal"])
                return {"type": "conductor", "eta": self.sampled(lambda_nm, n), "k": self.sampled(lambda_nm, k),
                        "specular_reflectance": reflectance}
            if desc.get("complex_ior") is not None:
                n, k = (float(v) for v in desc["complex_ior"])
                if not (n > 0.0 and k >= 0.0):
                    raise TranslationError(f"material {name!r}: complex_ior needs n > 0 and k >= 0")
                return {"type": "conductor", "eta": n, "k": k, "specular_reflectance": reflectance}
            if self.polarized:
                return {"type": "conductor", "eta": 0.0, "k": PEC_K, "specular_reflectance": reflectance}
            return {"type": "conductor", "material": "none", "specular_reflectance": reflectance}
        if kind == "dielectric":
            if resolved.get("absorption") is not None:
                raise TranslationError(f"material {name!r}: absorption is not translated")
            return {"type": "dielectric", "int_ior": self.ior(resolved["ior"], name), "ext_ior": 1.0}
        if kind == "polarizer":
            # The export's copy holds the transmittance as a diffuse albedo (exportable_copy).
            table = resolved.get("transmittance", resolved.get("albedo"))
            return {"type": "polarizer", "theta": 0.0, "transmittance": self.spectrum(table)}
        if kind == "retarder":
            delta = float(desc["retardance_deg"])
            if not 0.0 <= delta <= 360.0:
                raise TranslationError(f"material {name!r}: retardance_deg must be in [0, 360]")
            if self.retarder_plugin == "ideal_retarder":
                register_ideal_retarder()
                return {"type": "ideal_retarder", "delta": delta}
            return {"type": "retarder", "theta": 0.0, "delta": delta}
        raise TranslationError(f"material {name!r}: unknown type {kind!r}")

    def sampled(self, lambda_nm, values):
        """A tabulated quantity (linear in λ, constant beyond the ends) on the 1 nm grid
        (spectral) or at the chosen wavelength (mono)."""
        return self.spectrum(np.interp(self.scene.grid, lambda_nm, values)) if not self.mono else \
            {"type": "uniform", "value": float(np.interp(self.wavelength_nm, lambda_nm, values))}

    def sheet_axis(self, shape_desc, normal):
        """The in-plane axis (unit, world) that becomes local U of a polariser or retarder sheet
        (transmission or fast axis), or None for other materials."""
        material = self.scene.desc["materials"][shape_desc["material"]]
        key = {"polarizer": "axis", "retarder": "fast_axis"}.get(material["type"])
        if key is None:
            return None
        axis = np.asarray(material[key], dtype=np.float64)
        axis = axis - (axis @ normal) * normal
        if np.linalg.norm(axis) < 1e-3 * np.linalg.norm(material[key]):
            raise TranslationError(f"material {shape_desc['material']!r}: its {key} is along the sheet's normal")
        return axis / np.linalg.norm(axis)

    # Geometry -------------------------------------------------------------------------------

    @staticmethod
    def frame_transform(x_axis, y_axis, z_axis, origin):
        """The affine map taking local (x, y, z) to origin + x·x_axis + y·y_axis + z·z_axis."""
        m = np.identity(4)
        m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = x_axis, y_axis, z_axis, origin
        return mi.ScalarTransform4f(m.tolist())

    @classmethod
    def plane_transform(cls, point, normal, half_size=PLANE_HALF_SIZE):
        normal = np.asarray(normal, dtype=np.float64)
        normal = normal / np.linalg.norm(normal)
        # Any tangent pair with tangent × bitangent = normal.
        helper = np.array([1.0, 0.0, 0.0]) if abs(normal[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        tangent = np.cross(helper, normal)
        tangent /= np.linalg.norm(tangent)
        bitangent = np.cross(normal, tangent)
        return cls.frame_transform(half_size * tangent, half_size * bitangent, normal, point)

    def scene_points(self):
        """Points that bound the scene: the camera, sphere extremes, quad corners, lights, plane
        points (meshes and prisms by their position)."""
        desc = self.scene.desc
        points = [desc["camera"]["position"], desc["camera"]["look_at"]]
        for shape in desc.get("shapes", []):
            if shape["type"] == "sphere":
                c, r = np.asarray(shape["center"], dtype=np.float64), float(shape["radius"])
                points += [c - r, c + r]
            elif shape["type"] == "quad":
                c, e1, e2 = (np.asarray(shape[k], dtype=np.float64) for k in ("corner", "edge1", "edge2"))
                points += [c, c + e1, c + e2, c + e1 + e2]
            elif shape["type"] == "plane":
                points.append(shape["point"])
            else:
                points.append(shape.get("position", [0.0, 0.0, 0.0]))
        for light in desc.get("lights", []):
            if light["type"] == "quad":
                c, e1, e2 = (np.asarray(light[k], dtype=np.float64) for k in ("corner", "edge1", "edge2"))
                points += [c, c + e1 + e2]
            else:
                points.append(light["position"])
        return np.array(points, dtype=np.float64)

    def graded_plane_obj(self, index, point, normal, axis=None):
        """The plane through `point` as a triangle mesh out to GRADED_PLANE_HALF_SIZE: centred on
        the scene's projection onto it, a 16 × 16 grid of cells over a square that holds the whole
        scene, then rows and columns whose widths double outward (a tensor-product grid: no
        T-junctions, watertight). Normals along `normal`; with a sheet `axis`, texture
        coordinates (p·axis, p·(normal × axis)) so that local U follows the axis."""
        if axis is None:
            helper = np.array([1.0, 0.0, 0.0]) if abs(normal[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
            tangent = np.cross(helper, normal)
            tangent /= np.linalg.norm(tangent)
        else:
            tangent = axis
        bitangent = np.cross(normal, tangent)
        points = self.scene_points()
        centre_uv = np.mean(points @ np.stack([tangent, bitangent], axis=1), axis=0)
        centre = point + (centre_uv[0] - point @ tangent) * tangent + (centre_uv[1] - point @ bitangent) * bitangent
        extent = np.max(np.abs((points - centre) @ np.stack([tangent, bitangent], axis=1)))
        inner = 2.0 ** np.ceil(np.log2(max(extent * 1.25, 1.0)))
        outer = [inner * 2.0]
        while outer[-1] < GRADED_PLANE_HALF_SIZE:
            outer.append(outer[-1] * 2.0)
        coords = np.concatenate([-np.array(outer[::-1]), np.linspace(-inner, inner, 17), np.array(outer)])
        n = len(coords)
        path = self.scene.export_dir / f"plane_{index}.obj"
        lines = [f"# shape {index} of {self.scene.path}: infinite plane as a graded mesh to ±{outer[-1]:g}"]
        uv = []
        for v in coords:
            for u in coords:
                p = centre + u * tangent + v * bitangent
                lines.append("v " + " ".join(repr(float(c)) for c in p))
                uv.append((float(p @ tangent), float(p @ bitangent)))
        if axis is not None:
            lines += [f"vt {a!r} {b!r}" for a, b in uv]
        for j in range(n - 1):
            for i in range(n - 1):
                a, b, c, d = j * n + i + 1, j * n + i + 2, (j + 1) * n + i + 2, (j + 1) * n + i + 1
                if axis is not None:
                    lines += [f"f {a}/{a} {b}/{b} {c}/{c}", f"f {a}/{a} {c}/{c} {d}/{d}"]
                else:
                    lines += [f"f {a} {b} {c}", f"f {a} {c} {d}"]
        path.write_text("\n".join(lines) + "\n")
        return path

    def sheet_obj(self, index, corner, edge1, edge2, axis, normal):
        """A quad as two triangles (normal along edge1 × edge2) with texture coordinates
        (p·axis, p·(normal × axis)), so that Mitsuba's shading frame has U along `axis`."""
        path = self.scene.export_dir / f"sheet_{index}.obj"
        points = [corner, corner + edge1, corner + edge1 + edge2, corner + edge2]
        bitangent = np.cross(normal, axis)
        lines = [f"# shape {index} of {self.scene.path}: a polarizer/retarder quad, u along its axis"]
        lines += ["v " + " ".join(repr(float(c)) for c in p) for p in points]
        lines += [f"vt {float(p @ axis)!r} {float(p @ bitangent)!r}" for p in points]
        lines += ["f 1/1 2/2 3/3", "f 1/1 3/3 4/4"]
        path.write_text("\n".join(lines) + "\n")
        return path

    @classmethod
    def quad_transform(cls, corner, edge1, edge2, swap=False):
        """Rectangle transform of the parallelogram corner + u·edge1 + v·edge2; with `swap`,
        local x runs along edge2 and local y along edge1, so local +z is along edge2 × edge1."""
        corner, edge1, edge2 = (np.asarray(v, dtype=np.float64) for v in (corner, edge1, edge2))
        if swap:
            edge1, edge2 = edge2, edge1
        normal = np.cross(edge1, edge2)
        normal /= np.linalg.norm(normal)
        return cls.frame_transform(edge1 / 2, edge2 / 2, normal, corner + (edge1 + edge2) / 2)

    def shape(self, desc, mesh_index, index=0):
        kind = desc["type"]
        material = self.scene.desc["materials"][desc["material"]]["type"]
        if material in SHEET_MATERIALS and kind not in ("plane", "quad"):
            raise TranslationError(f"shape {index}: a {material} needs a flat shape (quad or plane)")
        if kind == "sphere":
            return {"type": "sphere", "center": [float(c) for c in desc["center"]],
                    "radius": float(desc["radius"])}
        if kind == "plane":
            normal = np.asarray(desc["normal"], dtype=np.float64)
            normal /= np.linalg.norm(normal)
            axis = self.sheet_axis(desc, normal)
            if self.plane_half_size == "graded":
                return {"type": "obj", "face_normals": True,
                        "filename": str(self.graded_plane_obj(index, np.asarray(desc["point"], dtype=np.float64),
                                                              normal, axis))}
            if axis is not None:
                # Local x (U) along the sheet's axis, local y (V) = normal × axis.
                return {"type": "rectangle", "to_world": self.frame_transform(
                    self.plane_half_size * axis, self.plane_half_size * np.cross(normal, axis), normal,
                    desc["point"])}
            return {"type": "rectangle", "to_world": self.plane_transform(desc["point"], desc["normal"],
                                                                          self.plane_half_size)}
        if kind == "quad":
            corner, edge1, edge2 = (np.asarray(desc[k], dtype=np.float64) for k in ("corner", "edge1", "edge2"))
            normal = np.cross(edge1, edge2)
            normal /= np.linalg.norm(normal)
            axis = self.sheet_axis(desc, normal)
            if axis is not None:
                return {"type": "obj", "filename": str(self.sheet_obj(index, corner, edge1, edge2, axis, normal)),
                        "face_normals": True}
            return {"type": "rectangle",
                    "to_world": self.quad_transform(desc["corner"], desc["edge1"], desc["edge2"])}
        if kind in ("mesh", "prism"):
            # prisma export wrote the k-th mesh or prism of the file in scene space; flat faces.
            return {"type": "obj", "filename": str(self.scene.export_dir / f"mesh_{mesh_index}.obj"),
                    "face_normals": True}
        raise TranslationError(f"unknown shape type {kind!r}")

    # Scene ----------------------------------------------------------------------------------

    def sensor(self, spp, pixel_format=None, sampler="independent", film="hdrfilm"):
        """The camera. film = "hdrfilm" (Mitsuba's colour pipeline in spectral variants) or
        "prisma_xyz": Mitsuba's specfilm with prisma's x̄, ȳ, z̄ as response functions (channels
        ∫L·cmf dλ, PRISMA_XYZ_CHANNELS), which `prisma_rgb` turns into prisma's XYZ and linear
        sRGB, so that no colour-pipeline difference remains (spectral variants, no AOVs)."""
        cam = self.scene.camera
        if pixel_format is None:
            pixel_format = "luminance" if self.mono else "rgb"
        if film == "prisma_xyz":
            if not self.spectral:
                raise TranslationError("the prisma_xyz film needs a spectral variant")
            nm, cmf, _, _ = prisma_observer()
            film_dict = {"type": "specfilm", "width": int(cam["width"]), "height": int(cam["height"]),
                         "rfilter": {"type": "box"}, "component_format": "float32"}
            for name, column in zip(PRISMA_XYZ_CHANNELS, cmf.T):
                film_dict[name] = {"type": "regular", "wavelength_min": float(nm[0]), "wavelength_max": float(nm[-1]),
                                   "values": ",".join(repr(float(v)) for v in column)}
        elif film == "hdrfilm":
            film_dict = {
                "type": "hdrfilm",
                "width": int(cam["width"]),
                "height": int(cam["height"]),
                "rfilter": {"type": "box"},
                "pixel_format": pixel_format,
                "component_format": "float32",
            }
        else:
            raise TranslationError(f"unknown film {film!r}")
        lens = {}
        if float(cam.get("aperture_radius", 0.0)) > 0.0:
            lens = {"type": "thinlens", "aperture_radius": float(cam["aperture_radius"]),
                    "focus_distance": float(cam["focus_distance"])}
        return {
            "type": "perspective",
            **lens,
            "fov_axis": "y",
            "fov": float(cam["fov_y_deg"]),
            "to_world": mi.ScalarTransform4f().look_at(
                origin=[float(c) for c in cam["position"]],
                target=[float(c) for c in cam["look_at"]],
                up=[float(c) for c in cam.get("up", [0.0, 1.0, 0.0])]),
            "film": film_dict,
            "sampler": {"type": sampler, "sample_count": int(spp)},
        }

    def scene_dict(self, integrator, spp, pixel_format=None, sampler="independent", film="hdrfilm"):
        """The Mitsuba scene dictionary, with `integrator` (a plugin dictionary), a sampler of
        plugin type `sampler` (references use "independent") and `film` (see `sensor`)."""
        desc, spectra = self.scene.desc, self.scene.spectra
        out = {"type": "scene", "integrator": integrator, "sensor": self.sensor(spp, pixel_format, sampler, film)}
        for name in desc.get("materials", {}):
            out[f"bsdf_{name}"] = self.bsdf(name)
        mesh_index = 0
        for i, shape_desc in enumerate(desc.get("shapes", [])):
            shape = self.shape(shape_desc, mesh_index, i)
            if shape_desc["type"] in ("mesh", "prism"):
                mesh_index += 1
            shape["bsdf"] = {"type": "ref", "id": f"bsdf_{shape_desc['material']}"}
            out[f"shape_{i}"] = shape
        for i, light in enumerate(desc.get("lights", [])):
            resolved = spectra["lights"][i]
            if light["type"] == "point":
                out[f"light_{i}"] = {
                    "type": "point",
                    "position": [float(c) for c in light["position"]],
                    "intensity": self.emitter_spectrum(light["intensity"], resolved["intensity"]),
                }
            elif light["type"] == "quad":
                emit = light.get("emit", "edge1_cross_edge2")
                if emit not in ("edge1_cross_edge2", "edge2_cross_edge1"):
                    raise TranslationError(f"light {i}: unknown emit side {emit!r}")
                out[f"light_{i}"] = {
                    "type": "rectangle",
                    "to_world": self.quad_transform(light["corner"], light["edge1"], light["edge2"],
                                                    swap=(emit == "edge2_cross_edge1")),
                    # prisma's quad lights are black: they emit and block, reflect nothing.
                    "bsdf": {"type": "diffuse", "reflectance": {"type": "uniform", "value": 0.0}},
                    "emitter": {"type": "area",
                                "radiance": self.emitter_spectrum(light["radiance"], resolved["radiance"])},
                }
            else:
                raise TranslationError(f"light {i}: unknown type {light['type']!r}")
        if any(v != 0.0 for v in spectra["background"]):
            out["background"] = {"type": "constant",
                                 "radiance": self.emitter_spectrum(desc.get("background"), spectra["background"])}
        return out


def path_integrator(prisma_max_depth):
    """Mitsuba's path tracer computing exactly Whitted's sum on a scene with no diffuse surface:
    max_depth counts vertices (prisma's bounces + 1) and Russian roulette never starts."""
    return {"type": "path", "max_depth": prisma_max_depth + 1, "rr_depth": prisma_max_depth + 2,
            "hide_emitters": False}


def full_transport_integrator(prisma_max_depth):
    """Mitsuba's path tracer as prisma's full-transport integrator (`integrator = "path"`):
    max_depth counts vertices, so prisma's bounces + 1; Russian roulette as Mitsuba's default
    (rr_depth 5, unbiased); emitters seen directly."""
    return {"type": "path", "max_depth": prisma_max_depth + 1, "hide_emitters": False}


def stokes_integrator(integrator):
    """Mitsuba's `stokes` around `integrator` (polarised variants): adds S0.R … S3.B."""
    return {"type": "stokes", "integrator": integrator}


def variant_for(scene, wavelength_nm=None, polarized=None):
    """The llvm variant comparing with prisma's render of `scene`: mono with a wavelength,
    polarised when prisma renders it polarised (the scene's setting unless `polarized` says)."""
    polarized = scene.polarized if polarized is None else polarized
    base = "llvm_ad_mono" if wavelength_nm is not None else "llvm_ad_spectral"
    return base + ("_polarized" if polarized else "")


def register_ideal_retarder():
    """Registers validation/mitsuba/ideal_retarder.py's BSDF for the current variant."""
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
    import ideal_retarder

    if ideal_retarder.VARIANT != mi.variant():
        importlib.reload(ideal_retarder)


def whitted_integrator(prisma_max_depth):
    """validation/mitsuba/whitted.py's integrator (imports it, which registers the plugin)."""
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
    import whitted

    # The class derives from the current variant's SamplingIntegrator: define and register it
    # again whenever the variant changed since the last import.
    if whitted.VARIANT != mi.variant():
        importlib.reload(whitted)
    return {"type": "whitted", "max_depth": prisma_max_depth}


def render(scene, spp, seed, passes=1, transform=None):
    """Renders `scene` (a loaded Mitsuba scene) with `passes` independent passes of `spp`
    samples each, seeds seed·PASS_SEED_STRIDE + k, and returns (mean image, per-pixel variance
    of that mean, channel names) as float64 numpy arrays (H, W, C). The variance is
    Σ_k (x_k − mean)² / (passes·(passes − 1)) from the passes (Welford's running sums; NaN with
    one pass). Passes bound the memory of a wavefront render. `transform(image, channels)`, if
    given, maps each pass to (image, channels) before it is accumulated (e.g. `prisma_rgb`)."""
    mean = m2 = None
    film = scene.sensors()[0].film()
    for k in range(passes):
        image = np.array(mi.render(scene, spp=spp, seed=pass_seed(seed, k)), dtype=np.float64)
        if image.ndim == 2:
            image = image[..., None]
        channels = [film.bitmap().struct_()[i].name for i in range(image.shape[-1])]
        if transform is not None:
            image, channels = transform(image, channels)
        if mean is None:
            mean, m2 = np.zeros_like(image), np.zeros_like(image)
        delta = image - mean
        mean += delta / (k + 1)
        m2 += delta * (image - mean)
    variance = m2 / (passes * (passes - 1)) if passes > 1 else np.full_like(mean, np.nan)
    return mean, variance, channels


PASS_SEED_STRIDE = 1000


def pass_seed(seed, k):
    """Seed of pass k of a render with seed `seed` (distinct for every seed < 4·10⁶ and k < 1000)."""
    return seed * PASS_SEED_STRIDE + k


def write_exr(path, image, channels):
    """Writes a float32 EXR with the given channel names."""
    image = np.ascontiguousarray(image, dtype=np.float32)
    bitmap = mi.Bitmap(image, channel_names=channels)
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    bitmap.write(str(path))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", type=pathlib.Path, help="prisma scene file")
    parser.add_argument("-o", "--output", type=pathlib.Path, help="EXR to write (default: print the dict)")
    parser.add_argument("--variant", help="Mitsuba variant (default llvm_ad_spectral, or llvm_ad_mono with "
                                          "--wavelength; *_polarized when the scene is polarised)")
    parser.add_argument("--wavelength", type=float, help="render one wavelength (nm) in a mono variant")
    parser.add_argument("--integrator", choices=["path", "whitted"],
                        help="default: whitted when the scene has a diffuse material, else path")
    parser.add_argument("--stokes", action="store_true", help="wrap the integrator in Mitsuba's stokes "
                                                             "(polarised variants): S0.R … S3.B channels")
    parser.add_argument("--spp", type=int, default=64, help="samples per pixel per pass")
    parser.add_argument("--passes", type=int, default=1, help="independent passes averaged")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--plane-half-size", default=str(PLANE_HALF_SIZE),
                        help="half-size of the rectangles standing in for infinite planes, or \"graded\" for the "
                             f"graded mesh (default {PLANE_HALF_SIZE:g})")
    parser.add_argument("--mitsuba-rgb-emitters", action="store_true",
                        help="give Mitsuba the file's RGB emitter colours (its own upsampling)")
    parser.add_argument("--export-dir", type=pathlib.Path, help="where prisma export writes (default: temp)")
    parser.add_argument("--prisma", help="prisma binary (default: $PRISMA or target/release/prisma)")
    args = parser.parse_args()

    with open(args.scene, "rb") as f:
        polarized = bool(tomllib.load(f).get("render", {}).get("polarized", True))
    variant = args.variant or (("llvm_ad_mono" if args.wavelength is not None else "llvm_ad_spectral")
                               + ("_polarized" if polarized else ""))
    mi.set_variant(variant)
    scene = PrismaScene.load(args.scene, args.export_dir, args.prisma)
    plane = args.plane_half_size if args.plane_half_size == "graded" else float(args.plane_half_size)
    translator = Translator(scene, args.wavelength, args.mitsuba_rgb_emitters, plane)
    kind = args.integrator or ("whitted" if scene.has_diffuse() else "path")
    integrator = (whitted_integrator if kind == "whitted" else path_integrator)(scene.max_depth)
    if args.stokes:
        if not mi.is_polarized:
            raise SystemExit("--stokes needs a polarised variant")
        integrator = stokes_integrator(integrator)
    scene_dict = translator.scene_dict(integrator, args.spp)
    if args.output is None:
        print(json.dumps(scene_dict, indent=1, default=str))
        return
    mitsuba_scene = mi.load_dict(scene_dict)
    image, _, channels = render(mitsuba_scene, args.spp, args.seed, args.passes)
    write_exr(args.output, image, channels)
    print(f"wrote {args.output} ({variant}, {kind}{' in stokes' if args.stokes else ''}, "
          f"{args.spp}×{args.passes} spp, channels {channels})")


if __name__ == "__main__":
    main()

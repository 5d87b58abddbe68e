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
  sphere            sphere (outward normals)
  plane             rectangle of half-size PLANE_HALF_SIZE centred on `point`, local +z = normal
  quad              rectangle mapping local (±1, ±1) to the corners: centre corner + (e1 + e2)/2,
                    local x = e1/2, local y = e2/2, local z = unit(e1 × e2)
  mesh, prism       obj (the mesh_<k>.obj of prisma export, scene space) with face normals
  diffuse           twosided(diffuse), reflectance = albedo (prisma shades both sides)
  mirror            conductor, material "none", specular_reflectance = reflectance
  dielectric        dielectric, int_ior = n, ext_ior = 1 (constant n only; a dispersive glass is
                    rendered band by band in a mono variant with n(λ))
  point light       point, intensity (W·sr⁻¹·nm⁻¹ in both renderers)
  quad light        rectangle with a black diffuse BSDF (prisma's quad lights reflect nothing) and
                    an area emitter; Mitsuba emits toward local +z, so for emit =
                    "edge2_cross_edge1" the roles of e1 and e2 are swapped to keep the frame
                    right-handed with +z on the emitting side
  background        constant emitter (left out when the background is black)
  max_depth         prisma counts specular bounces, Mitsuba's `path` counts path vertices:
                    Mitsuba max_depth = prisma max_depth + 1 (see `path_integrator`)

Spectra become `regular` spectra over 360–830 nm in spectral variants, and the value at the
chosen wavelength in mono variants. Optionally, emitters whose file gives an `rgb` colour can be
handed to Mitsuba as that RGB colour instead, so that Mitsuba upsamples it its own way (the
`color_upsampling` validation case).

Not translated (a TranslationError says so): Oren–Nayar roughness, Beer–Lambert absorption,
dispersive glass in a spectral variant.

As a command, renders a scene with Mitsuba for a quick look:
  validation/.venv/bin/python validation/mitsuba/translate.py validation/scenes/tp6_quad.toml \\
      --spp 256 -o /tmp/tp6_quad_mitsuba.exr
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


class TranslationError(Exception):
    """A prisma feature that the translation cannot express in Mitsuba."""


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


def export(scene_path, out_dir, prisma=None):
    """Runs `prisma export SCENE -o OUT_DIR` (1 nm grid) and returns OUT_DIR."""
    out_dir = pathlib.Path(out_dir)
    cmd = [prisma or find_prisma(), "export", str(scene_path), "-o", str(out_dir), "--step-nm", "1"]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return out_dir


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
    def max_depth(self):
        """prisma's maximum number of specular bounces (scene default 16)."""
        return int(self.render_settings.get("max_depth", 16))

    def has_diffuse(self):
        return any(m["type"] == "diffuse" for m in self.desc.get("materials", {}).values())


class Translator:
    """Builds the Mitsuba dictionary of a PrismaScene for the current Mitsuba variant.

    wavelength_nm: for mono variants, the wavelength at which every spectrum and IOR is taken.
    mitsuba_rgb_emitters: emitters whose file gives `{ rgb = [...] }` get Mitsuba's own RGB
      upsampling (an `rgb` spectrum, which Mitsuba multiplies by its D65) instead of prisma's table.
    """

    def __init__(self, scene, wavelength_nm=None, mitsuba_rgb_emitters=False):
        self.scene = scene
        self.mono = mi.is_monochromatic
        self.spectral = mi.is_spectral
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
            return {"type": "conductor", "material": "none",
                    "specular_reflectance": self.spectrum(resolved["reflectance"])}
        if kind == "dielectric":
            if resolved.get("absorption") is not None:
                raise TranslationError(f"material {name!r}: absorption is not translated")
            return {"type": "dielectric", "int_ior": self.ior(resolved["ior"], name), "ext_ior": 1.0}
        raise TranslationError(f"material {name!r}: unknown type {kind!r}")

    # Geometry -------------------------------------------------------------------------------

    @staticmethod
    def frame_transform(x_axis, y_axis, z_axis, origin):
        """The affine map taking local (x, y, z) to origin + x·x_axis + y·y_axis + z·z_axis."""
        m = np.identity(4)
        m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = x_axis, y_axis, z_axis, origin
        return mi.ScalarTransform4f(m.tolist())

    @classmethod
    def plane_transform(cls, point, normal):
        normal = np.asarray(normal, dtype=np.float64)
        normal = normal / np.linalg.norm(normal)
        # Any tangent pair with tangent × bitangent = normal.
        helper = np.array([1.0, 0.0, 0.0]) if abs(normal[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        tangent = np.cross(helper, normal)
        tangent /= np.linalg.norm(tangent)
        bitangent = np.cross(normal, tangent)
        return cls.frame_transform(PLANE_HALF_SIZE * tangent, PLANE_HALF_SIZE * bitangent, normal, point)

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

    def shape(self, desc, mesh_index):
        kind = desc["type"]
        if kind == "sphere":
            return {"type": "sphere", "center": [float(c) for c in desc["center"]],
                    "radius": float(desc["radius"])}
        if kind == "plane":
            return {"type": "rectangle", "to_world": self.plane_transform(desc["point"], desc["normal"])}
        if kind == "quad":
            return {"type": "rectangle",
                    "to_world": self.quad_transform(desc["corner"], desc["edge1"], desc["edge2"])}
        if kind in ("mesh", "prism"):
            # prisma export wrote the k-th mesh or prism of the file in scene space; flat faces.
            return {"type": "obj", "filename": str(self.scene.export_dir / f"mesh_{mesh_index}.obj"),
                    "face_normals": True}
        raise TranslationError(f"unknown shape type {kind!r}")

    # Scene ----------------------------------------------------------------------------------

    def sensor(self, spp, pixel_format=None, sampler="independent"):
        cam = self.scene.camera
        if pixel_format is None:
            pixel_format = "luminance" if self.mono else "rgb"
        return {
            "type": "perspective",
            "fov_axis": "y",
            "fov": float(cam["fov_y_deg"]),
            "to_world": mi.ScalarTransform4f().look_at(
                origin=[float(c) for c in cam["position"]],
                target=[float(c) for c in cam["look_at"]],
                up=[float(c) for c in cam.get("up", [0.0, 1.0, 0.0])]),
            "film": {
                "type": "hdrfilm",
                "width": int(cam["width"]),
                "height": int(cam["height"]),
                "rfilter": {"type": "box"},
                "pixel_format": pixel_format,
                "component_format": "float32",
            },
            "sampler": {"type": sampler, "sample_count": int(spp)},
        }

    def scene_dict(self, integrator, spp, pixel_format=None, sampler="independent"):
        """The Mitsuba scene dictionary, with `integrator` (a plugin dictionary) and a sampler of
        plugin type `sampler` (references use "independent")."""
        desc, spectra = self.scene.desc, self.scene.spectra
        out = {"type": "scene", "integrator": integrator, "sensor": self.sensor(spp, pixel_format, sampler)}
        for name in desc.get("materials", {}):
            out[f"bsdf_{name}"] = self.bsdf(name)
        mesh_index = 0
        for i, shape_desc in enumerate(desc.get("shapes", [])):
            shape = self.shape(shape_desc, mesh_index)
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


def whitted_integrator(prisma_max_depth):
    """validation/mitsuba/whitted.py's integrator (imports it, which registers the plugin)."""
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
    import whitted

    # The class derives from the current variant's SamplingIntegrator: define and register it
    # again whenever the variant changed since the last import.
    if whitted.VARIANT != mi.variant():
        importlib.reload(whitted)
    return {"type": "whitted", "max_depth": prisma_max_depth}


def render(scene, spp, seed, passes=1):
    """Renders `scene` (a loaded Mitsuba scene) with `passes` independent passes of `spp`
    samples each, seeds seed·PASS_SEED_STRIDE + k, and returns (mean image, per-pass images,
    channel names) as numpy arrays. Passes bound the memory of a wavefront render."""
    images = []
    for k in range(passes):
        images.append(np.array(mi.render(scene, spp=spp, seed=pass_seed(seed, k)), dtype=np.float64))
    stack = np.stack(images)
    if stack.ndim == 3:
        stack = stack[..., None]
    film = scene.sensors()[0].film()
    channels = [film.bitmap().struct_()[i].name for i in range(stack.shape[-1])]
    return stack.mean(axis=0), stack, channels


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
    parser.add_argument("--variant", help="Mitsuba variant (default llvm_ad_spectral, or llvm_ad_mono "
                                          "with --wavelength)")
    parser.add_argument("--wavelength", type=float, help="render one wavelength (nm) in a mono variant")
    parser.add_argument("--integrator", choices=["path", "whitted"],
                        help="default: whitted when the scene has a diffuse material, else path")
    parser.add_argument("--spp", type=int, default=64, help="samples per pixel per pass")
    parser.add_argument("--passes", type=int, default=1, help="independent passes averaged")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--mitsuba-rgb-emitters", action="store_true",
                        help="give Mitsuba the file's RGB emitter colours (its own upsampling)")
    parser.add_argument("--export-dir", type=pathlib.Path, help="where prisma export writes (default: temp)")
    parser.add_argument("--prisma", help="prisma binary (default: $PRISMA or target/release/prisma)")
    args = parser.parse_args()

    variant = args.variant or ("llvm_ad_mono" if args.wavelength is not None else "llvm_ad_spectral")
    mi.set_variant(variant)
    scene = PrismaScene.load(args.scene, args.export_dir, args.prisma)
    translator = Translator(scene, args.wavelength, args.mitsuba_rgb_emitters)
    kind = args.integrator or ("whitted" if scene.has_diffuse() else "path")
    integrator = (whitted_integrator if kind == "whitted" else path_integrator)(scene.max_depth)
    scene_dict = translator.scene_dict(integrator, args.spp)
    if args.output is None:
        print(json.dumps(scene_dict, indent=1, default=str))
        return
    mitsuba_scene = mi.load_dict(scene_dict)
    image, _, channels = render(mitsuba_scene, args.spp, args.seed, args.passes)
    write_exr(args.output, image, channels)
    print(f"wrote {args.output} ({variant}, {kind}, {args.spp}×{args.passes} spp, channels {channels})")


if __name__ == "__main__":
    main()

"""The rooms of bench.py --transport-scene: which scene, at which resolution, which Mitsuba
integrator and film, which converged reference and which pixels count.

Shared by bench.py (the race) and transport_reference.py (the references), so that both render
exactly the same translation.

- `room`: validation/scenes/stokes_room_path.toml (a glass sphere of constant index 1.5, a mirror
  sphere, a quad light and a grey sky, open at the top) in full transport and *spectral*: its
  validation case is monochromatic and polarised (550 nm, `stokes`); the race renders all
  wavelengths, prisma with `--integrator path` against Mitsuba's `path` in llvm_ad_spectral
  (prisma `--unpolarized`) and llvm_ad_spectral_polarized (prisma `--polarized`), both through
  prisma's colour pipeline (Mitsuba's specfilm with prisma's CIE table, then prisma's matrix:
  translate.prisma_rgb). The glass does not disperse (its index is a constant), so Mitsuba's
  one-index dielectric renders the same scene. A Fresnel interface changes S0 when the light
  meets a second one polarised, so each mode has its own reference.
- `room_point`: validation/scenes/transport_room_point.toml (a closed diffuse room, a floating
  glass sphere, a D65 point light) against Mitsuba's particle tracer `ptracer` (llvm_ad_spectral,
  full transport: caustics.full_transport_ptracer, twosided diffuse walls), through Mitsuba's
  hdrfilm times its luminance normalisation fix, as the validation case (transport_cases.toml
  says why not its specfilm). Compared only where ptracer is complete: the pixels whose camera
  ray first meets a diffuse surface. ptracer leaves glass black, so those are the pixels where
  both halves of the reference are positive, eroded by one pixel (a pixel next to the sphere's
  silhouette may see it over part of its area): caustics_bench.py's mask.

Both rooms are benchmarked at 75 × 50 pixels, a quarter of their validation cases' 150 × 100
(the camera, its field of view and its aspect ratio unchanged; prisma gets --width 75 --height
50), so that the converged references reach a noise well below relMSE 1e-4 in the time there was.
"""

import dataclasses
import pathlib
import sys

import numpy as np

REPO = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "validation" / "mitsuba"))
REFERENCES = REPO / "validation" / "bench" / "references"


@dataclasses.dataclass(frozen=True)
class BenchScene:
    """One room of the race (see the module's docstring)."""

    key: str
    title: str
    scene: pathlib.Path
    width: int
    height: int
    # "path" (Mitsuba's path tracer, prisma's colour pipeline) or "ptracer" (Mitsuba's particle
    # tracer, its hdrfilm, the diffuse-seen-directly mask).
    mitsuba: str
    # mode (bench.MODES' keys) -> the case name of its converged reference under REFERENCES.
    references: dict
    # prisma's estimator settings for the race (its "best sampler", as Mitsuba's fastest sampler
    # is taken): render options that change the noise and the cost, never the expectation (the
    # same references). See the note above LIGHT_PATHS.
    tuning: tuple = ()

    def prisma_args(self):
        """prisma render's arguments that make it render this benchmark's image."""
        return ["--integrator", "path", "--width", str(self.width), "--height", str(self.height), *self.tuning]


# prisma's settings in the race, chosen on 2026-12-05 (validation/bench/PROFILE.md, "The rooms"):
# relMSE × CPU time at 64–1024 spp, one thread, against the references below.
# - room: the light tracer on (`--caustics`: it then counts the quad light's L S⁺ D X* D E paths,
#   the light the mirror and the glass throw onto the walls and floor, which camera paths find only
#   by chance; the camera paths leave them out: path.rs's table), 500 light paths per pass (0.13 per
#   pixel at 75 × 50): relMSE × spp 0.30 → 0.085 at 512 spp for 1.14× the CPU per sample (3.1×
#   less relMSE × CPU); 250 to 1000 light paths per pass are within 10 % of it, the scene default
#   of one per pixel (3,750) costs 2.1× the CPU per sample for a fifth less error (1.7× worse).
# - room_point: its scene's light tracer (caustics = true) with 500 light paths per pass instead
#   of one per pixel: the same relMSE × spp (0.237 against 0.235 at 256 spp; the camera paths hold
#   most of this room's error) for about half the CPU per sample.
LIGHT_PATHS = "500"


ROOM = BenchScene(
    key="room",
    title="the glass-and-mirror room, spectral",
    scene=REPO / "validation" / "scenes" / "stokes_room_path.toml",
    width=75, height=50, mitsuba="path",
    references={"unpolarised": "stokes_room_path_spectral_75x50",
                "polarised": "stokes_room_path_spectral_polarized_75x50"},
    tuning=("--caustics", "--light-paths", LIGHT_PATHS))
ROOM_POINT = BenchScene(
    key="room_point",
    title="the point-light room against ptracer, spectral",
    scene=REPO / "validation" / "scenes" / "transport_room_point.toml",
    width=75, height=50, mitsuba="ptracer",
    references={"unpolarised": "transport_room_point_75x50"},
    tuning=("--light-paths", LIGHT_PATHS))
SCENES = {s.key: s for s in (ROOM, ROOM_POINT)}
# mode -> Mitsuba's variant (bench.MODES' llvm variants).
VARIANTS = {"unpolarised": "llvm_ad_spectral", "polarised": "llvm_ad_spectral_polarized"}


def load(bench, export_dir, prisma):
    """The prisma scene of `bench` exported and loaded (translate.PrismaScene), its camera at the
    benchmark's resolution. Needs a Mitsuba variant set."""
    import translate

    scene = translate.PrismaScene.load(bench.scene, export_dir, prisma)
    if scene.integrator != "path":
        raise SystemExit(f"{bench.scene}: the scene's integrator is {scene.integrator!r}, the race is for \"path\"")
    scene.desc["camera"] = dict(scene.desc["camera"], width=bench.width, height=bench.height)
    return scene


def mitsuba_integrator(bench, scene):
    """Mitsuba's full-transport integrator for `bench`, as the validation references use it."""
    import translate

    if bench.mitsuba == "path":
        return translate.full_transport_integrator(scene.max_depth)
    import caustics

    return caustics.full_transport_ptracer(scene.max_depth)


def mitsuba_description(bench, scene, spp, sampler):
    """Mitsuba's scene dictionary of `bench` (a variant set), with `spp` samples of `sampler`."""
    integrator = mitsuba_integrator(bench, scene)
    if bench.mitsuba == "path":
        import translate

        translator = translate.Translator(scene, None, False, plane_half_size="graded")
        return translator.scene_dict(integrator, spp, sampler=sampler, film="prisma_xyz")
    import caustics

    translator = caustics.CausticTranslator(scene, None, receiver=False)
    return translator.scene_dict(integrator, spp, sampler=sampler)


def to_rgb(bench, image, channels):
    """Linear sRGB (H, W, 3) of a Mitsuba render of `bench`: prisma's matrix on the prisma_xyz
    film (path), or the hdrfilm's RGB times Mitsuba's luminance normalisation fix (ptracer)."""
    import translate

    if bench.mitsuba == "path":
        rgb, names = translate.prisma_rgb(image, channels)
        return np.stack([rgb[..., names.index(c)] for c in "RGB"], -1)
    import caustics

    return caustics.y_normalisation_fix()[0] * image[..., [channels.index(c) for c in "RGB"]]


def erode(mask):
    """`mask` with every pixel off that has a neighbour (of 8) off or lies on the border."""
    out = mask.copy()
    padded = np.pad(mask, 1, constant_values=False)
    h, w = mask.shape
    for dy in (0, 1, 2):
        for dx in (0, 1, 2):
            out &= padded[dy:dy + h, dx:dx + w]
    return out


def mask(bench, halves):
    """The pixels compared: all of them for `path`; for `ptracer`, those where both halves of the
    reference are positive in every channel, eroded by one pixel."""
    if bench.mitsuba == "path":
        return np.ones(halves[0].shape[:2], dtype=bool)
    return erode(np.all((halves[0] > 0) & (halves[1] > 0), axis=-1))

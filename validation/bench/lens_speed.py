"""The lens-system camera's cost against the pinhole (issue 40, "Speed"), written into its own
section of validation/bench/RESULTS.md (between the `lens_speed.py` markers).

Three cameras on the scene of scenes/lens_dgauss50.toml (ghosts off, unpolarised):
- `lens, all lanes`: scenes/lens_dgauss50.toml as shipped (`lens_lanes = "per_lane"`, the
  default): every camera sample traces its 8 wavelength lanes through the double Gauss, each
  with its own integrator call;
- `lens, shared path`: the same with `lens_lanes = "shared"` (src/camera/lens_system.rs): the
  hero lane's ray traced out through the lens, the 7 others back through it from the scene ray
  (spectral MIS), one integrator call for all 8;
- `lens, one lane`: the same with `[render] wavelengths = 1`: each camera sample one wavelength,
  stratified over the pixel's samples (the wavelength dimension), one lens trace and one
  integrator call; unbiased as any `wavelengths` count is (the film divides by the sampling pdf);
- `pinhole`: scenes/lens_pinhole.toml (the same scene through a pinhole of the same field).

Plus a heavier scene, where the scene's paths cost more than the lens
(validation/scenes/stokes_room_path.toml, the glass-and-mirror room, max_depth 64, made
unpolarised, at 150×100), seen through the double Gauss (sensor 24 mm, f/2.8, focused at 5 m) and
through a pinhole of the same field (27°): equal spp only (16 spp, `--repeats` rounds alternating).

1. Equal spp: render_seconds (from `--stats`: no loading, no lens set-up, no writing) at the
   scenes' resolution and spp, the three alternating, `--repeats` rounds, best of each.
2. Equal error: at `--width` (height from the aspect), relMSE = mean (x − r)²/(r² + 0.01) over
   R, G, B against each camera's own converged reference (the mean of two renders with seeds 1
   and 2 at `--ref-spp`, the lens's in all-lanes mode; the pinhole's at 4× that), minus the
   reference's own noise (bench.py's estimate from the difference of the two); the time to reach
   an error is interpolated log-log between sample counts (bench.py's time_to_error).

Run from the repository root after `cargo build --release`, with the validation venv:
  validation/.venv/bin/python validation/bench/lens_speed.py [--prisma target/release/prisma]
"""

import argparse
import os
import platform
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench import read_exr, rel_mse, reference_noise, time_to_error  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
RESULTS = ROOT / "validation" / "bench" / "RESULTS.md"
BEGIN = "<!-- lens_speed.py: begin -->"
END = "<!-- lens_speed.py: end -->"
HEADLINE_MARK = "lens camera vs pinhole"
LENS = ROOT / "scenes" / "lens_dgauss50.toml"
PINHOLE = ROOT / "scenes" / "lens_pinhole.toml"
ROOM = ROOT / "validation" / "scenes" / "stokes_room_path.toml"
SERIES_SPP = {"lens, all lanes": [4, 16, 64], "lens, shared path": [4, 16, 64, 256],
              "lens, one lane": [4, 16, 64, 256, 1024],
              "pinhole": [1, 2, 4, 16, 64, 256]}
TARGETS = [1e-2, 3e-3, 1e-3]


def shared_scene(directory):
    """scenes/lens_dgauss50.toml with `lens_lanes = "shared"` in [camera] and the lens file's path
    made absolute."""
    text = LENS.read_text().replace('lens = "../data/', f'lens = "{ROOT}/data/')
    text = re.sub(r"(\[camera\]\n)", r'\1lens_lanes = "shared"\n', text, count=1)
    path = Path(directory) / "lens_dgauss50_shared.toml"
    path.write_text(text)
    return path


def one_lane_scene(directory):
    """scenes/lens_dgauss50.toml with `wavelengths = 1` in [render] and the lens file's path made
    absolute (the copy lives elsewhere)."""
    text = LENS.read_text()
    text = text.replace('lens = "../data/', f'lens = "{ROOT}/data/')
    text = re.sub(r"(\[render\]\n)", r"\1wavelengths = 1\n", text, count=1)
    path = Path(directory) / "lens_dgauss50_one_lane.toml"
    path.write_text(text)
    return path


def room_scenes(directory):
    """validation/scenes/stokes_room_path.toml through the double Gauss (per-lane and shared
    paths) and through a pinhole of the same vertical field (27°), unpolarised: (lens scene,
    shared-path lens scene, pinhole scene)."""
    text = ROOM.read_text().replace("polarized = true", "polarized = false")
    frame = "up = [0, 1, 0]\nfov_y_deg = 45\n"
    assert frame in text, "the room's camera block changed"
    lens = text.replace(frame, f'up = [0, 1, 0]\nlens = "{ROOT}/data/lenses/dgauss50.dat"\nsensor_height_mm = 24\n'
                               'focus_distance = 5\nf_number = 2.8\n')
    shared = lens.replace("f_number = 2.8\n", 'f_number = 2.8\nlens_lanes = "shared"\n')
    pinhole = text.replace(frame, "up = [0, 1, 0]\nfov_y_deg = 27\n")
    paths = tuple(Path(directory) / f"room_{name}.toml" for name in ("lens", "shared", "pinhole"))
    for path, scene in zip(paths, (lens, shared, pinhole)):
        path.write_text(scene)
    return paths


def render(prisma, scene, out, spp, threads, seed, width=None):
    """render_seconds of one render (the stats JSON's: loading and writing excluded)."""
    stats = out.with_suffix(".json")
    args = [prisma, "render", str(scene), "--spp", str(spp), "-o", str(out), "--quiet", "--seed", str(seed),
            "--threads", str(threads), "--stats", str(stats)]
    if width:
        args += ["--width", str(width)]
    subprocess.run(args, check=True)
    text = stats.read_text()
    return float(re.search(r'"render_seconds":\s*([0-9.eE+-]+)', text).group(1))



def alternating(rounds, out, args):
    """Render seconds of each (name, binary, scene) at 16 spp, seed 7, in `args.repeats` rounds
    that alternate the scenes (so that a change of load falls on all of them): every round's
    times by name, and the best by name."""
    times = {name: [] for name, _, _ in rounds}
    for _ in range(args.repeats):
        for name, binary, scene in rounds:
            times[name].append(render(binary, scene, out, 16, args.threads, 7))
    return times, {name: min(values) for name, values in times.items()}

def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--prisma", default=str(ROOT / "target" / "release" / "prisma"))
    parser.add_argument("--width", type=int, default=90)
    parser.add_argument("--ref-spp", type=int, default=512)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--baseline", help="an earlier prisma binary: its all-lanes lens render joins the equal-spp "
                                           "rounds (before/after)")
    parser.add_argument("--baseline-name", default="before")
    parser.add_argument("--refs", help="directory of earlier references to reuse (lens_1.exr, lens_2.exr, pin_1.exr, "
                                       "pin_2.exr)")
    args = parser.parse_args()
    started = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    load_before = os.getloadavg()[0]
    work = Path(tempfile.mkdtemp(prefix="lens_speed_"))
    one = one_lane_scene(work)
    cameras = {"lens, all lanes": LENS, "lens, shared path": shared_scene(work), "lens, one lane": one,
               "pinhole": PINHOLE}

    # 1. Equal spp at the scenes' own resolution and spp (16), alternating.
    rounds = [(name, args.prisma, scene) for name, scene in cameras.items()]
    if args.baseline:
        rounds.append((f"lens, all lanes ({args.baseline_name})", args.baseline, LENS))
    equal_spp, best = alternating(rounds, work / "equal.exr", args)

    # 1b. The heavier scene, equal spp.
    room_lens, room_shared, room_pinhole = room_scenes(work)
    room_rounds = [("room, lens", args.prisma, room_lens), ("room, lens, shared path", args.prisma, room_shared),
                   ("room, pinhole", args.prisma, room_pinhole)]
    if args.baseline:
        room_rounds.append((f"room, lens ({args.baseline_name})", args.baseline, room_lens))
    room_spp, room_best = alternating(room_rounds, work / "room.exr", args)

    # 2. References.
    refs = Path(args.refs) if args.refs else work
    for stem, scene, spp in [("lens", LENS, args.ref_spp), ("pin", PINHOLE, 4 * args.ref_spp)]:
        for seed in (1, 2):
            path = refs / f"{stem}_{seed}.exr"
            if not path.exists():
                render(args.prisma, scene, path, spp, args.threads, seed, args.width)
    channels = ["R", "G", "B"]
    reference = {}
    for stem in ("lens", "pin"):
        first, second = (read_exr(refs / f"{stem}_{seed}.exr", channels) for seed in (1, 2))
        reference[stem] = (0.5 * (first + second), reference_noise(first, second))

    # 3. Error against time.
    series = {}
    for name, scene in cameras.items():
        stem = "pin" if name == "pinhole" else "lens"
        ref, floor = reference[stem]
        points = []
        for spp in SERIES_SPP[name]:
            out = work / f"{stem}_{len(points)}_{spp}.exr"
            seconds = min(render(args.prisma, scene, out, spp, args.threads, 7, args.width) for _ in range(2))
            error = rel_mse(read_exr(out, channels), ref) - floor
            points.append((spp, seconds, error))
        series[name] = points
    load_after = os.getloadavg()[0]
    finished = time.strftime("%H:%M UTC", time.gmtime())

    # 4. The section.
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                            text=True).stdout.strip()
    share_note = ("the share of camera samples that pass the lens: see the section (from `cargo bench --bench lens`)")
    lines = [BEGIN, "### Measured by lens_speed.py", "",
             f"Date: {started}–{finished}; commit {commit}; {platform.processor() or platform.machine()}, "
             f"{os.cpu_count()} logical cores shared with other builds (load average {load_before:.1f} before, "
             f"{load_after:.1f} after). Command: `validation/.venv/bin/python validation/bench/lens_speed.py"
             f" --threads {args.threads} --repeats {args.repeats} --width {args.width} --ref-spp {args.ref_spp}"
             f"{' --baseline BIN --baseline-name ' + repr(args.baseline_name) if args.baseline else ''}`"
             f" (written to this file). Scenes: `scenes/lens_dgauss50.toml` (double Gauss 50 mm at f/2.8, ghosts "
             f"off, unpolarised, 8 wavelength lanes), the same with `lens_lanes = \"shared\"` (shared path), "
             f"the same with `[render] wavelengths = 1` (one lane), "
             f"`scenes/lens_pinhole.toml`; all `path`, max_depth 8, `--threads {args.threads}`.", "",
             "### Equal spp (360×240, 16 spp, seed 7)", "",
             "render_seconds (no loading, no lens set-up, no writing), rounds alternating the three cameras:", "",
             "| camera | render seconds, each round | best | / pinhole |", "|---|---|---|---|"]
    for name, times in equal_spp.items():
        lines.append(f"| {name} | {', '.join(f'{t:.2f}' for t in times)} | {best[name]:.2f} | "
                     f"**{best[name] / best['pinhole']:.1f}×** |")
    lines += ["", "### A heavier scene: the glass-and-mirror room (150×100, 16 spp, seed 7)", "",
              "`validation/scenes/stokes_room_path.toml` (max_depth 64) made unpolarised, through the double Gauss "
              "(sensor 24 mm, f/2.8, focused at 5 m) and a pinhole of the same 27° field (`room_scenes` in the "
              "script); render_seconds, rounds alternating:", "",
              "| camera | render seconds, each round | best | / pinhole |", "|---|---|---|---|"]
    for name, times in room_spp.items():
        lines.append(f"| {name} | {', '.join(f'{t:.2f}' for t in times)} | {room_best[name]:.2f} | "
                     f"**{room_best[name] / room_best['room, pinhole']:.1f}×** |")
    lines += ["", f"### Equal error ({args.width} px wide, seed 7; references seeds 1 and 2 at {args.ref_spp} spp "
                  f"(lens, all lanes) and {4 * args.ref_spp} spp (pinhole))", "",
              "| camera | spp | render seconds (best of 2) | relMSE |", "|---|---|---|---|"]
    for name, points in series.items():
        for spp, seconds, error in points:
            lines.append(f"| {name} | {spp} | {seconds:.3f} | {error:.3e} |")
    lines += ["", "Time to reach equal error (seconds, interpolated log-log; * extrapolated):", "",
              "| camera | " + " | ".join(f"relMSE {t:.0e}" for t in TARGETS) + " |",
              "|---|" + "---|" * len(TARGETS)]
    times_at = {}
    for name, points in series.items():
        cells = []
        for target in TARGETS:
            seconds, extrapolated = time_to_error([(s, e) for _, s, e in points], target)
            times_at[(name, target)] = seconds
            cells.append(f"{seconds:.3g}{'*' if extrapolated else ''}")
        lines.append(f"| {name} | " + " | ".join(cells) + " |")
    lines.append("")
    for target in TARGETS:
        pin = times_at[("pinhole", target)]
        lines.append(f"- relMSE {target:.0e}: lens all lanes **{times_at[('lens, all lanes', target)] / pin:.1f}×** "
                     f"the pinhole's time, shared path **{times_at[('lens, shared path', target)] / pin:.1f}×**, "
                     f"one lane **{times_at[('lens, one lane', target)] / pin:.1f}×**.")
    lines += ["", END]
    section = "\n".join(lines)
    text = RESULTS.read_text()
    if BEGIN in text:
        text = text[:text.index(BEGIN)] + section + text[text.index(END) + len(END):]
    else:
        marker = "## Rendering at equal error, polarised and unpolarised"
        heading = "## Lens-system camera against the pinhole (issue 40, \"Speed\")"
        text = text.replace(marker, heading + "\n\n" + section + "\n\n" + marker, 1)
    RESULTS.write_text(text)
    print(section)
    print(share_note)


if __name__ == "__main__":
    main()

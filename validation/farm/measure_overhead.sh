#!/bin/bash
# What splitting adds, separated from this machine's drift: the showcase as 8 parts (4 sample
# ranges × 2 crops) on one thread, merged, then rendered whole on one thread. Each render's
# --stats gives its render-loop time and its ray count: the parts cast exactly the single
# render's rays (same samples), so what splitting adds is each process's CPU time outside the
# render loop (loading, the image and the sums written) and the merge. The render loops' times
# are printed too; they differ by the machine's drift between the runs, not by work.
#
#   validation/farm/measure_overhead.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
prisma=target/release/prisma
scene=scenes/showcase.toml
out=out/farm_overhead
rm -rf "$out" && mkdir -p "$out"
cpu() { # command... → prints user+system seconds of it
    /usr/bin/time -f "%U %S" -o "$out/time" "$@" >/dev/null 2>&1
    awk '{ printf "%.2f", $1 + $2 }' "$out/time"
}
for t in $(seq 0 7); do
    r=$((t % 4)) c=$((t / 4))
    cpu "$prisma" render "$scene" --threads 1 --samples "$((8 * r))..$((8 * r + 8))" \
        --crop "0,$((225 * c)),800,$((225 * c + 225))" -o "$out/part_$t.exr" --preview /dev/null \
        --stats "$out/part_$t.json" >"$out/cpu_$t"
done
cpu "$prisma" merge --complete "$out"/part_*.exr -o "$out/merged.exr" >"$out/cpu_merge"
cpu "$prisma" render "$scene" --threads 1 -o "$out/single.exr" --preview /dev/null \
    --stats "$out/single.json" >"$out/cpu_single"
python3 - "$out" <<'PY'
import json, sys
out = sys.argv[1]
read = lambda name: float(open(f"{out}/{name}").read())
parts = [json.load(open(f"{out}/part_{t}.json")) for t in range(8)]
single = json.load(open(f"{out}/single.json"))
parts_cpu, merge, single_cpu = sum(read(f"cpu_{t}") for t in range(8)), read("cpu_merge"), read("cpu_single")
parts_loop = sum(p["render_seconds"] for p in parts)
rays = sum(p["rays"] for p in parts)
print(f"rays: parts {rays}, single {single['rays']} ({'the same' if rays == single['rays'] else 'DIFFERENT'})")
print(f"render loops: parts {parts_loop:.2f} s, single {single['render_seconds']:.2f} s")
outside_parts, outside_single = parts_cpu - parts_loop, single_cpu - single["render_seconds"]
added = outside_parts + merge - outside_single
print(f"outside the render loop: parts {outside_parts:.2f} s, single {outside_single:.2f} s; merge {merge:.2f} s")
print(f"added by splitting: {added:.2f} s = {100 * added / single['render_seconds']:.1f} % of the single render;"
      f" end to end: {(parts_cpu + merge) / single_cpu:.3f}")
PY

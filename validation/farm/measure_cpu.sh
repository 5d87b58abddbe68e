#!/bin/bash
# CPU time of the showcase rendered whole against split into 8 parts (4 sample ranges × 2
# crops) and merged: user+system seconds from /usr/bin/time, each command run in turn.
#
#   validation/farm/measure_cpu.sh [THREADS]
set -euo pipefail
cd "$(dirname "$0")/../.."
threads=${1:-2}
prisma=target/release/prisma
scene=scenes/showcase.toml
out=out/farm_cpu
rm -rf "$out" && mkdir -p "$out"
cpu() { # command... → prints user+system seconds of it
    /usr/bin/time -f "%U %S" -o "$out/time" "$@" >/dev/null
    awk '{ printf "%.2f", $1 + $2 }' "$out/time"
}
single=$(cpu "$prisma" render "$scene" --threads "$threads" -o "$out/single.exr" --preview /dev/null)
echo "single render: $single s"
parts=0
for t in $(seq 0 7); do
    r=$((t % 4)); c=$((t / 4))
    s=$(cpu "$prisma" render "$scene" --threads "$threads" --samples "$((8 * r))..$((8 * r + 8))" \
        --crop "0,$((225 * c)),800,$((225 * c + 225))" -o "$out/part_$t.exr" --preview /dev/null)
    echo "part $t: $s s"
    parts=$(echo "$parts + $s" | bc)
done
merge=$(cpu "$prisma" merge --complete "$out"/part_*.exr -o "$out/merged.exr")
echo "merge: $merge s"
total=$(echo "$parts + $merge" | bc)
echo "8 parts + merge: $total s; ratio to the single render: $(echo "scale=3; $total / $single" | bc)"
diff <("$prisma" info "$out/single.exr" | grep imageSha256) <("$prisma" info "$out/merged.exr" | grep imageSha256) \
    && echo "merged image bit-identical to the single render"

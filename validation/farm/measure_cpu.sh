#!/bin/bash
# CPU time of the showcase rendered whole against split into 8 parts (4 sample ranges × 2
# crops) and merged: user+system seconds from /usr/bin/time, each command run in turn,
# REPEATS times over, the single render first in odd repeats and last in even ones (this
# machine slows down over a run of renders: with the single render always first, the parts
# always ran on the slower end). Prints every repeat's ratio, their median, and the ratio of
# the medians.
#
#   validation/farm/measure_cpu.sh [THREADS] [REPEATS]
set -euo pipefail
cd "$(dirname "$0")/../.."
threads=${1:-2}
repeats=${2:-1}
prisma=target/release/prisma
scene=scenes/showcase.toml
out=out/farm_cpu
rm -rf "$out" && mkdir -p "$out"
cpu() { # command... → prints user+system seconds of it
    /usr/bin/time -f "%U %S" -o "$out/time" "$@" >/dev/null
    awk '{ printf "%.2f", $1 + $2 }' "$out/time"
}
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
singles=() totals=() merges=() ratios=()
for rep in $(seq 1 "$repeats"); do
    single() { cpu "$prisma" render "$scene" --threads "$threads" -o "$out/single.exr" --preview /dev/null; }
    if ((rep % 2 == 1)); then single=$(single); fi
    parts=0 list=""
    for t in $(seq 0 7); do
        r=$((t % 4)); c=$((t / 4))
        s=$(cpu "$prisma" render "$scene" --threads "$threads" --samples "$((8 * r))..$((8 * r + 8))" \
            --crop "0,$((225 * c)),800,$((225 * c + 225))" -o "$out/part_$t.exr" --preview /dev/null)
        parts=$(echo "$parts + $s" | bc) list="$list $s"
    done
    merge=$(cpu "$prisma" merge --complete "$out"/part_*.exr -o "$out/merged.exr")
    if ((rep % 2 == 0)); then single=$(single); fi
    total=$(echo "$parts + $merge" | bc)
    echo "repeat $rep: single $single s; parts$list = $parts s; merge $merge s;" \
        "parts + merge $total s; ratio $(echo "scale=3; $total / $single" | bc)"
    diff <("$prisma" info "$out/single.exr" | grep imageSha256) \
        <("$prisma" info "$out/merged.exr" | grep imageSha256) >/dev/null \
        || { echo "the merged image differs from the single render" >&2; exit 1; }
    singles+=("$single") totals+=("$total") merges+=("$merge")
    ratios+=("$(echo "scale=4; $total / $single" | bc)")
done
ms=$(printf '%s\n' "${singles[@]}" | median)
mt=$(printf '%s\n' "${totals[@]}" | median)
mm=$(printf '%s\n' "${merges[@]}" | median)
mr=$(printf '%s\n' "${ratios[@]}" | median)
echo "median of $repeats: single $ms s, parts + merge $mt s (merge $mm s): ratio of the medians" \
    "$(echo "scale=3; $mt / $ms" | bc), median ratio $mr; every merged image bit-identical to its single render"

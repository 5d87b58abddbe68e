#!/bin/bash
# One task of a split render's Slurm job array (submitted by submit.sh): task T renders sample
# range T mod RANGES of horizontal band T div RANGES, as a part EXR with its own log.
#
# Environment (exported by submit.sh): PRISMA (binary), SCENE, OUT (directory), SPP, RANGES,
# CROPS, WIDTH, HEIGHT (the scene's resolution).
set -euo pipefail
: "${PRISMA:?}" "${SCENE:?}" "${OUT:?}" "${SPP:?}" "${RANGES:?}" "${CROPS:?}" "${WIDTH:?}" "${HEIGHT:?}"
task=${SLURM_ARRAY_TASK_ID:?not running as a Slurm array task}
range=$((task % RANGES))
band=$((task / RANGES))
first=$((SPP * range / RANGES))
end=$((SPP * (range + 1) / RANGES))
y0=$((HEIGHT * band / CROPS))
y1=$((HEIGHT * (band + 1) / CROPS))
echo "task $task on $(hostname): samples $first..$end, window 0,$y0,$WIDTH,$y1"
# CPU time of the task (user+system seconds) on the last line of the log.
exec /usr/bin/time -f "cpu_seconds %U+%S" "$PRISMA" render "$SCENE" --spp "$SPP" \
    --samples "$first..$end" --crop "0,$y0,$WIDTH,$y1" \
    --threads "${SLURM_CPUS_PER_TASK:-1}" \
    -o "$OUT/part_$task.exr" --preview "$OUT/part_$task.png"

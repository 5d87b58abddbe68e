#!/bin/bash
# Submits a split render to Slurm: a job array of RANGES sample ranges × CROPS horizontal bands
# (one task each), then a merge job that starts when all of them succeeded. Prints the two job ids.
#
#   PRISMA=target/release/prisma SCENE=scenes/showcase.toml OUT=out/farm \
#   SPP=32 RANGES=4 CROPS=2 WIDTH=800 HEIGHT=450 validation/farm/submit.sh
#
# Each task writes OUT/part_T.exr and logs to OUT/part_T.log (progress with the time left, and
# its CPU time); the merge writes OUT/merged.exr and OUT/merge.log.
set -euo pipefail
: "${PRISMA:?}" "${SCENE:?}" "${OUT:?}" "${SPP:?}" "${RANGES:?}" "${CROPS:?}" "${WIDTH:?}" "${HEIGHT:?}"
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$OUT"
export PRISMA SCENE OUT SPP RANGES CROPS WIDTH HEIGHT
tasks=$((RANGES * CROPS))
array=$(sbatch --parsable --job-name=prisma-part --array=0-$((tasks - 1)) --cpus-per-task="${CPUS_PER_TASK:-1}" \
    --output="$OUT/part_%a.log" --export=ALL "$here/render_part.sh")
merge=$(sbatch --parsable --job-name=prisma-merge --dependency=afterok:"$array" \
    --output="$OUT/merge.log" --export=ALL "$here/merge_parts.sh")
echo "$array $merge"

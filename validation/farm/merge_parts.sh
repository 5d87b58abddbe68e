#!/bin/bash
# The job that runs after every task of the array succeeded (submit.sh: --dependency=afterok):
# merges the parts into the whole image, refusing unless they make all of it.
set -euo pipefail
: "${PRISMA:?}" "${OUT:?}"
exec /usr/bin/time -f "cpu_seconds %U+%S" "$PRISMA" merge --complete "$OUT"/part_*.exr -o "$OUT/merged.exr"

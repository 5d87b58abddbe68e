#!/bin/bash
# End-to-end check of the Slurm recipe on a real one-node Slurm on this machine (root needed;
# not run in CI): starts munge, slurmctld and slurmd (start_slurm.sh), submits the showcase
# (the default scene) as a job array of 4 sample ranges × 2 crops plus a dependent merge
# (submit.sh), waits, renders the same image in one piece, and compares the two bit for bit.
# Writes its log to out/slurm_run.log (ignored by git); LOG=validation/farm/slurm_run.log
# replaces the committed log that the README quotes.
#
#   sudo validation/farm/run_slurm_test.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
log=${LOG:-out/slurm_run.log}
mkdir -p "$(dirname "$log")"
exec > >(tee "$log") 2>&1
echo "== $(date -u +%FT%TZ) on $(hostname -s), $(nproc) CPUs, $(slurmctld -V 2>/dev/null || echo 'Slurm to install')"
bash validation/farm/start_slurm.sh
cargo build --release -q
export PRISMA=$PWD/target/release/prisma SCENE=$PWD/scenes/showcase.toml OUT=$PWD/out/farm
export SPP=32 RANGES=4 CROPS=2 WIDTH=800 HEIGHT=450
rm -rf "$OUT" && mkdir -p "$OUT"
echo "== $("$PRISMA" --version), scene $SCENE: ${WIDTH}×${HEIGHT}, $SPP spp, split into $RANGES sample ranges × $CROPS crops"
read -r array merge < <(validation/farm/submit.sh)
echo "== submitted job array $array and merge job $merge (afterok:$array)"
start=$(date +%s)
while squeue -h -j "$array,$merge" 2>/dev/null | grep -q .; do
    sleep 5
done
echo "== the jobs left the queue after $(($(date +%s) - start)) s"
scontrol show job "$merge" 2>/dev/null | grep -E "JobState|ExitCode" || true
for t in $(seq 0 $((RANGES * CROPS - 1))); do
    echo "-- part $t: $(head -n 1 "$OUT/part_$t.log"); $(grep -c '^progress:' "$OUT/part_$t.log") progress lines; $(tail -n 1 "$OUT/part_$t.log")"
done
echo "-- a part's log:"
cat "$OUT/part_0.log"
echo "-- merge: $(cat "$OUT/merge.log")"
test -s "$OUT/merged.exr"
echo "== the same image in one piece (all 32 samples, whole frame, with its sums)"
/usr/bin/time -f "cpu_seconds %U+%S" "$PRISMA" render "$SCENE" --part -o "$OUT/single.exr" --preview /dev/null
"$PRISMA" info "$OUT/merged.exr"
"$PRISMA" info "$OUT/single.exr" | grep -E "^(samples|crop|parts|wallSeconds|threads|sumsBlake3|imageSha256):"
# Bit for bit: the image channels and the exact sums (the headers differ in wall time, threads
# and number of parts, so the files themselves are compared through these digests).
"$PRISMA" info "$OUT/merged.exr" | grep -E "^(samples|crop|sceneSha256|settings|sumsBlake3|imageSha256):" > "$OUT/merged.digest"
"$PRISMA" info "$OUT/single.exr" | grep -E "^(samples|crop|sceneSha256|settings|sumsBlake3|imageSha256):" > "$OUT/single.digest"
if cmp "$OUT/merged.digest" "$OUT/single.digest"; then
    echo "== PASS: the merged Slurm render is bit-identical to the single render (image channels and sums)"
else
    echo "== FAIL: the merged render differs from the single render"
    exit 1
fi

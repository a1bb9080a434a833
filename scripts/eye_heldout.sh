#!/usr/bin/env bash
# The eye tracker's held-out numbers: detection, confidence and speed on eyesim seeds 9000-9049
# (set A), 8000-8049 (set B), 7000-7049 (set C), 6000-6049 (set D), 5000-5049 (set E) and
# 4000-4049 (set F) — seeds the detector is not developed on (seeds 1-300 are) — then the 2D and
# 3D gaze models before and after headset slippage on seeds 9000-9007, and binocular vergence on
# seeds 9000-9003. Writes JSON into OUT (default out/eye_heldout).
# DETECTOR_ONLY=1 skips slippage and vergence.
set -euo pipefail
G=${GAZETRACE:-build/gazetrace}
OUT=${1:-out/eye_heldout}
mkdir -p "$OUT"
for set in 9000-9049 8000-8049 7000-7049 6000-6049 5000-5049 4000-4049; do
    for preset in clean hard wild; do
        "$G" eyescore --preset "$preset" --seeds "$set" --frames 300 --json \
            > "$OUT/eyescore_${preset}_$set.json"
    done
done
"$G" bench --suite eye > "$OUT/bench_eye.txt" 2>&1
[ "${DETECTOR_ONLY:-0}" = 1 ] && exit 0
"$G" slippage --seeds 9000-9007 --slips-mm 1,2,3 --slip-deg 2 --json > "$OUT/slippage.json"
for seed in 9000 9001 9002 9003; do
    depth=$(( 30 + (seed - 9000) * 40 ))   # 30, 70, 110, 150 cm
    d="$OUT/bino_$seed"; mkdir -p "$d"
    "$G" eyesim --seed "$seed" --frames 2400 --eye both --depth-cm "$depth" --out "$d/both.mkv" \
        --truth "$d/left.csv" --truth-right "$d/right.csv" --json > "$d/eyesim.json"
    regions=$(python3 -c "import json,sys; print(json.load(open('$d/eyesim.json'))['regions'])")
    "$G" calibrate --source "video:$d/both.mkv" --regions "$regions" --targets "$d/left.csv" \
        --out "$d/cal.json" --json > "$d/calibrate.json"
    "$G" track --source "video:$d/both.mkv" --regions "$regions" --calibration "$d/cal.json" \
        --truth "$d/left.csv" --truth-right "$d/right.csv" --json > "$d/track.json"
done
echo "held-out results in $OUT"

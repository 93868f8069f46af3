#!/usr/bin/env bash
# The main job.
#  1. Replay: dataset -> LCM log -> stock lcm-logplayer over UDP multicast -> recorded
#     trajectory -> hs-eval against the dataset's ground truth (summary, JSON, PNG plot).
#  2. Tracking: the tracker over a simulated room_mav flight (in memory), alone and with the
#     mapper in process, with accuracy and timing; then the tracker benchmark.
#   tools/demo.sh [EUROC_DIR]      default: the bundled real EuRoC sample for part 1
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=build/bin
DATASET=${1:-tests/data/euroc_v1_01_static_sample}
OUT=out/demo
mkdir -p "$OUT"

for tool in hs-euroc2lcm hs-record-trajectory hs-eval hs-run; do
  [ -x "$BIN/$tool" ] || { echo "demo: $BIN/$tool missing: run tools/setup.sh first" >&2; exit 1; }
done
command -v lcm-logplayer >/dev/null || { echo "demo: lcm-logplayer missing (liblcm-bin)" >&2; exit 1; }

# A private multicast port, so a live system on the default port is not disturbed.
PORT=$((20000 + RANDOM % 20000))
URL="udpm://239.255.76.67:${PORT}?ttl=0&recv_buf_size=16777216"

echo "== 1/6 convert $DATASET to an LCM log"
"$BIN/hs-euroc2lcm" --dataset "$DATASET" --out "$OUT/dataset.lcmlog"

echo "== 2/6 replay with lcm-logplayer over $URL and record GROUND_TRUTH"
"$BIN/hs-record-trajectory" --channel GROUND_TRUTH --out "$OUT/replayed.tum" \
  --lcm-url "$URL" --idle-timeout 3 &
recorder=$!
sleep 0.5
lcm-logplayer -l "$URL" "$OUT/dataset.lcmlog"
wait "$recorder"

echo "== 3/6 evaluate the replayed trajectory against the dataset's ground truth"
GT=""
for f in "$DATASET"/mav0/state_groundtruth_estimate0/data.csv "$DATASET"/state_groundtruth_estimate0/data.csv; do
  if [ -f "$f" ]; then GT=$f; break; fi
done
[ -n "$GT" ] || { echo "demo: $DATASET has no state_groundtruth_estimate0/data.csv" >&2; exit 1; }
"$BIN/hs-eval" "$GT" "$OUT/replayed.tum" --align --json "$OUT/eval.json" --plot "$OUT/eval.png"

echo "== 4/6 track a simulated 40 s room_mav flight (stereo + IMU) with hs-run, tracker alone"
"$BIN/hs-run" --sim config/sim/room_mav.yaml --out "$OUT/tracking"

echo "== 5/6 the same flight with the mapper in process (local visual-inertial BA per keyframe)"
"$BIN/hs-run" --sim config/sim/room_mav.yaml --with-mapper --out "$OUT/tracking_mapper"

echo "== 6/6 benchmark: hybrid (ORB at keyframes only) vs every-frame ORB (paper Table 4)"
"$BIN/hs-bench-tracker" --sim config/sim/room_mav.yaml --json "$OUT/bench.json"
echo "demo: outputs in $OUT/ (replay: dataset.lcmlog, replayed.tum, eval.json, eval.png;"
echo "      tracking, tracking_mapper: trajectory.tum, timing.csv, eval.json, eval.png; bench.json)"

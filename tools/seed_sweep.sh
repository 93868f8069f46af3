#!/usr/bin/env bash
# Rank settings over several random seeds of a simulated scenario: one run's ATE moves by tens of
# percent with the noise draw, so compare means. For each seed it runs hs-run for the baseline
# (the tracker alone unless --baseline says otherwise) and with the mapper (two runs at a time)
# and prints both ATE RMSEs, their ratio, the mean ratio and the ratio of the sums.
#   tools/seed_sweep.sh SCENARIO.yaml [--seeds "1 2 3"] [--duration S] [--out DIR] [--final]
#                       [--baseline "hs-run args"] [-- hs-run args]
# Arguments after -- go to the mapper runs (e.g. --mapper-config F). --final compares the final
# trajectories (frames on their keyframes' final poses) where a run wrote one.
set -euo pipefail
scenario=${1:?usage: seed_sweep.sh SCENARIO.yaml [--seeds LIST] [--duration S] [--out DIR] [--final] [--baseline ARGS] [-- ARGS]}
shift
seeds="1 2 3"
duration=()
out=out/seed_sweep
extra=()
baseline=()
final=0
while (($#)); do
  case $1 in
  --seeds) seeds=$2; shift 2 ;;
  --duration) duration=(--duration "$2"); shift 2 ;;
  --out) out=$2; shift 2 ;;
  --final) final=1; shift ;;
  --baseline) read -r -a baseline <<<"$2"; shift 2 ;;
  --) shift; extra=("$@"); break ;;
  *) echo "seed_sweep.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
bin=$(dirname "$0")/../build/bin/hs-run
[[ -x $bin ]] || { echo "seed_sweep.sh: build first ($bin missing)" >&2; exit 2; }

run() {  # run NAME SEED ARGS...
  local name=$1 seed=$2
  shift 2
  "$bin" --sim "$scenario" --seed "$seed" "${duration[@]}" --out "$out/$seed/$name" "$@" \
    >"$out/$seed/$name.log" 2>&1 || { echo "seed $seed $name failed: $out/$seed/$name.log" >&2; return 1; }
}
ate_cm() {  # ate_cm RUN_DIR
  local json=$1/eval.json
  if ((final)) && [[ -f $1/trajectory_final.tum ]]; then
    json=$1/eval_final.json
    "$(dirname "$bin")/hs-eval" --align --json "$json" "$1/groundtruth.tum" \
      "$1/trajectory_final.tum" >/dev/null
  fi
  python3 -c 'import json,sys; print("%.3f" % (100 * json.load(open(sys.argv[1]))["ape"]["rmse"]))' "$json"
}

printf '%-6s %10s %10s %7s\n' seed base_cm mapper_cm ratio
bases=()
mappers=()
for seed in $seeds; do
  mkdir -p "$out/$seed"
  run base "$seed" "${baseline[@]}" &
  base_pid=$!
  run mapper "$seed" --with-mapper "${extra[@]}"
  wait "$base_pid"
  a=$(ate_cm "$out/$seed/base")
  m=$(ate_cm "$out/$seed/mapper")
  r=$(python3 -c "print('%.3f' % ($m / $a))")
  printf '%-6s %10s %10s %7s\n' "$seed" "$a" "$m" "$r"
  bases+=("$a")
  mappers+=("$m")
done
python3 - "${#bases[@]}" "${bases[@]}" "${mappers[@]}" <<'PY'
import sys
n = int(sys.argv[1])
v = [float(x) for x in sys.argv[2:]]
b, m = v[:n], v[n:]
mean = sum(y / x for x, y in zip(b, m)) / n
print("mean ratio %.3f, ratio of sums %.3f over %d seeds" % (mean, sum(m) / sum(b), n))
PY

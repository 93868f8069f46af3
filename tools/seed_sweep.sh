#!/usr/bin/env bash
# Rank settings over several random seeds of a simulated scenario: one run's ATE moves by tens of
# percent with the noise draw, so compare means. For each seed it runs hs-run on the tracker alone
# and with the mapper (two runs at a time) and prints both ATE RMSEs and their ratio.
#   tools/seed_sweep.sh SCENARIO.yaml [--seeds "1 2 3"] [--duration S] [--out DIR] [-- hs-run args]
# Arguments after -- go to the mapper runs (e.g. --mapper-config F).
set -euo pipefail
scenario=${1:?usage: seed_sweep.sh SCENARIO.yaml [--seeds LIST] [--duration S] [--out DIR] [-- ARGS]}
shift
seeds="1 2 3"
duration=()
out=out/seed_sweep
extra=()
while (($#)); do
  case $1 in
  --seeds) seeds=$2; shift 2 ;;
  --duration) duration=(--duration "$2"); shift 2 ;;
  --out) out=$2; shift 2 ;;
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
ate_cm() {
  python3 -c 'import json,sys; print("%.2f" % (100 * json.load(open(sys.argv[1]))["ape"]["rmse"]))' "$1"
}

printf '%-6s %10s %10s %7s\n' seed alone_cm mapper_cm ratio
sum_ratio=0
n=0
for seed in $seeds; do
  mkdir -p "$out/$seed"
  run alone "$seed" &
  alone_pid=$!
  run mapper "$seed" --with-mapper "${extra[@]}"
  wait "$alone_pid"
  a=$(ate_cm "$out/$seed/alone/eval.json")
  m=$(ate_cm "$out/$seed/mapper/eval.json")
  r=$(python3 -c "print('%.3f' % ($m / $a))")
  printf '%-6s %10s %10s %7s\n' "$seed" "$a" "$m" "$r"
  sum_ratio=$(python3 -c "print($sum_ratio + $r)")
  n=$((n + 1))
done
python3 -c "print('mean ratio %.3f over %d seeds' % ($sum_ratio / $n, $n))"

#!/usr/bin/env bash
# Screenshot of lcm-spy decoding an LCM log with the HS-SLAM types, on a virtual X display:
# starts Xvfb, tools/lcm-spy.sh, replays the log with lcm-logplayer, opens one channel's
# detail view and saves the screen as a PNG.
#   tools/spy_screenshot.sh (--log FILE | --dataset DIR) [--out PNG] [--detail CHANNEL]
#                           [--seconds S] [--build DIR]
# --dataset converts a EuRoC folder with DIR/bin/hs-euroc2lcm first. --out defaults to
# lcm-spy.png, --detail to TRACKER_STATUS (none: no detail view), --seconds (replay time before
# the screenshot) to 6. Traffic goes to a private multicast port, so live processes on the
# default URL neither disturb nor see it. Needs xvfb, imagemagick, xdotool.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"

log=""
dataset=""
out="lcm-spy.png"
detail="TRACKER_STATUS"
seconds=6
build="$root/build"
while [ $# -gt 0 ]; do
  case "$1" in
    --log) log="${2:?--log needs a file}"; shift 2 ;;
    --dataset) dataset="${2:?--dataset needs a EuRoC folder}"; shift 2 ;;
    --out) out="${2:?--out needs a file}"; shift 2 ;;
    --detail) detail="${2:?--detail needs a channel or none}"; shift 2 ;;
    --seconds) seconds="${2:?--seconds needs a number}"; shift 2 ;;
    --build) build="${2:?--build needs a directory}"; shift 2 ;;
    -h | --help) sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "spy_screenshot.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done

fail() {
  echo "spy_screenshot.sh: $1" >&2
  exit 1
}
if [ -z "$log$dataset" ] || { [ -n "$log" ] && [ -n "$dataset" ]; }; then
  fail "give exactly one of --log FILE and --dataset DIR (see --help)"
fi
for tool in Xvfb:xvfb import:imagemagick xdotool:xdotool lcm-logplayer:liblcm-bin python3:python3; do
  command -v "${tool%%:*}" >/dev/null || fail "${tool%%:*} not found (apt-get install ${tool#*:})"
done

tmp="$(mktemp -d)"
pids=()
cleanup() {
  local p
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$tmp"
}
trap cleanup EXIT

if [ -n "$dataset" ]; then
  converter="$build/bin/hs-euroc2lcm"
  [ -x "$converter" ] || fail "$converter not found: cmake --build $build --target hs-euroc2lcm"
  log="$tmp/dataset.lcmlog"
  "$converter" --dataset "$dataset" --out "$log" >"$tmp/convert.log" 2>&1 ||
    fail "hs-euroc2lcm failed on $dataset: $(tail -n 3 "$tmp/convert.log")"
fi
[ -f "$log" ] || fail "$log: no such log file"
# Java's UDP socket gets the kernel's default receive buffer; a raw stereo pair is ~720 kB.
if [ "$(sysctl -n net.core.rmem_default 2>/dev/null || echo 0)" -lt 2000000 ]; then
  echo "spy_screenshot.sh: note: net.core.rmem_default is small, so large messages" \
    "(CAM_STEREO) may be lost; tools/setup.sh raises it when run as root" >&2
fi

# Spy lists channels sorted by name; the detail row is found from the channels in the log.
channels="$(python3 - "$log" <<'EOF'
import struct, sys
path, names = sys.argv[1], set()
with open(path, "rb") as f:
    while len(head := f.read(28)) == 28:  # a truncated last event is ignored, as by the player
        if struct.unpack(">I", head[:4])[0] != 0xEDA1DA01:
            sys.exit(f"{path}: not an LCM log (bad event header at byte {f.tell() - len(head)})")
        channel_len, data_len = struct.unpack(">II", head[20:])
        names.add(f.read(channel_len).decode())
        f.seek(data_len, 1)
print("\n".join(sorted(names)))
EOF
)"
[ -n "$channels" ] || fail "$log: no events"

Xvfb -displayfd 3 -screen 0 1480x620x24 -nolisten tcp 3>"$tmp/display" 2>"$tmp/xvfb.log" &
pids+=($!)
for _ in $(seq 50); do [ -s "$tmp/display" ] && break; sleep 0.1; done
[ -s "$tmp/display" ] || fail "Xvfb did not start: $(cat "$tmp/xvfb.log")"
DISPLAY=":$(cat "$tmp/display")"
export DISPLAY

url="udpm://239.255.76.67:$((7700 + $$ % 1000))?ttl=0"
"$root/tools/lcm-spy.sh" --build "$build" --lcm-url "$url" >"$tmp/spy.log" 2>&1 &
pids+=($!)
timeout 60 xdotool search --sync --name '^LCM Spy$' >/dev/null ||
  fail "lcm-spy did not open a window: $(cat "$tmp/spy.log")"

lcm-logplayer -l "$url" "$log" >"$tmp/play.log" 2>&1 &
pids+=($!)
sleep "$seconds"

if [ "$detail" != "none" ]; then
  row="$(grep -n -x -F "$detail" <<<"$channels" | cut -d: -f1 || true)"
  [ -n "$row" ] || fail "channel $detail is not in $log"
  # Rows are 16 px high below a 20 px header (Metal look and feel); without a window manager
  # the Spy window sits at the origin.
  xdotool mousemove 100 $((27 + 16 * (row - 1))) click --repeat 2 --delay 80 1
  win="$(timeout 10 xdotool search --sync --name "^$detail\$" | head -n1)" ||
    fail "no detail window for $detail (was it received within $seconds s?)"
  xdotool windowmove "$win" 800 0 windowsize "$win" 680 620
  sleep 1.5
fi

import -window root "$out"
echo "spy_screenshot.sh: wrote $out"
grep -h -i -E "exception|error" "$tmp/spy.log" >&2 || true

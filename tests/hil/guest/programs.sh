#!/bin/sh
# The project's programs against the guest's kernel interfaces. LCM traffic stays in the guest
# (udpm on its loopback) and is recorded and checked there with hs-logger.
URL='udpm://239.255.76.67:7667?ttl=0'
status=0
# Waits (up to 20 s) until file $1 contains $2: a process saying it is ready.
ready() {
  i=0
  while ! grep -q "$2" "$1" 2>/dev/null; do
    i=$((i + 1))
    [ $i -gt 200 ] && return 1
    usleep 100000
  done
}
check() {
  if "$@"; then echo "HIL check $*: PASS"; else echo "HIL check $*: FAIL"; status=1; fi
}

# hs-trigger on gpio-sim. gpio-sim cannot wire an output to an input, so a mirror loop copies the
# trigger line (cam-trigger) to the strobe input (cam-strobe-in) by its pull, like a loopback
# wire with a shell's latency; hs-trigger times each pulse by that edge.
chip=$(gpiodetect | awk '/\[hil-sim\]/ {print $1}')
sim=/sys/bus/gpio/devices/$chip
(
  last=0
  while true; do
    v=$(cat $sim/sim_gpio0/value)
    if [ "$v" != "$last" ]; then
      if [ "$v" = 1 ]; then echo pull-up > $sim/sim_gpio1/pull; else echo pull-down > $sim/sim_gpio1/pull; fi
      last=$v
    fi
    usleep 200
  done
) &
mirror=$!
cat > /tmp/trigger.yaml <<EOT
trigger:
  chip: $chip
  output_line: cam-trigger
  edge_line: cam-strobe-in
  rate_hz: 20
  pulse_width_s: 0.02          # long enough for the mirror loop to see every pulse under load
  edge_timeout_s: 0.04
EOT
hs-logger --dir /tmp/log --lcm-url "$URL" > /tmp/logger.txt 2>&1 &
logger=$!
ready /tmp/logger.txt recording
hs-trigger --config /tmp/trigger.yaml --lcm-url "$URL" > /tmp/trigger.txt 2>&1 &
trigger=$!
sleep 4
kill -INT $trigger
wait $trigger
trigger_status=$?
sleep 1
kill -INT $logger
wait $logger
kill $mirror
cat /tmp/trigger.txt
hs-logger --check /tmp/log/*.lcmlog > /tmp/check.json
pulses=$(sed -n 's/^hs-trigger: \([0-9]*\) pulses, \([0-9]*\) timed by their edge.*/\1/p' /tmp/trigger.txt)
edges=$(sed -n 's/^hs-trigger: \([0-9]*\) pulses, \([0-9]*\) timed by their edge.*/\2/p' /tmp/trigger.txt)
recorded=$(grep -A12 '"TRIGGER"' /tmp/check.json | sed -n 's/.*"messages": \([0-9]*\).*/\1/p' | head -1)
lost=$(grep -A12 '"TRIGGER"' /tmp/check.json | sed -n 's/.*"lost_upstream": \([0-9]*\).*/\1/p' | head -1)
echo "hs-trigger: exit $trigger_status, $pulses pulses, $edges timed by their edge; TRIGGER recorded $recorded, lost $lost"
check [ "$trigger_status" = 0 ]
check [ "${pulses:-0}" -ge 60 ]                      # 4 s at 20 Hz, less the 0.1 s start
check [ "${edges:-0}" -ge $((pulses * 9 / 10)) ]     # the mirror's edges came back
check [ "${recorded:-0}" = "$pulses" ]               # every pulse published and recorded
check [ "${lost:-1}" = 0 ]                           # seq continuous
# hs-camera on the vivid stereo pair, free-running at 30 fps: frames stamped, paired and
# published; vivid drops half of the right device's buffers for 2 s (percentage_of_dropped_buffers),
# then the left device is disconnected (vivid's disconnect control, like an unplug) and must come
# back by itself.
cat > /tmp/camera.yaml <<EOT
camera:
  devices: [/dev/video0, /dev/video1]
  width: 320
  height: 180
  format: YUYV
  fps: 30
  max_stereo_skew_s: 0.034     # the two vivid instances free-run: up to a frame apart
EOT
hs-logger --dir /tmp/camlog --lcm-url "$URL" > /tmp/camlogger.txt 2>&1 &
logger=$!
ready /tmp/camlogger.txt recording
hs-camera --config /tmp/camera.yaml --lcm-url "$URL" > /tmp/camera.txt 2>&1 &
camera=$!
sleep 3
v4l2-ctl -d /dev/video1 -c percentage_of_dropped_buffers=50
sleep 2
v4l2-ctl -d /dev/video1 -c percentage_of_dropped_buffers=0
v4l2-ctl -d /dev/video0 -c disconnect=1
sleep 3
kill -INT $camera
wait $camera
camera_status=$?
sleep 1
kill -INT $logger
wait $logger
cat /tmp/camera.txt
hs-logger --check /tmp/camlog/*.lcmlog > /tmp/camcheck.json
summary=$(grep '^hs-camera: .* frames, ' /tmp/camera.txt)
field() { echo "$summary" | sed -n "s/$1/\1/p"; }
left=$(field '^hs-camera: \([0-9]*\) + .*')
published=$(field '.* frames, \([0-9]*\) published.*')
dropped_left=$(field '.*dropped by the devices \([0-9]*\) + .*')
dropped_right=$(field '.*dropped by the devices [0-9]* + \([0-9]*\);.*')
losses=$(field '.*; \([0-9]*\) device losses.*')
recorded=$(grep -A12 '"CAM_STEREO"' /tmp/camcheck.json | sed -n 's/.*"messages": \([0-9]*\).*/\1/p' | head -1)
lost=$(grep -A12 '"CAM_STEREO"' /tmp/camcheck.json | sed -n 's/.*"lost_upstream": \([0-9]*\).*/\1/p' | head -1)
echo "hs-camera: exit $camera_status, left $left, published $published, dropped $dropped_left + $dropped_right, losses $losses; CAM_STEREO recorded $recorded, lost $lost"
check [ "$camera_status" = 0 ]
check [ "${left:-0}" -ge 150 ]                       # 8 s at 30 fps, less the reopening
check [ "${published:-0}" -ge 100 ]                  # paired despite the drops
check [ "${dropped_right:-0}" -ge 10 ]               # vivid's drops seen in the sequence
check [ "${losses:-0}" = 1 ]                         # the disconnect, and then frames again
check [ "${recorded:-0}" = "$published" ]            # every published pair recorded
check [ "${lost:-1}" = 0 ]
exit $status

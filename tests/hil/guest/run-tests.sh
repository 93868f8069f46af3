#!/bin/sh
# The guest's test sequence: each step prints "HIL step NAME: PASS/FAIL"; the script fails when
# any step does.
status=0
step() {
  name=$1
  shift
  if "$@"; then echo "HIL step $name: PASS"; else echo "HIL step $name: FAIL"; status=1; fi
}

# Two vivid instances, capture nodes only: /dev/video0 and /dev/video1 (a stereo pair).
vivid_loaded() {
  [ -c /dev/video0 ] && [ -c /dev/video1 ]
}
# v4l2-ctl's own mmap capture at 30 fps: frames arrive with monotonic timestamps.
vivid_streams() {
  v4l2-ctl -d /dev/video0 --set-parm=30 >/dev/null &&
    v4l2-ctl -d /dev/video0 --stream-mmap --stream-count=20 --stream-to=/dev/null --verbose \
      > /tmp/stream.txt 2>&1
  grep -q 'ts-monotonic' /tmp/stream.txt && [ "$(grep -c 'seq:' /tmp/stream.txt)" -ge 20 ]
}
# gpio-sim through configfs: a chip with 8 lines, two of them named for the camera trigger and
# one for an IMU's data-ready output.
gpio_sim_chip() {
  d=/sys/kernel/config/gpio-sim/hil
  mkdir -p $d/bank0/line0 $d/bank0/line1 $d/bank0/line2 &&
    echo 8 > $d/bank0/num_lines && echo hil-sim > $d/bank0/label &&
    echo cam-trigger > $d/bank0/line0/name && echo cam-strobe-in > $d/bank0/line1/name &&
    echo imu-drdy > $d/bank0/line2/name &&
    echo 1 > $d/live &&
    gpiodetect | grep -q 'hil-sim'
}

step vivid-loaded vivid_loaded
step vivid-streams vivid_streams
step gpio-sim gpio_sim_chip
[ -x /hil/programs.sh ] && step programs /hil/programs.sh
exit $status

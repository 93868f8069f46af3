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
# hs-logger records the guest's LCM traffic into folder $1 until stop_recording, which checks the
# recording into $1.json.
start_recording() {
  recording=$1
  hs-logger --dir "$recording" --lcm-url "$URL" > "$recording.txt" 2>&1 &
  recorder=$!
  ready "$recording.txt" recording
}
stop_recording() {
  sleep 1
  kill -INT $recorder
  wait $recorder
  hs-logger --check "$recording"/*.lcmlog > "$recording.json"
}
# Starts program $1 (its arguments after it) with its output in $out, and waits until it says it
# is publishing: TCG makes start-up slow, and the steps time what the program does.
start_program() {
  "$@" --lcm-url "$URL" > "$out" 2>&1 3<&- &
  program=$!
  ready "$out" publishing
}
# Stops program $1 (SIGINT) and then the recording; prints the program's output file $2 and keeps
# its line matching $3 for field (its exit status in $stopped).
stop_program() {
  ready "$2" publishing  # a background program ignores SIGINT until it has set its handlers
  kill -INT $1
  wait $1
  stopped=$?
  stop_recording
  cat "$2"
  summary=$(grep "$3" "$2")
}
field() { echo "$summary" | sed -n "s/$1/\1/p"; }
# The frame counts in hs-camera's summary line (after stop_program).
camera_fields() {
  left=$(field '^hs-camera: \([0-9]*\) + .*')
  right=$(field '^hs-camera: [0-9]* + \([0-9]*\) frames.*')
  published=$(field '.* frames, \([0-9]*\) published.*')
}
# Field $3 (messages, lost_upstream...) of channel $2 in the check $1.json.
recorded() {
  grep -A12 "\"$2\"" "$1.json" | sed -n "s/.*\"$3\": \([0-9]*\).*/\1/p" | head -1
}

# hs-trigger on gpio-sim (free-running, then phase-locked). gpio-sim cannot wire an output to an input, so a mirror loop copies the
# trigger line (cam-trigger) to the strobe input (cam-strobe-in) by its pull, like a loopback
# wire with a shell's latency; hs-trigger times each pulse by that edge.
chip=$(gpiodetect | awk '/\[hil-sim\]/ {print $1}')
sim=/sys/bus/gpio/devices/$chip
(
  last=0
  while true; do
    read -r v < $sim/sim_gpio0/value  # a builtin: no fork per poll
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
start_recording /tmp/log
out=/tmp/trigger.txt start_program hs-trigger --config /tmp/trigger.yaml
trigger=$program
sleep 4
stop_program $trigger /tmp/trigger.txt '^hs-trigger: .* pulses, '
trigger_status=$stopped
pulses=$(field '^hs-trigger: \([0-9]*\) pulses.*')
edges=$(field '.* pulses, \([0-9]*\) timed by their edge.*')
recorded=$(recorded /tmp/log TRIGGER messages)
lost=$(recorded /tmp/log TRIGGER lost_upstream)
echo "hs-trigger: exit $trigger_status, $pulses pulses, $edges timed by their edge; TRIGGER recorded $recorded, lost $lost"
check [ "$trigger_status" = 0 ]
check [ "${pulses:-0}" -ge 60 ]                      # 4 s at 20 Hz, less the 0.1 s start
check [ "${edges:-0}" -ge $((pulses / 2)) ]          # the mirror's edges came back (a shell
                                                     # loop: it misses some when the host is busy)
check [ "${recorded:-0}" = "$pulses" ]               # every pulse published and recorded
check [ "${lost:-1}" = 0 ]                           # seq continuous
# hs-trigger phase-locked to an IMU's data-ready line (imu-drdy, toggled by a loop here at up to
# 100 Hz): a pulse on every 5th rising edge; then the data-ready line stalls and must be reported.
(
  while true; do
    echo pull-up > $sim/sim_gpio2/pull
    usleep 5000
    echo pull-down > $sim/sim_gpio2/pull
    usleep 5000
  done
) &
drdy=$!
cat >> /tmp/trigger.yaml <<EOT
  sync_line: imu-drdy
  sync_divider: 5
  sync_timeout_s: 0.5
EOT
start_recording /tmp/synclog
out=/tmp/sync.txt start_program hs-trigger --config /tmp/trigger.yaml
trigger=$program
sleep 4
kill $drdy
usleep 1200000
stop_program $trigger /tmp/sync.txt '^hs-trigger: .* pulses, '
trigger_status=$stopped
kill $mirror
pulses=$(field '^hs-trigger: \([0-9]*\) pulses.*')
sync_edges=$(field '.*; \([0-9]*\) data-ready edges.*')
stalls=$(field '.* \([0-9]*\) stalls.*')
recorded=$(recorded /tmp/synclog TRIGGER messages)
echo "hs-trigger phase-locked: exit $trigger_status, $pulses pulses on $sync_edges data-ready edges, $stalls stalls; TRIGGER recorded $recorded"
check [ "$trigger_status" = 0 ]
check [ "${sync_edges:-0}" -ge 40 ]                  # the loop's edges seen (4 s at <= 100 Hz; slower under load)
check [ "${pulses:-0}" = $(((sync_edges + 4) / 5)) ] # every 5th, from the first
check [ "${stalls:-0}" -ge 1 ]                       # the stalled line reported
check [ "${recorded:-0}" = "$pulses" ]
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
start_recording /tmp/camlog
out=/tmp/camera.txt start_program hs-camera --config /tmp/camera.yaml
camera=$program
sleep 3
v4l2-ctl -d /dev/video1 -c percentage_of_dropped_buffers=50
sleep 2
v4l2-ctl -d /dev/video1 -c percentage_of_dropped_buffers=0
v4l2-ctl -d /dev/video0 -c disconnect=1
sleep 3
stop_program $camera /tmp/camera.txt '^hs-camera: .* frames, '
camera_status=$stopped
camera_fields
dropped_left=$(field '.*dropped by the devices \([0-9]*\) + .*')
dropped_right=$(field '.*dropped by the devices [0-9]* + \([0-9]*\);.*')
losses=$(field '.*; \([0-9]*\) device losses.*')
recorded=$(recorded /tmp/camlog CAM_STEREO messages)
lost=$(recorded /tmp/camlog CAM_STEREO lost_upstream)
echo "hs-camera: exit $camera_status, left $left, published $published, dropped $dropped_left + $dropped_right, losses $losses; CAM_STEREO recorded $recorded, lost $lost"
check [ "$camera_status" = 0 ]
check [ "${left:-0}" -ge 120 ]                       # 8 s at 30 fps (vivid under TCG: ~20)
check [ "${published:-0}" -ge 100 ]                  # paired despite the drops
check [ "${dropped_right:-0}" -ge 10 ]               # vivid's drops seen in the sequence
check [ "${losses:-0}" = 1 ]                         # the disconnect, and then frames again
check [ "${recorded:-0}" = "$published" ]            # every published pair recorded
check [ "${lost:-1}" = 0 ]

# hs-imu on the kernel's IIO dummy device, triggered at 100 Hz by an hrtimer trigger (both made
# through configfs). The dummy has one accelerometer axis and four voltages, all constant: they
# stand in for the six axes. First a config naming scan elements it lacks (refused, saying what it
# has), then the device held open by another reader (busy, until released), then the device
# removed while streaming (like an unbind) and created again: hs-imu must come back by itself.
# hs-camera refusing what the device cannot do, with nothing published: a size vivid will not
# take (the error names what it gives instead), and external-trigger mode with a manual exposure
# vivid has no control for. Then external-trigger mode with the exposure set "by other means"
# (exposure_control: false) but no hs-trigger running: every frame counted without its pulse.
cat > /tmp/camera-size.yaml <<EOT
camera:
  devices: [/dev/video0]
  width: 10000
  height: 180
  format: YUYV
  fps: 30
EOT
sed -e 's/width: 10000/width: 320/' /tmp/camera-size.yaml > /tmp/camera-exposure.yaml
cat >> /tmp/camera-exposure.yaml <<EOT
  mode: external-trigger
  exposure_s: 0.005
EOT
cp /tmp/camera-exposure.yaml /tmp/camera-notrigger.yaml
echo "  exposure_control: false" >> /tmp/camera-notrigger.yaml
for bad in size exposure notrigger; do
  start_recording /tmp/cam$bad
  out=/tmp/camera-$bad.txt start_program hs-camera --config /tmp/camera-$bad.yaml
  camera=$program
  sleep 2
  stop_program $camera /tmp/camera-$bad.txt '^hs-camera: .* frames, '
  check [ "$stopped" = 0 ]
  check [ "$(field '.* frames, \([0-9]*\) published.*')" = 0 ]
  check [ -z "$(recorded /tmp/cam$bad CAM_STEREO messages)" ]
done
check grep -q 'YUYV 10000x180 .*refused' /tmp/camera-size.txt
check grep -q 'cannot set manual exposure' /tmp/camera-exposure.txt
check grep -q 'frames without a TRIGGER pulse' /tmp/camera-notrigger.txt
check [ "$(field '.*without trigger \([0-9]*\),.*')" -ge 20 ]  # 2 s at 30 fps, all of them
# hs-camera on a device another program is streaming from (v4l2-ctl): refused as busy, retried,
# and read once it is free. hs-camera starts once v4l2-ctl streams (its '<' per frame): started
# together, hs-camera may take the device first under TCG. v4l2-ctl holds the device until
# hs-camera has said it is busy: a fixed count of frames ran out before a slow guest got there.
v4l2-ctl -d /dev/video0 --stream-mmap --stream-count=100000 --stream-to=/dev/null >/tmp/holder.txt 2>&1 &
holder=$!
check ready /tmp/holder.txt '<'
sed -e 's/width: 10000/width: 320/' /tmp/camera-size.yaml > /tmp/camera-busy.yaml
start_recording /tmp/cambusy
out=/tmp/camera-busy.txt start_program hs-camera --config /tmp/camera-busy.yaml
camera=$program
check ready /tmp/camera-busy.txt 'another program is streaming from it'
kill $holder
wait $holder
ready /tmp/camera-busy.txt 'video0 opened'
sleep 2
stop_program $camera /tmp/camera-busy.txt '^hs-camera: .* frames, '
camera_fields
check [ "$stopped" = 0 ]
check grep -q 'video0: cannot set the format: Device or resource busy' /tmp/camera-busy.txt
check [ "${published:-0}" -ge 20 ]                   # 2 s at 30 fps once free (~20 under TCG)
check [ "$(recorded /tmp/cambusy CAM_STEREO messages)" = "$published" ]

# hs-camera in external-trigger mode on a stereo pair exposed by hs-trigger's pulses: two
# hil-triggered-camera write a frame each to v4l2loopback (/dev/video2, /dev/video3) on each rising
# edge of the trigger line; the left one misses pulse 30. Every frame must be paired with its own
# pulse (its buffer follows the pulse within max_latency) and stamped from it, the missed pulse
# counted and followed at once, and the right frame it leaves alone dropped.
cat > /tmp/trigger10.yaml <<EOT
trigger:
  chip: $chip
  output_line: cam-trigger
  rate_hz: 10
  pulse_width_s: 0.03
EOT
cat > /tmp/camera-triggered.yaml <<EOT
camera:
  devices: [/dev/video2, /dev/video3]
  width: 320
  height: 180
  format: GREY
  fps: 10
  mode: external-trigger
  exposure_s: 0.004
  exposure_control: false      # set "by other means": the loopback has no exposure control
trigger_pairing:
  max_latency_s: 0.08          # pulse to buffer under TCG; under the 0.1 s period: unambiguous
EOT
hil-triggered-camera /dev/video2 $sim/sim_gpio0/value 320 180 30 > /tmp/tcam-left.txt 2>&1 &
tcam_left=$!
hil-triggered-camera /dev/video3 $sim/sim_gpio0/value 320 180 0 > /tmp/tcam-right.txt 2>&1 &
tcam_right=$!
ready /tmp/tcam-left.txt ready && ready /tmp/tcam-right.txt ready
start_recording /tmp/triglog
out=/tmp/camera-triggered.txt start_program hs-camera --config /tmp/camera-triggered.yaml
camera=$program
ready /tmp/camera-triggered.txt 'video2 opened' && ready /tmp/camera-triggered.txt 'video3 opened'
out=/tmp/trigger10.txt start_program hs-trigger --config /tmp/trigger10.yaml
trigger=$program
sleep 6
kill -INT $trigger
wait $trigger
trigger_status=$?
usleep 500000                  # the last frames meet their TRIGGER messages
kill -INT $tcam_left $tcam_right
wait $tcam_left $tcam_right
cat /tmp/trigger10.txt /tmp/tcam-left.txt /tmp/tcam-right.txt
stop_program $camera /tmp/camera-triggered.txt '^hs-camera: .* frames, '
camera_status=$stopped
camera_fields
unpaired=$(field '.*unpaired \([0-9]* + [0-9]*\);.*')
matched=$(field '.*matched to their trigger \([0-9]*\),.*')
no_trigger=$(field '.*without trigger \([0-9]*\),.*')
no_frame=$(field '.*triggers without frame \([0-9]*\),.*')
mismatches=$(field '.*trigger time mismatches \([0-9]*\),.*')
relocks=$(field '.*relocks \([0-9]*\);.*')
pulses=$(sed -n 's/^hs-trigger: \([0-9]*\) pulses.*/\1/p' /tmp/trigger10.txt)
seen=$(sed -n 's/^hil-triggered-camera: \([0-9]*\) pulses.*/\1/p' /tmp/tcam-left.txt)
written=$(sed -n 's/.* pulses, \([0-9]*\) frames written.*/\1/p' /tmp/tcam-left.txt)
written_right=$(sed -n 's/.* pulses, \([0-9]*\) frames written.*/\1/p' /tmp/tcam-right.txt)
recorded=$(recorded /tmp/triglog CAM_STEREO messages)
lost=$(recorded /tmp/triglog CAM_STEREO lost_upstream)
triggers=$(recorded /tmp/triglog TRIGGER messages)
echo "triggered stereo: $pulses pulses, $seen seen, $written + $written_right frames; hs-camera exit $camera_status, $left + $right frames, $matched matched, $published published, unpaired $unpaired, $no_trigger without trigger, $no_frame pulses without frame, $mismatches mismatches, $relocks relocks; recorded CAM_STEREO $recorded (lost $lost), TRIGGER $triggers"
check [ "$trigger_status" = 0 ]
check [ "$camera_status" = 0 ]
check [ "${pulses:-0}" -ge 50 ]                      # 6 s at 10 Hz
check [ "${seen:-0}" = "$pulses" ]                   # the cameras saw every pulse ...
check [ "${written_right:-0}" = "$pulses" ]
check [ "${written:-0}" = $((pulses - 1)) ]          # ... and the left one missed one
check [ "${left:-0}" = "$written" ]                  # hs-camera read every frame
check [ "${right:-0}" = "$written_right" ]
check [ "${matched:-0}" = $((left + right)) ]        # each paired with its pulse, in time
check [ "${no_trigger:-1}" = 0 ]
check [ "${mismatches:-1}" = 0 ]
check [ "${relocks:-0}" = 1 ]                        # the missed pulse, followed at once ...
check [ "${no_frame:-0}" = $((2 * pulses - matched)) ]  # ... and counted: the skipped one
check [ "$unpaired" = "0 + 1" ]                      # the right frame of the missed pulse
check [ "${published:-0}" = "$left" ]                # stereo pairs stamped from one pulse
check [ "${recorded:-0}" = "$published" ]
check [ "${lost:-1}" = 0 ]
check [ "${triggers:-0}" = "$pulses" ]

echo "HIL: iio trigger"
mkdir /sys/kernel/config/iio/triggers/hrtimer/imu-timer
echo "HIL: iio device"
mkdir /sys/kernel/config/iio/devices/dummy/imu-dummy
echo "HIL: iio wrong config"
cat > /tmp/imu.yaml <<EOT
imu:
  backend: iio
  reconnect_period_s: 0.5
iio:
  device: imu-dummy
  trigger: imu-timer
  sampling_frequency_hz: 100
  accel_channels: [in_accel_x, in_voltage0, in_voltage1-voltage2]
  gyro_channels: [in_voltage3-voltage4, in_voltage0, in_accel_x]
EOT
sed 's/gyro_channels: .*/gyro_channels: [in_anglvel_x, in_anglvel_y, in_anglvel_z]/' \
  /tmp/imu.yaml > /tmp/imu-wrong.yaml
start_recording /tmp/imuwrong
out=/tmp/imu-wrong.txt start_program hs-imu --config /tmp/imu-wrong.yaml
ready /tmp/imu-wrong.txt 'no scan element'
stop_program $program /tmp/imu-wrong.txt '^hs-imu: .* samples in'
check [ "$stopped" = 0 ]
check grep -q "no scan element 'in_anglvel_x'.*in_accel_x, in_timestamp, in_voltage0" /tmp/imu-wrong.txt
check [ "$(field '^hs-imu: \([0-9]*\) samples.*')" = 0 ]
check [ -z "$(recorded /tmp/imuwrong IMU messages)" ]
start_recording /tmp/imulog
exec 3< /dev/iio:device0                             # another reader
out=/tmp/imu.txt start_program hs-imu --config /tmp/imu.yaml
imu=$program
ready /tmp/imu.txt 'resource busy'                  # refused while the other reader has it
exec 3<&-
sleep 4
rmdir /sys/kernel/config/iio/devices/dummy/imu-dummy
sleep 1
mkdir /sys/kernel/config/iio/devices/dummy/imu-dummy
sleep 3
stop_program $imu /tmp/imu.txt '^hs-imu: .* samples in'
imu_status=$stopped
samples=$(field '^hs-imu: \([0-9]*\) samples.*')
connects=$(field '.* \([0-9]*\) connects.*')
losses=$(field '.* \([0-9]*\) device losses.*')
backwards=$(field '.*backwards_timestamps=\([0-9]*\).*')
off_clock=$(field '.*off_clock_timestamps=\([0-9]*\).*')
messages=$(recorded /tmp/imulog IMU messages)
lost=$(recorded /tmp/imulog IMU lost_upstream)
echo "hs-imu: exit $imu_status, $samples samples, $connects connects, $losses losses, $backwards backwards, $off_clock off clock; IMU recorded $messages, lost $lost"
check grep -q 'Device or resource busy (another reader has it)' /tmp/imu.txt
check grep -q 'lost (unplugged?)' /tmp/imu.txt
check [ "$imu_status" = 0 ]
check [ "${connects:-0}" = 2 ]                       # after the busy spell, after the removal
check [ "${losses:-0}" = 1 ]
check [ "${samples:-0}" -ge 400 ]                    # ~6.5 s at 100 Hz
check [ "${backwards:-1}" = 0 ]                      # the kernel's timestamps advance
check [ "${off_clock:-1}" = 0 ]                      # ... on CLOCK_MONOTONIC
check [ "${messages:-0}" -ge $((samples / 4)) ]      # batches of 4 (fewer at pauses)
check [ "${lost:-1}" = 0 ]

echo "HIL: iio accelerometer and gyroscope as two devices"  # a BMI088's two drivers
mkdir /sys/kernel/config/iio/triggers/hrtimer/gyro-timer
mkdir /sys/kernel/config/iio/devices/dummy/imu-gyro
cat /tmp/imu.yaml - > /tmp/imu-split.yaml <<EOT
  gyro_device: imu-gyro
  gyro_trigger: gyro-timer
  gyro_sampling_frequency_hz: 200
  pair_max_gap_s: 0.05         # TCG delays the hrtimer by tens of ms at times
EOT
start_recording /tmp/imusplit
out=/tmp/imu-split.txt start_program hs-imu --config /tmp/imu-split.yaml
sleep 4
stop_program $program /tmp/imu-split.txt '^hs-imu: .* samples in'
samples=$(field '^hs-imu: \([0-9]*\) samples.*')
paired=$(field '.*paired_samples=\([0-9]*\).*')
unpaired=$(field '.*unpaired_gyro_samples=\([0-9]*\).*')
messages=$(recorded /tmp/imusplit IMU messages)
echo "hs-imu split: exit $stopped, $samples samples, $paired paired, $unpaired unpaired; IMU recorded $messages"
check [ "$stopped" = 0 ]
check grep -q 'iio:device[0-9]* (imu-dummy) + iio:device[0-9]* (imu-gyro) opened' /tmp/imu-split.txt
check [ "${samples:-0}" -ge 400 ]                   # ~4 s at the gyroscope's 200 Hz
check [ "${samples:-0}" = "${paired:-1}" ]
check [ "${unpaired:-1}" -le $((samples / 50)) ]   # hrtimer stalls under TCG only
check [ "${messages:-0}" -ge $((samples / 4)) ]
exit $status

#!/usr/bin/env bash
# Installs the Debian 12 packages HS-SLAM needs and builds it into build/ (-j2).
# Idempotent and non-interactive. Run as root (or with sudo available).
#   tools/setup.sh            install + Release build
#   CI=true tools/setup.sh    also treats warnings as errors
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
  build-essential cmake pkg-config git ccache
  liblcm-dev liblcm-bin liblcm-java libglib2.0-dev
  libeigen3-dev libopencv-dev libceres-dev libv4l-dev libgpiod-dev
  googletest libgtest-dev libbenchmark-dev libcli11-dev libyaml-cpp-dev nlohmann-json3-dev
  default-jdk-headless libjchart2d-java
  iproute2 procps python3 xvfb x11-utils xdotool imagemagick
)

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "[setup] installing: ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "[setup] all ${#PACKAGES[@]} packages present"
fi

# LCM over UDP multicast: a loopback-only host needs a multicast route, and a stereo pair
# (~720 kB raw) needs receive buffers far above Debian's 208 kB default (see README).
if [ "$(id -u)" -eq 0 ] || [ -n "$SUDO" ]; then
  ip route show 224.0.0.0/4 | grep -q . || \
    $SUDO ip route add 224.0.0.0/4 dev lo 2>/dev/null || echo "[setup] note: could not add a multicast route on lo"
  for key in net.core.rmem_max net.core.rmem_default; do
    cur=$(sysctl -n "$key" 2>/dev/null || echo 0)
    if [ "$cur" -lt 16777216 ]; then
      $SUDO sysctl -q -w "$key=16777216" >/dev/null 2>&1 || echo "[setup] note: could not raise $key"
    fi
  done
fi

werror=OFF
if [ "${CI:-}" = "true" ]; then werror=ON; fi
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DHS_WERROR=$werror
cmake --build build -j2
echo "[setup] done: executables in build/bin/"

#!/usr/bin/env bash
# Prepares the hardware-in-the-loop harness: Debian's own kernel (the version linux-image-amd64
# points to today) with vivid (virtual V4L2 cameras), gpio-sim and the IIO dummy device with the
# hrtimer trigger (built here out of tree from Debian's linux-source: Debian does not ship them),
# v4l2loopback (a camera with a trigger input, with hil-triggered-camera),
# and an initramfs holding busybox, the modules,
# the V4L2/GPIO tools, the programs under test and their shared libraries. Idempotent.
#   tests/hil/setup.sh WORKDIR [PROGRAM...]      (root: installs packages with apt-get)
# Exit 77 (skip) when the packages are missing and cannot be installed.
set -euo pipefail
work=$(realpath -m "${1:?usage: setup.sh WORKDIR [PROGRAM...]}")
shift
programs=()
for p in "$@"; do programs+=("$(realpath "$p")"); done
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$work"
cd "$work"

log() { echo "[hil-setup] $*"; }

packages=(qemu-system-x86 busybox-static v4l-utils cpio gpiod kmod xz-utils make gcc)
missing=()
for p in "${packages[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" -ne 0 ]; then
    log "packages ${missing[*]} missing and not root to install them: HIL tests skipped"
    exit 77
  fi
  log "installing ${missing[*]}"
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# The kernel of today's linux-image-amd64 (its ABI number changes with security updates).
kpkg=$(apt-cache depends linux-image-amd64 | awk '/Depends: linux-image-[0-9]/{print $2; exit}')
kver=${kpkg#linux-image-}
abi=${kver%-amd64}
upstream=$(echo "$abi" | cut -d. -f1-2)
echo "$kver" > kver
mkdir -p debs
if [ ! -f "debs/.done-$kver" ]; then
  log "downloading $kpkg, headers, kbuild and source"
  rm -f debs/*.deb
  (cd debs && apt-get download "$kpkg" "linux-headers-$kver" "linux-headers-$abi-common" \
     "linux-kbuild-$upstream" "linux-source-$upstream" 2>/dev/null)
  touch "debs/.done-$kver"
fi
if [ ! -f "kernel/.done-$kver" ]; then
  log "extracting the kernel and headers"
  rm -rf kernel kheaders
  dpkg-deb -x debs/linux-image-*.deb kernel
  for p in debs/linux-headers-*.deb debs/linux-kbuild-*.deb; do dpkg-deb -x "$p" kheaders; done
  # The headers' Makefile includes the common headers by absolute path.
  sed -i "s#^include /usr/src/#include $work/kheaders/usr/src/#" \
    "kheaders/usr/src/linux-headers-$kver/Makefile"
  touch "kernel/.done-$kver"
fi
if [ ! -f "mod/.done-$kver-iio" ]; then
  log "building irq-sim, gpio-sim and the IIO dummy device out of tree"
  rm -rf mod && mkdir mod
  dpkg-deb --fsys-tarfile debs/linux-source-*.deb |
    tar -xO "./usr/src/linux-source-$upstream.tar.xz" |
    tar -xJ -C mod --strip-components=3 --wildcards '*/drivers/gpio/gpio-sim.c' \
      '*/drivers/gpio/gpiolib.h' '*/kernel/irq/irq_sim.c' '*/drivers/iio/industrialio-configfs.c' \
      '*/drivers/iio/industrialio-sw-*.c' '*/drivers/iio/trigger/iio-trig-hrtimer.c' \
      '*/drivers/iio/dummy/iio_simple_dummy*.[ch]'
  find mod -mindepth 2 -type f -exec mv -t mod {} +  # one flat folder
  # irq_to_desc is not exported to modules; generic_handle_irq does the same here.
  sed -i 's/handle_simple_irq(irq_to_desc(\([a-z_]*\)))/generic_handle_irq(\1)/' mod/irq_sim.c
  grep -q 'generic_handle_irq(irqnum)' mod/irq_sim.c
  printf '#include <linux/module.h>\nMODULE_LICENSE("GPL");\n' > mod/irq_sim_mod.c
  # Debian builds IIO without its configfs, software devices and triggers: the dummy device
  # (its triggered buffer) and the hrtimer trigger need them.
  cat > mod/Kbuild <<'EOK'
obj-m += irq-sim.o gpio-sim.o industrialio-configfs.o industrialio-sw-device.o \
         industrialio-sw-trigger.o iio-trig-hrtimer.o iio_dummy.o
irq-sim-y := irq_sim.o irq_sim_mod.o
iio_dummy-y := iio_simple_dummy.o iio_simple_dummy_buffer.o
ccflags-y += -DCONFIG_IIO_SIMPLE_DUMMY_BUFFER
EOK
  make -s -C "kheaders/usr/src/linux-headers-$kver" M="$work/mod" modules 2>&1 | grep -v BTF || true
  mkdir -p "kernel/lib/modules/$kver/extra"
  cp mod/*.ko "kernel/lib/modules/$kver/extra/"
  depmod -b kernel "$kver"
  touch "mod/.done-$kver-iio"
fi

if [ ! -f "loopback/.done-$kver" ]; then
  # A camera with a trigger input: v4l2loopback (Debian's DKMS source, built here) whose output
  # side the guest's hil-triggered-camera writes on each trigger pulse.
  log "building v4l2loopback"
  rm -rf loopback debs/v4l2loopback-dkms_*.deb && mkdir loopback
  (cd debs && apt-get download v4l2loopback-dkms 2>/dev/null)
  dpkg-deb --fsys-tarfile debs/v4l2loopback-dkms_*.deb |
    tar -x -C loopback --strip-components=4 --wildcards './usr/src/v4l2loopback-*/*'
  make -s -C "kheaders/usr/src/linux-headers-$kver" M="$work/loopback" modules 2>&1 |
    grep -v BTF || true
  mkdir -p "kernel/lib/modules/$kver/extra"
  cp loopback/v4l2loopback.ko "kernel/lib/modules/$kver/extra/"
  depmod -b kernel "$kver"
  touch "loopback/.done-$kver"
fi

log "building the initramfs"
root=$work/root
rm -rf "$root"
mkdir -p "$root"/{bin,dev,proc,sys,tmp,modules,hil,lib64,out}
cp /bin/busybox "$root/bin/busybox"
# Modules in load order, for busybox insmod.
: > "$root/modules/order"
for m in vivid configfs gpio-sim iio-trig-hrtimer iio_dummy v4l2loopback; do
  modprobe -d kernel -S "$kver" --show-depends "$m" | awk '$1 == "insmod" {print $2}' |
    while read -r ko; do
      name=$(basename "$ko")
      if [ ! -f "$root/modules/$name" ]; then
        cp "$ko" "$root/modules/$name"
        echo "$name" >> "$root/modules/order"
      fi
    done
done
# Two vivid instances with a capture node each: /dev/video0 and /dev/video1, a stereo pair.
echo "n_devs=2 node_types=0x1,0x1 vid_cap_nr=0,1" > "$root/modules/vivid.ko.params"
# The triggered stereo pair: /dev/video2 and /dev/video3, capture and output on each node.
echo "devices=2 video_nr=2,3 exclusive_caps=0,0 card_label=hil-left,hil-right" \
  > "$root/modules/v4l2loopback.ko.params"
# Tools and programs with their shared libraries (and the loader).
copy_with_libs() {
  local bin=$1
  cp "$bin" "$root/bin/"
  ldd "$bin" | awk '/=>/ {print $3} /ld-linux/ {print $1}' | while read -r lib; do
    [ -f "$lib" ] || continue
    mkdir -p "$root$(dirname "$lib")"
    [ -f "$root$lib" ] || cp -L "$lib" "$root$lib"
  done
}
for tool in /usr/bin/v4l2-ctl /usr/bin/gpiodetect /usr/bin/gpioinfo /usr/bin/gpioset \
            /usr/bin/gpioget; do
  copy_with_libs "$tool"
done
for p in "${programs[@]}"; do copy_with_libs "$p"; done
cp "$here/guest/init" "$root/init"
cp "$here"/guest/*.sh "$root/hil/"
chmod +x "$root/init" "$root"/hil/*.sh
(cd "$root" && find . | cpio -o -H newc --quiet | gzip -1) > initramfs.cpio.gz
log "ready: kernel $kver, initramfs $(du -h initramfs.cpio.gz | cut -f1)"

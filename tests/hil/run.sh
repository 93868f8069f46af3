#!/usr/bin/env bash
# Boots the HIL guest made by setup.sh under qemu (TCG: this machine has no usable KVM) and
# reports its test steps. Exit 0: every guest step passed; 1: a step failed; 2: no result
# (boot failure, timeout); 77: qemu cannot run here (skipped).
#   tests/hil/run.sh WORKDIR [TIMEOUT_S]
set -uo pipefail
work=${1:?usage: run.sh WORKDIR [TIMEOUT_S]}
timeout_s=${2:-180}
if ! command -v qemu-system-x86_64 >/dev/null; then
  echo "[hil] qemu-system-x86_64 missing (tests/hil/setup.sh installs it): HIL tests skipped"
  exit 77
fi
kver=$(cat "$work/kver")
log=$work/serial.log
timeout "$timeout_s" qemu-system-x86_64 -accel tcg -cpu max -m 1G -smp 2 \
  -kernel "$work/kernel/boot/vmlinuz-$kver" -initrd "$work/initramfs.cpio.gz" \
  -append "console=ttyS0 panic=-1 loglevel=4" \
  -nographic -serial mon:stdio -no-reboot -nodefaults -vga none \
  -device isa-debug-exit,iobase=0xf4,iosize=0x04 </dev/null >"$log" 2>&1
code=$?
grep -a 'HIL \|^hs-' "$log"
case $code in
  1) exit 0 ;;
  3) echo "[hil] a guest step failed: $log"; tail -n 40 "$log"; exit 1 ;;
  *) echo "[hil] no result (qemu exit $code): $log"; tail -n 40 "$log"; exit 2 ;;
esac

#!/usr/bin/env bash
# The GPU check of HROC's frame against hzb's, in one command, on any
# machine with a GPU, from a binary built elsewhere (`cargo build
# --release`, then `objcopy --strip-debug target/release/hroc`):
#   - the sweep 100 -> 1M objects (radial-city's own path, 120 frames,
#     640x360), noc, vfc, hzb, hroc and auto side by side in each run;
#   - the default scene (README's first command) with hzb and auto added;
#   - an engine's frame: the camera and 3 shadow cascades, at 5,000 and
#     20,000 objects (hroc / hzb and hroc / noc; the culler's passes and
#     dispatches summed over the views, in the JSON).
# Prints each run's table and, per size, hroc / hzb and auto / hzb (ratios
# within one run). Where no Vulkan loader is installed, it unpacks the
# .deb files of `.gl/` (the device tool's README says how to bring them).
# Usage: scripts/gpu-check.sh [HROC_BINARY] (default target/release/hroc);
# writes its tables under ${OUT:-gpu-check}/; SIZES="100 1000" runs fewer
# sizes, DEFAULT=0 skips the default scene, CASCADES=0 the cascade runs.
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${1:-target/release/hroc}"
out="${OUT:-gpu-check}"
mkdir -p "$out"
if ! ldconfig -p 2>/dev/null | grep -q libvulkan && compgen -G ".gl/*.deb" >/dev/null; then
  for f in .gl/*.deb; do dpkg -x "$f" /; done
  ldconfig
fi
if [ -f /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json ]; then
  export VK_DRIVER_FILES="${VK_DRIVER_FILES:-/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json}"
fi
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp/hroc-xdg}"
mkdir -p "$XDG_RUNTIME_DIR"
echo "# $(date -u +%Y-%m-%d) $(git rev-parse --short HEAD 2>/dev/null || echo '?') | $(nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null || echo 'no nvidia-smi')"
# ms/frame of `method` in a bench table (its second column).
ms() { awk -v m="$2" '$1 == m { print $2; exit }' "$1"; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (a == "" || b == "" || b == 0) print "-"; else printf "%.3f", a / b }'; }
echo "| objects | noc | vfc | hzb | hroc | auto | hroc / hzb | auto / hzb |"
echo "|--:|--:|--:|--:|--:|--:|--:|--:|"
for n in ${SIZES:-100 1000 4000 16000 64000 256000 1000000}; do
  t="$out/sweep-$n.txt"
  "$bin" bench --objects "$n" --frames 120 --methods noc,vfc,hzb,hroc,auto --json "$out/sweep-$n.json" >"$t" 2>"$out/sweep-$n.err"
  echo "| $n | $(ms "$t" noc) | $(ms "$t" vfc) | $(ms "$t" hzb) | $(ms "$t" hroc) | $(ms "$t" auto) | $(ratio "$(ms "$t" hroc)" "$(ms "$t" hzb)") | $(ratio "$(ms "$t" auto)" "$(ms "$t" hzb)") |"
done
if [ "${DEFAULT:-1}" != 0 ]; then
  t="$out/default.txt"
  "$bin" bench --methods noc,vfc,ref,hzb,hroc,auto --json "$out/default.json" >"$t" 2>"$out/default.err"
  echo
  echo "The default scene:"
  cat "$t"
  echo "hroc / hzb $(ratio "$(ms "$t" hroc)" "$(ms "$t" hzb)"), auto / hzb $(ratio "$(ms "$t" auto)" "$(ms "$t" hzb)")"
fi
[ "${CASCADES:-1}" = 0 ] && exit 0
echo
echo "The camera and 3 shadow cascades:"
echo "| objects | noc | vfc | hzb | hroc | auto | hroc / hzb | hroc / noc |"
echo "|--:|--:|--:|--:|--:|--:|--:|--:|"
for n in 5000 20000; do
  t="$out/cascades-$n.txt"
  "$bin" bench --objects "$n" --shadow-cascades 3 --methods noc,vfc,hzb,hroc,auto --json "$out/cascades-$n.json" >"$t" 2>"$out/cascades-$n.err"
  echo "| $n | $(ms "$t" noc) | $(ms "$t" vfc) | $(ms "$t" hzb) | $(ms "$t" hroc) | $(ms "$t" auto) | $(ratio "$(ms "$t" hroc)" "$(ms "$t" hzb)") | $(ratio "$(ms "$t" hroc)" "$(ms "$t" noc)") |"
done

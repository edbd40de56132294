#!/usr/bin/env bash
# Runs the benchmark tables recorded in docs/history/baselines.md and prints them as
# Markdown with the exact command above each. Usage: scripts/bench-tables.sh [OUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-bench-out}"
mkdir -p "$out"
cargo build --release -q
bin=target/release/hroc
run() {
  local name="$1"; shift
  echo
  echo "\`\`\`"
  echo "hroc $* --markdown"
  echo "\`\`\`"
  echo
  "$bin" "$@" --markdown --json "$out/$name.json"
}
echo "Date: $(date -u +%Y-%m-%d), machine: $(nproc) cores, $(uname -m), $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
# Foundation: noc, vfc, ref.
run rc20k bench --scene radial-city --objects 20000 --methods noc,vfc,ref --frames 60
# HROC and the raster baselines: 150 frames over the 10 s path.
M=noc,vfc,ref,roc,roc-all,ioc,hzb,woc,hroc-na,hroc-cr,hroc-of,hroc-cr+of
run rc bench --scene radial-city --objects 20000 --methods $M --frames 150 --breakdown
run fc bench --scene factory --objects 10000 --methods $M --frames 150 --breakdown
run st bench --scene satellites --objects 10000 --methods $M --frames 150 --breakdown
# The HROC variants at 60 frames per path second
# (600 frames; the paper's 10 s sequences are animations played at frame rate).
A=noc,vfc,ref,hroc-na,hroc-cr,hroc-of,hroc-cr+of
run acc-rc bench --scene radial-city --objects 20000 --methods $A --frames 600
run acc-fc bench --scene factory --objects 10000 --methods $A --frames 600
run acc-st bench --scene satellites --objects 10000 --methods $A --frames 600
# Satellites at the size where its occlusion matches the paper's ST (BENCHMARKS.md).
run acc-st40k bench --scene satellites --objects 40000 --methods $A --frames 600
# Query baselines.
Q=noc,vfc,oq,soq,chc++,hroc
run q-rc bench --scene radial-city --objects 3000 --methods $Q --frames 60 --breakdown
run q-lib bench --scene library --objects 3000 --methods $Q --frames 60 --breakdown
run q-tea bench --scene teapots --objects 3000 --methods $Q --frames 60 --breakdown

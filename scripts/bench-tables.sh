#!/usr/bin/env bash
# Runs the benchmark tables recorded in BENCHMARKS.md and prints them as
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
  echo "hroc $*"
  echo "\`\`\`"
  echo
  "$bin" "$@" --markdown --json "$out/$name.json"
}
echo "Date: $(date -u +%Y-%m-%d), machine: $(nproc) cores, $(uname -m), $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
# Issue 2 acceptance.
run rc20k bench --scene radial-city --objects 20000 --methods noc,vfc,ref --frames 60
# Issue 3 acceptance: every HROC variant beside the baselines, with the breakdown.
M=noc,vfc,ref,hroc-na,hroc-cr,hroc-of,hroc-cr+of
run rc bench --scene radial-city --objects 20000 --methods $M --frames 300 --resolution 640x360 --breakdown
run fc bench --scene factory --objects 10000 --methods $M --frames 300 --resolution 640x360 --breakdown
run st bench --scene satellites --objects 10000 --methods $M --frames 300 --resolution 640x360 --breakdown

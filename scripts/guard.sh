#!/usr/bin/env bash
# Re-runs the accepted headline figure of every capability and prints each
# against its limit (crates/hroc-bench/examples/guard.rs); exits non-zero
# when one fails. Writes the output to BENCHMARKS.guard.txt, which is
# committed with each change's figures so that a regression shows in the
# diff. Takes several minutes; not part of CI.
# Usage: scripts/guard.sh [--quick]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/ensure-run-deps.sh
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp/hroc-xdg}"
mkdir -p "$XDG_RUNTIME_DIR"
cargo build --release -q -p hroc-bench --example guard
out=BENCHMARKS.guard.txt
echo "# $(date -u +%Y-%m-%d) at $(git rev-parse --short HEAD 2>/dev/null || echo '?') | $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)" > "$out"
status=0
target/release/examples/guard "$@" | tee -a "$out" || status=$?
exit "$status"

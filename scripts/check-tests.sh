#!/usr/bin/env bash
# Every test can fail: each `#[test]` function of the workspace asserts
# something (an `assert*!`, a `panic!`, an `unwrap`/`expect`, or a call to
# a function of the workspace that does, directly or through others), or
# carries `#[ignore = "why"]`; and none skips itself with an early
# `return`. Prints each offender and exits 1 if there is one. Run by CI.
set -euo pipefail
cd "$(dirname "$0")/.."

find crates examples -name '*.rs' -not -path '*/target/*' | sort | xargs awk -f scripts/check-tests.awk ||
  { echo "check-tests: the tests above cannot fail as written" >&2; exit 1; }

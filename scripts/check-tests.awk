# The check of scripts/check-tests.sh, over the workspace's Rust files.
  # The text of every function, by name (functions of one name share an entry).
  function finish() {
    body[name] = body[name] "\n" text
    if (is_test) { ntests++; tname[ntests] = name; tfile[ntests] = FILENAME; tline[ntests] = start_line; tbody[ntests] = text; tignored[ntests] = ignored }
    name = ""; text = ""; is_test = 0; ignored = 0
  }
  FNR == 1 { if (name != "") finish(); depth = 0; pending = 0 }
  /^[[:space:]]*\/\// { next }
  /#\[test\]/ { pending = 1 }
  /#\[ignore/ {
    if (pending && $0 ~ /#\[ignore *= *"/) ignored = 1
    else if (pending) { printf "%s:%d: a test is ignored without a reason (#[ignore = \"why\"])\n", FILENAME, FNR; bad = 1 }
  }
  {
    if (name == "" && match($0, /fn [A-Za-z0-9_]+/)) {
      name = substr($0, RSTART + 3, RLENGTH - 3); start_depth = depth; start_line = FNR; opened = 0; text = ""
      is_test = pending; pending = 0; if (!is_test) ignored = 0
    }
    # Braces counted outside string and character literals.
    line = $0
    gsub(/\\\\/, "", line); gsub(/\\"/, "", line); gsub(/"[^"]*"/, "\"\"", line); gsub(/'[^'\\]'/, "", line); gsub(/'\\.'/, "", line)
    n = gsub(/\{/, "{", line); m = gsub(/\}/, "}", line)
    depth += n - m
    if (name != "") {
      text = text "\n" $0
      if (n > 0) opened = 1
      if (opened && depth <= start_depth) finish()
      else if (!opened && $0 ~ /;[[:space:]]*$/) { name = ""; text = ""; is_test = 0 } # a declaration without a body
    }
  }
  function asserting(t) { return t ~ /assert|panic!|unreachable!|\.unwrap\(|\.unwrap_err\(|\.expect\(|\.expect_err\(/ }
  # Does `t` call a function known to assert?
  function calls_asserting(t, self,   rest, callee) {
    rest = t
    while (match(rest, /[A-Za-z_][A-Za-z0-9_]*\(/)) {
      callee = substr(rest, RSTART, RLENGTH - 1)
      if (callee != self && (callee in asserts)) return 1
      rest = substr(rest, RSTART + RLENGTH)
    }
    return 0
  }
  END {
    if (name != "") finish()
    for (f in body) if (asserting(body[f])) asserts[f] = 1
    do {
      grew = 0
      for (f in body) if (!(f in asserts) && calls_asserting(body[f], f)) { asserts[f] = 1; grew = 1 }
    } while (grew)
    for (i = 1; i <= ntests; i++) {
      if (tignored[i]) continue
      if (!asserting(tbody[i]) && !calls_asserting(tbody[i], tname[i])) {
        printf "%s:%d: test %s asserts nothing (assert what it checks, or #[ignore = \"why\"])\n", tfile[i], tline[i], tname[i]; bad = 1
      }
      if (tbody[i] ~ /(^|[^A-Za-z_])return(;| Ok\(\(\)\);)/) {
        printf "%s:%d: test %s returns early (assert what it found, or #[ignore = \"why\"])\n", tfile[i], tline[i], tname[i]; bad = 1
      }
    }
    printf "check-tests: %d tests\n", ntests > "/dev/stderr"; if (ENVIRON["LIST"] != "") for (i = 1; i <= ntests; i++) print tfile[i] > "/dev/stderr"
    exit bad
  }

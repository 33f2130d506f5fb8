# Sourced by the CLI tests: a scratch folder removed at exit, and the two checks they are written in.
#   check NAME CONDITION...                     runs CONDITION, prints ok/FAIL NAME, counts failures
#   expect_exit CODE PATTERN -- COMMAND...       COMMAND exits with CODE and says PATTERN on stderr
#   finish NAME                                  prints the count, exits non-zero on any failure
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
check() {
  local name=$1; shift
  if "$@"; then echo "ok   $name"; else echo "FAIL $name"; failures=$((failures + 1)); fi
}
expect_exit() {
  local code=$1 pattern=$2; shift 3
  "$@" > "$work/stdout" 2> "$work/stderr"
  local got=$?
  [ "$got" -eq "$code" ] && grep -q -- "$pattern" "$work/stderr" || { echo "  exit $got, stderr: $(cat "$work/stderr")"; return 1; }
}
finish() {
  echo "$1: $failures failure(s)"
  [ "$failures" -eq 0 ]
}

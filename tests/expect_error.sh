#!/bin/sh
# expect_error.sh CODE PATTERN COMMAND...: COMMAND must exit with CODE and
# print a message matching PATTERN (grep -E) on stderr or stdout.
code=$1; pattern=$2; shift 2
out=$("$@" 2>&1); got=$?
echo "$out"
[ "$got" -eq "$code" ] || { echo "FAIL: exit code $got, expected $code"; exit 1; }
echo "$out" | grep -Eq -- "$pattern" || { echo "FAIL: no match for: $pattern"; exit 1; }

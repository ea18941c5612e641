#!/bin/sh
# Runs a test program and checks its output as well as its exit status: it must exit 0, print a line
# matching REQUIRED (an extended regular expression) and none matching FORBIDDEN.
# usage: run_checked.sh REQUIRED FORBIDDEN PROGRAM [ARGS...]
required="$1"
forbidden="$2"
shift 2
log=$(mktemp)
"$@" > "$log" 2>&1
rc=$?
cat "$log"
status=0
if [ "$rc" -ne 0 ]; then echo "run_checked: exit status $rc"; status=1; fi
if ! grep -Eq -- "$required" "$log"; then echo "run_checked: no line matches '$required'"; status=1; fi
if grep -Eq -- "$forbidden" "$log"; then echo "run_checked: a line matches '$forbidden':"; grep -E -- "$forbidden" "$log" | head -5; status=1; fi
rm -f "$log"
exit $status

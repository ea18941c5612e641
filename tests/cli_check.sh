# Sourced by the command-line test scripts. `cli_check NAME EXPECTED_RC PATTERN COMMAND...` runs
# COMMAND with its output in $out/NAME.log and checks its exit status and that the output contains
# PATTERN (a basic regular expression; a fixed string when CLI_FIXED=1; nothing when empty).
# Counts checks in $count and failures in $fails; a script ends with `cli_summary`.
count=0 fails=0
cli_check() {
    name=$1 want=$2 pattern=$3
    shift 3
    count=$((count + 1))
    "$@" >"$out/$name.log" 2>&1
    rc=$?
    if [ "$rc" -ne "$want" ]; then
        echo "FAIL $name: exit $rc, expected $want"; cat "$out/$name.log"; fails=$((fails + 1)); return
    fi
    if [ -n "$pattern" ] && ! grep -q ${CLI_FIXED:+-F} -- "$pattern" "$out/$name.log"; then
        echo "FAIL $name: output lacks '$pattern'"; cat "$out/$name.log"; fails=$((fails + 1)); return
    fi
    echo "ok   $name"
}
cli_summary() {
    echo "$count checks, $fails failed"
    [ "$fails" -eq 0 ]
}

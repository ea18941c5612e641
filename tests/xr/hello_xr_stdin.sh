# Sourced by the scripts that run hello_xr (after cli_check.sh, with $out set).
# hello_xr quits at a key press or when stdin ends: a detached thread waits in getchar(), holding
# stdin's lock while it waits. `hello_xr_until_ended LOG COMMAND...` runs COMMAND (a hello_xr, its
# output going to LOG) with stdin from a fifo that nothing writes, so only the runtime's frame limit
# (STOPPING, then EXITING) can end the run. Once LOG shows that the session has ended (xrDestroySession,
# after hello_xr has left its render loop), the fifo's only writer is closed: getchar() returns, the
# thread ends and releases stdin. Without that, hello_xr's exit() waits forever on a C library that
# locks every stream at exit (glibc 2.39 and later); older ones flush without the locks.
hello_xr_until_ended() {
    log=$1
    shift
    rm -f "$out/stdin"
    mkfifo "$out/stdin"
    exec 4<>"$out/stdin"  # the writer, held by this shell alone (the command closes its copy)
    "$@" <"$out/stdin" 4>&- &
    pid=$!
    while kill -0 "$pid" 2>/dev/null && ! grep -q "session ended" "$log" 2>/dev/null; do sleep 0.2; done
    exec 4>&-
    wait "$pid"
}

// Preloaded into hello_xr by the XR test scripts: at exit, each standard stream's lock must be free
// or become free soon. glibc 2.39 and later lock every stream in exit() (_IO_cleanup, after the
// shared objects' destructors), so a stream that another thread keeps locked, such as stdin in
// hello_xr's key-press thread blocked in getchar(), hangs the exit for good; glibc 2.36 (Debian 12)
// flushes without the locks and exits. This destructor waits as the newer glibc does, but at most
// 10 s, then reports the stream and ends the process with status 86 instead of hanging.
#include <stdio.h>
#include <time.h>
#include <unistd.h>

static int waitForLock(FILE* f) {
    const struct timespec step = {0, 10 * 1000 * 1000};
    for (int i = 0; i < 1000; ++i) {
        if (ftrylockfile(f) == 0) {
            funlockfile(f);
            return 1;
        }
        nanosleep(&step, NULL);
    }
    return 0;
}

__attribute__((destructor)) static void checkStreamsAtExit(void) {
    FILE* const streams[] = {stdout, stderr, stdin};
    const char* const names[] = {"stdout", "stderr", "stdin"};
    for (int i = 0; i < 3; ++i) {
        if (!waitForLock(streams[i])) {
            // dprintf: stderr's own lock may be the one held.
            dprintf(2,
                    "exit_stdio_check: %s is still locked by another thread 10 s into exit(); glibc >= 2.39 "
                    "would wait for it forever\n",
                    names[i]);
            _exit(86);
        }
        if (streams[i] != stdin) fflush(streams[i]);  // what exit() would have written (lock known free)
    }
}

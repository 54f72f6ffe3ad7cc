/* signals.c: interrupting `run` without a half row (see signals.h). Only
 * async-signal-safe calls in the handler: write(2), _exit(2), atomics. */
#include "signals.h"

#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

static const int handled[] = {SIGINT, SIGTERM, SIGHUP};
#define NHANDLED (int)(sizeof handled / sizeof handled[0])

static struct sigaction previous[NHANDLED];
static bool installed[NHANDLED];
static atomic_int pending;     /* the signal that came, or 0 */
static atomic_int in_write;    /* inside a write section */
static atomic_int cells_done;
static atomic_int leaving;     /* a thread is on its way out */
static char message[8192];
static size_t message_len;

_Static_assert(ATOMIC_INT_LOCK_FREE == 2, "the signal handler needs lock-free atomics");

static void put(const char *s, size_t n)
{
    while (n) {
        ssize_t w = write(STDERR_FILENO, s, n);
        if (w <= 0) return;
        s += w;
        n -= (size_t)w;
    }
}

static void put_str(const char *s)
{
    put(s, strlen(s)); /* strlen is async-signal-safe (POSIX.1-2016) */
}

static void put_int(int v)
{
    char buf[16];
    int n = sizeof buf;
    unsigned u = v < 0 ? 0u : (unsigned)v;
    do buf[--n] = (char)('0' + u % 10);
    while ((u /= 10) && n > 0);
    put(buf + n, sizeof buf - (size_t)n);
}

static const char *signal_name(int sig)
{
    return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : sig == SIGHUP ? "SIGHUP" : "a signal";
}

static _Noreturn void leave(int sig)
{
    if (atomic_exchange(&leaving, 1)) /* another thread is writing the message and exiting */
        for (;;) pause();
    int done = atomic_load(&cells_done);
    put_str("\naccelbench: interrupted by ");
    put_str(signal_name(sig));
    put_str(": the cell in progress is abandoned, ");
    put_int(done);
    put_str(done == 1 ? " cell was measured and written" : " cells were measured and written");
    put_str(" by this run. ");
    put(message, message_len);
    _exit(128 + sig);
}

static void on_signal(int sig)
{
    int none = 0;
    atomic_compare_exchange_strong(&pending, &none, sig); /* the first signal is the one reported */
    if (!atomic_load(&in_write)) leave(atomic_load(&pending));
    /* Inside a write: signals_end_write() exits when it is done. */
}

void signals_install(const char *resume_message)
{
    message_len = (size_t)snprintf(message, sizeof message, "%s", resume_message);
    if (message_len >= sizeof message) message_len = sizeof message - 1;
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigfillset(&sa.sa_mask); /* one handler at a time on a thread */
    sa.sa_flags = SA_RESTART;
    for (int i = 0; i < NHANDLED; i++) {
        installed[i] = false;
        if (sigaction(handled[i], NULL, &previous[i]) != 0) continue;
        if (previous[i].sa_handler == SIG_IGN) continue; /* nohup, or a script's background job: stay ignored */
        installed[i] = sigaction(handled[i], &sa, NULL) == 0;
    }
}

void signals_restore(void)
{
    for (int i = 0; i < NHANDLED; i++)
        if (installed[i]) {
            sigaction(handled[i], &previous[i], NULL);
            installed[i] = false;
        }
}

void signals_cell_done(void)
{
    atomic_fetch_add(&cells_done, 1);
}

bool signals_begin_write(void)
{
    atomic_store(&in_write, 1);
    return atomic_load(&pending) == 0;
}

void signals_end_write(void)
{
    atomic_store(&in_write, 0);
    int sig = atomic_load(&pending);
    if (sig) leave(sig);
}

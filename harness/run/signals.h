/* signals.h: SIGINT, SIGTERM and SIGHUP during `run`: the cell in progress
 * is abandoned, never half written.
 *
 * The handler ends the process at once (_exit(128 + signal), after writing
 * a message: how many cells are done and the command that resumes) unless
 * the process is inside a write section (a row, run.txt, a ray file),
 * which then finishes first: signals_end_write() exits. Tracing threads
 * may take the signal as well as the main thread; the handshake (C11
 * atomics, lock-free, so safe in a handler) leaves no order in which a
 * write is cut: the handler publishes the signal before it looks at the
 * section flag, the writer raises the flag before it looks at the signal.
 * A signal the process inherited as ignored (nohup, a background job of
 * a script) stays ignored. */
#ifndef ACCELBENCH_SIGNALS_H
#define ACCELBENCH_SIGNALS_H

#include <stdbool.h>

/* Install the handlers. resume_message is printed (after "accelbench:
 * interrupted by SIGNAME; N cells done") on the way out; it is copied. */
void signals_install(const char *resume_message);
/* Put back the dispositions signals_install() found. */
void signals_restore(void);
/* One more cell is done (counted in the message). */
void signals_cell_done(void);

/* Enter a write section. Returns false when a signal came first: do not
 * write; call signals_end_write(), which exits. */
bool signals_begin_write(void);
/* Leave it; exits (128 + signal) when a signal came during it. */
void signals_end_write(void);

#endif

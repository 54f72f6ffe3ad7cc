/* isolate.h: run a piece of work in a child process and collect what it
 * writes, so that a crash, an abort or a runaway allocation there becomes
 * an error the caller reports instead of the end of the program.
 *
 * Why: the mesh loader hands files to assimp (Debian's 5.2.5), a large
 * parser built with its internal assertions on. Our pre-checks
 * (mesh_check.c) catch every malformed input we have found, but a fuzzer
 * keeps finding new ones that make assimp read out of bounds or abort
 * (CI's fuzz run found one in assimp's own code after 1,027 inputs). A
 * research testbed must not die on a bad file, so assimp runs in a forked
 * child: whatever happens there, the parent names the file and exits 2.
 *
 * The child starts with the default action for every fatal signal (so a
 * crash ends it at once, without a sanitizer's or a fuzzer's handler doing
 * anything in its name), SIGINT, SIGTERM and SIGHUP, and with an
 * address-space limit of what it has mapped plus the memory cap
 * (scenes/memory_cap.h), so that an absurd allocation fails inside it
 * (assimp then reports std::bad_alloc, which the mesh loader words as the
 * cap stopping it) rather than exhausting the machine.
 * It leaves through _exit: nothing of the parent's (stdio buffers, atexit
 * handlers, LeakSanitizer's exit check) runs twice.
 *
 * The parent reads the child's output while it runs (a pipe), up to a
 * bound, then waits for it. Output is only trusted when the child exited
 * with status 0. */
#ifndef ACCELBENCH_ISOLATE_H
#define ACCELBENCH_ISOLATE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The work: write the result to fd (isolate_write) and return the child's
 * exit status (0 for done, whatever the result says). */
typedef int (*isolate_fn)(int fd, void *arg);

/* Run fn(fd, arg) in a child. On success (the child exited with status 0)
 * returns 0 with its output in *out (malloc'd, *out_len bytes, followed by
 * a NUL). Otherwise -1 with how the child ended in why ("crashed with
 * signal 11 (Segmentation fault)", "exited with status 3", "wrote more
 * than N bytes", or why it could not be started) and *out NULL. max_bytes
 * bounds the output kept; a child that writes more is killed. */
int isolate_run(isolate_fn fn, void *arg, uint64_t max_bytes, char **out, size_t *out_len, char *why, size_t whylen);

/* The same work and contract as isolate_run, in this process: fn writes to
 * a memory file (memfd) that is read back once it returns, and a status
 * other than 0 is "exited with status N". Nothing isolates it: a crash or
 * an abort in fn is the caller's. Only for a caller whose own process is
 * the isolation (a fuzzer, which runs every input in a process of its own
 * making and must see a crash, not fork one away). */
int isolate_run_in_process(isolate_fn fn, void *arg, uint64_t max_bytes, char **out, size_t *out_len, char *why,
                           size_t whylen);

/* Write all of len bytes to fd (restarting on EINTR and short writes):
 * 0, or -1 when the pipe is gone (the parent stopped reading). */
int isolate_write(int fd, const void *data, size_t len);

#ifdef __cplusplus
}
#endif

#endif

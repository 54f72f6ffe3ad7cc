/* isolate.c: work in a child process (isolate.h says why). */
#include "isolate.h"
#include "memory_cap.h"

#include <errno.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

int isolate_write(int fd, const void *data, size_t len)
{
    const char *p = data;
    while (len) {
        ssize_t n = write(fd, p, len);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return -1;
        p += n;
        len -= (size_t)n;
    }
    return 0;
}

/* The child's set-up: default actions, so a crash ends it at once and the
 * user's ^C ends it with the parent; and the address-space limit. */
static void child_setup(void)
{
    static const int defaults[] = {SIGSEGV, SIGBUS, SIGABRT, SIGFPE, SIGILL, SIGTRAP, SIGSYS,
                                   SIGINT,  SIGTERM, SIGHUP, SIGPIPE, SIGALRM, SIGUSR1, SIGUSR2};
    for (size_t i = 0; i < sizeof defaults / sizeof defaults[0]; i++) signal(defaults[i], SIG_DFL);
    memory_limits l;
    memory_limits_read(&l);
    struct rlimit rl;
    if (l.as_used && getrlimit(RLIMIT_AS, &rl) == 0) {
        uint64_t want = memory_add(l.as_used, memory_cap_bytes());
        if (rl.rlim_cur == RLIM_INFINITY || want < (uint64_t)rl.rlim_cur) {
            rl.rlim_cur = want >= (uint64_t)RLIM_INFINITY ? RLIM_INFINITY : (rlim_t)want;
            setrlimit(RLIMIT_AS, &rl); /* best effort: the parent's checks stand behind it */
        }
    }
}

/* How a child ended, in words. */
static void describe_status(int status, char *why, size_t whylen)
{
    if (WIFSIGNALED(status))
        snprintf(why, whylen, "crashed with signal %d (%s)", WTERMSIG(status), strsignal(WTERMSIG(status)));
    else if (WIFEXITED(status))
        snprintf(why, whylen, "exited with status %d", WEXITSTATUS(status));
    else
        snprintf(why, whylen, "ended with wait status %d", status);
}

static int wait_child(pid_t pid, int *status)
{
    for (;;) {
        if (waitpid(pid, status, 0) == pid) return 0;
        if (errno != EINTR) return -1;
    }
}

int isolate_run(isolate_fn fn, void *arg, uint64_t max_bytes, char **out, size_t *out_len, char *why, size_t whylen)
{
    *out = NULL;
    *out_len = 0;
    int fds[2];
    if (pipe(fds) != 0) {
        snprintf(why, whylen, "could not be started: pipe: %s", strerror(errno));
        return -1;
    }
    fflush(NULL); /* nothing buffered is written twice, even by a child that flushes */
    pid_t pid = fork();
    if (pid < 0) {
        snprintf(why, whylen, "could not be started: fork: %s", strerror(errno));
        close(fds[0]);
        close(fds[1]);
        return -1;
    }
    if (pid == 0) {
        close(fds[0]);
        child_setup();
        int rc = fn(fds[1], arg);
        _exit(rc);
    }
    close(fds[1]);

    char *buf = NULL;
    size_t len = 0, cap = 0;
    bool over = false, failed = false;
    int read_errno = 0; /* a read's error, before kill() and waitpid() can change errno */
    for (;;) {
        if (len + 65536 + 1 > cap) {
            size_t ncap = cap ? cap * 2 : 1 << 20;
            char *nb = realloc(buf, ncap);
            if (!nb) {
                failed = true;
                read_errno = ENOMEM;
                break;
            }
            buf = nb;
            cap = ncap;
        }
        ssize_t n = read(fds[0], buf + len, cap - len - 1);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            failed = n < 0;
            read_errno = errno;
            break;
        }
        len += (size_t)n;
        if (len > max_bytes) {
            over = true;
            break;
        }
    }
    close(fds[0]);
    if (over || failed) kill(pid, SIGKILL);
    int status = 0;
    if (wait_child(pid, &status) != 0) {
        snprintf(why, whylen, "could not be waited for: %s", strerror(errno));
        free(buf);
        return -1;
    }
    if (over || failed || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        if (over)
            snprintf(why, whylen, "wrote more than %llu bytes", (unsigned long long)max_bytes);
        else if (failed)
            snprintf(why, whylen, "could not be read: %s", strerror(read_errno));
        else
            describe_status(status, why, whylen);
        free(buf);
        return -1;
    }
    if (!buf) buf = malloc(1);
    if (!buf) {
        snprintf(why, whylen, "could not be read: out of memory");
        return -1;
    }
    buf[len] = '\0';
    *out = buf;
    *out_len = len;
    return 0;
}

int isolate_run_in_process(isolate_fn fn, void *arg, uint64_t max_bytes, char **out, size_t *out_len, char *why,
                           size_t whylen)
{
    *out = NULL;
    *out_len = 0;
    int fd = memfd_create("accelbench-isolate", MFD_CLOEXEC);
    if (fd < 0) {
        snprintf(why, whylen, "could not be started: memfd_create: %s", strerror(errno));
        return -1;
    }
    int rc = fn(fd, arg);
    off_t end = lseek(fd, 0, SEEK_END);
    if (rc != 0 || end < 0 || (uint64_t)end > max_bytes) {
        if (rc != 0)
            snprintf(why, whylen, "exited with status %d", rc);
        else if (end < 0)
            snprintf(why, whylen, "could not be read: %s", strerror(errno));
        else
            snprintf(why, whylen, "wrote more than %llu bytes", (unsigned long long)max_bytes);
        close(fd);
        return -1;
    }
    size_t len = (size_t)end;
    char *buf = malloc(len + 1);
    if (!buf) {
        snprintf(why, whylen, "could not be read: out of memory");
        close(fd);
        return -1;
    }
    for (size_t got = 0; got < len;) {
        ssize_t n = pread(fd, buf + got, len - got, (off_t)got);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            snprintf(why, whylen, "could not be read: %s", n < 0 ? strerror(errno) : "the memory file was cut");
            free(buf);
            close(fd);
            return -1;
        }
        got += (size_t)n;
    }
    close(fd);
    buf[len] = '\0';
    *out = buf;
    *out_len = len;
    return 0;
}

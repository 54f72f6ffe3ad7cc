/* output.c: results folders and plot scripts (see output.h). */
#include "output.h"

#ifndef ACCELBENCH_SOURCE_DIR
#define ACCELBENCH_SOURCE_DIR "."
#endif
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include "../../scenes/compressed.h"

int mkdir_p(const char *path)
{
    char buf[1024];
    if (strlen(path) >= sizeof buf) { /* never a folder of a cut name */
        errno = ENAMETOOLONG;
        return -1;
    }
    snprintf(buf, sizeof buf, "%s", path);
    for (char *p = buf + 1; *p; p++)
        if (*p == '/') {
            *p = 0;
            if (mkdir(buf, 0777) && errno != EEXIST) return -1;
            *p = '/';
        }
    return mkdir(buf, 0777) && errno != EEXIST ? -1 : 0;
}

const char *term_text(const char *s)
{
    static _Thread_local char bufs[4][2048];
    static _Thread_local int next;
    char *buf = bufs[next++ & 3];
    size_t n = 0, cap = sizeof bufs[0];
    const unsigned char *c = (const unsigned char *)(s ? s : "");
    for (; *c && n + 12 < cap; c++) {
        const char *named = *c == '\n' ? "\\n" : *c == '\r' ? "\\r" : *c == '\t' ? "\\t" : NULL;
        if (named) n += (size_t)snprintf(buf + n, cap - n, "%s", named);
        else if (*c < 0x20 || *c == 0x7f) n += (size_t)snprintf(buf + n, cap - n, "\\x%02x", *c);
        else if (*c == 0xc2 && c[1] >= 0x80 && c[1] <= 0x9f) { /* U+0080..U+009F: C1 controls (CSI is U+009B) */
            n += (size_t)snprintf(buf + n, cap - n, "\\xc2\\x%02x", c[1]);
            c++;
        } else buf[n++] = (char)*c;
    }
    if (*c) n += (size_t)snprintf(buf + n, cap - n, "...");
    buf[n] = 0;
    return buf;
}

int output_replaceable(const char *path, char *err, size_t errlen)
{
    struct stat st;
    if (stat(path, &st) != 0 || S_ISREG(st.st_mode)) return 0;
    snprintf(err, errlen, "%s: is %s, not a regular file: not written (give the path of a file)", path,
             file_kind(st.st_mode));
    return -1;
}

int output_folder(const char *given, const char *prefix, char *out, size_t outlen)
{
    if (given && strlen(given) >= outlen) {
        fprintf(stderr, "accelbench: --out '%.60s...': a path of %zu bytes, more than %zu\n", given, strlen(given),
                outlen - 1);
        return 2;
    }
    if (given) snprintf(out, outlen, "%s", given);
    else {
        char stamp[32];
        time_t now = time(NULL);
        struct tm tm;
        gmtime_r(&now, &tm);
        strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &tm);
        snprintf(out, outlen, "results/%s%s", prefix, stamp);
    }
    if (mkdir_p(out)) {
        fprintf(stderr, "accelbench: %s: cannot create output folder: %s\n", out, strerror(errno));
        return 2;
    }
    return 0;
}

int spawn_wait(char *const argv[])
{
    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        if (strchr(argv[0], '/')) execv(argv[0], argv);
        else execvp(argv[0], argv);
        fprintf(stderr, "accelbench: cannot run %s: %s\n", argv[0], strerror(errno));
        _exit(127);
    }
    int st;
    while (waitpid(pid, &st, 0) < 0)
        if (errno != EINTR) return -1;
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

bool path_is_dir(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

int run_folder_csv(const char *cmd, const char *dir, char *csv, size_t csvlen)
{
    if (!path_is_dir(dir)) {
        fprintf(stderr, "accelbench %s: %s: no such folder\n", cmd, term_text(dir));
        return 2;
    }
    if ((size_t)snprintf(csv, csvlen, "%s/matrix.csv", dir) >= csvlen) {
        fprintf(stderr, "accelbench %s: %.60s...: a path longer than %zu bytes\n", cmd, term_text(dir), csvlen);
        return 2;
    }
    if (access(csv, R_OK) != 0) {
        fprintf(stderr, "accelbench %s: %s: %s (not a run folder?)\n", cmd, term_text(csv), strerror(errno));
        return 2;
    }
    return 0;
}

const char *python_interpreter(void)
{
    const char *env = getenv("ACCELBENCH_PYTHON");
    if (env && *env) return env;
    return access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3";
}

void run_plot_script(const char *script, const char *csv_path, bool quiet)
{
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/scripts/%s", ACCELBENCH_SOURCE_DIR, script);
    /* The script reads the parameters' defaults from this binary (its labels: name[what differs]). */
    char self[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    if (n > 0) {
        self[n] = 0;
        setenv("ACCELBENCH", self, 0);
    }
    char *argv[] = {(char *)python_interpreter(), path, (char *)csv_path, quiet ? "--quiet" : NULL, NULL};
    int rc = spawn_wait(argv);
    if (rc != 0) fprintf(stderr, "accelbench: warning: plotting failed (exit %d); the CSV is complete: %s\n", rc, csv_path);
}

/* Append one shell word to buf, single-quoted when the shell would split
 * or expand it (a quote inside becomes '\''), or as $'...' with \xHH
 * escapes when it holds a control character. */
void shell_word(char *buf, size_t len, const char *word)
{
    size_t n = strlen(buf);
    bool plain = *word != 0;
    for (const char *c = word; *c; c++)
        if (!strchr("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789:,._/=+-@%", *c)) plain = false;
    if (n && n + 1 < len) buf[n++] = ' ', buf[n] = 0;
    if (plain) {
        snprintf(buf + n, len - n, "%s", word);
        return;
    }
    bool control = false;
    for (const unsigned char *c = (const unsigned char *)word; *c; c++) control |= *c < 0x20 || *c == 0x7f;
    if (control) {
        /* bash's $'...': the terminal sees no control character, and the line still pastes. */
        if (n + 2 < len) n += (size_t)snprintf(buf + n, len - n, "$'");
        for (const unsigned char *c = (const unsigned char *)word; *c && n + 6 < len; c++) {
            if (*c < 0x20 || *c == 0x7f) n += (size_t)snprintf(buf + n, len - n, "\\x%02x", *c);
            else if (*c == '\'' || *c == '\\') n += (size_t)snprintf(buf + n, len - n, "\\%c", *c);
            else buf[n++] = (char)*c, buf[n] = 0;
        }
        if (n + 1 < len) buf[n++] = '\'', buf[n] = 0;
        return;
    }
    if (n + 1 < len) buf[n++] = '\'', buf[n] = 0;
    for (const char *c = word; *c && n + 5 < len; c++) {
        if (*c == '\'') n += (size_t)snprintf(buf + n, len - n, "'\\''");
        else buf[n++] = *c, buf[n] = 0;
    }
    if (n + 1 < len) buf[n++] = '\'', buf[n] = 0;
}

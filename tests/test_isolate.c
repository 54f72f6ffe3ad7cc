/* test_isolate: work in a child process (scenes/isolate.h), the mesh
 * loader's shield against assimp: a child that crashes, aborts, exits with
 * an error, writes past the bound or allocates past the memory cap is
 * reported, never fatal; what a child writes arrives whole; and the mesh
 * loader gives the same scene through the child as the file says. The
 * in-process form the fuzzers use (isolate_run_in_process,
 * scene_mesh_from_memory_in_process) gives the same output, statuses,
 * scenes and messages. */
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "../scenes/isolate.h"
#include "../scenes/memory_cap.h"
#include "../scenes/scene.h"
#include "check.h"

static int child_segv(int fd, void *arg)
{
    (void)fd, (void)arg;
    volatile int *volatile p = NULL;
    raise(SIGSEGV); /* as a wild read would; the sanitizers' handlers must not catch it */
    return *p;
}

static int child_abort(int fd, void *arg)
{
    (void)fd, (void)arg;
    abort(); /* assimp's internal assertions end this way */
}

static int child_status(int fd, void *arg)
{
    (void)fd;
    return *(int *)arg;
}

/* Writes n bytes of a known pattern. */
static int child_writes(int fd, void *arg)
{
    size_t n = *(size_t *)arg;
    char block[4096];
    for (size_t done = 0; done < n;) {
        size_t k = n - done < sizeof block ? n - done : sizeof block;
        for (size_t i = 0; i < k; i++) block[i] = (char)((done + i) * 7);
        if (isolate_write(fd, block, k)) return 1;
        done += k;
    }
    return 0;
}

/* Asks for twice the memory cap: the child's address-space limit refuses it. */
static int child_allocates(int fd, void *arg)
{
    (void)fd, (void)arg;
    size_t n = (size_t)memory_cap_bytes() * 2;
    char *p = malloc(n);
    if (!p) return 7;
    memset(p, 1, n); /* would take the machine's memory if the limit did not hold */
    free(p);
    return 0;
}

static void check_fails(isolate_fn fn, void *arg, uint64_t max, const char *expect)
{
    char *out = (char *)1, why[256] = "";
    size_t len = 99;
    int rc = isolate_run(fn, arg, max, &out, &len, why, sizeof why);
    CHECK_MSG(rc == -1 && out == NULL && len == 0, "rc %d", rc);
    CHECK_MSG(strstr(why, expect) != NULL, "why '%s', expected '%s'", why, expect);
    printf("child: %s\n", why);
}

/* child_writes's n bytes came back whole and in order (how: "" or "in process: "); frees out. */
static void check_written(const char *how, int rc, char *out, size_t len, size_t n, const char *why)
{
    CHECK_MSG(rc == 0 && len == n, "%src %d, %zu of %zu bytes: %s", how, rc, len, n, rc ? why : "");
    if (rc != 0) return;
    size_t bad = 0;
    for (size_t i = 0; i < len; i++) bad += out[i] != (char)(i * 7);
    CHECK_MSG(bad == 0 && out[len] == '\0', "%s%zu bytes differ", how, bad);
    free(out);
}

int main(void)
{
    check_fails(child_segv, NULL, 1 << 20, "crashed with signal 11");
    check_fails(child_abort, NULL, 1 << 20, "crashed with signal 6");
    int three = 3;
    check_fails(child_status, &three, 1 << 20, "exited with status 3");
    size_t big = 3 << 20;
    check_fails(child_writes, &big, 1 << 20, "wrote more than 1048576 bytes");

    /* The address-space limit: a cap of 64 MiB, an allocation of 128 MiB.
     * (Under AddressSanitizer malloc of that size returns NULL or dies by
     * its own report; either way the child, not this process, ends.) */
    memory_cap_set_mib(64);
    char *out, why[256];
    size_t len;
    int rc = isolate_run(child_allocates, NULL, 1 << 20, &out, &len, why, sizeof why);
    CHECK_MSG(rc == -1, "a child allocating twice the cap exited 0");
    printf("child allocating 128 MiB under a 64 MiB cap: %s\n", why);
    memory_cap_set_mib(0);

    /* Output arrives whole, in order, across many pipe buffers. */
    size_t n = 5u << 20;
    rc = isolate_run(child_writes, &n, 64u << 20, &out, &len, why, sizeof why);
    check_written("", rc, out, len, n, why);
    int zero = 0;
    rc = isolate_run(child_status, &zero, 1 << 20, &out, &len, why, sizeof why);
    CHECK(rc == 0 && len == 0 && out && out[0] == '\0');
    free(out);

    /* The mesh loader through the child: a quad and a lone line (skipped),
     * vertices and faces exactly as written. */
    static const char obj[] = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 2 2\nf 1 2 3 4\nl 1 5\n";
    char err[512] = "";
    scene_t *s = scene_mesh_from_memory("quad", "quad.obj", "quad.obj", obj, sizeof obj - 1, err, sizeof err);
    CHECK_MSG(s != NULL, "%s", err);
    if (s) {
        CHECK_MSG(s->prims.ntris == 2, "%u triangles", s->prims.ntris);
        CHECK_MSG(strstr(s->source, "1 point/line faces skipped") != NULL, "source '%s'", s->source);
        scene_free(s);
    }
    /* A file assimp refuses: its error comes back from the child. */
    static const char ply[] = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n";
    s = scene_mesh_from_memory("bad", "bad.ply", "bad.ply", ply, sizeof ply - 1, err, sizeof err);
    CHECK_MSG(s == NULL && strstr(err, "bad.ply") != NULL, "err '%s'", err);
    printf("bad.ply: %s\n", err);
    scene_free(s);

    /* In process: the same output, whole, and the same failures (but a crash would be ours). */
    rc = isolate_run_in_process(child_writes, &n, 64u << 20, &out, &len, why, sizeof why);
    check_written("in process: ", rc, out, len, n, why);
    out = (char *)1;
    rc = isolate_run_in_process(child_status, &three, 1 << 20, &out, &len, why, sizeof why);
    CHECK_MSG(rc == -1 && out == NULL && strstr(why, "exited with status 3"), "in process: rc %d, why '%s'", rc, why);
    rc = isolate_run_in_process(child_writes, &big, 1 << 20, &out, &len, why, sizeof why);
    CHECK_MSG(rc == -1 && out == NULL && strstr(why, "wrote more than 1048576 bytes"), "in process: rc %d, why '%s'",
              rc, why);
    rc = isolate_run_in_process(child_status, &zero, 1 << 20, &out, &len, why, sizeof why);
    CHECK(rc == 0 && len == 0 && out && out[0] == '\0');
    free(out);

    s = scene_mesh_from_memory_in_process("quad", "quad.obj", "quad.obj", obj, sizeof obj - 1, err, sizeof err);
    scene_t *c = scene_mesh_from_memory("quad", "quad.obj", "quad.obj", obj, sizeof obj - 1, err, sizeof err);
    CHECK_MSG(s != NULL && c != NULL, "in process: %s", err);
    if (s && c) {
        CHECK_MSG(s->prims.ntris == 2 && s->prims.nverts == c->prims.nverts &&
                      !memcmp(s->prims.verts, c->prims.verts, c->prims.nverts * sizeof *c->prims.verts) &&
                      !memcmp(s->prims.tris, c->prims.tris, 2 * sizeof *c->prims.tris),
                  "in process: %u triangles, %u vertices, not the child's", s->prims.ntris, s->prims.nverts);
        CHECK_MSG(strcmp(s->source, c->source) == 0, "in process: source '%s'", s->source);
    }
    scene_free(s);
    scene_free(c);
    char err_child[512];
    snprintf(err_child, sizeof err_child, "%s", err);
    s = scene_mesh_from_memory("bad", "bad.ply", "bad.ply", ply, sizeof ply - 1, err_child, sizeof err_child);
    scene_free(s);
    s = scene_mesh_from_memory_in_process("bad", "bad.ply", "bad.ply", ply, sizeof ply - 1, err, sizeof err);
    CHECK_MSG(s == NULL && strcmp(err, err_child) == 0, "in process: err '%s', through the child '%s'", err, err_child);
    scene_free(s);
    return check_report();
}

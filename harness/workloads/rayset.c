/* rayset.c: ray set storage, hashing and the ray file (see rayset.h). */
#include "rayset.h"
#include "workload.h"
#include "../../prims/checked_alloc.h"
#include "../../scenes/memory_cap.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <stddef.h>
#include <string.h>
#include <sys/stat.h>

/* rayset_push's first capacity; it doubles from there. */
#define RAYSET_FIRST_CAP 4096u

/* Version 3: rays carry their origin primitive (ray_t.origin). Version 2
 * had 0 in that field on every ray, which would read as "leaves primitive
 * 0", so its files are refused rather than misread. Version 2 made the
 * stored hash cover the whole file (version 1's covered the rays, the query
 * and the count only). */
static const char MAGIC[8] = {'A', 'B', 'R', 'A', 'Y', 'S', '3', '\n'};
static const char MAGIC_V2[8] = {'A', 'B', 'R', 'A', 'Y', 'S', '2', '\n'};
static const char MAGIC_V1[8] = {'A', 'B', 'R', 'A', 'Y', 'S', '1', '\n'};

typedef struct {
    char magic[8];
    uint32_t query, count, width, height, spp, has_pixels;
    uint64_t seed, hash;
    char workload[32];
    char scene[256];
} file_header;

rayset_t *rayset_new(const char *workload, const char *scene, uint64_t seed, query_kind q)
{
    rayset_t *rs = checked_calloc(1, sizeof *rs, "a ray set");
    snprintf(rs->workload, sizeof rs->workload, "%s", workload);
    snprintf(rs->scene, sizeof rs->scene, "%s", scene);
    rs->seed = seed;
    rs->query = q;
    return rs;
}

void rayset_push(rayset_t *rs, const ray_t *r, uint32_t pixel)
{
    if (rs->count == UINT32_MAX) { /* the count is a uint32 in memory and in the file; the workloads' estimates refuse first */
        fprintf(stderr, "accelbench: %s on %s: a ray set holds at most 2^32 - 1 rays\n", rs->workload, rs->scene);
        exit(2);
    }
    if (rs->count == rs->cap) {
        rs->cap = rs->cap > UINT32_MAX / 2 ? UINT32_MAX : rs->cap ? rs->cap * 2 : RAYSET_FIRST_CAP;
        rs->rays = checked_realloc(rs->rays, (size_t)rs->cap * sizeof *rs->rays, "a ray set's rays");
        if (rs->width) rs->pixel = checked_realloc(rs->pixel, (size_t)rs->cap * sizeof *rs->pixel, "a ray set's pixels");
    }
    rs->rays[rs->count] = *r;
    if (rs->pixel) rs->pixel[rs->count] = pixel;
    rs->count++;
}

/* FNV-1a 64 over n more bytes. */
static uint64_t fnv(uint64_t h, const void *data, size_t n)
{
    const unsigned char *b = data;
    for (size_t i = 0; i < n; i++) h = (h ^ b[i]) * 0x100000001b3ull;
    return h;
}

uint64_t rayset_hash(const rayset_t *rs)
{
    uint32_t head[2] = {(uint32_t)rs->query, rs->count};
    return fnv(fnv(0xcbf29ce484222325ull, head, sizeof head), rs->rays, (size_t)rs->count * sizeof *rs->rays);
}

void rayset_seal(rayset_t *rs) { rs->hash = rayset_hash(rs); }

void rayset_free(rayset_t *rs)
{
    if (!rs) return;
    free(rs->rays);
    free(rs->pixel);
    free(rs);
}

/* The file's checksum: every byte of it, the header with its hash field
 * zero, so that no field can change unnoticed (rayset_file_rehash is the
 * same over a file's bytes). */
static uint64_t file_hash(file_header h, const ray_t *rays, const uint32_t *pixel)
{
    h.hash = 0;
    uint64_t x = fnv(0xcbf29ce484222325ull, &h, sizeof h);
    x = fnv(x, rays, (size_t)h.count * sizeof *rays);
    return pixel ? fnv(x, pixel, (size_t)h.count * sizeof *pixel) : x;
}

void rayset_file_rehash(void *data, size_t size)
{
    file_header h;
    if (size < sizeof h) return;
    memcpy(&h, data, sizeof h);
    h.hash = 0;
    h.hash = fnv(fnv(0xcbf29ce484222325ull, &h, sizeof h), (const char *)data + sizeof h, size - sizeof h);
    memcpy(data, &h, sizeof h);
}

int rayset_save(const rayset_t *rs, const char *path, char *err, size_t errlen)
{
    FILE *f = fopen(path, "wb");
    if (!f) {
        snprintf(err, errlen, "%s: cannot write: %s", path, strerror(errno));
        return -1;
    }
    file_header h;
    memset(&h, 0, sizeof h);
    memcpy(h.magic, MAGIC, sizeof MAGIC);
    h.query = rs->query;
    h.count = rs->count;
    h.width = rs->width;
    h.height = rs->height;
    h.spp = rs->spp;
    h.has_pixels = rs->pixel != NULL;
    h.seed = rs->seed;
    memcpy(h.workload, rs->workload, sizeof h.workload);
    memcpy(h.scene, rs->scene, sizeof h.scene);
    h.hash = file_hash(h, rs->rays, rs->pixel);
    /* fwrite of 0 items from a NULL array (a set of 0 rays) is undefined: skip it. */
    bool ok = fwrite(&h, sizeof h, 1, f) == 1 &&
              (!rs->count || fwrite(rs->rays, sizeof *rs->rays, rs->count, f) == rs->count) &&
              (!rs->count || !rs->pixel || fwrite(rs->pixel, sizeof *rs->pixel, rs->count, f) == rs->count);
    if (fclose(f) != 0) ok = false;
    if (!ok) {
        snprintf(err, errlen, "%s: write failed: %s", path, strerror(errno));
        return -1;
    }
    return 0;
}

/* The header's fields, once the checksum has said they are the ones
 * written: what a writer of this version can have written. */
static int check_header(const file_header *h, const char *path, char *err, size_t errlen)
{
    if (!memchr(h->workload, 0, sizeof h->workload) || !memchr(h->scene, 0, sizeof h->scene)) {
        snprintf(err, errlen, "%s: corrupt header (the workload or scene name is not terminated)", path);
        return -1;
    }
    const workload_def *w = workload_find(h->workload);
    if (!w || w->query != (query_kind)h->query) {
        snprintf(err, errlen, "%s: header names workload '%s' with query %u, which this version does not make", path,
                 h->workload, h->query);
        return -1;
    }
    if (h->count == 0) {
        snprintf(err, errlen, "%s: holds no rays", path);
        return -1;
    }
    if (h->has_pixels && (h->width == 0 || h->height == 0 || h->spp == 0 || (uint64_t)h->width * h->height > UINT32_MAX)) {
        snprintf(err, errlen, "%s: corrupt header (pixels of a %ux%u image at %u samples)", path, h->width, h->height, h->spp);
        return -1;
    }
    return 0;
}

/* Why ray r may not reach an accelerator (prims/ray.h ray_traceable, the
 * harness's one rule, in words), or NULL when it may. */
static const char *untraceable(const ray_t *r, char *buf, size_t len)
{
    if (!v3_finite(r->org) || !v3_finite(r->dir)) return "has a NaN or infinite origin or direction";
    if (ray_traceable(r)) return NULL;
    if (r->dir.x == 0.0f && r->dir.y == 0.0f && r->dir.z == 0.0f) return "has a zero-length direction";
    if (isnan(r->tnear) || isnan(r->tfar)) return "has a NaN tnear or tfar";
    if (r->tnear < 0.0f || r->tnear > RAY_COORD_MAX) {
        snprintf(buf, len, "has tnear %g outside [0, 2^60]", r->tnear);
        return buf;
    }
    if (r->tnear > r->tfar) {
        snprintf(buf, len, "has an empty range [%g, %g]", r->tnear, r->tfar);
        return buf;
    }
    return "has an origin or direction component beyond 2^60 (RAY_COORD_MAX, prims/ray.h)";
}

rayset_t *rayset_from_memory(const void *data, size_t size, const char *path, char *err, size_t errlen)
{
    file_header h;
    rayset_t *rs = NULL;
    if (size < sizeof h || memcmp(data, MAGIC, sizeof MAGIC) != 0) {
        if (size >= sizeof MAGIC_V1 && memcmp(data, MAGIC_V1, sizeof MAGIC_V1) == 0)
            snprintf(err, errlen, "%s: a ray file of an older format (ABRAYS1, header not hashed): save it again", path);
        else if (size >= sizeof MAGIC_V2 && memcmp(data, MAGIC_V2, sizeof MAGIC_V2) == 0)
            snprintf(err, errlen, "%s: a ray file of an older format (ABRAYS2, rays without their origin primitive): save it again",
                     path);
        else
            snprintf(err, errlen, "%s: not an accelbench ray file (bad header)", path);
        return NULL;
    }
    memcpy(&h, data, sizeof h);
    if (h.query > QUERY_ANY || h.has_pixels > 1) {
        snprintf(err, errlen, "%s: corrupt header (query %u, has_pixels %u)", path, h.query, h.has_pixels);
        return NULL;
    }
    /* The size first, so a corrupt count cannot ask for terabytes. */
    size_t per_ray = sizeof(ray_t) + (h.has_pixels ? sizeof(uint32_t) : 0), body = size - sizeof h;
    if (body != (size_t)h.count * per_ray) {
        snprintf(err, errlen, "%s: truncated or oversized: header says %u rays (%zu bytes), file has %zu bytes after the header",
                 path, h.count, (size_t)h.count * per_ray, body);
        return NULL;
    }
    if (memory_cap_exceeded((uint64_t)h.count * per_ray, err, errlen, "%s: %u rays", path, h.count)) return NULL;
    rs = checked_calloc(1, sizeof *rs, "a ray set");
    rs->count = rs->cap = h.count;
    rs->rays = malloc((size_t)(h.count ? h.count : 1) * sizeof *rs->rays);
    if (h.has_pixels) rs->pixel = malloc((size_t)(h.count ? h.count : 1) * sizeof *rs->pixel);
    if (!rs->rays || (h.has_pixels && !rs->pixel)) {
        snprintf(err, errlen, "%s: out of memory for %u rays", path, h.count);
        goto fail;
    }
    const char *bytes = (const char *)data + sizeof h;
    memcpy(rs->rays, bytes, (size_t)h.count * sizeof *rs->rays);
    if (rs->pixel) memcpy(rs->pixel, bytes + (size_t)h.count * sizeof *rs->rays, (size_t)h.count * sizeof *rs->pixel);
    uint64_t sum = file_hash(h, rs->rays, rs->pixel);
    if (sum != h.hash) {
        snprintf(err, errlen, "%s: contents do not match the stored hash (%016llx != %016llx): file corrupt", path,
                 (unsigned long long)sum, (unsigned long long)h.hash);
        goto fail;
    }
    if (check_header(&h, path, err, errlen) != 0) goto fail;
    snprintf(rs->workload, sizeof rs->workload, "%s", h.workload);
    snprintf(rs->scene, sizeof rs->scene, "%s", h.scene);
    rs->seed = h.seed;
    rs->query = (query_kind)h.query;
    rs->width = h.width;
    rs->height = h.height;
    rs->spp = h.spp;
    for (uint32_t i = 0; i < rs->count; i++) {
        char buf[96];
        const char *why = untraceable(&rs->rays[i], buf, sizeof buf);
        if (why) {
            snprintf(err, errlen, "%s: ray %u %s", path, i, why);
            goto fail;
        }
        if (rs->pixel && rs->pixel[i] >= h.width * h.height) {
            snprintf(err, errlen, "%s: ray %u belongs to pixel %u of a %ux%u image", path, i, rs->pixel[i], h.width, h.height);
            goto fail;
        }
    }
    rayset_seal(rs);
    return rs;
fail:
    rayset_free(rs);
    return NULL;
}

rayset_t *rayset_load(const char *path, char *err, size_t errlen)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(err, errlen, "%s: cannot open ray file: %s", path, strerror(errno));
        return NULL;
    }
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISDIR(st.st_mode)) { /* fopen opens a folder; its "size" is LONG_MAX */
        snprintf(err, errlen, "%s: a folder, not a ray file (give the file --save-rays wrote)", path);
        fclose(f);
        return NULL;
    }
    long size = fseek(f, 0, SEEK_END) == 0 ? ftell(f) : -1;
    /* Read whole, then copied into the set: twice the file at the peak. */
    if (size >= 0 && memory_cap_exceeded(2 * (uint64_t)size, err, errlen, "%s: a ray file of %ld bytes, read and copied,", path, size)) {
        fclose(f);
        return NULL;
    }
    char *data = size >= 0 ? checked_malloc((size_t)size + 1, "a ray file's contents") : NULL;
    bool ok = data && fseek(f, 0, SEEK_SET) == 0 && fread(data, 1, (size_t)size, f) == (size_t)size;
    fclose(f);
    rayset_t *rs = NULL;
    if (!ok)
        snprintf(err, errlen, "%s: cannot read ray file: %s", path, size < 0 ? strerror(errno) : "read failed");
    else
        rs = rayset_from_memory(data, (size_t)size, path, err, errlen);
    free(data);
    return rs;
}

/* Every ray's index field (at offset field of ray_t) is `none` or below
 * bound; else one line: "PATH: ray I VERB NOUN V, but scene 'S' has N NOUNs". */
static int check_index_field(const rayset_t *rs, size_t field, uint32_t none, uint32_t bound, const char *verb,
                             const char *noun, const char *path, const char *scene, char *err, size_t errlen)
{
    for (uint32_t i = 0; i < rs->count; i++) {
        uint32_t v;
        memcpy(&v, (const char *)&rs->rays[i] + field, sizeof v);
        if (v != none && v >= bound) {
            snprintf(err, errlen, "%s: ray %u %s %s %u, but scene '%s' has %u %s%s", path, i, verb, noun, v, scene, bound,
                     noun, bound == 1 ? "" : "s");
            return -1;
        }
    }
    return 0;
}

int rayset_check_lights(const rayset_t *rs, const char *path, const char *scene, uint32_t nlights, char *err,
                        size_t errlen)
{
    return check_index_field(rs, offsetof(ray_t, light), RAY_NO_LIGHT, nlights, "goes to", "light", path, scene, err,
                             errlen);
}

int rayset_check_origins(const rayset_t *rs, const char *path, const char *scene, uint32_t nprims, char *err,
                         size_t errlen)
{
    return check_index_field(rs, offsetof(ray_t, origin), RAY_NO_ORIGIN, nprims, "leaves", "primitive", path, scene,
                             err, errlen);
}

uint64_t rayset_bytes(uint64_t n, bool pixels)
{
    if (n == 0) return 0;
    uint64_t cap = RAYSET_FIRST_CAP;
    while (cap < n && cap < RAYSET_RAYS_MAX) cap *= 2;
    if (cap > RAYSET_RAYS_MAX) cap = RAYSET_RAYS_MAX;
    if (n > cap) cap = n; /* beyond what a set holds: the count is refused anyway */
    return memory_mul(cap, sizeof(ray_t) + (pixels ? sizeof(uint32_t) : 0));
}

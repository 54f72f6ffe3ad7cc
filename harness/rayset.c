/* rayset.c: ray set storage, hashing and the ray file (see rayset.h). */
#include "rayset.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char MAGIC[8] = {'A', 'B', 'R', 'A', 'Y', 'S', '1', '\n'};

typedef struct {
    char magic[8];
    uint32_t query, count, width, height, spp, has_pixels;
    uint64_t seed, hash;
    char workload[32];
    char scene[256];
} file_header;

rayset_t *rayset_new(const char *workload, const char *scene, uint64_t seed, query_kind q)
{
    rayset_t *rs = calloc(1, sizeof *rs);
    if (!rs) abort();
    snprintf(rs->workload, sizeof rs->workload, "%s", workload);
    snprintf(rs->scene, sizeof rs->scene, "%s", scene);
    rs->seed = seed;
    rs->query = q;
    return rs;
}

void rayset_push(rayset_t *rs, const ray_t *r, uint32_t pixel)
{
    if (rs->count == rs->cap) {
        rs->cap = rs->cap ? rs->cap * 2 : 4096;
        rs->rays = realloc(rs->rays, (size_t)rs->cap * sizeof *rs->rays);
        if (rs->width) rs->pixel = realloc(rs->pixel, (size_t)rs->cap * sizeof *rs->pixel);
        if (!rs->rays || (rs->width && !rs->pixel)) {
            fprintf(stderr, "accelbench: out of memory for %u rays\n", rs->cap);
            abort();
        }
    }
    rs->rays[rs->count] = *r;
    if (rs->pixel) rs->pixel[rs->count] = pixel;
    rs->count++;
}

uint64_t rayset_hash(const rayset_t *rs)
{
    uint64_t h = 0xcbf29ce484222325ull;
    const uint64_t prime = 0x100000001b3ull;
    uint32_t head[2] = {(uint32_t)rs->query, rs->count};
    const unsigned char *b = (const unsigned char *)head;
    for (size_t i = 0; i < sizeof head; i++) h = (h ^ b[i]) * prime;
    b = (const unsigned char *)rs->rays;
    size_t n = (size_t)rs->count * sizeof *rs->rays;
    for (size_t i = 0; i < n; i++) h = (h ^ b[i]) * prime;
    return h;
}

void rayset_seal(rayset_t *rs) { rs->hash = rayset_hash(rs); }

void rayset_free(rayset_t *rs)
{
    if (!rs) return;
    free(rs->rays);
    free(rs->pixel);
    free(rs);
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
    h.hash = rs->hash;
    memcpy(h.workload, rs->workload, sizeof h.workload);
    memcpy(h.scene, rs->scene, sizeof h.scene);
    bool ok = fwrite(&h, sizeof h, 1, f) == 1 && fwrite(rs->rays, sizeof *rs->rays, rs->count, f) == rs->count &&
              (!rs->pixel || fwrite(rs->pixel, sizeof *rs->pixel, rs->count, f) == rs->count);
    if (fclose(f) != 0) ok = false;
    if (!ok) {
        snprintf(err, errlen, "%s: write failed: %s", path, strerror(errno));
        return -1;
    }
    return 0;
}

rayset_t *rayset_load(const char *path, char *err, size_t errlen)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(err, errlen, "%s: cannot open ray file: %s", path, strerror(errno));
        return NULL;
    }
    file_header h;
    rayset_t *rs = NULL;
    if (fread(&h, sizeof h, 1, f) != 1 || memcmp(h.magic, MAGIC, sizeof MAGIC) != 0) {
        snprintf(err, errlen, "%s: not an accelbench ray file (bad header)", path);
        goto fail;
    }
    if (h.query > QUERY_ANY || h.has_pixels > 1) {
        snprintf(err, errlen, "%s: corrupt header (query %u, has_pixels %u)", path, h.query, h.has_pixels);
        goto fail;
    }
    h.workload[sizeof h.workload - 1] = 0;
    h.scene[sizeof h.scene - 1] = 0;
    /* Check the size before allocating, so a corrupt count cannot ask for terabytes. */
    long here = ftell(f);
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, here, SEEK_SET);
    size_t per_ray = sizeof(ray_t) + (h.has_pixels ? sizeof(uint32_t) : 0);
    if (size < 0 || (size_t)(size - here) != (size_t)h.count * per_ray) {
        snprintf(err, errlen, "%s: truncated or oversized: header says %u rays (%zu bytes), file has %ld bytes after the header",
                 path, h.count, (size_t)h.count * per_ray, size - here);
        goto fail;
    }
    rs = rayset_new(h.workload, h.scene, h.seed, (query_kind)h.query);
    rs->count = rs->cap = h.count;
    rs->width = h.width;
    rs->height = h.height;
    rs->spp = h.spp;
    rs->rays = malloc((size_t)(h.count ? h.count : 1) * sizeof *rs->rays);
    if (h.has_pixels) rs->pixel = malloc((size_t)(h.count ? h.count : 1) * sizeof *rs->pixel);
    if (!rs->rays || (h.has_pixels && !rs->pixel) || fread(rs->rays, sizeof *rs->rays, h.count, f) != h.count ||
        (h.has_pixels && fread(rs->pixel, sizeof *rs->pixel, h.count, f) != h.count)) {
        snprintf(err, errlen, "%s: read failed", path);
        goto fail;
    }
    rayset_seal(rs);
    if (rs->hash != h.hash) {
        snprintf(err, errlen, "%s: ray data does not match the stored hash (%016llx != %016llx): file corrupt",
                 path, (unsigned long long)rs->hash, (unsigned long long)h.hash);
        goto fail;
    }
    for (uint32_t i = 0; i < rs->count; i++) {
        const ray_t *r = &rs->rays[i];
        if (!v3_finite(r->org) || !v3_finite(r->dir) || r->tnear != r->tnear || r->tfar != r->tfar) {
            snprintf(err, errlen, "%s: ray %u has a NaN or infinite origin/direction", path, i);
            goto fail;
        }
        if (v3_dot(r->dir, r->dir) == 0.0f) {
            snprintf(err, errlen, "%s: ray %u has a zero-length direction", path, i);
            goto fail;
        }
        if (!(r->tnear <= r->tfar)) {
            snprintf(err, errlen, "%s: ray %u has an empty range [%g, %g]", path, i, r->tnear, r->tfar);
            goto fail;
        }
    }
    fclose(f);
    return rs;
fail:
    rayset_free(rs);
    fclose(f);
    return NULL;
}

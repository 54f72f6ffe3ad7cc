/* resources.h: what the harness's commands would allocate, estimated
 * before they allocate it and refused above the memory cap
 * (scenes/memory_cap.h, --memcap MIB) with exit 2 and one line: what, how
 * many bytes, the cap and where it came from, how to raise it.
 *
 * Estimated: a workload's ray set with everything alive while it is made
 * and while one cell traces it (resources_workload), render's image
 * (resources_render), the answers of a trace, the tracing threads' stacks
 * (resources_threads), and, from the scene name alone, a generated scene's
 * primitive store (resources_check_options; the generator itself makes the
 * exact estimate before generating, scenes/spd.c). Counts a ray set cannot
 * hold (2^32 - 1 rays) are refused whatever the cap.
 *
 * The accelerators' own caps (accel/common/memcap.h): the harness's cap
 * is the memcap_mib field of every accelerator's parameters, and a build
 * refuses past min(its own cap, that) (params_memcap), so --memcap bounds
 * everything a command builds. It is not a table row: the CSV's params
 * column, the cell key and the label do not hold it, since the cap bounds
 * memory and does not change what a cell measures. */
#ifndef ACCELBENCH_RESOURCES_H
#define ACCELBENCH_RESOURCES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "../scenes/memory_cap.h"
#include "options.h"
#include "rayset.h"
#include "workload.h"

/* The most rays a ray set holds (its count is a uint32, in memory and in
 * the file). */
#define RESOURCES_RAYS_MAX UINT32_MAX

/* Heap bytes of a ray set of n rays (with each ray's pixel or not) as
 * rayset_push grows it: its capacity doubles from 4096, so it holds up to
 * twice n. */
uint64_t resources_rayset_bytes(uint64_t n, bool pixels);
/* Heap bytes of the answers of n rays (answers_new). */
uint64_t resources_answers_bytes(uint64_t n, query_kind q, bool per_ray_counters);

typedef struct {
    uint64_t rays;  /* an upper bound on the rays of the set */
    uint64_t bytes; /* and on the bytes alive at once, at the peak */
} resources_estimate;

/* The ray set of workload `name` ("primary", "shadow", ...) under o for a
 * scene with nlights lights, made and traced in one cell: the larger of
 * what is alive while it is made (the primary rays and the reference's
 * answers it is derived from, the generations of reflection) and while the
 * cell traces it (the set, the reference's answers, the ill-posed count's,
 * the accelerator's and the timing's). Upper bounds: every primary ray is
 * taken to hit, every hit to see every light. */
resources_estimate resources_workload(const char *name, const workload_opts *o, uint32_t nlights);
/* 0, or -1 with one line in err: more rays than a set holds, or more bytes
 * than the cap. scene names the scene in the message. */
int resources_check_workload(const char *name, const char *scene, const workload_opts *o, uint32_t nlights, char *err,
                             size_t errlen);
/* A part of the whitted workload: the eye rays (W+1)(H+1); the tree's
 * closest-hit generations at most double where the scene has a
 * transmitter (T > 0: reflection and refraction) and stay as wide where it
 * has none; every hit sees every light. resources_workload("whitted:...")
 * assumes transmitters; the workload itself checks with what the scene
 * has (resources_check_whitted). */
resources_estimate resources_whitted(const workload_opts *o, uint32_t nlights, bool transmitters, whitted_part part);
int resources_check_whitted(const char *scene, const workload_opts *o, uint32_t nlights, bool transmitters,
                            whitted_part part, char *err, size_t errlen);

/* render's image of width x height at spp samples (corners: SPD's corner
 * rays): the primary rays, and the image with its sums (Whitted) or the
 * per-ray counters and the per-pixel costs (heat maps). */
resources_estimate resources_render(int width, int height, int spp, bool corners, bool heatmap);
int resources_check_render(const char *scene, int width, int height, int spp, bool corners, bool heatmap, char *err,
                           size_t errlen);

/* The address space one thread reserves for its stack (the process's
 * default pthread stack and its guard page). */
uint64_t resources_thread_stack_bytes(void);
/* threads - 1 of them (the calling thread traces too) against the cap: 0,
 * or -1 with "--threads N: ..." (option names the option) in err. */
int resources_check_threads(int threads, const char *option, char *err, size_t errlen);

/* --memcap MIB: 0 with *mib, or -1 with the reason in err. */
int resources_parse_memcap(const char *arg, uint64_t *mib, char *err, size_t errlen);

/* The harness's memory cap as params' memcap_mib (memory_cap_mib(), at
 * least 1). */
void resources_bound_accel_params(accel_params *params);

/* Options parsed (a command's accelerators expanded, --memcap read): set
 * the cap (o->memcap_mib, 0 for the default) and give it to every
 * accelerator's parameters. 0, or 2 after printing one line. */
int resources_apply_memcap(options *o);
/* Then everything the options of command cmd size, before any scene is
 * loaded: the threads, every generated scene's store at the fewest bytes a
 * primitive takes (the generator's own estimate follows), --rays' file,
 * and every workload's ray set at one light (a lower bound: every scene
 * has a light; the exact count is checked when each set is made), or for
 * render the image when --res gives its size. 0, or 2 after printing one
 * line. */
int resources_check_options(const options *o, const char *cmd);

#endif

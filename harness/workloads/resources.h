/* resources.h: the memory policy of the harness's commands: what they
 * would allocate is estimated before they allocate it and refused above
 * the memory cap (scenes/memory_cap.h, --memcap MIB) with exit 2 and one
 * line: what, how many bytes, the cap and where it came from, how to raise
 * it. Each module sizes what it allocates: a ray set (rayset_bytes), a
 * trace's answers and a cell's (trace.h), a workload's ray set with
 * everything alive while it is made and traced (workload_estimate,
 * whitted_estimate), render's image (render/render.h render_estimate);
 * from the scene name alone, a generated scene's primitive store
 * (cli/options.h resources_check_options; the generator itself makes the
 * exact estimate before generating, scenes/spd.c). Here: the tracing
 * threads' stacks, --memcap, and the accelerators' own caps. Counts a ray
 * set cannot hold (2^32 - 1 rays) are refused whatever the cap.
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
#include "../../scenes/memory_cap.h"
#include "../../accel/accel.h"

typedef struct {
    uint64_t rays;  /* an upper bound on the rays of the set */
    uint64_t bytes; /* and on the bytes alive at once, at the peak */
} resources_estimate;

static inline uint64_t resources_max(uint64_t a, uint64_t b) { return a > b ? a : b; }

/* "WxH at S spp" or "WxH corners", for messages. */
void resources_describe_image(char *buf, size_t len, int w, int h, int spp, bool corners);

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

#endif

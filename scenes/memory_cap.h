/* memory_cap.h: the process's memory cap, --memcap MIB.
 *
 * Everything a command can size before allocating it is estimated first
 * and refused above this cap with exit 2 and one line (what, how many
 * bytes, the cap and where it came from, how to raise it): a generated
 * scene's primitive store (scenes/spd.c, before generating), ray sets and
 * the answers traced for them, images, thread stacks (harness/workloads/resources.h).
 * A failed allocation behind an estimate is the checked allocator's exit 2
 * (prims/checked_alloc.h). The cap lives here, in the scenes library,
 * because the SPD generators are its lowest user; the harness sets it from
 * --memcap and reads it for its own estimates.
 *
 * The default is HALF of the memory this process may use: the smallest of
 * physical memory, the address-space limit (RLIMIT_AS, `ulimit -v`) less
 * what the process has mapped already (its libraries: about 100 MiB), the
 * data limit (RLIMIT_DATA, `ulimit -d`) less the data it holds, and its
 * cgroup's memory limit (cgroup v2 memory.max, or v1 memory.limit_in_bytes,
 * the smallest along the path to the root) less the group's usage. Why
 * half: each estimate is checked on its own, and nothing estimated lives
 * alone: a ray set lives beside the scene it is made for, that scene's
 * Embree BVH and the accelerator under test; a scene beside its BVH. Half
 * is the largest share one of them can take and still leave room for the
 * others (which the checked allocator still guards). The accelerators'
 * own caps (accel/common/memcap.h) are bounded by it as well: the harness
 * hands it to every build as accel_params.memcap_mib
 * (harness/workloads/resources.h resources_bound_accel_params).
 *
 * Not thread-safe to set; set it once when a command starts. */
#ifndef ACCELBENCH_MEMORY_CAP_H
#define ACCELBENCH_MEMORY_CAP_H

#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The default cap is MEMORY_CAP_SHARE_NUM / MEMORY_CAP_SHARE_DEN of what
 * the process may use (above). */
#define MEMORY_CAP_SHARE_NUM 1
#define MEMORY_CAP_SHARE_DEN 2
#define MEMORY_CAP_SHARE_WORD "half"
/* The largest --memcap, in MiB (2^30 MiB = 1 EiB: "no cap"). */
#define MEMORY_CAP_MIB_MAX (1ull << 30)

/* The largest image side any command makes: --res WxH and an NFF file's
 * resolution are refused above it where they are read. An image of
 * 16384^2 = 2^28 pixels keeps its pixel ids and, at up to 15 samples, its
 * primary rays within a ray set's 2^32 - 1; the memory cap decides
 * whether it fits. */
#define IMAGE_SIDE_MAX 16384

/* No limit. */
#define MEMORY_UNLIMITED UINT64_MAX

/* What bounds the process's memory, in bytes; MEMORY_UNLIMITED where there
 * is no bound, 0 for a usage that is not known. */
typedef struct {
    uint64_t physical;    /* installed memory (sysconf); MEMORY_UNLIMITED if unknown */
    uint64_t as_limit;    /* RLIMIT_AS, the soft limit */
    uint64_t as_used;     /* the process's virtual size now (/proc/self/statm) */
    uint64_t data_limit;  /* RLIMIT_DATA, the soft limit */
    uint64_t data_used;   /* its data and stack now (/proc/self/statm) */
    uint64_t cgroup_max;  /* the cgroup's memory limit */
    uint64_t cgroup_used; /* the cgroup's usage */
} memory_limits;

/* Read the limits of this process now. */
void memory_limits_read(memory_limits *l);
/* The default cap for l: MEMORY_CAP_SHARE of the smallest bound (at least
 * 1 MiB). why gets the reason in words for messages, e.g. "default: half of
 * the 2650 MiB left under the address-space limit (ulimit -v)". */
uint64_t memory_cap_default(const memory_limits *l, char *why, size_t whylen);
/* A cgroup limit or usage file's text: "max" (v2's none) gives
 * MEMORY_UNLIMITED, a decimal count of bytes gives itself (v1's "none",
 * about 2^63, also MEMORY_UNLIMITED: anything from 2^62 up). false when it
 * is neither. */
bool memory_cap_parse_bytes(const char *text, uint64_t *bytes);

/* Set the cap to mib MiB (--memcap), or with 0 to the default for the
 * limits read now. */
void memory_cap_set_mib(uint64_t mib);
/* The cap in bytes (the default, read on first use, when none was set). */
uint64_t memory_cap_bytes(void);
/* The cap in whole MiB. */
uint64_t memory_cap_mib(void);
/* Where it came from: "--memcap 512" or the default's reason. */
const char *memory_cap_source(void);

/* true when bytes exceed the cap: then err holds one line, "WHAT need N
 * bytes (N.N MiB), above the memory cap of C MiB (SOURCE); raise it with
 * --memcap MIB" (WHAT from the format). false: err untouched. */
bool memory_cap_exceeded(uint64_t bytes, char *err, size_t errlen, const char *what_fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* One line for work the cap stopped part-way, where the bytes it would
 * have needed are not known (a file read past the cap, a reader that ran
 * out of memory under it): "WHAT: stopped by the memory cap of C MiB
 * (SOURCE); raise it with --memcap MIB" (WHAT from the format). */
void memory_cap_stopped(char *err, size_t errlen, const char *what_fmt, ...) __attribute__((format(printf, 3, 4)));

/* The WHAT of a refusal: what_fmt formatted into err (cut to fit);
 * returns the length written, where the caller appends its reason. Every
 * refusal of a cap (this one and the accelerators' memcap,
 * accel/common/memcap.h) is WHAT and a reason on one line. */
size_t memory_refusal_what(char *err, size_t errlen, const char *what_fmt, va_list ap);

/* Saturating arithmetic for estimates: an absurd request stays absurd
 * instead of wrapping to a small number. */
static inline uint64_t memory_add(uint64_t a, uint64_t b) { return a > UINT64_MAX - b ? UINT64_MAX : a + b; }
static inline uint64_t memory_mul(uint64_t n, uint64_t size)
{
    return size && n > UINT64_MAX / size ? UINT64_MAX : n * size;
}

#ifdef __cplusplus
}
#endif

#endif

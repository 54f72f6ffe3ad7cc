/* shard_plan.h: the cells of one shard of a run --shard K/N (shard.h has
 * the enumeration, the cost model, the split and the manifest). */
#ifndef ACCELBENCH_SHARD_PLAN_H
#define ACCELBENCH_SHARD_PLAN_H

#include <stddef.h>
#include "machine.h"
#include "run_options.h"
#include "../workloads/rayset.h"

/* Every cell of the whole matrix in the run loop's order (shard.h), its
 * estimated cost (each scene loaded once for its primitives and lights,
 * then freed), the split of all of them into N shards, and this shard's
 * cells in *mine ([scene][workload][accel], 1 for this shard's). The
 * manifest goes to DIR/shard.txt; a folder whose shard.txt is of another
 * shard or matrix is refused. shard_line gets the line run.txt says.
 * Returns 0, or 1/2 after printing why. */
int plan_shard(const options *o, const rayset_t *replay, const char *out_dir, const machine_info *mi,
               unsigned char **mine, char *shard_line, size_t shard_line_len);

#endif

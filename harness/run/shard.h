/* shard.h: splitting a run's matrix into N shards (run --shard K/N) and the
 * manifest each shard folder holds (shard.txt), which merge reads.
 *
 * Enumeration: the cells of a matrix in the run loop's order, scene-major,
 * then workload, then accelerator instance (o->accels[i] with its
 * parameters: a parameter sweep's instances are cells of their own), the
 * (accelerator, workload) pairs the accelerator does not answer left out.
 * Cell i of that list is the same cell for every shard of a matrix.
 *
 * Cost: an estimate in abstract work units, made without building anything
 * (shard_cell_cost): P primitives (the scene loaded once, then freed), R
 * rays (workload_estimate's upper bound for the scene's lights, or a
 * replayed file's count), L = log2(P + 2), passes = repeat + 1 (the warm-up
 * and the timed samples):
 *
 *     build  = wb(accel) x P x L
 *     trace  = wt(accel) x R x L per pass (ACCEL_COST_TRACE_LINEAR: wt x R x P)
 *     embree = (1 + repeat) x R x L (the reference's answers and the paired samples)
 *     cost   = build (x passes under ACCEL_COST_BUILD_EACH_PASS) + passes x trace + embree
 *
 * with the weights (wt, wb) and shape of the accelerator's own table
 * (accel_ops.cost, accel.h: rough guesses from the committed runs;
 * ACCEL_COST_DEFAULT where a table leaves one 0).
 *
 * Assignment (shard_assign): greedy longest processing time: cells sorted
 * by cost, largest first, ties by enumeration index; each goes to the shard
 * of least load so far, ties to the lowest shard. A pure function of the
 * costs and N, so every shard computes the same split on its own; LPT's
 * bound: the largest load is at most 4/3 of the best split's, and at most
 * the mean load plus the largest single cost.
 *
 * Manifest (DIR/shard.txt), written by run --shard before the first cell
 * and checked again when a run resumes the folder:
 *
 *     accelbench shard manifest 1
 *     shard: K/N
 *     git_rev: REV          (the build that last wrote the manifest)
 *     options: WORD ...     (shard_options_line: what shapes the matrix, in a fixed order)
 *     command: ...          (as typed; not compared)
 *     cells: M
 *     cell: I S COST KEY    (every cell of the whole matrix: enumeration index, its shard 1..N, the estimate, the cell key)
 */
#ifndef ACCELBENCH_SHARD_H
#define ACCELBENCH_SHARD_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "run_options.h"

#define SHARD_MAX 4096
#define SHARD_MANIFEST "shard.txt"
#define SHARD_MANIFEST_MAGIC "accelbench shard manifest 1"

/* Parse "K/N" (1 <= K <= N <= SHARD_MAX). 0, or -1 with the reason in err. */
int shard_parse(const char *s, int *k, int *n, char *err, size_t errlen);

/* The estimated cost of one cell (see above). */
double shard_cell_cost(const struct accel_ops *ops, uint64_t prims, uint64_t rays, int repeat);

/* Assign ncells cells of the given costs to nshards shards (0-based in
 * shard_of). load, when not NULL, gets each shard's summed cost
 * (nshards entries). Returns 0, or -1 out of memory. */
int shard_assign(const double *cost, int ncells, int nshards, int *shard_of, double *load);

/* The options line of the manifest: every option that shapes the
 * matrix's cells or their checks, as NAME=VALUE words in a fixed order
 * (scenes, accels with their full parameters, workloads, res, spp,
 * corners, depth, seed, threads, repeat, rays, judge-seconds, memcap).
 * Two shards of one matrix have equal lines. */
void shard_options_line(const options *o, char *buf, size_t len);

/* One cell of a matrix, as the manifest lists it. */
typedef struct {
    int index, shard; /* shard 1..N */
    double cost;
    char *key;
} shard_cell;

typedef struct {
    int k, n;
    char git_rev[128];
    char *options;
    char *command;
    int ncells;
    shard_cell *cells;
} shard_manifest;

/* The manifest's text (malloc'd; NULL out of memory). */
char *shard_manifest_format(const shard_manifest *m);
/* Read DIR/shard.txt. 0; 1 when the file does not exist (err says so); -1
 * with the reason (file and line) in err. */
int shard_manifest_read(const char *dir, shard_manifest *m, char *err, size_t errlen);
void shard_manifest_free(shard_manifest *m);
/* Whether two manifests describe the same shard of the same matrix
 * (shard, options and cells; not git_rev or command). */
bool shard_manifest_same_matrix(const shard_manifest *a, const shard_manifest *b);

#endif

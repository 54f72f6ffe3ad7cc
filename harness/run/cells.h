/* cells.h: what run (matrix.h) and verify (cli/verify_cmd.h) share on the
 * way to a cell: a scene with its reference and verifier, each workload's
 * ray set with the reference's answers (made, loaded from --rays, or
 * saved with --save-rays), the (accelerator, workload) pairs that make
 * cells, and a cell's key. */
#ifndef ACCELBENCH_CELLS_H
#define ACCELBENCH_CELLS_H

#include <stdbool.h>
#include <stddef.h>
#include "run_options.h"
#include "../measure/measure.h"
#include "../workloads/workload.h"

/* --save-rays, checked before any work: the folder of several sets is
 * made, the folder of one set's file must exist. Returns 0 or 2 (printed). */
int save_rays_check(const options *o, int nsets);
/* Save one ray set (--save-rays). Returns 0, or -1 after printing why. */
int save_rays(const options *o, const rayset_t *rs, int nsets);

/* Make (or load, or take the preloaded) ray set of one workload and the
 * reference's answers. A loaded set's light indices are checked against
 * the scene it is replayed on. */
int cell_prepare(const options *o, const scene_t *s, accel *ref, verifier_t *ver, const workload_def *w,
                 rayset_t **preloaded, cell_rays *in);

/* Whether an accelerator answers rays of query q. */
bool accel_runs_workload(const struct accel_ops *ops, query_kind q);
/* The (accelerator, workload) pairs no cell is made of, said before any
 * work: one line per accelerator that skips some workload, naming them and
 * why (say_skips, once the command's other checks have passed). When the
 * pairs leave no cell at all, only one line saying why, and 2: a command
 * that measures nothing should not look like a success. replay is the --rays
 * file's set (its query decides), or NULL. Returns 0 or 2. */
int check_pairs(const options *o, const char *cmd, const rayset_t *replay, bool say_skips);

/* Load scene number si, build its reference and its verifier; errors go
 * to stderr and give NULL. */
scene_t *open_scene(const options *o, int si, accel **ref, verifier_t **ver);
void close_scene(scene_t *s, accel *ref, verifier_t *ver);

/* The key of cell (scene si, workload wi, accelerator ac): the options
 * form, or the ray-set form for a replayed file (cellkey.h). 0, or -1
 * after printing why. */
int run_cell_key(const options *o, int si, int wi, const accel_config *ac, const rayset_t *replay, char *buf,
                 size_t len);

#endif

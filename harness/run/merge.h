/* merge.h: `accelbench merge DIR... --out DIR`: the folders of a sharded
 * run (run --shard K/N, shard.h) into one matrix.csv, every cell checked
 * to be there exactly once (merge.c). */
#ifndef ACCELBENCH_MERGE_H
#define ACCELBENCH_MERGE_H

/* argv[0] is "merge". Returns the exit status: 0, 1 (a write failed) or 2. */
int merge_main(int argc, char **argv);

#endif

/* test_shard.c: the shard split (harness/run/shard.h):
 *  - on a matrix of 36 cells (3 scenes x 4 accelerators x 3 workloads, costs
 *    from shard_cell_cost over primitives and rays that differ by orders of
 *    magnitude), for N = 1..7: every cell in exactly one shard, the loads the
 *    sums of their cells' costs, the largest load within LPT's bound (mean
 *    plus the largest single cost), and the same split when asked again;
 *  - the rule by hand: largest first, to the least-loaded shard, ties by
 *    enumeration index and to the lowest shard; more shards than cells;
 *  - --shard's K/N parsing and its refusals;
 *  - the manifest (shard.txt) written, read back and compared. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "harness/run/shard.h"
#include "check.h"

static void check_split(const double *cost, int ncells, int n)
{
    int *of = malloc((size_t)ncells * sizeof *of), *of2 = malloc((size_t)ncells * sizeof *of2);
    double load[16] = {0}, load2[16], sum[16] = {0};
    int count[16] = {0};
    CHECK(shard_assign(cost, ncells, n, of, load) == 0);
    CHECK(shard_assign(cost, ncells, n, of2, load2) == 0);
    bool once = true, same = memcmp(of, of2, (size_t)ncells * sizeof *of) == 0;
    double total = 0, biggest = 0;
    for (int i = 0; i < ncells; i++) {
        once &= of[i] >= 0 && of[i] < n;
        if (of[i] < 0 || of[i] >= n) continue;
        count[of[i]]++;
        sum[of[i]] += cost[i];
        total += cost[i];
        if (cost[i] > biggest) biggest = cost[i];
    }
    int cells = 0;
    double largest = 0;
    bool sums = true;
    for (int k = 0; k < n; k++) {
        cells += count[k];
        sums &= fabs(sum[k] - load[k]) <= 1e-9 * total;
        if (load[k] > largest) largest = load[k];
    }
    CHECK_MSG(once && cells == ncells, "N=%d: %d of %d cells placed in 0..N-1", n, cells, ncells);
    CHECK_MSG(sums, "N=%d: the loads are not the sums of their cells' costs", n);
    CHECK_MSG(largest <= total / n + biggest, "N=%d: largest load %g > mean %g + largest cost %g", n, largest, total / n, biggest);
    CHECK_MSG(same, "N=%d: another split when asked again", n);
    if (n >= 2 && ncells >= n) CHECK_MSG(count[n - 1] > 0, "N=%d: the last shard is empty", n);
    free(of);
    free(of2);
}

int main(void)
{
    /* The matrix: scenes of 10, 10^4 and 10^6 primitives, four accelerators, three workloads. */
    const uint64_t prims[] = {10, 10000, 1000000};
    const char *accels[] = {"exhaustive", "embree", "bsp", "raycls"};
    const uint64_t rays[] = {256, 1024, 3 * 256};
    double cost[36];
    int nc = 0;
    for (int s = 0; s < 3; s++)
        for (int w = 0; w < 3; w++)
            for (int a = 0; a < 4; a++) cost[nc++] = shard_cell_cost(accel_find(accels[a]), prims[s], rays[w], 3);
    CHECK(nc == 36);
    double lo = cost[0], hi = cost[0];
    for (int i = 0; i < nc; i++) lo = fmin(lo, cost[i]), hi = fmax(hi, cost[i]);
    CHECK_MSG(hi > 1000 * lo, "the costs vary too little to test balance: %g..%g", lo, hi);
    for (int n = 1; n <= 7; n++) check_split(cost, nc, n);
    /* The same with the exhaustive cells (quadratic: one dominates) left out. */
    double rest[27];
    int nr = 0;
    for (int i = 0; i < nc; i++)
        if (i % 4) rest[nr++] = cost[i];
    for (int n = 1; n <= 7; n++) check_split(rest, nr, n);

    /* Cost: grows with primitives and rays; exhaustive is quadratic. */
    const struct accel_ops *bvh = accel_find("bvh");
    CHECK(shard_cell_cost(bvh, 1000, 100, 1) < shard_cell_cost(bvh, 100000, 100, 1));
    CHECK(shard_cell_cost(bvh, 1000, 100, 1) < shard_cell_cost(bvh, 1000, 10000, 1));
    CHECK(shard_cell_cost(accel_find("exhaustive"), 100000, 10000, 1) >
          100 * shard_cell_cost(accel_find("embree"), 100000, 10000, 1));
    CHECK(shard_cell_cost(bvh, 1000, 100, 1) < shard_cell_cost(bvh, 1000, 100, 5));
    /* The weights and shape come from the table; a table that states none
     * is planned at ACCEL_COST_DEFAULT for both, and a lazy build counts
     * once per pass. */
    const struct accel_ops unstated = {.name = "unstated"}, twice = {.name = "twice", .cost = {2, 2, 0}},
                           lazy = {.name = "lazy", .cost = {2, 2, ACCEL_COST_BUILD_EACH_PASS}};
    CHECK(shard_cell_cost(&unstated, 5000, 300, 2) == shard_cell_cost(&twice, 5000, 300, 2));
    CHECK(shard_cell_cost(&lazy, 5000, 300, 2) > shard_cell_cost(&twice, 5000, 300, 2));
    double L = log2(5000 + 2.0);
    CHECK(fabs(shard_cell_cost(&unstated, 5000, 300, 2) - (2 * 5000 * L + 3 * 2 * 300 * L + 3 * 300 * L)) < 1e-6);
    for (int i = 0; accel_registry[i]; i++)
        CHECK_MSG(accel_registry[i]->cost.trace > 0 && accel_registry[i]->cost.build > 0,
                  "%s: the registered accelerators state their cost weights", accel_registry[i]->name);

    /* The rule by hand: 5 4 3 3 3 on two shards: 5->0, 4->1, 3->1 (7), 3->0 (8), 3->1 (10). */
    {
        double c[] = {5, 4, 3, 3, 3}, load[2];
        int of[5];
        CHECK(shard_assign(c, 5, 2, of, load) == 0);
        CHECK(of[0] == 0 && of[1] == 1 && of[2] == 1 && of[3] == 0 && of[4] == 1);
        CHECK(load[0] == 8 && load[1] == 10);
    }
    /* Ties: equal costs go round the shards in enumeration order. */
    {
        double c[8] = {1, 1, 1, 1, 1, 1, 1, 1};
        int of[8];
        CHECK(shard_assign(c, 8, 4, of, NULL) == 0);
        bool round = true;
        for (int i = 0; i < 8; i++) round &= of[i] == i % 4;
        CHECK(round);
    }
    /* More shards than cells: one cell each, the rest empty. */
    {
        double c[3] = {2, 9, 4};
        int of[3];
        double load[7];
        CHECK(shard_assign(c, 3, 7, of, load) == 0);
        CHECK(of[1] == 0 && of[2] == 1 && of[0] == 2);
        CHECK(load[3] == 0 && load[6] == 0);
        CHECK(shard_assign(c, 0, 3, of, load) == 0 && load[0] == 0);
    }

    /* K/N. */
    int k, n;
    char err[256];
    CHECK(shard_parse("1/1", &k, &n, err, sizeof err) == 0 && k == 1 && n == 1);
    CHECK(shard_parse("3/4", &k, &n, err, sizeof err) == 0 && k == 3 && n == 4);
    CHECK(shard_parse("4096/4096", &k, &n, err, sizeof err) == 0 && k == 4096);
    const char *badk[] = {"0/3", "3/2", "1/4097", "1/0", "a/b", "1/2x", "-1/2", "+1/2", "1/ 2", "1", "/2", "1/", ""};
    for (size_t i = 0; i < sizeof badk / sizeof badk[0]; i++) {
        int rc = shard_parse(badk[i], &k, &n, err, sizeof err);
        CHECK_MSG(rc == -1 && strstr(err, "expected K/N"), "'%s' accepted", badk[i]);
    }

    /* The manifest: written, read back, compared. */
    char dir[] = "/tmp/accelbench-shard.XXXXXX";
    CHECK(mkdtemp(dir) != NULL);
    shard_cell cells[3] = {{0, 2, 10.5, "scene=a accel=x"}, {1, 1, 99, "scene=a accel=y"}, {2, 2, 1, "scene=b accel=x"}};
    shard_manifest m = {.k = 2, .n = 2, .options = "scenes=a,b accels=x[],y[]", .command = "run --shard 2/2",
                        .ncells = 3, .cells = cells};
    snprintf(m.git_rev, sizeof m.git_rev, "abc1234");
    char *text = shard_manifest_format(&m), path[300];
    CHECK(text && strstr(text, "shard: 2/2\n") && strstr(text, "cell: 1 1 99 scene=a accel=y\n"));
    snprintf(path, sizeof path, "%s/%s", dir, SHARD_MANIFEST);
    FILE *f = fopen(path, "w");
    fputs(text, f);
    fclose(f);
    shard_manifest r;
    CHECK(shard_manifest_read(dir, &r, err, sizeof err) == 0);
    CHECK(r.k == 2 && r.n == 2 && r.ncells == 3 && !strcmp(r.git_rev, "abc1234") && !strcmp(r.cells[2].key, "scene=b accel=x"));
    CHECK(shard_manifest_same_matrix(&m, &r));
    r.cells[0].shard = 1;
    CHECK(!shard_manifest_same_matrix(&m, &r));
    shard_manifest_free(&r);
    /* Cut short, and absent. */
    f = fopen(path, "w");
    fwrite(text, 1, strlen(text) - 20, f);
    fclose(f);
    CHECK(shard_manifest_read(dir, &r, err, sizeof err) == -1);
    unlink(path);
    CHECK(shard_manifest_read(dir, &r, err, sizeof err) == 1 && strstr(err, "shard.txt"));
    rmdir(dir);
    free(text);
    return check_report();
}

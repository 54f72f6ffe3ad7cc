/* test_example_accel: the worked example of docs/contributing.md
 * (docs/examples/boxlist.c), registered by one line beside the real
 * accelerators (tests/meson.build), measured the way `run` measures a cell:
 *
 *   - the registry finds it and `boxlist` is in it after the others;
 *   - measure_cell on every workload of spd:balls:2 gives no real
 *     mismatch against Embree, one box test per primitive per closest-hit
 *     ray (at most that per any-hit ray), fewer primitive tests than box
 *     tests, and its own statistic;
 *   - the CSV has a column for that statistic (after the shared ones) and
 *     the cell's row fills it, while boxes=off leaves box_tests at 0;
 *   - shard planning gives it the stated default weights, as its table
 *     states none.
 * (The conformance suite runs over it as test_accels boxlist.) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "harness/measure/measure.h"
#include "harness/run/cell_row.h"
#include "harness/run/csv.h"
#include "harness/run/shard.h"
#include "testlib.h"

/* The value of column `name` in the row's CSV record, or NAN when empty. */
static double row_value(const csv_row *row, const char *name)
{
    char *text = NULL;
    size_t len = 0;
    if (csv_format_row(row, &text, &len)) return NAN;
    csv_span spans[512];
    int nfields = 0;
    bool complete = false;
    csv_split_record(text, len, &nfields, &complete, spans, 512);
    int col = csv_column_index(name);
    char buf[64] = "";
    if (col >= 0 && col < nfields && col < 512) csv_field(text, spans[col], buf, sizeof buf);
    free(text);
    return *buf ? strtod(buf, NULL) : NAN;
}

/* One cell of ac on workload w of s: the measurement, and its row's
 * stat_box_hit_chance (read before the cell's rays go: the row points into
 * them). */
static void measure(const scene_t *s, accel *ref, verifier_t *ver, int w, const accel_config *ac,
                    cell_measurement *m, double *chance, uint32_t *nrays)
{
    workload_opts o = test_wl(24, 24, 2);
    rayset_t *rs = workload_table[w].make(s, ref, &o);
    *nrays = rs->count;
    cell_rays c;
    cell_rays_init(&c, s, ref, ver, rs, 2);
    machine_info mi = {0};
    row_settings st = {.cell = {.threads = 2, .repeat = 1}, .mi = &mi};
    CHECK_MSG(measure_cell(&c, ac, &st.cell, m) == 0, "%s on %s: measure_cell failed", ac->label, workload_table[w].name);
    csv_row row;
    CHECK(cell_row(&c, ac, &st, m, &row) == 0);
    *chance = row_value(&row, "stat_box_hit_chance");
    cell_rays_release(&c);
}

static accel_config config(const char *settings)
{
    accel_config ac = {.ops = accel_find("boxlist")};
    params_defaults(&ac.params, ac.ops->params);
    char err[256];
    CHECK_MSG(params_set_list(&ac.params, settings, err, sizeof err) == 0, "%s", err);
    params_format(&ac.params, ac.params_str, sizeof ac.params_str);
    snprintf(ac.label, sizeof ac.label, "boxlist%s%s%s", *settings ? "[" : "", settings, *settings ? "]" : "");
    return ac;
}

int main(void)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    const struct accel_ops *ops = accel_find("boxlist");
    CHECK_MSG(ops != NULL, "boxlist is not registered in this program");
    if (!ops) return check_report();
    int n = 0;
    while (accel_registry[n]) n++;
    CHECK_MSG(n > 1 && accel_registry[n - 1] == ops && accel_find("embree"), "the registry is the list plus one line");

    /* Its own statistic has a CSV column, after the shared ones. */
    char h[CSV_HEADER_MAX];
    csv_header(h, sizeof h);
    CHECK(strstr(h, ",stat_box_hit_chance,") != NULL);
    CHECK(csv_column_index("stat_box_hit_chance") > csv_column_index("stat_avg_children"));

    scene_t *s = test_scene("spd:balls:2");
    accel *ref = test_build(ACCEL_REFERENCE, s, 2);
    verifier_t *ver = verifier_new(s, 0);
    accel_config on = config(""), off = config("boxes=off");
    for (int w = 0; workload_table[w].name; w++) {
        cell_measurement m;
        double chance;
        uint32_t nrays;
        measure(s, ref, ver, w, &on, &m, &chance, &nrays);
        if (m.no_rays) continue;
        uint64_t real = m.vr.mismatches[MM_REAL];
        CHECK_MSG(real == 0, "boxlist on %s: %llu real mismatches", workload_table[w].name, (unsigned long long)real);
        /* A closest-hit ray tests every box; an any-hit ray stops at its first hit. */
        uint64_t all = (uint64_t)nrays * s->prims.count;
        bool closest = workload_table[w].query == QUERY_CLOSEST;
        CHECK_MSG(closest ? m.counters.box_tests == all : m.counters.box_tests <= all && m.counters.box_tests > 0,
                  "boxlist on %s: %llu box tests for %u rays over %u primitives", workload_table[w].name,
                  (unsigned long long)m.counters.box_tests, nrays, s->prims.count);
        CHECK_MSG(m.counters.prim_tests < m.counters.box_tests, "boxlist on %s: the boxes culled nothing",
                  workload_table[w].name);
        CHECK_MSG(chance > 0 && chance < 1, "boxlist on %s: stat_box_hit_chance = %g", workload_table[w].name, chance);
        CHECK(!strcmp(m.timed_path, "fast"));

        measure(s, ref, ver, w, &off, &m, &chance, &nrays);
        CHECK(m.vr.mismatches[MM_REAL] == 0 && m.counters.box_tests == 0);
        printf("boxlist on %-10s %6u rays: no real mismatch, boxes=on and off\n", workload_table[w].name, nrays);
    }

    /* No cost in its table: planned at the stated default, as a table
     * saying {2, 2} would be. */
    struct accel_ops stated = *ops;
    stated.cost = (accel_cost){ACCEL_COST_DEFAULT, ACCEL_COST_DEFAULT, 0};
    CHECK(ops->cost.trace == 0 && shard_cell_cost(ops, 1000, 500, 3) == shard_cell_cost(&stated, 1000, 500, 3));

    verifier_free(ver);
    ref->ops->destroy(ref);
    scene_free(s);
    return check_report();
}

/* line_model.c: the random-line cost model of the spatial subdivisions
 * (line_model.h says the argument). */
#include <stdlib.h>
#include "line_model.h"

/* In double: a cell may be a millionth of the root's area. */
static double area(box3 b)
{
    if (box_is_empty(b)) return 0.0;
    double x = (double)b.hi.x - b.lo.x, y = (double)b.hi.y - b.lo.y, z = (double)b.hi.z - b.lo.z;
    return 2.0 * (x * y + y * z + z * x);
}

int line_model_init(line_model *m, box3 root, uint32_t nprims, bool mailbox)
{
    *m = (line_model){.root_area = area(root), .mailbox = mailbox, .nprims = nprims};
    if (!mailbox || !nprims) return 0;
    m->hull = malloc((size_t)nprims * sizeof *m->hull);
    m->share = calloc(nprims, sizeof *m->share);
    if (!m->hull || !m->share) {
        line_model_free(m);
        return -1;
    }
    for (uint32_t i = 0; i < nprims; i++) m->hull[i] = box_empty();
    return 0;
}

double line_model_prob(const line_model *m, box3 b)
{
    if (!(m->root_area > 0.0)) return 1.0;
    double p = area(b) / m->root_area;
    return p < 1.0 ? p : 1.0;
}

void line_model_cell(line_model *m, box3 cell, int depth, const uint32_t *ids, uint32_t count)
{
    const double p = line_model_prob(m, cell);
    m->cells += p;
    m->deep_cells += p * (depth + 1);
    m->entries += p * count;
    if (!m->hull) return;
    for (uint32_t k = 0; k < count; k++) {
        m->hull[ids[k]] = box_union(m->hull[ids[k]], cell);
        m->share[ids[k]] += p;
    }
}

line_prediction line_model_result(const line_model *m)
{
    line_prediction r = {.cells = m->cells, .entries = m->entries, .tests = m->entries, .descents = m->deep_cells};
    if (m->hull) {
        double tests = 0.0;
        for (uint32_t i = 0; i < m->nprims; i++) {
            if (m->share[i] == 0.0) continue; /* in no cell (or only cells of zero area) */
            double hull = line_model_prob(m, m->hull[i]);
            tests += hull < m->share[i] ? hull : m->share[i];
        }
        r.tests = tests;
    }
    r.mailbox_hits = r.entries - r.tests;
    return r;
}

void line_model_free(line_model *m)
{
    free(m->hull);
    free(m->share);
    m->hull = NULL;
    m->share = NULL;
}

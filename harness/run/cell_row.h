/* cell_row.h: a measured cell as a CSV row (csv.h): the cell's identity,
 * its ray set's image, the machine, this process's run id and the cell's
 * key (cellkey.h), then what measure_cell measured. run and reproduce
 * write their rows through it. */
#ifndef ACCELBENCH_CELL_ROW_H
#define ACCELBENCH_CELL_ROW_H

#include "csv.h"
#include "machine.h"
#include "../measure/measure.h"

/* What every row of a run shares. */
typedef struct {
    cell_settings cell;     /* how each cell is measured */
    int width, height, spp; /* the CSV's res and spp where the ray set has no image of its own (random), 0 = none */
    const machine_info *mi;
} row_settings;

typedef struct {
    csv_row row;         /* complete; scene, accel, params and workload point into the cell's scene, config and rays;
                            its cell_key is the ray-set form (rays=HASH, cellkey.h), which run replaces by the
                            options form when it made the rays itself */
    verify_result vr;
} cell_result;

/* The row of cell (c, ac) that measured m. Returns 0, or -1 when the cell
 * key does not fit (reported on stderr). */
int cell_row(const cell_rays *c, const accel_config *ac, const row_settings *st, const cell_measurement *m, csv_row *r);

/* measure_cell, then its row (a set of no rays: rays 0 with the measured
 * columns empty, csv.h no_rays). Returns 0, -1 when the build failed or
 * -2 when the cell key does not fit (each reported on stderr). */
int measure_cell_row(const cell_rays *c, const accel_config *ac, const row_settings *st, cell_result *out);

/* A row's statistics as "name value, name value" ("" when there are none). */
void stats_format(const csv_row *row, char *buf, size_t len);

#endif

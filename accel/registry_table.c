/* registry_table.c: accel_registry[], the accelerators a program knows, in
 * the order `accelbench list accels` shows them. ACCEL_TABLES is the list
 * X(accel_exhaustive) X(accel_embree) ... that accel/meson.build makes from
 * its `accelerators` list. This file is alone so that a program can link
 * another table in its place (an object given to the linker is used before
 * the accel library's member): tests/meson.build registers the worked
 * example of docs/contributing.md that way. */
#include "accel.h"

#ifndef ACCEL_TABLES
#error "ACCEL_TABLES comes from accel/meson.build's accelerators list"
#endif

#define X(table) extern const struct accel_ops table;
ACCEL_TABLES
#undef X

const struct accel_ops *const accel_registry[] = {
#define X(table) &table,
    ACCEL_TABLES
#undef X
    NULL,
};

/* registry.c: the static table of accelerators, found by name.
 * Adding an accelerator: write accel/NAME.c exporting `const struct
 * accel_ops accel_NAME`, declare it here and list it in the table. */
#include <string.h>
#include "accel.h"

extern const struct accel_ops accel_exhaustive;
extern const struct accel_ops accel_embree;
extern const struct accel_ops accel_grid;
extern const struct accel_ops accel_grid_raybox;
extern const struct accel_ops accel_cgal_aabb;

const struct accel_ops *const accel_registry[] = {
    &accel_exhaustive,
    &accel_embree,
    &accel_grid,
    &accel_grid_raybox,
    &accel_cgal_aabb,
    NULL,
};

const struct accel_ops *accel_find(const char *name)
{
    for (int i = 0; accel_registry[i]; i++)
        if (strcmp(accel_registry[i]->name, name) == 0) return accel_registry[i];
    return NULL;
}

/* spd_sombrero.c: the "sombrero" height field of the SPD 3.14
 * (src/sombrero.c, by Alexander Enzmann), written from the rules in
 * shared/SPD-SCENES.md, not from the original code.
 *
 * w = 32 * 2^(SIZE-1) samples a side of h = cos(2 pi rho) e^(-rho),
 * rho = sqrt(x^2 + y^2), at x, y = -4 + j*8/w (row i is y, column j is x);
 * the grid vertex (i, j) is (-4 + j*8/(w-1), -3 + h[i][j], -4 + i*8/(w-1))
 * (y is height). Each cell (i, j), i outer, gives the triangles
 * (i,j), (i+1,j+1), (i,j+1) and (i,j), (i+1,j), (i+1,j+1):
 * 2 (w-1)^2 triangles (1,922 at 1; 7,938; 32,258; 130,050 at 4).
 * View: from (0, 5, -8) at 0, up +Z, 40 degrees, hither 0.01; light
 * (10, 10, -10). Material f 1 0.1 0.1 0.8 0 (shiny red). */
#include "spd.h"
#include "../prims/checked_alloc.h"

#include <stdlib.h>

static uint64_t width(int size) { return 32ull << (size - 1); }

void spd_census_sombrero(int size, spd_census *n)
{
    uint64_t w = width(size), tris = 2 * (w - 1) * (w - 1);
    *n = (spd_census){.polygons = tris, .polygon_tris = tris, .polygon_verts = 3 * tris};
}

void spd_gen_sombrero(spd_ctx *c, int size)
{
    spd_background(c, SPD_SKY_BLUE);
    spd_view(c, spd_v(0, 5, -8), spd_v(0, 0, 0), spd_v(0, 0, 1), 40.0, 0.01, 512, 512);
    spd_light(c, spd_v(10, 10, -10));
    spd_material(c, 1.0, 0.1, 0.1, 0.8, 0.0, spd_shine(40.0), 0.0, 1.0);

    const int w = (int)width(size);
    spd_vec *g = checked_calloc((size_t)w * w, sizeof *g, "the SPD sombrero's height grid");
    for (int i = 0; i < w; i++)
        for (int j = 0; j < w; j++) {
            double x = -4.0 + j * 8.0 / w, y = -4.0 + i * 8.0 / w, rho = sqrt(x * x + y * y);
            double h = cos(2.0 * M_PI * rho) * exp(-rho);
            g[i * w + j] = spd_v(-4.0 + j * 8.0 / (w - 1), -3.0 + h, -4.0 + i * 8.0 / (w - 1));
        }
    for (int i = 0; i + 1 < w; i++)
        for (int j = 0; j + 1 < w; j++) {
            spd_vec a[3] = {g[i * w + j], g[(i + 1) * w + j + 1], g[i * w + j + 1]};
            spd_vec b[3] = {g[i * w + j], g[(i + 1) * w + j], g[(i + 1) * w + j + 1]};
            spd_polygon(c, a, 3);
            spd_polygon(c, b, 3);
        }
    free(g);
}

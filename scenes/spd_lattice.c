/* spd_lattice.c: the "lattice" scene of the SPD 3.14 (src/lattice.c, by
 * Antonio Costa), written from the rules in shared/SPD-SCENES.md, not from
 * the original code.
 *
 * Shiny spheres on a cubic lattice joined by matte cylinders:
 * (SIZE+1)^3 spheres + 3 SIZE (SIZE+1)^2 cylinders (8,281 at 12).
 * - Lattice points p = (x, y, z)/SIZE for integers 0..SIZE, x outer, then
 *   y, z inner. Per point: the sphere, radius 0.25/SIZE; then, for each of
 *   x, y, z whose index is below SIZE, the cylinder from p + delta axis to
 *   p + (1/SIZE - delta) axis, radius (1/16)/SIZE, with
 *   delta = 0.99 (0.25/SIZE)(1 - sqrt(0.25)) (ends inside the spheres).
 * View: from (((SIZE>>1) + 0.5)/SIZE, 1, 1 - 1/(2 SIZE)) at
 * (((SIZE>>1) + 0.5)/SIZE, -1, -1 - 1/(2 SIZE)), up (0.2, 1, 0), 60
 * degrees, hither 0; six lights at (2,.5,.5), (-1,.5,.5), (.5,2,.5),
 * (.5,-1,.5), (.5,.5,2), (.5,.5,-1). Materials: spheres f 0.9 0.9 0.9 0.5 0.5;
 * cylinders along x, y, z red, green, blue (0.9/0.1) with kd 0.99, ks 0. */
#include "spd.h"

void spd_census_lattice(int size, spd_census *n)
{
    uint64_t k = (uint64_t)size;
    *n = (spd_census){.spheres = (k + 1) * (k + 1) * (k + 1), .cones = 3 * k * (k + 1) * (k + 1)};
}

void spd_gen_lattice(spd_ctx *c, int size)
{
    const double inv = 1.0 / size, r1 = 0.25 / size, r2 = (1.0 / 16.0) / size;
    const double delta = 0.99 * r1 * (1.0 - sqrt(0.25));
    double vx = ((size >> 1) + 0.5) * inv;
    spd_background(c, SPD_SKY_BLUE);
    spd_view(c, spd_v(vx, 1.0, 1.0 - 1.0 / (2.0 * size)), spd_v(vx, -1.0, -1.0 - 1.0 / (2.0 * size)), spd_v(0.2, 1, 0),
             60.0, 0.0, 512, 512);
    static const double lights[6][3] = {{2, .5, .5}, {-1, .5, .5}, {.5, 2, .5}, {.5, -1, .5}, {.5, .5, 2}, {.5, .5, -1}};
    for (int i = 0; i < 6; i++) spd_light(c, spd_v(lights[i][0], lights[i][1], lights[i][2]));

    for (int x = 0; x <= size; x++)
        for (int y = 0; y <= size; y++)
            for (int z = 0; z <= size; z++) {
                spd_vec p = spd_v(x * inv, y * inv, z * inv);
                spd_material(c, 0.9, 0.9, 0.9, 0.5, 0.5, spd_shine(37.0), 0.0, 0.0);
                spd_sphere(c, p, r1);
                const int idx[3] = {x, y, z};
                for (int a = 0; a < 3; a++) {
                    if (idx[a] == size) continue;
                    spd_vec axis = spd_v(a == 0, a == 1, a == 2);
                    spd_material(c, a == 0 ? 0.9 : 0.1, a == 1 ? 0.9 : 0.1, a == 2 ? 0.9 : 0.1, 0.99, 0.0, spd_shine(0.0),
                                 0.0, 0.0);
                    spd_cone(c, spd_add(p, spd_scale(axis, delta)), r2, spd_add(p, spd_scale(axis, inv - delta)), r2);
                }
            }
}

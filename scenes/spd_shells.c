/* spd_shells.c: the "shells" scene of the SPD 3.14 (src/shells.c), after
 * Pickover (IEEE CG&A, November 1989), written from the rules in
 * shared/SPD-SCENES.md, not from the original code.
 *
 * A sea shell of many tiny, heavily overlapping spheres ("brings ray
 * tracers to their knees"): steps = 180 * 2^SIZE, and for the integers
 * i = -floor(2 steps/3) .. floor(steps/3), theta = 18 pi i/steps,
 * r = e^(0.15 theta), the sphere at (r sin theta, r cos theta, -2r) with
 * radius r (Pickover's defaults gamma 1, alpha 0, beta -2, a 0.15, k 1).
 * 180 * 2^SIZE + 1 spheres (5,761 at 5; the original's header says 5,760
 * plus a square, but writes no square).
 * View: from (-6, -60, 35) at (0, 8, -15), 45 degrees, hither 0.5; light
 * (-100, -100, 100). Material f 1 0.8 0.4 0.8 0.2. */
#include "spd.h"

void spd_census_shells(int size, spd_census *n)
{
    *n = (spd_census){.spheres = (180ull << size) + 1};
}

void spd_gen_shells(spd_ctx *c, int size)
{
    spd_background(c, SPD_SKY_BLUE);
    spd_view(c, spd_v(-6, -60, 35), spd_v(0, 8, -15), spd_v(0, 0, 1), 45.0, 0.5, 512, 512);
    spd_light(c, spd_v(-100, -100, 100));
    spd_material(c, 1.0, 0.8, 0.4, 0.8, 0.2, spd_shine(10.0), 0.0, 1.0);
    long steps = 180L << size;
    for (long i = -(2 * steps / 3); i <= steps / 3; i++) {
        double theta = 18.0 * M_PI * (double)i / (double)steps, r = exp(0.15 * theta);
        spd_sphere(c, spd_v(r * sin(theta), r * cos(theta), -2.0 * r), r);
    }
}

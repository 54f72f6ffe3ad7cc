/* spd_jacks.c: the "jacks" scene of the SPD 3.14 (src/jacks.c, by
 * Alexander Enzmann), written from the rules in shared/SPD-SCENES.md, not
 * from the original code.
 *
 * Recursive jacks, like a Menger sponge: sum_{k<SIZE} 8^k jacks of 9
 * primitives (9 at the default 1; 81, 657, 5,265, ... at 2, 3, 4).
 * - A jack in its frame, all scaled by 0.75: 3 cylinders of radius 0.1
 *   along x, y, z from -1 to +1, then 6 spheres of radius 0.2 at +x, +y,
 *   +z, -x, -y, -z (unit distance).
 * - Recursion: a jack, then (SIZE permitting) 8 children, i, j, k in
 *   {-0.5, +0.5} nested in that order, in the frame
 *   parent o translate(i, j, k) o scale(0.5). Radii scale with the frame.
 * - Root frame Rx(-30 deg) o Ry(-20 deg).
 * Tessellated, the resolution is always 2 (the original sets it after
 * reading -t), so jacks 4 at -t 3 is 585 * (6*48 + 3*16) = 196,560.
 * View: from (0, 0, -8) at 0, up (0, 1, 0), 25 degrees, hither 0.001,
 * 256 x 256; background (0.2, 0.05, 0.2); light (-10, 3, -20). Material
 * f 0.737 0.561 0.561 0.7 0.7 (pink). */
#include "spd.h"

typedef struct { spd_mat M; spd_vec t; double s; } frame; /* p -> M p + t, M = rotation * s */

static spd_vec at(const frame *f, double x, double y, double z)
{
    return spd_add(spd_mat_apply(&f->M, spd_v(x, y, z)), f->t);
}

static void jack(spd_ctx *c, const frame *f, int depth, int max_depth)
{
    const double k = 0.75; /* the jack's own scale */
    const double r_cyl = 0.1 * k * f->s, r_sph = 0.2 * k * f->s;
    for (int a = 0; a < 3; a++)
        spd_cone(c, at(f, -k * (a == 0), -k * (a == 1), -k * (a == 2)), r_cyl, at(f, k * (a == 0), k * (a == 1), k * (a == 2)),
                 r_cyl);
    for (int sgn = 1; sgn >= -1; sgn -= 2)
        for (int a = 0; a < 3; a++) spd_sphere(c, at(f, sgn * k * (a == 0), sgn * k * (a == 1), sgn * k * (a == 2)), r_sph);
    if (depth >= max_depth) return;
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++)
            for (int l = 0; l < 2; l++) {
                frame child;
                child.t = at(f, i - 0.5, j - 0.5, l - 0.5);
                spd_mat half = spd_mat_scaling(0.5);
                child.M = spd_mat_mul(&f->M, &half);
                child.s = f->s * 0.5;
                jack(c, &child, depth + 1, max_depth);
            }
}

void spd_census_jacks(int size, spd_census *n)
{
    uint64_t jacks = 0, p = 1;
    for (int k = 0; k < size; k++, p *= 8) jacks += p;
    *n = (spd_census){.spheres = 6 * jacks, .cones = 3 * jacks};
}

void spd_gen_jacks(spd_ctx *c, int size)
{
    spd_background(c, 0.2, 0.05, 0.2);
    spd_view(c, spd_v(0, 0, -8), spd_v(0, 0, 0), spd_v(0, 1, 0), 25.0, 0.001, 256, 256);
    spd_light(c, spd_v(-10, 3, -20));
    spd_material(c, 0.737, 0.561, 0.561, 0.7, 0.7, spd_shine(20.0), 0.0, 1.0);
    spd_mat rx = spd_mat_rotation(spd_v(1, 0, 0), -30.0 * M_PI / 180.0);
    spd_mat ry = spd_mat_rotation(spd_v(0, 1, 0), -20.0 * M_PI / 180.0);
    frame root = {spd_mat_mul(&rx, &ry), spd_v(0, 0, 0), 1.0};
    jack(c, &root, 1, size);
}

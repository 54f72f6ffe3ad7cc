/* spd_balls.c: the "balls" (sphereflake) scene of Eric Haines' Standard
 * Procedural Databases (SPD 3.14, src/balls.c), written from the rules in
 * shared/SPD-SCENES.md, not from the original code.
 *
 * A sphere of radius r carries 9 spheres of radius r/3 touching it, 3 on
 * an upper cone and 6 around its equator, recursively, to SIZE levels:
 * sum_{k=0..SIZE} 9^k spheres, over a square floor. Order, as in the SPD:
 * the floor quad first (one polygon), then the spheres depth-first (a
 * sphere, then each of its children's whole subtrees in list order). Size 4
 * gives the SPD's 7,381 spheres + 1 quad = 7,382 primitives.
 *
 * Children: the trio (1,1,0)/sqrt2, (1,0,-1)/sqrt2, (0,1,-1)/sqrt2 turned
 * about normalize(1,-1,0) by asin(2/sqrt6), then copied at 0, 120 and 240
 * degrees about +Z. A child of the sphere (C, r, direction d) is at
 * C + M u_i (r + r/3), radius r/3, direction M u_i, where M takes +Z to d
 * (identity for d.z >= 0.9999, half turn about +Y for d.z <= -0.9999, else
 * the rotation about Z x d by acos(d.z)).
 *
 * View: from (2.1, 1.3, 1.7) at 0, 45 degrees, hither 0.01; lights (4,3,2),
 * (1,-4,4), (-3,1,5). Floor f 1 0.75 0.33 0.8 0; spheres f 1 0.9 0.7 0.5 0.5
 * (mirrors). */
#include "spd.h"

/* The rotation taking +Z to the unit vector d, by the SPD's rule. */
static spd_mat rotation_z_to(spd_vec d)
{
    if (d.z >= 0.9999) return spd_mat_scaling(1.0);
    if (d.z <= -0.9999) return spd_mat_rotation(spd_v(0, 1, 0), M_PI);
    spd_vec axis = spd_norm(spd_v(-d.y, d.x, 0.0)); /* Z x d */
    return spd_mat_rotation(axis, acos(d.z));
}

/* The 9 child directions of a sphere whose direction is +Z. */
static void child_directions(spd_vec u[9])
{
    const double s2 = sqrt(0.5);
    spd_vec trio[3] = {spd_v(s2, s2, 0), spd_v(s2, 0, -s2), spd_v(0, s2, -s2)};
    spd_mat tilt = spd_mat_rotation(spd_norm(spd_v(1, -1, 0)), asin(2.0 / sqrt(6.0)));
    for (int k = 0; k < 3; k++) {
        spd_mat turn = spd_mat_rotation(spd_v(0, 0, 1), k * 2.0 * M_PI / 3.0);
        for (int i = 0; i < 3; i++) {
            spd_vec t = spd_mat_apply(&tilt, trio[i]);
            u[3 * k + i] = spd_mat_apply(&turn, t);
        }
    }
}

/* Emit a sphere, then, depth levels deep, its children. */
static void grow_flake(spd_ctx *c, const spd_vec u[9], spd_vec centre, double r, spd_vec dir, int depth)
{
    spd_sphere(c, centre, r);
    if (depth == 0) return;
    spd_mat M = rotation_z_to(dir);
    double rc = r / 3.0;
    for (int i = 0; i < 9; i++) {
        spd_vec d = spd_mat_apply(&M, u[i]);
        grow_flake(c, u, spd_add(centre, spd_scale(d, r + rc)), rc, d, depth - 1);
    }
}

uint64_t spd_balls_sphere_count(int size)
{
    uint64_t n = 0, p = 1;
    for (int k = 0; k <= size; k++, p *= 9) n += p;
    return n;
}

void spd_census_balls(int size, spd_census *n)
{
    *n = (spd_census){.spheres = spd_balls_sphere_count(size), .polygons = 1, .polygon_tris = 2, .polygon_verts = 4};
}

void spd_gen_balls(spd_ctx *c, int size)
{
    spd_background(c, SPD_SKY_BLUE);
    spd_view(c, spd_v(2.1, 1.3, 1.7), spd_v(0, 0, 0), spd_v(0, 0, 1), 45.0, 0.01, 512, 512);
    spd_light(c, spd_v(4, 3, 2));
    spd_light(c, spd_v(1, -4, 4));
    spd_light(c, spd_v(-3, 1, 5));

    spd_material(c, 1.0, 0.75, 0.33, 0.8, 0.0, spd_shine(0.0), 0.0, 1.0);
    const spd_vec floor[4] = {spd_v(12, 12, -0.5), spd_v(-12, 12, -0.5), spd_v(-12, -12, -0.5), spd_v(12, -12, -0.5)};
    spd_polygon(c, floor, 4);

    spd_material(c, 1.0, 0.9, 0.7, 0.5, 0.5, spd_shine(37.0), 0.0, 1.0);
    spd_vec u[9];
    child_directions(u);
    grow_flake(c, u, spd_v(0, 0, 0), 0.5, spd_v(0, 0, 1), size);
}

scene_t *scene_spd_balls(const char *name, int size, int tess_res, char *err, size_t errlen)
{
    return scene_spd(name, "balls", size, tess_res, err, errlen);
}

/* spd_rings.c: the "rings" scene of the SPD 3.14 (src/rings.c), written
 * from the rules in shared/SPD-SCENES.md, not from the original code.
 *
 * A pyramid of sum_{d=1..SIZE} d^2 objects, each 6 pentagonal rings of 5
 * cylinders and 5 spheres through the edge midpoints of a dodecahedron,
 * behind a wall (emitted first): 5 SIZE(SIZE+1)(2 SIZE+1) cylinders and as
 * many spheres + 1 polygon (8,401 at 7).
 * - Radius rho = 0.07412 for all; spread s = 1/sin(pi/8).
 * - Object vertices V[5p + k], scale 1/(1 + rho): pentagon 0 is
 *   (cos 2 pi k/5, sin 2 pi k/5, 0); pentagon p = 1..5 is pentagon 0 turned
 *   about +X by 2 acos(cos(pi/3)/sin(pi/5)), then about +Z by
 *   pi (2(p-1) + 1)/5.
 * - Objects at depth d = 0..SIZE-1, oz = 0..d, ox = 0..d (that nesting),
 *   offset (2ox - d, s (d+1), 2oz - d). Element e = 0..29: the cylinder
 *   from V[e] + off to V[prev] + off (prev = e + 4 when e mod 5 = 0, else
 *   e - 1), then the sphere at V[e] + off; every ring of 5 has its colour.
 * - Wall: the plane y = s (SIZE+1), half-size h = 1.01 (s (SIZE+1) + s)
 *   tan(pi/8) about x = -1, z = 0.5: corners (h-1, y, h+.5), (-h-1, y, h+.5),
 *   (-h-1, y, -h+.5), (h-1, y, -h+.5).
 * View: from (-1, -s, 0.5) at from + (0,1,0), 45 degrees, hither 1; lights
 * (3,-s,3), (-4,-s,1), (2,-s,-4). Wall f 1 1 1 1 0; rings red, green,
 * blue, cyan, magenta, yellow with kd 0.5, ks 0.2. */
#include "spd.h"

void spd_census_rings(int size, spd_census *n)
{
    uint64_t k = 5ull * size * (size + 1) * (2 * size + 1);
    *n = (spd_census){.spheres = k, .cones = k, .polygons = 1, .polygon_tris = 2, .polygon_verts = 4};
}

void spd_gen_rings(spd_ctx *c, int size)
{
    const double rho = 0.07412, s = 1.0 / sin(M_PI / 8.0);
    spd_vec from = spd_v(-1.0, -s, 0.5);
    spd_background(c, SPD_SKY_BLUE);
    spd_view(c, from, spd_add(from, spd_v(0, 1, 0)), spd_v(0, 0, 1), 45.0, 1.0, 512, 512);
    spd_light(c, spd_v(3, -s, 3));
    spd_light(c, spd_v(-4, -s, 1));
    spd_light(c, spd_v(2, -s, -4));

    spd_material(c, 1.0, 1.0, 1.0, 1.0, 0.0, spd_shine(0.0), 0.0, 0.0);
    double wy = s * (size + 1), h = 1.01 * (wy + s) * tan(M_PI / 8.0);
    const spd_vec wall[4] = {spd_v(h - 1, wy, h + 0.5), spd_v(-h - 1, wy, h + 0.5), spd_v(-h - 1, wy, -h + 0.5),
                             spd_v(h - 1, wy, -h + 0.5)};
    spd_polygon(c, wall, 4);

    /* The 30 vertices of one object. */
    spd_vec V[30];
    double scale = 1.0 / (1.0 + rho);
    for (int k = 0; k < 5; k++) V[k] = spd_v(scale * cos(k * 2.0 * M_PI / 5.0), scale * sin(k * 2.0 * M_PI / 5.0), 0.0);
    spd_mat rx = spd_mat_rotation(spd_v(1, 0, 0), 2.0 * acos(cos(M_PI / 3.0) / sin(M_PI / 5.0)));
    for (int p = 1; p < 6; p++) {
        spd_mat rz = spd_mat_rotation(spd_v(0, 0, 1), M_PI * (2.0 * (p - 1) + 1.0) / 5.0);
        for (int k = 0; k < 5; k++) {
            spd_vec t = spd_mat_apply(&rx, V[k]);
            V[5 * p + k] = spd_mat_apply(&rz, t);
        }
    }

    static const double colour[6][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 1, 1}, {1, 0, 1}, {1, 1, 0}};
    for (int d = 0; d < size; d++)
        for (int oz = 0; oz <= d; oz++)
            for (int ox = 0; ox <= d; ox++) {
                spd_vec off = spd_v(2.0 * ox - d, s * (d + 1), 2.0 * oz - d);
                for (int e = 0; e < 30; e++) {
                    int prev = e % 5 == 0 ? e + 4 : e - 1;
                    if (e % 5 == 0) {
                        const double *col = colour[e / 5];
                        spd_material(c, col[0], col[1], col[2], 0.5, 0.2, spd_shine(37.0), 0.0, 0.0);
                    }
                    spd_vec base = spd_add(V[e], off);
                    spd_cone(c, base, rho, spd_add(V[prev], off), rho);
                    spd_sphere(c, base, rho);
                }
            }
}

/* spd_tetra.c: the "tetra" scene of the SPD 3.14 (src/tetra.c), written
 * from the rules in shared/SPD-SCENES.md, not from the original code.
 *
 * A recursive tetrahedral (Sierpinski) pyramid. A node is a centre c and a
 * half-size r, starting at (0,0,0), 1. The cube corners k with
 * x*y*z = +1, in the order (-,-,+), (-,+,-), (+,-,-), (+,+,+), place the
 * node's 4 children at c + (r/2) k with half-size r/2, recursively, SIZE - 1
 * times; a leaf is the tetrahedron P_i = c + r k_i with the faces
 * (0,1,2), (3,2,1), (2,3,0), (1,0,3). 4^SIZE triangles (4,096 at 6).
 *
 * View: from (1.022846, -3.177154, -2.174512) at (-0.004103, -0.004103,
 * 0.216539), up (-0.816497, -0.816497, 0.816497), 45 degrees, hither 1;
 * light (2, -18, -5). Material f 1 0.2 0.2 1 0 (matte red). */
#include "spd.h"

static const double corner[4][3] = {{-1, -1, 1}, {-1, 1, -1}, {1, -1, -1}, {1, 1, 1}};

static void tetra(spd_ctx *c, spd_vec ctr, double r, int depth)
{
    if (depth > 1) {
        for (int i = 0; i < 4; i++)
            tetra(c, spd_add(ctr, spd_scale(spd_v(corner[i][0], corner[i][1], corner[i][2]), r / 2)), r / 2, depth - 1);
        return;
    }
    static const int face[4][3] = {{0, 1, 2}, {3, 2, 1}, {2, 3, 0}, {1, 0, 3}};
    spd_vec P[4];
    for (int i = 0; i < 4; i++) P[i] = spd_add(ctr, spd_scale(spd_v(corner[i][0], corner[i][1], corner[i][2]), r));
    for (int f = 0; f < 4; f++) {
        spd_vec t[3] = {P[face[f][0]], P[face[f][1]], P[face[f][2]]};
        spd_polygon(c, t, 3);
    }
}

void spd_census_tetra(int size, spd_census *n)
{
    uint64_t tris = 1ull << (2 * size);
    *n = (spd_census){.polygons = tris, .polygon_tris = tris, .polygon_verts = 3 * tris};
}

void spd_gen_tetra(spd_ctx *c, int size)
{
    spd_background(c, SPD_SKY_BLUE);
    spd_view(c, spd_v(1.022846, -3.177154, -2.174512), spd_v(-0.004103, -0.004103, 0.216539),
             spd_v(-0.816497, -0.816497, 0.816497), 45.0, 1.0, 512, 512);
    spd_light(c, spd_v(2, -18, -5));
    spd_material(c, 1.0, 0.2, 0.2, 1.0, 0.0, spd_shine(0.0), 0.0, 0.0);
    tetra(c, spd_v(0, 0, 0), 1.0, size);
}

/* spd_tree.c: the "tree" scene of the SPD 3.14 (src/tree.c), after Aono
 * and Kunii (IEEE CG&A, May 1984), written from the rules in
 * shared/SPD-SCENES.md, not from the original code.
 *
 * A binary tree of 2^(SIZE+1) - 1 branches, each a cone and a sphere, over
 * a field square (emitted first): 8,191 primitives at 11.
 * - A branch has an affine frame A (the root: identity) and a scale (root
 *   1). It emits the cone from A(0,0,0), radius 0.15 scale, to A(0,0,1),
 *   radius 0.67 * 0.15 scale, then the sphere at A(0,0,1) with the apex
 *   radius; then, depth permitting, its children 0 and 1 (depth-first)
 *   with the frame A o L_i and scale 0.67 scale.
 * - L_i(p) = c_i Rz(div_i) Rx(ang_i) p + (0,0,1) with (ang, div, c) =
 *   (40, 90, 0.65) for child 0 and (25, 230, 0.70) for child 1 (degrees).
 *   The contraction c (positions) and 0.67 (radii) are independent.
 * View: from (4.5, 0.4, 2.0) at (0, 0, 1.5), 45 degrees, hither 1; seven
 * lights. Field f 0.2 0.7 0.2 1 0 (green); tree f 0.55 0.4 0.2 1 0 (brown). */
#include "spd.h"

typedef struct { spd_mat M; spd_vec t; } affine; /* p -> M p + t */

static spd_vec affine_apply(const affine *A, spd_vec p) { return spd_add(spd_mat_apply(&A->M, p), A->t); }

/* A o B */
static affine affine_compose(const affine *A, const affine *B)
{
    affine r = {spd_mat_mul(&A->M, &B->M), affine_apply(A, B->t)};
    return r;
}

static void grow(spd_ctx *c, const affine L[2], const affine *A, double scale, int depth)
{
    double rb = 0.15 * scale, ra = rb * 0.67;
    spd_vec base = affine_apply(A, spd_v(0, 0, 0)), apex = affine_apply(A, spd_v(0, 0, 1));
    spd_cone(c, base, rb, apex, ra);
    spd_sphere(c, apex, ra);
    if (depth == 0) return;
    for (int i = 0; i < 2; i++) {
        affine child = affine_compose(A, &L[i]);
        grow(c, L, &child, scale * 0.67, depth - 1);
    }
}

void spd_census_tree(int size, spd_census *n)
{
    uint64_t br = (2ull << size) - 1;
    *n = (spd_census){.spheres = br, .cones = br, .polygons = 1, .polygon_tris = 2, .polygon_verts = 4};
}

void spd_gen_tree(spd_ctx *c, int size)
{
    spd_background(c, SPD_SKY_BLUE);
    spd_view(c, spd_v(4.5, 0.4, 2.0), spd_v(0, 0, 1.5), spd_v(0, 0, 1), 45.0, 1.0, 512, 512);
    static const double lights[7][3] = {{-5, 5, 50}, {30, -30, 30}, {-40, -30, 20}, {10, 30, 40},
                                        {-30, 40, 10}, {50, 25, 20}, {-10, -60, 30}};
    for (int i = 0; i < 7; i++) spd_light(c, spd_v(lights[i][0], lights[i][1], lights[i][2]));

    spd_material(c, 0.2, 0.7, 0.2, 1.0, 0.0, spd_shine(0.0), 0.0, 0.0);
    const spd_vec field[4] = {spd_v(50, 50, 0), spd_v(-50, 50, 0), spd_v(-50, -50, 0), spd_v(50, -50, 0)};
    spd_polygon(c, field, 4);

    spd_material(c, 0.55, 0.4, 0.2, 1.0, 0.0, spd_shine(0.0), 0.0, 0.0);
    static const double ang[2] = {40.0, 25.0}, div[2] = {90.0, 230.0}, con[2] = {0.65, 0.70};
    affine L[2];
    for (int i = 0; i < 2; i++) {
        spd_mat rx = spd_mat_rotation(spd_v(1, 0, 0), ang[i] * M_PI / 180.0);
        spd_mat rz = spd_mat_rotation(spd_v(0, 0, 1), div[i] * M_PI / 180.0);
        spd_mat s = spd_mat_scaling(con[i]), rzx = spd_mat_mul(&rz, &rx);
        L[i].M = spd_mat_mul(&s, &rzx);
        L[i].t = spd_v(0, 0, 1);
    }
    affine root = {spd_mat_scaling(1.0), spd_v(0, 0, 0)};
    grow(c, L, &root, 1.0, size);
}

/* spd_mount.c: the "mount" scene of the SPD 3.14 (src/mount.c), written
 * from the rules in shared/SPD-SCENES.md, not from the original code.
 *
 * A fractal mountain (midpoint displacement over a quadtree) of 2*4^SIZE
 * triangles and a pyramid of 4 glass spheres, the spheres first: 8,196
 * primitives at 6.
 * - Spheres: radius 0.17 about c = (-0.8, 0.8, 1.0): the top one at
 *   c + q0, q0 = (0, 0, 0.17 sqrt(1.5)); then q0 turned about
 *   normalize(1,1,0) by acos(-1/3) and about +Z by 0, 120, 240 degrees.
 * - Mountain over [-1,1]^2, n = 2^SIZE cells a side, corner heights 0. A
 *   cell (x, y, width w > 1, corners ll, lr, ur, ul) gets, with hw = w/2 and
 *   rise = (2 hw/n) * roughness (roughness = sqrt(ratio^2 - 1), ratio =
 *   2/2^(1/1.2) for fractal dimension 2.2), the heights lower, right,
 *   upper, left (edge means + rise*G at the edge midpoints) and middle
 *   (mean of 4 + 1.4142136*rise*G), then recurses into its quadrants
 *   (x,y), (x+hw,y), (x+hw,y+hw), (x,y+hw). A cell of width 1 gives the
 *   triangles (ll, lr, ur) and (ur, ul, ll) at xy = -1 + 2 index/n.
 * - G(A,B) = gauss(21 + hash(A,B)): hash = ((A << (23-SIZE)) +
 *   (B << (15-SIZE)) + (A << (7-SIZE))) & 0xFFFF, unsigned, and gauss is
 *   the SPD's polar-method normal deviate over the generator
 *   ix = (28411 + 8121 ix) mod 134456 (see gauss() below). This is the
 *   original "faulty" patterned hash, kept for comparability.
 *   Sizes >= 8: the shift 7 - SIZE is negative, undefined behaviour in C,
 *   so the original's heights there are whatever its compiler made of it.
 *   Here a negative left shift is defined as a right shift by the
 *   magnitude (A >> (SIZE - 7)). Counts are right at every size, but the
 *   mountain of sizes 8..10 is not comparable with any original output.
 * View: from (-1.6, 1.6, 1.7) at 0, 45 degrees, hither 0.01; one light at
 * (-100, -100, 100). Spheres f 1 1 1 0.1 0.1 (T 0.9, ior 1.5); mountain
 * f 0.5 0.45 0.35 1 0. */
#include "spd.h"

typedef struct {
    spd_ctx *c;
    int size;
    double n;         /* cells per side */
    double roughness;
} mountain;

/* a << s for a shift that may be negative: then a >> -s (see above). */
static uint64_t shl(uint64_t a, int s) { return s >= 0 ? a << s : a >> -s; }

static unsigned hash(const mountain *m, int A, int B)
{
    uint64_t a = (uint64_t)(unsigned)A, b = (uint64_t)(unsigned)B;
    return (unsigned)((shl(a, 23 - m->size) + shl(b, 15 - m->size) + shl(a, 7 - m->size)) & 0xFFFF);
}

/* The SPD's gaussian deviate of a seed (Marsaglia's polar method over a
 * small linear congruential generator). */
static double gauss(long seed)
{
    long ix1, ix2 = seed;
    double v1, v2, r;
    do {
        ix1 = (28411 + 8121 * ix2) % 134456;
        ix2 = (28411 + 8121 * ix1) % 134456;
        v1 = 2.0 * ix1 / 134456.0 - 1.0;
        v2 = 2.0 * ix2 / 134456.0 - 1.0;
        r = v1 * v1 + v2 * v2;
    } while (r >= 1.0);
    return v1 * sqrt(-2.0 * log(r) / r);
}

static double G(const mountain *m, int A, int B) { return gauss(21 + (long)hash(m, A, B)); }

static void grow(const mountain *m, int x, int y, int w, double ll, double lr, double ur, double ul)
{
    if (w == 1) {
        double x0 = -1.0 + 2.0 * x / m->n, x1 = -1.0 + 2.0 * (x + 1) / m->n;
        double y0 = -1.0 + 2.0 * y / m->n, y1 = -1.0 + 2.0 * (y + 1) / m->n;
        spd_vec LL = spd_v(x0, y0, ll), LR = spd_v(x1, y0, lr), UR = spd_v(x1, y1, ur), UL = spd_v(x0, y1, ul);
        spd_vec t1[3] = {LL, LR, UR}, t2[3] = {UR, UL, LL};
        spd_polygon(m->c, t1, 3);
        spd_polygon(m->c, t2, 3);
        return;
    }
    int hw = w / 2;
    double rise = (hw * 2.0 / m->n) * m->roughness;
    double lower = (ll + lr) / 2 + rise * G(m, x + hw, y);
    double right = (lr + ur) / 2 + rise * G(m, x + w, y + hw);
    double upper = (ur + ul) / 2 + rise * G(m, x + hw, y + w);
    double left = (ul + ll) / 2 + rise * G(m, x, y + hw);
    double middle = (ll + lr + ur + ul) / 4 + 1.4142136 * rise * G(m, x + hw, y + hw);
    grow(m, x, y, hw, ll, lower, middle, left);
    grow(m, x + hw, y, hw, lower, lr, right, middle);
    grow(m, x + hw, y + hw, hw, middle, right, ur, upper);
    grow(m, x, y + hw, hw, left, middle, upper, ul);
}

void spd_census_mount(int size, spd_census *n)
{
    uint64_t tris = 2ull << (2 * size);
    *n = (spd_census){.spheres = 4, .polygons = tris, .polygon_tris = tris, .polygon_verts = 3 * tris};
}

void spd_gen_mount(spd_ctx *c, int size)
{
    spd_background(c, SPD_SKY_BLUE);
    spd_view(c, spd_v(-1.6, 1.6, 1.7), spd_v(0, 0, 0), spd_v(0, 0, 1), 45.0, 0.01, 512, 512);
    spd_light(c, spd_v(-100, -100, 100));

    /* The glass spheres. */
    spd_material(c, 1.0, 1.0, 1.0, 0.1, 0.1, spd_shine(6.7), 0.9, 1.5);
    const double r = 0.17;
    spd_vec ctr = spd_v(-0.8, 0.8, 1.0), q0 = spd_v(0, 0, r * sqrt(1.5));
    spd_sphere(c, spd_add(ctr, q0), r);
    spd_mat tip = spd_mat_rotation(spd_norm(spd_v(1, 1, 0)), acos(-1.0 / 3.0));
    spd_vec q1 = spd_mat_apply(&tip, q0);
    for (int i = 0; i < 3; i++) {
        spd_mat turn = spd_mat_rotation(spd_v(0, 0, 1), i * 2.0 * M_PI / 3.0);
        spd_sphere(c, spd_add(ctr, spd_mat_apply(&turn, q1)), r);
    }

    /* The mountain. */
    spd_material(c, 0.5, 0.45, 0.35, 1.0, 0.0, spd_shine(0.0), 0.0, 0.0);
    double ratio = 2.0 / exp(log(2.0) / (2.2 - 1.0));
    mountain m = {c, size, (double)(1 << size), sqrt(ratio * ratio - 1.0)};
    grow(&m, 0, 0, 1 << size, 0.0, 0.0, 0.0, 0.0);
}

/* spd_teapot.c: the "teapot" scene of the SPD 3.14 (src/teapot.c), written
 * from the rules in shared/SPD-SCENES.md, not from the original code.
 *
 * The 32 bicubic Bezier patches of the Newell teapot (with its 4 bottom
 * patches) on an n x n checkerboard, n = SIZE: n^2 squares (emitted first),
 * then 64 n^2 - 8 n triangle patches (9,264 primitives at the Readme's
 * n = 12; the original program's own default is 6, 2,292).
 * - Data: scenes/data/newell_teapot.txt (public-domain "teaset" data),
 *   compiled in at build time by scenes/data/embed_teapot.py.
 * - Patch (control grid G[row][col], rows along s): s, t step 0..n; the
 *   cell (s0, t0) gives (s0,t0), (s0,t1), (s1,t1) and (s1,t1), (s1,t0),
 *   (s0,t0). P(s,t) = sum_rc B_r(s) B_c(t) G[r][c] (Bernstein).
 * - Cusps: a vertex with |x| < 1e-4 and |y| < 1e-4 is on the axis; a
 *   triangle with 2 or more such vertices is dropped (8n of them).
 * - Vertex normals, as the SPD's `pp 3` output: normalize(dP/dt x dP/ds)
 *   from the Bernstein derivatives; a triangle's one vertex on the axis
 *   gets (0, 0, +1) when z > 1.5, else (0, 0, -1). Kept in
 *   scene_t.normals (the whitted workload and render shade with them).
 * - Checkerboard over [-4,4]^2 at z = 0: square (s,t) spans
 *   x in [4(2s/n - 1), 4(2(s+1)/n - 1)], y likewise with t, corners
 *   (lo,lo), (hi,lo), (hi,hi), (lo,hi); the (s+t) odd ones first (white),
 *   then the even ones (grey), s outer, t inner.
 * View: from (4.86, 7.2, 5.4) at 0, 45 degrees, hither 1; lights
 * (-3.1, 9.8, 12.1), (11.3, 5.1, 8.8). Teapot f 1 0.5 0.1 0.75 0.25;
 * squares f 1 1 1 0.5 0.5 and f 0.5 0.5 0.5 0.5 0.5. Render the teapot
 * double-sided (the lid does not fit tightly); all kinds are two-sided. */
#include "spd.h"
#include "../prims/checked_alloc.h"

#include <stdlib.h>

/* From the build directory's spd_teapot_data.c (see above). */
extern const int spd_teapot_npatches, spd_teapot_nverts;
extern const unsigned short spd_teapot_patches[][16];
extern const double spd_teapot_verts[][3];

static void bernstein(double u, double b[4], double db[4])
{
    double v = 1.0 - u;
    b[0] = v * v * v;
    b[1] = 3.0 * u * v * v;
    b[2] = 3.0 * u * u * v;
    b[3] = u * u * u;
    db[0] = -3.0 * v * v;
    db[1] = 3.0 * v * v - 6.0 * u * v;
    db[2] = 6.0 * u * v - 3.0 * u * u;
    db[3] = 3.0 * u * u;
}

/* A grid point of a patch: position and unit normal. */
typedef struct { spd_vec p, n; } patch_point;

static int on_axis(spd_vec p) { return fabs(p.x) < 1e-4 && fabs(p.y) < 1e-4; }

static void patch_triangle(spd_ctx *c, patch_point a, patch_point b, patch_point d)
{
    patch_point v[3] = {a, b, d};
    if (on_axis(a.p) + on_axis(b.p) + on_axis(d.p) >= 2) return; /* degenerate at a cusp */
    spd_vec pts[3], nrm[3];
    for (int k = 0; k < 3; k++) {
        pts[k] = v[k].p;
        nrm[k] = on_axis(v[k].p) ? spd_v(0, 0, v[k].p.z > 1.5 ? 1.0 : -1.0) : v[k].n;
    }
    spd_patch(c, pts, nrm);
}

static void square(spd_ctx *c, int n, int s, int t)
{
    double x0 = 4.0 * (2.0 * s / n - 1.0), x1 = 4.0 * (2.0 * (s + 1) / n - 1.0);
    double y0 = 4.0 * (2.0 * t / n - 1.0), y1 = 4.0 * (2.0 * (t + 1) / n - 1.0);
    spd_vec q[4] = {spd_v(x0, y0, 0), spd_v(x1, y0, 0), spd_v(x1, y1, 0), spd_v(x0, y1, 0)};
    spd_polygon(c, q, 4);
}

void spd_census_teapot(int size, spd_census *n)
{
    uint64_t k = (uint64_t)size, patches = 64 * k * k - 8 * k;
    *n = (spd_census){.polygons = k * k + patches, .polygon_tris = 2 * k * k + patches, .patches = patches,
                      .polygon_verts = 4 * k * k + 3 * patches};
}

void spd_gen_teapot(spd_ctx *c, int size)
{
    const int n = size;
    spd_background(c, SPD_SKY_BLUE);
    spd_view(c, spd_v(4.86, 7.2, 5.4), spd_v(0, 0, 0), spd_v(0, 0, 1), 45.0, 1.0, 512, 512);
    spd_light(c, spd_v(-3.1, 9.8, 12.1));
    spd_light(c, spd_v(11.3, 5.1, 8.8));

    spd_material(c, 1.0, 1.0, 1.0, 0.5, 0.5, spd_shine(30.0), 0.0, 0.0);
    for (int s = 0; s < n; s++)
        for (int t = 0; t < n; t++)
            if ((s + t) % 2) square(c, n, s, t);
    spd_material(c, 0.5, 0.5, 0.5, 0.5, 0.5, spd_shine(30.0), 0.0, 0.0);
    for (int s = 0; s < n; s++)
        for (int t = 0; t < n; t++)
            if (!((s + t) % 2)) square(c, n, s, t);

    spd_material(c, 1.0, 0.5, 0.1, 0.75, 0.25, spd_shine(37.0), 0.0, 0.0);
    /* Bernstein weights of the n + 1 parameter steps, and one patch's grid. */
    /* Bernstein weights and their derivatives at the n + 1 parameter steps, and one patch's grid. */
    double (*B)[4] = checked_calloc((size_t)(n + 1), sizeof *B, "the SPD teapot's Bernstein weights");
    double (*dB)[4] = checked_calloc((size_t)(n + 1), sizeof *dB, "the SPD teapot's Bernstein derivatives");
    patch_point *P = checked_calloc((size_t)(n + 1) * (n + 1), sizeof *P, "the SPD teapot's patch grid");
    for (int i = 0; i <= n; i++) bernstein((double)i / n, B[i], dB[i]);
    for (int p = 0; p < spd_teapot_npatches; p++) {
        const unsigned short *g = spd_teapot_patches[p];
        for (int i = 0; i <= n; i++)
            for (int j = 0; j <= n; j++) {
                spd_vec q = spd_v(0, 0, 0), ds = q, dt = q;
                for (int r = 0; r < 4; r++)
                    for (int k = 0; k < 4; k++) {
                        const double *v = spd_teapot_verts[g[4 * r + k]];
                        spd_vec cp = spd_v(v[0], v[1], v[2]);
                        q = spd_add(q, spd_scale(cp, B[i][r] * B[j][k]));
                        ds = spd_add(ds, spd_scale(cp, dB[i][r] * B[j][k]));
                        dt = spd_add(dt, spd_scale(cp, B[i][r] * dB[j][k]));
                    }
                spd_vec nrm = spd_cross(dt, ds);
                double len = spd_len(nrm);
                /* s = i/n, t = j/n; a zero normal (a degenerate point) leaves the vertex without one */
                P[i * (n + 1) + j] = (patch_point){q, len > 0.0 ? spd_scale(nrm, 1.0 / len) : spd_v(0, 0, 0)};
            }
        for (int s = 0; s < n; s++)
            for (int t = 0; t < n; t++) {
                patch_point s0t0 = P[s * (n + 1) + t], s0t1 = P[s * (n + 1) + t + 1];
                patch_point s1t0 = P[(s + 1) * (n + 1) + t], s1t1 = P[(s + 1) * (n + 1) + t + 1];
                patch_triangle(c, s0t0, s0t1, s1t1);
                patch_triangle(c, s1t1, s1t0, s0t0);
            }
    }
    free(B);
    free(dB);
    free(P);
}

/* spd_gears.c: the "gears" scene of the SPD 3.14 (src/gears.c), written
 * from the rules in shared/SPD-SCENES.md, not from the original code.
 *
 * SIZE^3 gears in a cube, each 36 teeth: a concave 144-vertex top face,
 * 144 side quads and a 144-vertex bottom face, over a ground square
 * (emitted first): 146*SIZE^3 + 1 polygons (9,345 at 4).
 * - R = 1 / (SIZE - (SIZE-1)*0.05); gear (ix, iy, iz), loops iz outer, iy,
 *   ix inner, at x, y = -1 + R + i*1.9R, z = 1 - iz/SIZE; thickness
 *   t = min(0.1, 1/(2 SIZE)); outer radius 0.995R, inner 0.9R; angular
 *   offset a0 = pi ((ix+iy+iz) mod 2) / 36.
 * - Tooth k: ga = a0 + 2 pi k/36, ta = 2 pi/36, points at the polar
 *   positions (ro, ga - 0.19ta), (ro, ga + 0.19ta), (ri, ga + 0.3ta),
 *   (ri, ga + 0.7ta) around the centre; the top face is all teeth in order.
 * - Side i: [p_i, p_i - (0,0,t), p_i+1 - (0,0,t), p_i+1] (i+1 mod 144).
 * - Bottom: at z - t, with ga = a0 - 2 pi k/36 and ta negated (reversed
 *   winding). Order per gear: top, 144 sides, bottom.
 * Materials: ground f 1 0.85 0.7 0.3 0.6 (reflective); gear colour
 * (0.01 + frac((3ix+2iy+iz+1) 5/7), 0.01 + frac((3iy+2iz+ix+1) 3/7),
 * 0.01 + frac((3iz+2ix+iy+1) 2/7)) divided by its largest component; glass
 * (kd 0.2, T 0.8, ior 1.1) when (4ix+2iy+iz) mod 5 = 0, else kd 1.
 * View: from (-1.1, -2.1, 2.6) at 0, 45 degrees, hither 1; 5 lights. */
#include "spd.h"

#define TEETH 36

static double frac(double x) { return x - floor(x); }

/* One face's 144 points: the teeth k = 0..35 at height z. */
static void gear_face(spd_vec *pts, spd_vec ctr, double z, double a0, double ro, double ri, int sign)
{
    double ta = sign * 2.0 * M_PI / TEETH;
    static const double frac_angle[4] = {-0.19, 0.19, 0.3, 0.7};
    for (int k = 0; k < TEETH; k++) {
        double ga = a0 + sign * 2.0 * M_PI * k / TEETH;
        for (int j = 0; j < 4; j++) {
            double rad = j < 2 ? ro : ri, a = ga + frac_angle[j] * ta;
            pts[4 * k + j] = spd_v(ctr.x + rad * cos(a), ctr.y + rad * sin(a), z);
        }
    }
}

static void gear(spd_ctx *c, spd_vec ctr, double a0, double ro, double ri, double t)
{
    spd_vec pts[4 * TEETH];
    gear_face(pts, ctr, ctr.z, a0, ro, ri, +1);
    spd_polygon(c, pts, 4 * TEETH);
    for (int i = 0; i < 4 * TEETH; i++) {
        spd_vec a = pts[i], b = pts[(i + 1) % (4 * TEETH)];
        spd_vec q[4] = {a, spd_v(a.x, a.y, a.z - t), spd_v(b.x, b.y, b.z - t), b};
        spd_polygon(c, q, 4);
    }
    gear_face(pts, ctr, ctr.z - t, a0, ro, ri, -1);
    spd_polygon(c, pts, 4 * TEETH);
}

void spd_census_gears(int size, spd_census *n)
{
    uint64_t g = (uint64_t)size * size * size;
    *n = (spd_census){.polygons = 146 * g + 1,
                      .polygon_tris = g * (2 * (4 * TEETH - 2) + 4 * TEETH * 2) + 2,
                      .polygon_verts = g * (2 * 4 * TEETH + 4 * 4 * TEETH) + 4};
}

void spd_gen_gears(spd_ctx *c, int size)
{
    spd_background(c, SPD_SKY_BLUE);
    spd_view(c, spd_v(-1.1, -2.1, 2.6), spd_v(0, 0, 0), spd_v(0, 0, 1), 45.0, 1.0, 512, 512);
    spd_light(c, spd_v(2, 4, 4));
    spd_light(c, spd_v(-2, 4, 3));
    spd_light(c, spd_v(2, -2.5, 2.5));
    spd_light(c, spd_v(-1, -4, 2));
    spd_light(c, spd_v(-1.111, -2.121, 2.626)); /* just behind the eye */

    spd_material(c, 1.0, 0.85, 0.7, 0.3, 0.6, spd_shine(37.0), 0.0, 0.0);
    const spd_vec ground[4] = {spd_v(2, 2, 0), spd_v(-2, 2, 0), spd_v(-2, -2, 0), spd_v(2, -2, 0)};
    spd_polygon(c, ground, 4);

    double R = 1.0 / (size - (size - 1) * 0.05);
    double t = fmin(0.1, 1.0 / (2.0 * size));
    for (int iz = 0; iz < size; iz++)
        for (int iy = 0; iy < size; iy++)
            for (int ix = 0; ix < size; ix++) {
                double r = 0.01 + frac((ix * 3 + iy * 2 + iz + 1) * 5.0 / 7.0);
                double g = 0.01 + frac((iy * 3 + iz * 2 + ix + 1) * 3.0 / 7.0);
                double b = 0.01 + frac((iz * 3 + ix * 2 + iy + 1) * 2.0 / 7.0);
                double m = fmax(fmax(r, g), b);
                if ((ix * 4 + iy * 2 + iz) % 5 == 0)
                    spd_material(c, r / m, g / m, b / m, 0.2, 0.0, spd_shine(0.0), 0.8, 1.1);
                else
                    spd_material(c, r / m, g / m, b / m, 1.0, 0.0, spd_shine(0.0), 0.0, 0.0);
                spd_vec ctr = spd_v(-1.0 + R + ix * 1.9 * R, -1.0 + R + iy * 1.9 * R, 1.0 - (double)iz / size);
                gear(c, ctr, M_PI * ((ix + iy + iz) % 2) / TEETH, 0.995 * R, 0.9 * R, t);
            }
}

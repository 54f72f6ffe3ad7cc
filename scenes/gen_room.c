/* gen_room.c: a hall at large coordinates, the hard case of secondary-ray
 * robustness (see scene.h, scene_gen_room).
 *
 * Interior scenes from public repositories (Sibenik, Sponza) have floors
 * thousands of units long, coordinates in the hundreds to thousands and thin
 * sliver triangles; a shadow or reflection ray leaving such a floor starts
 * within float noise of a surface that is large and far from the origin.
 * This generator makes that case on purpose and bigger: a 10000 x 8000 x 600
 * hall (each floor, wall and ceiling two triangles, one wall a single quad
 * polygon), rotated 23 degrees about y, tilted 3 degrees about x and moved
 * to (7000, 1.57, -5000), so that no plane is axis-aligned, x and z are in
 * the thousands and the floor's height stays within a few hundred of 0: the
 * case where an offset of a fixed number of float steps of the point's own
 * coordinates is far smaller than the error of the point (o + t d carries
 * the error of t |d| ~ 1e3). It holds overlapping decals in the floor
 * plane, sliver trims in the wall planes along every corner, and (unless
 * "empty") needles 0.01 wide and 300 tall, a slanted panel, a box, a
 * mirror sphere, a glass sphere (T 0.8, ior 1.5) and a column (a
 * cylinder). Two point lights hang inside.
 *
 * "gen:room:empty" keeps only the shell with its decals and trims: a convex
 * room lit from inside, where every visible point sees both lights, so any
 * shadow found there is self-shadowing. */
#include "scene.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define HALL_X 5000.0
#define HALL_Z 4000.0
#define HALL_H 600.0

typedef struct {
    scene_t *s;
    double rot[3][3];
    double at[3];
} room_ctx;

/* Local hall coordinates (y up, floor at y = 0) to world. */
static vec3 place(const room_ctx *c, double x, double y, double z)
{
    double l[3] = {x, y, z}, w[3];
    for (int i = 0; i < 3; i++) w[i] = c->rot[i][0] * l[0] + c->rot[i][1] * l[1] + c->rot[i][2] * l[2] + c->at[i];
    return v3((float)w[0], (float)w[1], (float)w[2]);
}

static void tri(room_ctx *c, const double a[3], const double b[3], const double d[3])
{
    prims_t *p = &c->s->prims;
    uint32_t i = prims_add_vertex(p, place(c, a[0], a[1], a[2]));
    uint32_t j = prims_add_vertex(p, place(c, b[0], b[1], b[2]));
    uint32_t k = prims_add_vertex(p, place(c, d[0], d[1], d[2]));
    prims_add_triangle(p, i, j, k);
}

/* A rectangle as two triangles: corner o, edges u and v. */
static void quad(room_ctx *c, const double o[3], const double u[3], const double v[3])
{
    double a[3], b[3], d[3];
    for (int k = 0; k < 3; k++) a[k] = o[k] + u[k], b[k] = o[k] + u[k] + v[k], d[k] = o[k] + v[k];
    tri(c, o, a, b);
    tri(c, o, b, d);
}

static void material(room_ctx *c, float r, float g, float b, float kd, float ks)
{
    material_t m = {v3(r, g, b), kd, ks, 0.0f, 1.0f};
    scene_set_material_upto(c->s, scene_add_material(c->s, m));
}

static void shell(room_ctx *c)
{
    const double X = HALL_X, Z = HALL_Z, H = HALL_H;
    quad(c, (double[]){-X, 0, -Z}, (double[]){0, 0, 2 * Z}, (double[]){2 * X, 0, 0}); /* floor */
    material(c, 0.75f, 0.7f, 0.6f, 0.7f, 0.3f);
    /* Overlapping decals lying exactly in the floor plane (before rounding). */
    for (int k = 0; k < 12; k++) {
        double x = -900.0 + 150.0 * k, z = 600.0 - 90.0 * (k % 4), r = 120.0 + 35.0 * (k % 5);
        tri(c, (double[]){x - r, 0, z + r}, (double[]){x + r, 0, z + 0.6 * r}, (double[]){x + 0.2 * r, 0, z - r});
    }
    material(c, 0.8f, 0.2f, 0.2f, 0.8f, 0.1f);
    quad(c, (double[]){-X, H, -Z}, (double[]){2 * X, 0, 0}, (double[]){0, 0, 2 * Z}); /* ceiling */
    quad(c, (double[]){-X, 0, -Z}, (double[]){0, H, 0}, (double[]){0, 0, 2 * Z});     /* walls */
    quad(c, (double[]){X, 0, -Z}, (double[]){0, 0, 2 * Z}, (double[]){0, H, 0});
    quad(c, (double[]){-X, 0, Z}, (double[]){0, H, 0}, (double[]){2 * X, 0, 0});
    prims_t *p = &c->s->prims; /* the far wall: one quad polygon */
    uint32_t ids[4] = {prims_add_vertex(p, place(c, -X, 0, -Z)), prims_add_vertex(p, place(c, X, 0, -Z)),
                       prims_add_vertex(p, place(c, X, H, -Z)), prims_add_vertex(p, place(c, -X, H, -Z))};
    prims_add_polygon(p, ids, 4);
    material(c, 0.8f, 0.8f, 0.85f, 0.8f, 0.0f);
    /* Sliver trims in the wall planes along the four vertical corners. */
    for (int k = 0; k < 4; k++) {
        double sx = (k & 1) ? X : -X, sz = (k & 2) ? Z : -Z, in = 0.02;
        tri(c, (double[]){sx, 0, sz}, (double[]){sx, H, sz}, (double[]){sx - copysign(in, sx), H / 2, sz});
        tri(c, (double[]){sx, 0, sz}, (double[]){sx, H, sz}, (double[]){sx, H / 2, sz - copysign(in, sz)});
    }
    material(c, 0.3f, 0.3f, 0.3f, 0.8f, 0.0f);
}

static void contents(room_ctx *c)
{
    /* Needles: slivers 0.01 wide at the base, 300 tall, some leaning. */
    for (int k = 0; k < 24; k++) {
        double x = -3000.0 + 260.0 * k, z = -1500.0 + 120.0 * (k % 6), lean = 40.0 * ((k % 3) - 1);
        tri(c, (double[]){x, 0, z}, (double[]){x + 0.01, 0, z + 0.004}, (double[]){x + lean, 300, z + 0.5 * lean});
    }
    /* A panel leaning against the left wall, and a box on the floor. */
    quad(c, (double[]){-HALL_X + 400, 0, -800}, (double[]){0, 0, 1600}, (double[]){-400, 500, 0});
    double b0[3] = {1200, 0, -600}, e[3][3] = {{300, 0, 0}, {0, 180, 0}, {0, 0, 240}};
    for (int a = 0; a < 3; a++) {
        const double *u = e[(a + 1) % 3], *v = e[(a + 2) % 3];
        double far[3];
        for (int k = 0; k < 3; k++) far[k] = b0[k] + e[a][k];
        quad(c, b0, v, u);
        quad(c, far, u, v);
    }
    material(c, 0.6f, 0.65f, 0.7f, 0.6f, 0.3f);
    prims_add_sphere(&c->s->prims, place(c, -600, 60, -1200), 60.0f);
    material(c, 0.9f, 0.9f, 0.9f, 0.2f, 0.8f);
    /* Glass, so that refracted rays (the whitted workload) leave a surface at these coordinates too. */
    prims_add_sphere(&c->s->prims, place(c, 2200, 150, 300), 150.0f);
    scene_set_material_upto(c->s, scene_add_material(c->s, (material_t){v3(0.9f, 0.95f, 1.0f), 0.1f, 0.2f, 0.8f, 1.5f}));
    prims_add_cone(&c->s->prims, place(c, 300, 0, -2200), 40.0f, place(c, 300, HALL_H, -2200), 40.0f);
    material(c, 0.7f, 0.6f, 0.5f, 0.8f, 0.1f);
}

scene_t *scene_gen_room(const char *name, bool empty, char *err, size_t errlen)
{
    room_ctx c;
    c.s = scene_new(name);
    snprintf(c.s->source, sizeof c.s->source, "generated hall at large coordinates%s", empty ? ", empty" : "");
    /* rot = Rx(3 deg) * Ry(23 deg) */
    double ay = 23.0 * M_PI / 180.0, ax = 3.0 * M_PI / 180.0;
    double ry[3][3] = {{cos(ay), 0, sin(ay)}, {0, 1, 0}, {-sin(ay), 0, cos(ay)}};
    double rx[3][3] = {{1, 0, 0}, {0, cos(ax), -sin(ax)}, {0, sin(ax), cos(ax)}};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            c.rot[i][j] = 0.0;
            for (int k = 0; k < 3; k++) c.rot[i][j] += rx[i][k] * ry[k][j];
        }
    c.at[0] = 7000.0, c.at[1] = 1.57, c.at[2] = -5000.0;
    shell(&c);
    if (!empty) contents(&c);
    scene_add_light(c.s, place(&c, -1500, 550, 0));
    scene_add_light(c.s, place(&c, 2000, 550, 1500));
    camera_t *cam = &c.s->camera;
    cam->from = place(&c, 0, 260, 1800);
    cam->at = place(&c, 0, 60, -1200);
    vec3 up0 = place(&c, 0, 0, 0), up1 = place(&c, 0, 1000, 0);
    cam->up = v3_norm(v3_sub(up1, up0));
    cam->fov_deg = 65.0f;
    cam->hither = 0.0f;
    cam->width = cam->height = 256;
    c.s->background = v3(0.1f, 0.1f, 0.15f);
    if (scene_finish(c.s, true, err, errlen) != 0) {
        scene_free(c.s);
        return NULL;
    }
    return c.s;
}

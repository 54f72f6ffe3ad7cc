/* view.c: view specs (eye=X,Y,Z;at=X,Y,Z;up=X,Y,Z;fov=DEG) and applying a
 * view to a loaded scene.
 *
 * A mesh file has no camera, and the automatic one (scene_finish) sees a
 * building from outside; a view is how the command line (--view, NAME@SPEC)
 * and the catalogue's named views (catalogue.c) put the eye somewhere else.
 * The parser is strict because a typo that silently kept the old camera
 * would give a benchmark of other rays than the one asked for. */
#include "scene.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* light has no bit: it may be given up to SCENE_VIEW_MAX_LIGHTS times. */
static const struct {
    const char *key;
    unsigned bit;
} parts[] = {{"eye", SCENE_VIEW_EYE}, {"at", SCENE_VIEW_AT}, {"up", SCENE_VIEW_UP}, {"fov", SCENE_VIEW_FOV}, {"light", 0}};
#define NPARTS (sizeof parts / sizeof parts[0])

/* Parse exactly n comma-separated finite numbers filling all of s. */
static bool parse_numbers(const char *s, float *out, int n)
{
    for (int i = 0; i < n; i++) {
        char *end;
        if (!strchr("+-.0123456789", *s) || !*s) return false; /* strtod would skip blanks, take "inf" */
        errno = 0;
        double v = strtod(s, &end);
        if (end == s || errno == ERANGE || !isfinite(v) || !isfinite((float)v)) return false;
        out[i] = (float)v;
        if (*end != (i + 1 < n ? ',' : '\0')) return false;
        s = end + 1;
    }
    return true;
}

/* One part "key=value" (len bytes at p). */
static int parse_part(const char *p, size_t len, scene_view *v, char *err, size_t errlen)
{
    char part[256];
    if (len == 0) {
        snprintf(err, errlen, "empty part (parts are separated by one ';')");
        return -1;
    }
    if (len >= sizeof part) {
        snprintf(err, errlen, "'%.40s...': part too long", p);
        return -1;
    }
    memcpy(part, p, len);
    part[len] = '\0';
    char *eq = strchr(part, '=');
    if (!eq) {
        snprintf(err, errlen, "'%s': expected KEY=VALUE (eye, at, up, fov or light)", part);
        return -1;
    }
    *eq = '\0';
    const char *val = eq + 1;
    size_t k = 0;
    while (k < NPARTS && strcmp(part, parts[k].key) != 0) k++;
    if (k == NPARTS) {
        snprintf(err, errlen, "'%s=%s': unknown part '%s' (known: eye, at, up, fov, light)", part, val, part);
        return -1;
    }
    if (v->given & parts[k].bit) {
        snprintf(err, errlen, "'%s=%s': %s given twice", part, val, part);
        return -1;
    }
    v->given |= parts[k].bit;
    if (parts[k].bit == 0) {
        float xyz[3];
        if (v->nlights == SCENE_VIEW_MAX_LIGHTS) {
            snprintf(err, errlen, "'light=%s': more than %d lights", val, SCENE_VIEW_MAX_LIGHTS);
            return -1;
        }
        if (!parse_numbers(val, xyz, 3)) {
            snprintf(err, errlen, "'light=%s': expected light=X,Y,Z, three finite numbers", val);
            return -1;
        }
        v->lights[v->nlights++] = v3(xyz[0], xyz[1], xyz[2]);
        return 0;
    }
    if (parts[k].bit == SCENE_VIEW_UP) {
        static const char *const axes[] = {"X", "Y", "Z", "auto"};
        for (int a = 0; a < 4; a++)
            if (!strcasecmp(val, axes[a])) {
                v->up_axis = SCENE_UP_X + a;
                return 0;
            }
    }
    if (parts[k].bit == SCENE_VIEW_FOV) {
        if (!parse_numbers(val, &v->fov_deg, 1) || !(v->fov_deg > 0.0f && v->fov_deg < 180.0f)) {
            snprintf(err, errlen, "'fov=%s': expected an angle in degrees, 0 < DEG < 180", val);
            return -1;
        }
        return 0;
    }
    vec3 *dst = parts[k].bit == SCENE_VIEW_EYE ? &v->eye : parts[k].bit == SCENE_VIEW_AT ? &v->at : &v->up;
    float xyz[3];
    if (!parse_numbers(val, xyz, 3)) {
        snprintf(err, errlen, "'%s=%s': expected %s=X,Y,Z, three finite numbers%s", part, val, part,
                 parts[k].bit == SCENE_VIEW_UP ? ", or an axis X, Y, Z or auto" : "");
        return -1;
    }
    *dst = v3(xyz[0], xyz[1], xyz[2]);
    return 0;
}

int scene_view_parse(const char *spec, scene_view *v, char *err, size_t errlen)
{
    memset(v, 0, sizeof *v);
    if (!spec || !*spec) {
        snprintf(err, errlen, "empty view (expected eye=X,Y,Z;at=X,Y,Z;up=X,Y,Z;fov=DEG, any of the parts)");
        return -1;
    }
    for (const char *p = spec;;) {
        const char *semi = strchr(p, ';');
        size_t len = semi ? (size_t)(semi - p) : strlen(p);
        if (parse_part(p, len, v, err, errlen) != 0) return -1;
        if (!semi) break;
        p = semi + 1;
    }
    return 0;
}

int scene_view_apply(scene_t *s, const scene_view *v, const char *label, char *err, size_t errlen)
{
    /* An up axis first: on a made-up camera it makes the camera (and the
     * made-up lights) again, which the other parts then adjust. */
    camera_t before = s->camera;
    if (v->up_axis) scene_set_up_axis(s, v->up_axis);
    camera_t c = s->camera;
    s->camera = before;
    if (v->given & SCENE_VIEW_EYE) c.from = v->eye;
    if (v->given & SCENE_VIEW_AT) c.at = v->at;
    if ((v->given & SCENE_VIEW_UP) && !v->up_axis) c.up = v->up;
    if (v->given & SCENE_VIEW_FOV) c.fov_deg = v->fov_deg;
    /* Checked on the result, since a spec may give only some parts: the
     * ranges every scene's view lies in (scene.h), an eye apart from at and
     * an up the workloads' frame can use (they normalise the directions). */
    char why[400];
    const vec3 *lights = v->nlights ? v->lights : s->lights;
    uint32_t nlights = v->nlights ? (v->nlights < SCENE_VIEW_MAX_LIGHTS ? v->nlights : SCENE_VIEW_MAX_LIGHTS) : s->nlights;
    if (scene_check_view(&c, lights, nlights, why, sizeof why) != 0) {
        snprintf(err, errlen, "view %s: %s", label, why);
        return -1;
    }
    s->camera = c;
    /* A camera a view has placed is no longer made up: a later up axis turns it, not rebuilds it. */
    if (v->given & (SCENE_VIEW_EYE | SCENE_VIEW_AT | SCENE_VIEW_FOV) || ((v->given & SCENE_VIEW_UP) && !v->up_axis))
        s->made_up &= ~SCENE_MADE_CAMERA;
    if (v->nlights) s->made_up &= ~SCENE_MADE_LIGHTS;
    if (v->nlights) {
        s->nlights = 0;
        for (uint32_t i = 0; i < v->nlights && i < SCENE_VIEW_MAX_LIGHTS; i++) scene_add_light(s, v->lights[i]);
    }
    /* The first view replaces "automatic"/"source"; later ones chain,
     * except the one just applied again (sibenik@nave over its default nave). */
    const char *last = strrchr(s->view, '@');
    if (!strcmp(last ? last + 1 : s->view, label)) return 0;
    bool first = !strcmp(s->view, "automatic") || !strcmp(s->view, "source") || !s->view[0];
    size_t n = first ? 0 : strlen(s->view);
    snprintf(s->view + n, sizeof s->view - n, "%s%s", first ? "" : "@", label);
    return 0;
}

int scene_view_option(char *spec, size_t speclen, const char *option, const char *value, char *err, size_t errlen)
{
    size_t n = strlen(spec);
    const char *key = !strcmp(option, "up") ? "up=" : !strcmp(option, "light") ? "light=" : "";
    scene_view v;
    char why[512];
    if (snprintf(spec + n, speclen - n, "%s%s%s", n ? ";" : "", key, value) >= (int)(speclen - n)) {
        spec[n] = '\0';
        snprintf(err, errlen, "--%s %.60s: the view (--view, --up and --light together) is too long", option, value);
        return -1;
    }
    if (scene_view_parse(spec, &v, why, sizeof why) != 0) {
        spec[n] = '\0';
        snprintf(err, errlen, "--%s %s: %s", option, value, why);
        return -1;
    }
    return 0;
}

/* test_render: the same scene through two correct accelerators gives the
 * same picture (pixels may differ only where a ray grazes an edge), the
 * picture is not blank, and a PNG is written. */
#include <string.h>
#include <unistd.h>
#include "harness/render/render.h"
#include "testlib.h"

static void compare(const char *scene_name, int res)
{
    scene_t *s = test_scene(scene_name);
    accel *ex = test_build("exhaustive", s, 1), *em = test_build("embree", s, 1);
    workload_opts o = test_wl(res, res, 1);
    rayset_t *prim = workload_primary(s, &o);
    image_t *a = render_whitted(s, ex, prim, NULL), *b = render_whitted(s, em, prim, NULL);
    int differ = 0, distinct = 0, n = res * res;
    for (int i = 0; i < n; i++) {
        const uint8_t *p = &a->rgb[i * 3], *q = &b->rgb[i * 3];
        if (abs(p[0] - q[0]) > 2 || abs(p[1] - q[1]) > 2 || abs(p[2] - q[2]) > 2) differ++;
        if (i && memcmp(p, &a->rgb[0], 3)) distinct++;
    }
    printf("%s %dx%d: %d pixels differ, %d differ from the first pixel\n", scene_name, res, res, differ, distinct);
    CHECK_MSG(differ * 1000 <= n * 2, "%s: %d of %d pixels differ between exhaustive and embree", scene_name, differ, n);
    CHECK_MSG(distinct > n / 10, "%s: the image is nearly uniform", scene_name);
    char path[128], err[256];
    snprintf(path, sizeof path, "/tmp/accelbench-test-render-%d.png", (int)getpid());
    CHECK(image_write_png(a, path, err, sizeof err) == 0);
    FILE *f = fopen(path, "rb");
    unsigned char sig[8] = {0};
    CHECK(f && fread(sig, 1, 8, f) == 8 && sig[1] == 'P' && sig[2] == 'N' && sig[3] == 'G');
    if (f) fclose(f);
    remove(path);
    image_free(a);
    image_free(b);
    rayset_free(prim);
    ex->ops->destroy(ex);
    em->ops->destroy(em);
    scene_free(s);
}

int main(void)
{
    compare("spd:balls:2", 96);
    compare("spd:balls:1:t", 64);
    return check_report();
}

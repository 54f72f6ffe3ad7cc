/* image.c: PNG output through libpng and the heat-map colour map. */
#include "image.h"
#include "../../prims/checked_alloc.h"

#include <errno.h>
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

image_t *image_new(int width, int height)
{
    /* render checks an image's size against the memory cap before making it (resources.h). */
    image_t *im = checked_calloc(1, sizeof *im, "an image");
    im->width = width;
    im->height = height;
    im->rgb = checked_calloc(checked_array_bytes((size_t)width, (size_t)height, "an image's pixels"), 3, "an image's pixels");
    return im;
}

void image_free(image_t *im)
{
    if (!im) return;
    free(im->rgb);
    free(im);
}

static uint8_t to8(float v)
{
    v = v < 0.0f ? 0.0f : v > 1.0f ? 1.0f : v;
    return (uint8_t)lrintf(powf(v, 1.0f / 2.2f) * 255.0f);
}

void image_set(image_t *im, int x, int y, vec3 c)
{
    uint8_t *p = &im->rgb[((size_t)y * (size_t)im->width + (size_t)x) * 3];
    p[0] = to8(c.x);
    p[1] = to8(c.y);
    p[2] = to8(c.z);
}

int image_write_png(const image_t *im, const char *path, char *err, size_t errlen)
{
    FILE *f = fopen(path, "wb");
    if (!f) {
        snprintf(err, errlen, "%s: cannot write: %s", path, strerror(errno));
        return -1;
    }
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!png || !info || setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        fclose(f);
        snprintf(err, errlen, "%s: libpng failed while writing", path);
        return -1;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)im->width, (png_uint_32)im->height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < im->height; y++) png_write_row(png, &im->rgb[(size_t)y * (size_t)im->width * 3]);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    if (fclose(f) != 0) {
        snprintf(err, errlen, "%s: write failed: %s", path, strerror(errno));
        return -1;
    }
    return 0;
}

void colormap_inferno(float x, uint8_t rgb[3])
{
    /* Eight stops sampled from the inferno map; linear in between. */
    static const uint8_t stops[8][3] = {{0, 0, 4},     {40, 11, 84},   {101, 21, 110}, {159, 42, 99},
                                        {212, 72, 66}, {245, 125, 21}, {250, 193, 39}, {252, 255, 164}};
    if (!(x > 0.0f)) x = 0.0f;
    if (x > 1.0f) x = 1.0f;
    float f = x * 7.0f;
    int i = (int)f;
    if (i > 6) i = 6;
    float w = f - (float)i;
    for (int k = 0; k < 3; k++) rgb[k] = (uint8_t)lrintf((float)stops[i][k] * (1.0f - w) + (float)stops[i + 1][k] * w);
}

/* image.h: 8-bit RGB images written as PNG through libpng, and the colour
 * map of the cost heat maps. */
#ifndef ACCELBENCH_IMAGE_H
#define ACCELBENCH_IMAGE_H

#include <stddef.h>
#include <stdint.h>
#include "../../prims/vec3.h"

typedef struct {
    int width, height;
    uint8_t *rgb; /* width*height*3, rows top to bottom */
} image_t;

image_t *image_new(int width, int height);
void image_free(image_t *im);
/* Linear [0,1] colour to sRGB-ish 8 bit (gamma 2.2), clamped. */
void image_set(image_t *im, int x, int y, vec3 c);
int image_write_png(const image_t *im, const char *path, char *err, size_t errlen);
/* Sequential colour map (dark blue -> purple -> orange -> light yellow,
 * after matplotlib's "inferno"), for x in [0,1]. Returns linear-free 8-bit RGB. */
void colormap_inferno(float x, uint8_t rgb[3]);

#endif

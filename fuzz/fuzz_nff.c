/* fuzz_nff: the NFF reader (scenes/nff_read.c) on any bytes. What it
 * accepts is built and traced by every accelerator (exercise.c), so a
 * scene it lets through that tracing cannot take is found too. */
#include <stdlib.h>
#include <string.h>
#include "../scenes/nff.h"
#include "exercise.h"

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size);

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size)
{
    char *text = malloc(size + 1); /* the reader wants the NUL a file read gives */
    if (!text) return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    char err[512];
    scene_t *s = scene_parse_nff("fuzz", "fuzz.nff", text, size, err, sizeof err);
    free(text);
    if (s) fuzz_exercise(s, NULL);
    scene_free(s);
    return 0;
}

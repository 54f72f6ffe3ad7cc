/* fuzz_nff: the NFF reader (scenes/nff_read.c) on any bytes. What it
 * accepts is built and traced by one accelerator, the one a hash of the
 * input picks (exercise.c fuzz_exercise_one), so that a scene it lets
 * through that tracing cannot take is found too, at the cost of one build
 * an input: with every accelerator built over each accepted scene the
 * campaign fell to tens of inputs a second once its corpus held larger
 * scenes, and a mutation anywhere in the file picks another accelerator. */
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
    /* The key: the input's bytes as a string, each NUL made a space so that
     * bytes past one still count. */
    for (size_t i = 0; i < size; i++)
        if (!text[i]) text[i] = ' ';
    if (s) fuzz_exercise_one(s, text);
    free(text);
    scene_free(s);
    return 0;
}

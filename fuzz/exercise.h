/* exercise.h: what every fuzz harness does with an input its parser
 * accepted: build every registered accelerator over the scene and trace a
 * few rays through every method each one has, so that a scene or a ray
 * the parsers let through but an accelerator cannot take shows up as a
 * crash, a sanitizer report, a leak or a hang (scripts/fuzz.sh runs them). */
#ifndef ACCELBENCH_FUZZ_EXERCISE_H
#define ACCELBENCH_FUZZ_EXERCISE_H

#include "../accel/accel.h"
#include "../harness/rayset.h"

/* Build ops over s with params (NULL: its defaults) and trace every ray of
 * sets[0..nsets) that the harness's rule lets through (ray_traceable)
 * through intersect, occluded and their fast forms, resetting a mutating
 * one between sets. Aborts on an answer the harness would index out of
 * bounds with: a hit with a primitive id out of range, a miss with one. A
 * refused build (a parameter value, a memory cap) is fine. */
void fuzz_accel(const struct accel_ops *ops, const scene_t *s, const accel_params *params, rayset_t *const *sets,
                int nsets);

/* Every registered accelerator with its defaults over s, on rays of s's own
 * workloads at 4x4 (primary, shadow, reflection, diffuse, random), plus
 * extra when it is not NULL. */
void fuzz_exercise(const scene_t *s, const rayset_t *extra);

/* A small fixed scene with every kind of primitive (triangles, a sphere, a
 * cone, a concave polygon), for the harnesses whose input is not a scene;
 * made once, never freed (LeakSanitizer ignores what a global holds). */
const scene_t *fuzz_scene(void);

/* The rays of fuzz_scene's workloads, made once like it (count sets). */
rayset_t *const *fuzz_scene_rays(int *count);

#endif

/* exercise.h: what every fuzz harness does with an input its parser
 * accepted: build every registered accelerator over the scene and trace a
 * few rays through every method each one has, so that a scene or a ray
 * the parsers let through but an accelerator cannot take shows up as a
 * crash, a sanitizer report, a leak or a hang (scripts/fuzz.sh runs them). */
#ifndef ACCELBENCH_FUZZ_EXERCISE_H
#define ACCELBENCH_FUZZ_EXERCISE_H

#include "../accel/accel.h"
#include "../harness/workloads/rayset.h"

/* The fuzzer stops at 2 GB of memory and at 30 s an input; an
 * accelerator's own cap (the grids' and the octree's, 4096 MiB by
 * default) lets a legal setting past both (grid density=385 filled 1 GiB of
 * cells in more than 10 s; the octree's default depth over coincident
 * spheres and a cone built 131,000 nodes in 14 s, and made fuzz_nff run 67
 * inputs a second). Every build here is capped at FUZZ_MEMCAP_MIB: that
 * still takes grids of 250,000 cells and octrees of ~12,000 nodes, and
 * every refusal path. */
#define FUZZ_MEMCAP_MIB 1
/* params' memory cap (memcap_mib) at most FUZZ_MEMCAP_MIB. */
void fuzz_cap_memory(accel_params *p);

/* Build ops over s with params (NULL: its defaults; either capped by
 * fuzz_cap_memory) and trace every ray of
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

/* One registered accelerator over s, the one key picks (a hash of key over
 * the registry), on the same rays as fuzz_exercise: for a harness whose
 * inputs are scenes, so that a new scene costs one build, not every one
 * (fuzz_scenes ran at tens of inputs a second once its corpus held scenes
 * of thousands of primitives); the mutations of a scene's name pick the
 * others. */
void fuzz_exercise_one(const scene_t *s, const char *key);

/* A small fixed scene with every kind of primitive (triangles, a sphere, a
 * cone, a concave polygon), for the harnesses whose input is not a scene;
 * made once, never freed (LeakSanitizer ignores what a global holds). */
const scene_t *fuzz_scene(void);

/* The rays of fuzz_scene's workloads, made once like it (count sets). */
rayset_t *const *fuzz_scene_rays(int *count);

/* true the first time the pair (kind, key) comes in this process, then
 * remembered: the harnesses skip the build and trace of an input that only
 * repeats one already exercised (most mutations change no setting, or one
 * the parser refuses; the same settings build the same structure over the
 * same scene, so building it again finds nothing new, and skipping took
 * fuzz_params from ~190 to thousands of executions a second). Kept as
 * 64-bit hashes in a table that is cleared when half full: a forgotten
 * pair is only exercised again. */
bool fuzz_first_time(const char *kind, const char *key);

#endif

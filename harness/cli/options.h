/* options.h: parsing and checking the command line of run, verify and
 * render into an options value (run/run_options.h). */
#ifndef ACCELBENCH_OPTIONS_H
#define ACCELBENCH_OPTIONS_H

#include <stdio.h>
#include "../run/run_options.h"

/* --up and --light, as run, verify, render and scene info take them. */
#define SCENE_UP_LIGHT_USAGE \
    "  --up X|Y|Z|auto         the up axis of the camera: a scene with no camera of its own (a mesh file, a catalogue\n" \
    "                          mesh without a named view) gets its automatic camera and lights built around it; a\n" \
    "                          camera of the scene's (NFF, spd:, gen:, a named view) keeps its eye and look-at and\n" \
    "                          turns its up vector to it. auto: the scene's thinnest bounding-box extent, ties to Y,\n" \
    "                          then Z. Default: auto for a mesh file (file:PATH or a path) without a view; a catalogue\n" \
    "                          mesh keeps Y (Z when Y alone is thinnest). Same as the view part up=AXIS\n" \
    "  --light X,Y,Z           a point light at X,Y,Z; repeatable up to 4 times; the lights given replace the scene's\n" \
    "                          (its own, or the automatic two above and behind the camera). Same as the part light=X,Y,Z\n" \
    "                          --view, --up and --light make one view, applied to every scene: the CSV's scene column\n" \
    "                          says it (mesh.obj@up=Z;light=0,0,9)\n"

/* The value checks of run's options, shared with the commands that run
 * it (calibrate, tune): 0, or -1 after printing one line naming the
 * option. An integer in lo..hi; an unsigned 64-bit seed (no sign); WxH
 * with each side in 1..IMAGE_SIDE_MAX (digits only, never wrapped). */
int options_parse_long(const char *opt, const char *s, long lo, long hi, long *out);
int options_parse_seed(const char *s, uint64_t *out);
int options_parse_res(const char *s, int *width, int *height);

/* --scenes LIST into o->scenes: each scene once, a set's name standing for
 * its scenes (the names are o's own copies; options_free frees them). 0,
 * or 2 after printing why. advise reads its SCENE operand with it. */
int options_add_scenes(options *o, const char *arg);

/* Parse the options of subcommand `cmd` (run, verify, render). Returns 0,
 * 1 after printing --help, or 2 after printing a one-line error. */
int options_parse(options *o, const char *cmd, int argc, char **argv);
void options_free(options *o);
void options_usage(FILE *out, const char *cmd);
/* The verify command line that replays ray `ray` of one cell exactly: the
 * scene, the ray file or every option that shaped the ray set (workload,
 * res, spp, seed, depth, corners), the accelerator and each of its
 * parameters that differs from the default. */
void options_replay_command(const options *o, const char *scene, const char *workload, const accel_config *ac,
                            uint32_t ray, char *buf, size_t len);

/* For run, verify and render once their options are parsed (options.c):
 * set the cap (o->memcap_mib, 0 for the default) and bound every
 * accelerator's memcap parameter by it. 0, or 2 after printing one line. */
int resources_apply_memcap(options *o);
/* Then everything the options of command cmd size, before any scene is
 * loaded: the threads, every generated scene's store at the fewest bytes a
 * primitive takes (the generator's own estimate follows), --rays' file,
 * and every workload's ray set at one light (a lower bound: every scene
 * has a light; the exact count is checked when each set is made), or for
 * render the image when --res gives its size. 0, or 2 after printing one
 * line. */
int resources_check_options(const options *o, const char *cmd);

#endif

/* catalogue.h: what scene_load.c asks the catalogue (catalogue.c); not
 * for outside the scenes library. */
#ifndef ACCELBENCH_CATALOGUE_H
#define ACCELBENCH_CATALOGUE_H

#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Whether name is a catalogue mesh (bunny, sibenik ...). */
bool catalogue_has(const char *name);
/* Where catalogue mesh name's file is, without reading it: true with its
 * path in file, false with load's reason in err. */
bool catalogue_locate(const char *name, char *file, size_t filelen, char *err, size_t errlen);
/* Load catalogue mesh name, with its default view when it has one; NULL with
 * a one-line reason naming the file, where it was looked for and where to
 * get it (a Debian package, or a public repository). */
scene_t *catalogue_load(const char *name, char *err, size_t errlen);
/* The named view `view` of scene `scene` (a catalogue name, or any other
 * scene name, which has none); NULL with "unknown view 'x' (known: ...)"
 * in err. */
const scene_view *catalogue_view(const char *scene, const char *view, char *err, size_t errlen);

#ifdef __cplusplus
}
#endif

#endif

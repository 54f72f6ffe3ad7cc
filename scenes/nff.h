/* nff.h: reading and writing Eric Haines' Neutral File Format (NFF), the
 * format of the Standard Procedural Databases (format reference: NFF.TXT
 * v3.9 by Eric Haines; the grammar as the SPD 3.14 writer uses it is
 * summarised in shared/SPD-SCENES.md).
 *
 * Why: the SPD scenes are defined by their NFF output, so reading NFF lets
 * the testbed trace the original files, and writing it lets any scene
 * (generated, or a mesh) be handed to another renderer or compared with
 * the original generators' output.
 *
 * What scene_t keeps of NFF: the view (from/at/up/angle/hither/resolution),
 * the background, the light positions (not their optional colours), the
 * material colour, Kd, Ks, T and ior (not Shine), and every primitive in
 * file order: `p 3` and `pp 3` become triangles, larger `p`/`pp` polygons,
 * `s` spheres and `c` cones. Patch normals are kept as vertex normals
 * (scene_t.normals): a `pp` is a smooth primitive. */
#ifndef ACCELBENCH_NFF_H
#define ACCELBENCH_NFF_H

#include <stddef.h>
#include <stdint.h>
#include "scene.h"

/* Read the NFF file PATH (plain or compressed, or ARCHIVE#MEMBER; see
 * compressed.h) into a finished scene named name. Returns NULL with one
 * line "PATH:LINE: reason" in err on a syntax or value error (unreadable
 * files and "no primitives" name just the path). Never crashes on garbage.
 * A file without `v` gets scene_finish's default camera; one without `l`
 * the default lights. Cones with both radii negative ("inside visible")
 * are stored with the absolute radii and counted in scene_t.source. */
scene_t *scene_load_nff(const char *name, const char *path, char *err, size_t errlen);
/* The same from size bytes in memory, data[size] == '\0' (the tokenizer
 * stops there); path names the file in messages. For the fuzzers (fuzz/). */
scene_t *scene_parse_nff(const char *name, const char *path, const char *data, size_t size, char *err, size_t errlen);

/* Write s as NFF: `b`, `v`, the `l` lines, then the primitives in order with
 * an `f` line whenever the material changes; smooth primitives (vertex
 * normals) as `pp`. Shine, which scene_t does not keep, is written as
 * 3.0827 (the SPD's usual highlight exponent). Numbers are printed with
 * %.9g, so every float reads back bit for bit (same scene_geometry_hash,
 * which covers the `pp` normals). Returns 0, or -1 with "PATH: reason" in
 * err. */
int scene_write_nff(const scene_t *s, const char *path, char *err, size_t errlen);

/* FNV-1a (64-bit) over the primitives in order: each one's kind, then its
 * float geometry (triangle: the 3 vertex positions; sphere: centre,
 * radius; cone: base, base radius, apex, apex radius; polygon: the vertex
 * count and the positions), and after a smooth primitive its vertex
 * normals. Positions, not vertex indices, so two scenes
 * with the same geometry hash alike however their vertices are shared:
 * an NFF round trip keeps the hash. */
uint64_t scene_geometry_hash(const scene_t *s);

#endif

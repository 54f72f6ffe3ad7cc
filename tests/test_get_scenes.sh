#!/bin/bash
# test_get_scenes.sh: scripts/get-scenes.sh on local copies of the four
# sources, made here small and in the repositories' layout (tests cannot reach
# the network): a sibenik.zip holding the two C arrays, Sponza's per-object
# OBJ files (numbered past 9, so a name sort would merge them in the wrong
# order; corners as v/vt/vn, a quad, a negative index), the photon models.
# Each converted mesh must have the geometry hash of an OBJ written by hand
# here; a hash other than the expected one installs nothing; broken sources
# give one line naming the file. Prints "N passed, N failed"; exits 1 on a
# failure.
set -u
AB=${ACCELBENCH:?set ACCELBENCH to the accelbench binary}
SRC=${SRCDIR:?set SRCDIR to the source tree}
T=$(mktemp -d /tmp/accelbench-get-scenes.XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/cli_lib.sh"
GET=("$SRC/scripts/get-scenes.sh")
hash_of() { "$AB" scene info "$1" | awk '/^hash/ {print $2}'; }

S=$T/src
mkdir -p "$S/BoundingVolumeHierarchy" "$S/GPU-Raytracer/Data/Sponza/models" "$S/photon/models"
python3 - "$S/BoundingVolumeHierarchy/sibenik.zip" <<'PY'
import sys, zipfile
text = ("float sibenik_vertices[] =\n{\n  0, 0, 0, 1, 0, 0,\n  0, 1, 0, 1e-006, 1, 2\n};\n"
        "unsigned int sibenik_indices[]=\n{\n  0, 1, 2, 1, 3,\n  2\n};\n")
with zipfile.ZipFile(sys.argv[1], 'w') as z:
    z.writestr('sibenik/copyright.txt', 'made by the test\n')
    z.writestr('sibenik/sibenik.bin', text)
PY
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1e-006 1 2\nf 1 2 3\nf 2 4 3\n' > "$T/sibenik.want.obj"
M=$S/GPU-Raytracer/Data/Sponza/models
printf 'o a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1\n' > "$M/sponza_0.obj"
printf 'o b\nv 5 0 0\nv 6 0 0\nv 6 1 0\nv 5 1 0\nf 1//1 2//1 3//1 4//1\n' > "$M/sponza_2.obj"
printf 'o c\nv 9 9 9\nv 9 8 9\nv 8 9 9\nf -3 -2 -1\n' > "$M/sponza_10.obj"
printf 'newmtl x\n' > "$M/sponza.mtl"
printf 'v 7 7 7\nv 7 6 7\nv 6 7 7\nf 1 2 3\n' > "$M/Plane.001.obj" # not a sponza_ part: left out
cat > "$T/sponza.want.obj" <<'OBJ'
v 0 0 0
v 1 0 0
v 0 1 0
v 5 0 0
v 6 0 0
v 6 1 0
v 5 1 0
v 9 9 9
v 9 8 9
v 8 9 9
f 1 2 3
f 4 5 6
f 4 6 7
f 8 9 10
OBJ
printf '# a comment\nv 0 0 0\nv 2 0 0\nv 0 2 0\nv 0 0 2\n\nf 1 2 3 \nf 1 2 4 \n' > "$S/photon/models/dragon.obj"
printf 'v 0 0 1\nv 3 0 0\nv 0 3 0\nf 1 2 3\n' > "$S/photon/models/buddha.obj"
cp "$S/photon/models/dragon.obj" "$T/dragon100k.want.obj"
cp "$S/photon/models/buddha.obj" "$T/buddha100k.want.obj"

# Every mesh converted, checked against the hand-made OBJ's hash, installed.
expect_hash=()
for n in sibenik sponza dragon100k buddha100k; do
    h=$(hash_of "$T/$n.want.obj")
    [ -n "$h" ] && ok || bad "no hash for the hand-made $n"
    expect_hash+=(--expect-hash "$n=$h")
done
expect 0 "get-scenes: buddha100k: $T/dest/buddha100k.obj.xz" -- env ACCELBENCH="$AB" "${GET[@]}" --from "$S" --dest "$T/dest" "${expect_hash[@]}"
for n in sibenik sponza dragon100k buddha100k; do
    [ "$(hash_of "$T/dest/$n.obj.xz")" = "$(hash_of "$T/$n.want.obj")" ] && ok || bad "$n: installed hash differs from the hand-made OBJ's"
done
# An installed mesh is found by its catalogue name through $ACCELBENCH_SCENES.
expect 0 "source +$T/dest/sponza.obj.xz" -- env ACCELBENCH_SCENES="$T/dest" "$AB" scene info sponza
[ -z "$(find "$T/dest" -name '.get-scenes.*')" ] && ok || bad "get-scenes left its work folder behind"

# The recorded hashes are the real meshes': these small ones are refused and nothing is installed.
refused "get-scenes: sibenik: geometry hash [0-9a-f]{16}, expected 22762eac1e9e0b41; not installed" -- \
    env ACCELBENCH="$AB" "${GET[@]}" --from "$S" --dest "$T/dest2" sibenik
[ ! -e "$T/dest2/sibenik.obj.xz" ] && ok || bad "a mesh with the wrong hash was installed"

# Broken sources and arguments: one line naming what is wrong.
refused "'teapot' is not a repository mesh" -- env ACCELBENCH="$AB" "${GET[@]}" --dest "$T/d3" teapot
refused "--from $T/none: not a folder" -- env ACCELBENCH="$AB" "${GET[@]}" --from "$T/none" --dest "$T/d3" sibenik
refused "--expect-hash sibenik=xyz: want NAME=16 hex digits" -- env ACCELBENCH="$AB" "${GET[@]}" --expect-hash sibenik=xyz
mkdir -p "$T/bad/BoundingVolumeHierarchy" "$T/bad/GPU-Raytracer/Data/Sponza/models" "$T/bad/photon"
printf 'not a zip' > "$T/bad/BoundingVolumeHierarchy/sibenik.zip"
refused "get-scenes: sibenik: $T/bad/BoundingVolumeHierarchy/sibenik.zip: File is not a zip file" -- \
    env ACCELBENCH="$AB" "${GET[@]}" --from "$T/bad" --dest "$T/d3" sibenik
printf 'v 0 0 0\nf 1 2 3\n' > "$T/bad/GPU-Raytracer/Data/Sponza/models/sponza_0.obj"
refused "get-scenes: sponza: $T/bad/GPU-Raytracer/Data/Sponza/models/sponza_0.obj:2: a face names a vertex the file does not have" -- \
    env ACCELBENCH="$AB" "${GET[@]}" --from "$T/bad" --dest "$T/d3" sponza
refused "get-scenes: dragon100k: $T/bad/photon/models/dragon.obj: No such file or directory" -- \
    env ACCELBENCH="$AB" "${GET[@]}" --from "$T/bad" --dest "$T/d3" dragon100k

echo "$pass passed, $fail failed"
[ "$fail" = 0 ]

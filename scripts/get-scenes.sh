#!/bin/bash
# get-scenes.sh [--from DIR] [--dest DIR] [--expect-hash NAME=HASH]... [NAME...]
#
# The meshes of public repositories that the catalogue names but the project
# does not hold (sibenik, sponza, dragon100k, buddha100k; all four when no
# NAME is given): fetch each one's public source, convert it as
# scenes/README.md says (scripts/scene_convert.py), compress it with xz, check
# its geometry hash (what `accelbench scene info` prints) against the one
# recorded below, and put it into the scene path's user folder,
# ${XDG_CACHE_HOME:-~/.cache}/accelbench/scenes, where every command finds it.
# A mesh whose hash differs is not installed: exit 2, with both hashes.
#
#   --from DIR   take the sources from local copies instead of the network:
#                DIR/BoundingVolumeHierarchy/sibenik.zip,
#                DIR/GPU-Raytracer/Data/Sponza/models/sponza_*.obj,
#                DIR/photon/models/{dragon,buddha}.obj (the repositories' layout)
#   --dest DIR   install into DIR instead (put DIR on $ACCELBENCH_SCENES)
#   --expect-hash NAME=HASH   check NAME against HASH instead of the recorded
#                hash (a source you changed on purpose)
#
# Without --from it needs git and network access to github.com; nothing else in
# the project does. The binary must be built (scripts/setup.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
AB=${ACCELBENCH:-build/harness/accelbench} # the tests name their build's
usage() { echo "usage: scripts/get-scenes.sh [--from DIR] [--dest DIR] [--expect-hash NAME=HASH]... [NAME...]" >&2; exit 2; }

declare -A REPO=([sibenik]=taqu/BoundingVolumeHierarchy [sponza]=jan-van-bergen/GPU-Raytracer
                 [dragon100k]=nwtnni/photon [buddha100k]=nwtnni/photon)
declare -A SPARSE=([sibenik]=/sibenik.zip [sponza]=/Data/Sponza/models/ [dragon100k]=/models/dragon.obj
                   [buddha100k]=/models/buddha.obj)
# The geometry hashes of the converted meshes (accelbench scene info NAME).
declare -A HASH=([sibenik]=22762eac1e9e0b41 [sponza]=98e0b5974e9b0f89 [dragon100k]=6486c93e0cb75196
                 [buddha100k]=2971fe28410e2e4f)
ALL=(sibenik sponza dragon100k buddha100k)

from="" dest=""
names=()
while [ $# -gt 0 ]; do
    case "$1" in
        --from) [ $# -ge 2 ] || usage; from=$2; shift 2 ;;
        --dest) [ $# -ge 2 ] || usage; dest=$2; shift 2 ;;
        --expect-hash)
            [ $# -ge 2 ] || usage
            n=${2%%=*} h=${2#*=}
            [ -n "${REPO[$n]+x}" ] && [[ "$h" =~ ^[0-9a-f]{16}$ ]] || { echo "get-scenes: --expect-hash $2: want NAME=16 hex digits, NAME one of ${ALL[*]}" >&2; exit 2; }
            HASH[$n]=$h; shift 2 ;;
        -h | --help) sed -n '2,22s/^# \{0,1\}//p' "$0"; exit 0 ;;
        -*) echo "get-scenes: unknown option $1" >&2; usage ;;
        *) [ -n "${REPO[$1]+x}" ] || { echo "get-scenes: '$1' is not a repository mesh (${ALL[*]})" >&2; exit 2; }
           names+=("$1"); shift ;;
    esac
done
[ ${#names[@]} -gt 0 ] || names=("${ALL[@]}")
[ -x "$AB" ] || { echo "get-scenes: $AB is not built (run scripts/setup.sh)" >&2; exit 2; }
if [ -z "$dest" ]; then
    base=${XDG_CACHE_HOME:-}
    [ "${base:0:1}" = / ] || base=$HOME/.cache
    dest=$base/accelbench/scenes
fi
[ -z "$from" ] || [ -d "$from" ] || { echo "get-scenes: --from $from: not a folder" >&2; exit 2; }
mkdir -p "$dest"
work=$(mktemp -d "$dest/.get-scenes.XXXXXX")
trap 'rm -rf "$work"' EXIT

for name in "${names[@]}"; do
    repo=${REPO[$name]}
    src=$from/${repo#*/}
    if [ -z "$from" ]; then
        src=$work/src-${repo#*/}
        if [ ! -d "$src" ]; then
            echo "get-scenes: $name: fetching github.com/$repo (${SPARSE[$name]})"
            command -v git > /dev/null || { echo "get-scenes: git is needed to fetch github.com/$repo" >&2; exit 2; }
            git clone -q --depth 1 --filter=blob:none --no-checkout "https://github.com/$repo" "$src" ||
                { echo "get-scenes: $name: cannot clone github.com/$repo" >&2; exit 2; }
            git -C "$src" sparse-checkout set --no-cone "${SPARSE[$name]}" && git -C "$src" checkout -q ||
                { echo "get-scenes: $name: cannot check out ${SPARSE[$name]} of github.com/$repo" >&2; exit 2; }
        fi
    fi
    obj=$work/$name.obj
    python3 scripts/scene_convert.py "$name" "$src" "$obj"
    xz -T1 -c "$obj" > "$obj.xz"
    rm -f "$obj"
    got=$("$AB" scene info "$obj.xz" | awk '/^hash/ {print $2}') || true
    if [ "$got" != "${HASH[$name]}" ]; then
        echo "get-scenes: $name: geometry hash ${got:-(none: the file does not load)}, expected ${HASH[$name]}; not installed" >&2
        exit 2
    fi
    mv -f "$obj.xz" "$dest/$name.obj.xz"
    echo "get-scenes: $name: $dest/$name.obj.xz (hash $got)"
done

#!/usr/bin/python3
"""scene_convert.py NAME SOURCE_DIR OUT.obj: one repository mesh, from a local
copy of its public source, to the geometry-only OBJ the scene path holds
(vertices and triangles, nothing else); scripts/get-scenes.sh compresses it
with xz and checks its geometry hash. The conversion of each mesh, as
scenes/README.md describes it:

  sibenik     SOURCE_DIR/sibenik.zip (taqu/BoundingVolumeHierarchy): the
              member sibenik/sibenik.bin is C source, two arrays: the
              vertex coordinates (float, x y z in turn) and the triangles'
              vertex indices (from 0). Each coordinate keeps its text.
  sponza      SOURCE_DIR/Data/Sponza/models/sponza_*.obj (jan-van-bergen/
              GPU-Raytracer): 381 per-object OBJ files, merged in the order
              of their numbers; each file's vertex indices are shifted by
              the vertices before it. A face keeps its first vertex index of
              each corner (v/vt/vn -> v); a polygon becomes a fan.
  dragon100k  SOURCE_DIR/models/dragon.obj (nwtnni/photon), as it is.
  buddha100k  SOURCE_DIR/models/buddha.obj (nwtnni/photon), as it is.

Errors are one line naming the file and what is wrong, exit 2."""
import os
import re
import sys
import zipfile


class ConvertError(Exception):
    pass


def c_array(text, name, path):
    """The comma-separated numbers of the C array `name` in text, as strings."""
    m = re.search(r'\b' + re.escape(name) + r'\s*\[\s*\]\s*=\s*\{([^}]*)\}', text)
    if not m:
        raise ConvertError(f"{path}: no C array {name}[] in it")
    return [t for t in (s.strip() for s in m.group(1).split(',')) if t]


def sibenik(src, out):
    path = os.path.join(src, 'sibenik.zip')
    try:
        with zipfile.ZipFile(path) as z:
            text = z.read('sibenik/sibenik.bin').decode('ascii')
    except (OSError, KeyError, zipfile.BadZipFile, UnicodeDecodeError) as e:
        raise ConvertError(f"{path}: {e}")
    coords = c_array(text, 'sibenik_vertices', path)
    indices = c_array(text, 'sibenik_indices', path)
    if len(coords) % 3 or len(indices) % 3:
        raise ConvertError(f"{path}: {len(coords)} coordinates and {len(indices)} indices are not whole triples")
    nverts = len(coords) // 3
    out.write("# sibenik: positions and triangle indices of sibenik.zip (taqu/BoundingVolumeHierarchy)\n")
    for i in range(0, len(coords), 3):
        out.write(f"v {coords[i]} {coords[i + 1]} {coords[i + 2]}\n")
    for i in range(0, len(indices), 3):
        tri = [int(t) for t in indices[i:i + 3]]
        if min(tri) < 0 or max(tri) >= nverts:
            raise ConvertError(f"{path}: triangle {i // 3} names vertex {max(tri)} of {nverts}")
        out.write(f"f {tri[0] + 1} {tri[1] + 1} {tri[2] + 1}\n")


def sponza(src, out):
    folder = os.path.join(src, 'Data', 'Sponza', 'models')
    try:
        names = os.listdir(folder)
    except OSError as e:
        raise ConvertError(f"{folder}: {e.strerror}")
    parts = sorted((int(m.group(1)), n) for n in names for m in [re.fullmatch(r'sponza_(\d+)\.obj', n)] if m)
    if not parts:
        raise ConvertError(f"{folder}: no sponza_*.obj files")
    out.write("# sponza: geometry of Data/Sponza/models/sponza_*.obj (jan-van-bergen/GPU-Raytracer), merged\n")
    base = 0
    for _, name in parts:
        path = os.path.join(folder, name)
        count = 0
        with open(path, encoding='latin-1') as f:
            for lineno, line in enumerate(f, 1):
                tok = line.split()
                if not tok:
                    continue
                if tok[0] == 'v':
                    if len(tok) < 4:
                        raise ConvertError(f"{path}:{lineno}: a vertex needs three coordinates")
                    out.write(f"v {tok[1]} {tok[2]} {tok[3]}\n")
                    count += 1
                elif tok[0] == 'f':
                    try:
                        idx = [int(t.split('/')[0]) for t in tok[1:]]
                    except ValueError:
                        raise ConvertError(f"{path}:{lineno}: a face corner is not a number")
                    idx = [i - 1 if i > 0 else count + i for i in idx]  # negative: from the file's last vertex
                    if len(idx) < 3 or min(idx) < 0 or max(idx) >= count:
                        raise ConvertError(f"{path}:{lineno}: a face names a vertex the file does not have")
                    for k in range(1, len(idx) - 1):
                        out.write(f"f {base + idx[0] + 1} {base + idx[k] + 1} {base + idx[k + 1] + 1}\n")
        base += count


def as_it_is(member):
    def convert(src, out):
        path = os.path.join(src, 'models', member)
        try:
            with open(path, encoding='latin-1') as f:
                for line in f:
                    out.write(line)
        except OSError as e:
            raise ConvertError(f"{path}: {e.strerror}")
    return convert


CONVERTERS = {
    'sibenik': sibenik,
    'sponza': sponza,
    'dragon100k': as_it_is('dragon.obj'),
    'buddha100k': as_it_is('buddha.obj'),
}


def main(argv):
    if len(argv) != 4 or argv[1] not in CONVERTERS:
        print(f"usage: scene_convert.py {{{'|'.join(CONVERTERS)}}} SOURCE_DIR OUT.obj", file=sys.stderr)
        return 2
    name, src, dest = argv[1:]
    try:
        with open(dest, 'w', encoding='latin-1') as out:
            CONVERTERS[name](src, out)
    except ConvertError as e:
        print(f"get-scenes: {name}: {e}", file=sys.stderr)
        return 2
    except OSError as e:
        print(f"get-scenes: {name}: {dest}: {e.strerror}", file=sys.stderr)
        return 2
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))

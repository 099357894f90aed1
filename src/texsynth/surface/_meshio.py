"""Reading and writing meshes: Wavefront OBJ (with MTL and texture) and PLY in numpy, other formats via trimesh.

OBJ: ``v x y z`` (optionally ``r g b`` after the coordinates, the vertex
colour extension MeshLab and others write), ``vt u v``, ``f`` with ``v``,
``v/vt``, ``v/vt/vn`` or ``v//vn`` corners (1-based or negative, relative
indices), ``mtllib`` and ``usemtl`` with one ``map_Kd`` texture image.

PLY: ``ascii``, ``binary_little_endian`` and ``binary_big_endian``; vertex
``x y z``, colours ``red green blue [alpha]`` (uchar, ushort or float), per-vertex
texture coordinates (``s t``, ``u v`` or ``texture_u texture_v``, as Blender
writes them), faces ``vertex_indices`` (or ``vertex_index``) with a per-face
``texcoord`` list (as MeshLab writes it) and the texture named by a
``comment TextureFile`` line.

Polygons with more than three corners are split into fans of triangles.
Normals, groups, materials other than the texture, and lines are ignored.
Vertices must be finite and faces must index them (refused at read time,
naming the line or element); the files a mesh names (material, texture) are
followed only inside the mesh's folder unless ``allow_outside=True``.
"""

from __future__ import annotations

import importlib
import os
import re
import warnings
from pathlib import Path

import numpy as np

from ..core._extras import install_hint
from ..core._validate import check_bool
from ..core.files import as_path, atomic_write, prepare_target
from ..io import load_image, save_image
from ._mesh import Mesh, checked

__all__ = ["as_mesh", "read_mesh", "write_mesh"]

_NATIVE = {".obj", ".ply"}
_PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
              "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
              "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}
_PLY_UV_NAMES = (("s", "t"), ("u", "v"), ("texture_u", "texture_v"), ("texture_s", "texture_t"))


class _Garbled(ValueError):
    """A file that is not what its suffix says; read_mesh adds the file name."""


# ---------------------------------------------------------------------------- shared helpers
def _fan(polygons):
    """Triangles ``(0, k, k + 1)`` of polygons given as an ``(L, n)`` array of corners (any trailing shape)."""
    n = polygons.shape[1]
    if n < 3:
        raise _Garbled(f"a face has {n} corners; faces need at least 3")
    k = np.arange(1, n - 1)
    return np.stack([np.broadcast_to(polygons[:, :1], (len(polygons), n - 2) + polygons.shape[2:]),
                     polygons[:, k], polygons[:, k + 1]], axis=2).reshape((-1, 3) + polygons.shape[2:])


def _triangulate(polygons, *per_corner):
    """Fan triangles of polygons of mixed sizes, in file order, and the same split of per-corner data.

    ``polygons`` and each of ``per_corner`` are sequences with one entry per polygon, an entry holding
    one value (or row) per corner. Polygons of one size are fanned together.
    """
    counts = np.array([len(p) for p in polygons])
    pieces, source = [], []
    for n in np.unique(counts):
        chosen = np.flatnonzero(counts == n)
        pieces.append([_fan(np.array([values[i] for i in chosen])) for values in (polygons, *per_corner)])
        source.append(np.repeat(chosen, n - 2))
    order = np.argsort(np.concatenate(source), kind="stable")  # back to file order, fans kept together
    return [np.concatenate([piece[k] for piece in pieces])[order] for k in range(1 + len(per_corner))]


def _colors_from_file(values, what):
    """Colour values read from a file as floats in [0, 1]: [0, 1] as is, whole numbers up to 255 divided by 255."""
    if values.size == 0 or values.max() <= 1:
        return np.clip(values, 0, 1)
    if values.max() <= 255 and np.all(values == np.round(values)):
        return values / 255.0
    raise _Garbled(f"{what} are not in [0, 1] or 0..255 (largest {values.max():.4g})")


def _inside(path, name, what, allow_outside):
    """``name``, a file the mesh file ``path`` refers to (``what``: where and how), relative to the mesh's
    folder; refused if it leads out of that folder (``../``, an absolute path, a link), unless ``allow_outside``."""
    folder = path.parent.resolve()
    target = folder / name
    if not allow_outside and not target.resolve().is_relative_to(folder):
        raise _Garbled(f"{what} {name!r} is outside the mesh's folder ({folder}); copy the file into that folder, or "
                       "pass allow_outside=True if you trust the mesh file")
    return target


def _texture_beside(path, name, what, allow_outside):
    """The texture image ``name`` (relative to the mesh file's folder), or None with a warning if unreadable."""
    image_path = _inside(path, name, what, allow_outside)
    try:
        return load_image(image_path)
    except (OSError, ValueError) as exc:
        warnings.warn(f"{str(path)!r} names the texture {name!r}, which cannot be read ({exc}); the mesh is read "
                      "without it (its uv coordinates are kept)", stacklevel=4)
        return None


# ---------------------------------------------------------------------------- OBJ
def _obj_index(token, count, line_number, what):
    """A 0-based index from an OBJ index token (1-based, or negative: relative to the ``count`` read so far)."""
    try:
        value = int(token)
    except ValueError:
        raise _Garbled(f"line {line_number}: {token!r} is not a {what} index") from None
    if value == 0:
        raise _Garbled(f"line {line_number}: {what} index 0 (OBJ indices count from 1)")
    if value < -count:
        raise _Garbled(f"line {line_number}: {what} index {value} points before the first {what} ({count} read so "
                       "far)")
    return value - 1 if value > 0 else count + value


def _obj_line(text, key, k):
    """The number of the ``k``-th (0-based) line of ``text`` that starts with ``key``, for an error message."""
    lines = (number for number, line in enumerate(text.splitlines(), 1) if line.split()[:1] == [key])
    return next(number for i, number in enumerate(lines) if i == k)


def _read_mtl(path, name, line_number, allow_outside):
    """``{material: texture file}`` of the ``map_Kd`` lines of an MTL file (empty if it cannot be read) and
    ``{texture file: where it is named}``."""
    mtl_path = _inside(path, name, f"line {line_number}: mtllib", allow_outside)
    try:
        text = mtl_path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        warnings.warn(f"{str(path)!r} names the material file {name!r}, which cannot be read ({exc}); the mesh is "
                      "read without its texture", stacklevel=4)
        return {}, {}
    textures, named, material = {}, {}, None
    for number, line in enumerate(text.splitlines(), 1):
        words = line.split()
        if len(words) >= 2 and words[0] == "newmtl":
            material = " ".join(words[1:])
        elif len(words) >= 2 and words[0] == "map_Kd" and material is not None:
            # options (-s 1 1 1, -clamp on, ...) come first; the file name is the rest of the line after them
            textures[material] = re.sub(r"^(?:-\w+(?:\s+[-+\d.eE]+|\s+on|\s+off)*\s+)*", "",
                                        line.split(None, 1)[1].strip())
            named.setdefault(textures[material], f"{name} line {number}: map_Kd")
    return textures, named


def _read_obj(path, allow_outside):
    positions, colors, texcoords = [], [], []
    corners_v, corners_vt, face_material = [], [], []
    material, mtl_files = None, []
    text = path.read_text(encoding="utf-8", errors="replace")
    for line_number, line in enumerate(text.splitlines(), 1):
        words = line.split()
        if not words or words[0].startswith("#"):
            continue
        key = words[0]
        try:
            if key == "v":
                if len(words) not in (4, 5, 7, 8):
                    raise _Garbled(f"line {line_number}: a vertex needs x y z [w] or x y z r g b, got "
                                   f"{len(words) - 1} numbers")
                positions.append([float(w) for w in words[1:4]])
                colors.append([float(w) for w in words[4:7]] if len(words) >= 7 else None)
            elif key == "vt":
                texcoords.append([float(w) for w in words[1:3]] if len(words) >= 3 else [float(words[1]), 0.0])
            elif key == "f":
                if len(words) < 4:
                    raise _Garbled(f"line {line_number}: a face needs at least 3 corners, got {len(words) - 1}")
                v, vt = [], []
                for corner in words[1:]:
                    parts = corner.split("/")
                    v.append(_obj_index(parts[0], len(positions), line_number, "vertex"))
                    has_vt = len(parts) > 1 and parts[1] != ""
                    vt.append(_obj_index(parts[1], len(texcoords), line_number, "texture") if has_vt else -1)
                corners_v.append(v)
                corners_vt.append(vt)
                face_material.append(material)
            elif key == "mtllib":
                mtl_files.append((line.split(None, 1)[1].strip(), line_number))
            elif key == "usemtl":
                material = line.split(None, 1)[1].strip() if len(words) > 1 else None
        except _Garbled:
            raise
        except (ValueError, IndexError) as exc:
            raise _Garbled(f"line {line_number}: cannot read {line.strip()[:60]!r} ({exc})") from None
    vertices = np.array(positions, dtype=np.float64).reshape(-1, 3)
    bad = np.flatnonzero(~np.isfinite(vertices).all(axis=1))
    if len(bad):
        raise _Garbled(f"line {_obj_line(text, 'v', bad[0])}: vertex {tuple(vertices[bad[0]].tolist())} is not "
                       "finite; a mesh needs real coordinates")
    top = np.fromiter(map(max, corners_v), np.int64, len(corners_v))  # negative indices were checked as read
    bad = np.flatnonzero(top >= len(vertices))
    if len(bad):
        raise _Garbled(f"line {_obj_line(text, 'f', bad[0])}: a face uses vertex {top[bad[0]] + 1}, but the file "
                       f"has {len(vertices)} vertices")
    if not corners_v:
        return Mesh(vertices, np.zeros((0, 3), np.int64))
    faces, faces_vt, face_material = _triangulate(corners_v, corners_vt, [[m] * len(c) for m, c in
                                                                          zip(face_material, corners_v)])
    face_material = face_material[:, 0]

    vertex_colors = None
    if colors and all(c is not None for c in colors):
        vertex_colors = _colors_from_file(np.array(colors, dtype=np.float64), "vertex colours (v x y z r g b)")
    uv = texture = None
    if len(faces) and np.all(faces_vt >= 0):
        if faces_vt.max() >= len(texcoords) or faces_vt.min() < 0:
            raise _Garbled(f"a face uses texture coordinate {faces_vt.max() + 1}, but the file has "
                           f"{len(texcoords)} vt lines")
        uv = np.array(texcoords, dtype=np.float64)[faces_vt]
        textures, named = {}, {}
        for name, line_number in mtl_files:
            found, where = _read_mtl(path, name, line_number, allow_outside)
            textures.update(found)
            named.update(where)
        used = {textures[m] for m in set(face_material) if m in textures}
        if len(used) > 1:
            warnings.warn(f"{str(path)!r} uses {len(used)} texture images ({sorted(used)}); a texsynth Mesh holds "
                          "one, so the mesh is read without a texture (its uv coordinates are kept)", stacklevel=3)
        elif used:
            name = used.pop()
            texture = _texture_beside(path, name, named[name], allow_outside)
    elif np.any(faces_vt >= 0):
        warnings.warn(f"{str(path)!r}: only some faces have texture coordinates; the mesh is read without them",
                      stacklevel=3)
    return Mesh(vertices, faces, colors=vertex_colors, uv=uv, texture=texture)


def _format_rows(prefix, rows, spec):
    """Text lines ``prefix`` + the formatted numbers of each row (one % operation for all rows)."""
    rows = np.asarray(rows)
    if rows.size == 0:
        return ""
    line = prefix + " ".join([spec] * rows.shape[1]) + "\n"
    return (line * len(rows)) % tuple(rows.ravel().tolist())


def _write_obj(path, mesh, overwrite):
    targets = [path]
    if mesh.texture is not None:
        targets += [path.with_suffix(".mtl"), path.with_suffix(".png")]
    for target in targets:
        prepare_target(target, overwrite)
    parts = ["# written by texsynth\n"]
    if mesh.texture is not None:
        parts.append(f"mtllib {targets[1].name}\n")
    rows = mesh.vertices
    if mesh.colors is not None:  # the v x y z r g b extension: RGB, grey repeated, alpha dropped
        rgb = mesh.colors[:, :3] if mesh.colors.shape[1] >= 3 else np.repeat(mesh.colors[:, :1], 3, axis=1)
        rows = np.hstack([rows, rgb.astype(np.float64)])
    parts.append(_format_rows("v ", rows, "%.17g"))  # 17 digits: float64 read back exactly
    if mesh.uv is not None:
        unique_uv, corner_vt = np.unique(mesh.uv.reshape(-1, 2), axis=0, return_inverse=True)
        parts.append(_format_rows("vt ", unique_uv, "%.17g"))
        if mesh.texture is not None:
            parts.append("usemtl texture\n")
        corners = np.stack([mesh.faces + 1, corner_vt.reshape(-1, 3) + 1], axis=2)
        parts.append(("f %d/%d %d/%d %d/%d\n" * len(corners)) % tuple(corners.ravel().tolist()))
    else:
        parts.append(_format_rows("f ", mesh.faces + 1, "%d"))
    if mesh.texture is not None:
        save_image(targets[2], mesh.texture, overwrite=True)
        mtl = f"# written by texsynth\nnewmtl texture\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nmap_Kd {targets[2].name}\n"
        atomic_write(targets[1], lambda tmp: Path(tmp).write_text(mtl, encoding="utf-8"))
    text = "".join(parts)
    atomic_write(path, lambda tmp: Path(tmp).write_text(text, encoding="utf-8"))


# ---------------------------------------------------------------------------- PLY
def _ply_header(data):
    """(format, [(element, count, [(property, dtype) or (property, count dtype, item dtype)])], comments, body offset)."""
    end = data.find(b"end_header")
    if not data.startswith(b"ply") or end < 0:
        raise _Garbled("it does not start with 'ply' or has no 'end_header' line: this is not a PLY file")
    newline = data.find(b"\n", end)
    body = len(data) if newline < 0 else newline + 1
    fmt, elements, comments = None, [], []
    for number, line in enumerate(data[:end].decode("ascii", errors="replace").splitlines()[1:], 2):
        words = line.split()
        if not words:
            continue
        if words[0] == "format" and len(words) >= 2:
            fmt = words[1]
        elif words[0] == "comment":
            comments.append(line.split(None, 1)[1] if len(words) > 1 else "")
        elif words[0] == "element" and len(words) == 3 and words[2].isdigit():
            elements.append((words[1], int(words[2]), []))
        elif words[0] == "property" and elements:
            if len(words) == 5 and words[1] == "list" and words[2] in _PLY_TYPES and words[3] in _PLY_TYPES:
                elements[-1][2].append((words[4], _PLY_TYPES[words[2]], _PLY_TYPES[words[3]]))
            elif len(words) == 3 and words[1] in _PLY_TYPES:
                elements[-1][2].append((words[2], _PLY_TYPES[words[1]]))
            else:
                raise _Garbled(f"header line {number}: cannot read property {line.strip()!r}")
        elif words[0] not in ("obj_info",):
            raise _Garbled(f"header line {number}: cannot read {line.strip()!r}")
    if fmt not in ("ascii", "binary_little_endian", "binary_big_endian"):
        raise _Garbled(f"format {fmt!r}; expected ascii, binary_little_endian or binary_big_endian")
    return fmt, elements, comments, body


def _ply_read_element(stream, pos, count, props, fmt):
    """Read ``count`` rows of one element from ``pos``; return ({property: array or list of arrays}, new pos).

    Scalars become ``(count,)`` arrays, lists ``(count, n)`` arrays when every row has ``n`` items (the
    common case, read in one go), else lists of arrays.
    """
    ascii_ = fmt == "ascii"
    order = ">" if fmt == "binary_big_endian" else "<"
    if count == 0:
        return {p[0]: np.zeros((0,) if len(p) == 2 else (0, 0)) for p in props}, pos
    # the layout of the first row decides a fixed row layout, checked on every row
    layout, cursor = [], pos
    for p in props:
        if len(p) == 2:
            layout.append((p[0], p[1], None))
            cursor += 1 if ascii_ else np.dtype(p[1]).itemsize
        else:
            if ascii_:
                n = int(stream[cursor]) if cursor < len(stream) else 0
            else:
                n = int(np.frombuffer(stream, order + p[1], 1, cursor)[0]) if cursor < len(stream) else 0
            layout.append((p[0], p[1], (n, p[2])))
            cursor += 1 + n if ascii_ else np.dtype(p[1]).itemsize + n * np.dtype(p[2]).itemsize
    if ascii_:
        width = cursor - pos
        rows = stream[pos:pos + width * count]
        if len(rows) == width * count:
            rows = rows.reshape(count, width)
            out, col, fixed = {}, 0, True
            for name, kind, lst in layout:
                if lst is None:
                    out[name] = rows[:, col]
                    col += 1
                else:
                    fixed &= bool(np.all(rows[:, col] == lst[0]))
                    out[name] = rows[:, col + 1:col + 1 + lst[0]]
                    col += 1 + lst[0]
            if fixed:
                return out, pos + width * count
    else:
        fields = []
        for name, kind, lst in layout:
            if lst is None:
                fields.append((name, order + kind))
            else:
                fields += [(name + "#count", order + kind), (name, order + lst[1], (lst[0],))]
        row = np.dtype(fields)
        if len(stream) - pos >= row.itemsize * count:
            rows = np.frombuffer(stream, row, count, pos)
            if all(np.all(rows[name + "#count"] == lst[0]) for name, _, lst in layout if lst is not None):
                return {name: rows[name] for name, _, _ in layout}, pos + row.itemsize * count
    return _ply_read_rows(stream, pos, count, props, fmt)


def _ply_read_rows(stream, pos, count, props, fmt):
    """Row by row, for elements whose list lengths vary (polygons of different sizes)."""
    order = ">" if fmt == "binary_big_endian" else "<"
    out = {p[0]: [] for p in props}
    try:
        for _ in range(count):
            for p in props:
                if fmt == "ascii":
                    if len(p) == 2:
                        out[p[0]].append(stream[pos])
                        pos += 1
                    else:
                        n = int(stream[pos])
                        out[p[0]].append(stream[pos + 1:pos + 1 + n])
                        pos += 1 + n
                else:
                    if len(p) == 2:
                        out[p[0]].append(np.frombuffer(stream, order + p[1], 1, pos)[0])
                        pos += np.dtype(p[1]).itemsize
                    else:
                        n = int(np.frombuffer(stream, order + p[1], 1, pos)[0])
                        pos += np.dtype(p[1]).itemsize
                        out[p[0]].append(np.frombuffer(stream, order + p[2], n, pos))
                        pos += n * np.dtype(p[2]).itemsize
    except (IndexError, ValueError):
        pos = len(stream) + 1
    if pos > len(stream):
        raise _Garbled("the data end before the header's element counts are reached (truncated file?)")
    return {p[0]: np.array(out[p[0]]) if len(p) == 2 else out[p[0]] for p in props}, pos


def _ply_check_faces(polygons, n):
    """Refuse a face (a row of ``polygons``: an array or a list of arrays) with a vertex index outside 0..n-1."""
    if isinstance(polygons, np.ndarray):
        if polygons.size == 0 or 0 <= polygons.min() and polygons.max() < n:
            return
        wrong = ((polygons < 0) | (polygons >= n)).any(axis=1)
    else:
        wrong = np.array([len(p) > 0 and (np.min(p) < 0 or np.max(p) >= n) for p in polygons], dtype=bool)
    if wrong.any():
        face = int(np.argmax(wrong))
        corners = np.asarray(polygons[face], np.int64)
        index = corners[(corners < 0) | (corners >= n)][0]
        raise _Garbled(f"face {face} (element face) uses vertex {index}, but the file has {n} vertices"
                       + (f" (0..{n - 1})" if n else ""))


def _read_ply(path, allow_outside):
    data = path.read_bytes()
    fmt, elements, comments, body = _ply_header(data)
    if fmt == "ascii":
        try:
            stream = np.array(data[body:].split(), dtype=np.float64)
        except ValueError:
            raise _Garbled("the ascii data hold something that is not a number") from None
    else:
        stream = data
    pos, found = 0 if fmt == "ascii" else body, {}
    for name, count, props in elements:
        found[name], pos = _ply_read_element(stream, pos, count, props, fmt)
        if "vertex" in found and "face" in found:  # later elements (edges, materials) are not needed
            break
    if "vertex" not in found:
        raise _Garbled("no 'element vertex' in the header")
    vert = found["vertex"]
    missing = [c for c in "xyz" if c not in vert]
    if missing:
        raise _Garbled(f"the vertices have no {'/'.join(missing)} property")
    vertices = np.stack([np.asarray(vert[c], dtype=np.float64) for c in "xyz"], axis=1)
    bad = np.flatnonzero(~np.isfinite(vertices).all(axis=1))
    if len(bad):
        raise _Garbled(f"vertex {bad[0]} (element vertex) is {tuple(vertices[bad[0]].tolist())}, not finite "
                       f"({len(bad)} such vertices); a mesh needs real coordinates")
    colors = None
    channels = [c for c in ("red", "green", "blue", "alpha") if c in vert]
    if channels[:3] == ["red", "green", "blue"]:
        vertex_props = next(props for name, _, props in elements if name == "vertex")
        kinds = {p[1] for p in vertex_props if p[0] in channels}
        values = np.stack([np.asarray(vert[c], dtype=np.float64) for c in channels], axis=1)
        white = 255.0 if kinds <= {"u1"} else 65535.0 if kinds <= {"u2"} else 1.0
        colors = _colors_from_file(values / white, "vertex colours")
    face = found.get("face")
    if face is None:
        raise _Garbled("no 'element face' in the header (a point cloud?); texsynth needs a triangle mesh")
    key = "vertex_indices" if "vertex_indices" in face else "vertex_index" if "vertex_index" in face else None
    if key is None:
        raise _Garbled("the faces have no vertex_indices list")
    polygons = face[key]
    _ply_check_faces(polygons, len(vertices))
    texcoord = face.get("texcoord")
    fixed = isinstance(polygons, np.ndarray) and isinstance(texcoord, np.ndarray)
    if texcoord is not None and (texcoord.shape[1] != 2 * polygons.shape[1] if fixed else
                                 any(len(t) != 2 * len(p) for p, t in zip(polygons, texcoord))):
        warnings.warn(f"{str(path)!r}: some faces' texcoord lists do not hold one (u, v) pair per corner; the mesh "
                      "is read without texture coordinates", stacklevel=3)
        texcoord = None
    if isinstance(polygons, np.ndarray) and (texcoord is None or isinstance(texcoord, np.ndarray)):  # one size
        faces = _fan(polygons.astype(np.int64))
        corner_uv = None if texcoord is None else _fan(texcoord.astype(np.float64).reshape(len(polygons), -1, 2))
    elif texcoord is None:  # polygons of different sizes
        faces, = _triangulate([np.asarray(p, np.int64) for p in polygons])
        corner_uv = None
    else:
        faces, corner_uv = _triangulate([np.asarray(p, np.int64) for p in polygons],
                                        [np.asarray(t, np.float64).reshape(-1, 2) for t in texcoord])
    if corner_uv is None:
        for u, v in _PLY_UV_NAMES:
            if u in vert and v in vert:
                corner_uv = np.stack([vert[u], vert[v]], axis=1).astype(np.float64)[faces]
                break
    texture = None
    if corner_uv is not None:
        names = [c.split(None, 1)[1] for c in comments if c.startswith("TextureFile") and len(c.split()) > 1]
        if names:
            texture = _texture_beside(path, names[0].strip(), "comment TextureFile", allow_outside)
    return Mesh(vertices, faces, colors=colors, uv=corner_uv, texture=texture)


def _write_ply(path, mesh, overwrite):
    targets = [path] + ([path.with_suffix(".png")] if mesh.texture is not None else [])
    for target in targets:
        prepare_target(target, overwrite)
    header = ["ply", "format binary_little_endian 1.0", "comment written by texsynth"]
    if mesh.texture is not None:
        header.append(f"comment TextureFile {targets[1].name}")
    header += [f"element vertex {len(mesh.vertices)}", "property double x", "property double y", "property double z"]
    fields = [("x", "<f8"), ("y", "<f8"), ("z", "<f8")]
    if mesh.colors is not None:
        c = mesh.colors.shape[1]
        rgba = np.repeat(mesh.colors[:, :1], 3, axis=1) if c <= 2 else mesh.colors[:, :3]
        if c in (2, 4):
            rgba = np.hstack([rgba, mesh.colors[:, -1:]])
        names = ["red", "green", "blue", "alpha"][:rgba.shape[1]]
        header += [f"property uchar {n}" for n in names]
        fields += [(n, "u1") for n in names]
    vertex_rows = np.empty(len(mesh.vertices), dtype=fields)
    for k, axis in enumerate("xyz"):
        vertex_rows[axis] = mesh.vertices[:, k]
    if mesh.colors is not None:
        byte = np.round(rgba.astype(np.float64) * 255).astype(np.uint8)
        for k, n in enumerate(names):
            vertex_rows[n] = byte[:, k]
    header += [f"element face {len(mesh.faces)}", "property list uchar int vertex_indices"]
    face_fields = [("n", "u1"), ("vertex_indices", "<i4", (3,))]
    if mesh.uv is not None:
        header.append("property list uchar float texcoord")
        face_fields += [("m", "u1"), ("texcoord", "<f4", (6,))]
    face_rows = np.empty(len(mesh.faces), dtype=face_fields)
    face_rows["n"] = 3
    face_rows["vertex_indices"] = mesh.faces
    if mesh.uv is not None:
        face_rows["m"] = 6
        face_rows["texcoord"] = mesh.uv.reshape(-1, 6)
    data = ("\n".join(header + ["end_header"]) + "\n").encode("ascii") + vertex_rows.tobytes() + face_rows.tobytes()
    if mesh.texture is not None:
        save_image(targets[1], mesh.texture, overwrite=True)
    atomic_write(path, lambda tmp: Path(tmp).write_bytes(data))


# ---------------------------------------------------------------------------- other formats (trimesh)
def _trimesh():
    try:
        return importlib.import_module("trimesh")
    except ModuleNotFoundError:
        raise ModuleNotFoundError("formats other than .obj and .ply are read and written through trimesh, which is "
                                  f"not installed; {install_hint('mesh')}") from None


def _read_other(path):
    trimesh = _trimesh()
    try:
        loaded = trimesh.load(str(path), force="mesh", process=False)
    except Exception as exc:  # trimesh raises many types; one clear message
        raise _Garbled(f"trimesh cannot read it ({type(exc).__name__}: {exc})") from None
    if path.suffix.lower() == ".stl":  # STL stores each triangle's corners separately: join equal ones
        loaded.merge_vertices()
    faces = np.asarray(loaded.faces, dtype=np.int64)
    colors = uv = texture = None
    visual = loaded.visual
    if getattr(visual, "kind", None) == "vertex":
        colors = np.asarray(visual.vertex_colors, dtype=np.float64) / 255.0
    elif getattr(visual, "kind", None) == "texture" and getattr(visual, "uv", None) is not None:
        uv = np.asarray(visual.uv, dtype=np.float64)[faces]
        image = getattr(getattr(visual, "material", None), "image", None)
        if image is not None:
            texture = np.asarray(image)
    return Mesh(np.asarray(loaded.vertices, dtype=np.float64), faces, colors=colors, uv=uv, texture=texture)


def _write_other(path, mesh, overwrite):
    trimesh = _trimesh()
    prepare_target(path, overwrite)
    colors = None
    if mesh.colors is not None:
        c = mesh.colors.shape[1]
        colors = np.repeat(mesh.colors[:, :1], 3, axis=1) if c <= 2 else mesh.colors[:, :3]
        colors = np.round(np.hstack([colors, mesh.colors[:, -1:] if c in (2, 4) else np.ones((len(colors), 1))])
                          * 255).astype(np.uint8)
    out = trimesh.Trimesh(mesh.vertices, mesh.faces, vertex_colors=colors, process=False)
    suffix = path.suffix.lower().lstrip(".")
    try:
        atomic_write(path, lambda tmp: out.export(tmp, file_type=suffix))
    except (ValueError, KeyError, NotImplementedError) as exc:
        raise ValueError(f"path {str(path)!r}: trimesh cannot write {suffix!r} files ({exc}); use .obj or .ply"
                         ) from None


# ---------------------------------------------------------------------------- public
def as_mesh(value, name="mesh"):
    """Check a mesh and return it as a :class:`Mesh`.

    Parameters
    ----------
    value : Mesh, (vertices, faces) tuple, str or os.PathLike
        A mesh, a pair of arrays ``(N, 3)`` and ``(M, 3)``, or the path of a
        mesh file (read with :func:`texsynth.surface.read_mesh`).
    name : str
        Parameter name used in error messages.

    Returns
    -------
    Mesh
        ``value`` itself when it is a valid :class:`Mesh`.

    Raises
    ------
    TypeError
        For anything else, or arrays of the wrong type.
    ValueError
        For an empty mesh, NaN or infinite vertices, face indices out of
        range, zero-area faces, isolated vertices, or edges shared by more
        than two faces: the message names ``name``, counts the offenders,
        gives the first and says how to fix it.

    Warns
    -----
    UserWarning
        If two faces run along their shared edge in the same direction (their
        orientations disagree, so the normals flip between them); the mesh is
        still returned. The checks run once per mesh object.

    Examples
    --------
    >>> as_mesh(([[0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 5, 5]], [[0, 1, 2]]), "surface")
    Traceback (most recent call last):
    ...
    ValueError: surface has 1 isolated vertices that no face uses (first: vertex 3); remove the unused vertices with surface.compact()
    """
    if isinstance(value, (str, bytes, os.PathLike)):
        value = read_mesh(value)
    return checked(value, name)


def read_mesh(path, *, allow_outside=False):
    """Read a triangle mesh from a file.

    Examples
    --------
    >>> import tempfile, texsynth
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = texsynth.write_mesh(folder + "/ball.ply", texsynth.surface.sphere(42))
    ...     texsynth.read_mesh(path)
    Mesh(42 vertices, 80 faces)

    Parameters
    ----------
    path : str or os.PathLike
        An ``.obj`` (with its ``.mtl`` and texture image) or ``.ply`` file,
        read by texsynth itself; any other suffix (``.stl``, ``.off``,
        ``.glb``, ...) is read through trimesh (``pip install '.[mesh]'`` in a checkout).
    allow_outside : bool
        Follow the files an OBJ or PLY file names (``mtllib``, ``map_Kd``,
        ``comment TextureFile``) wherever they are. Off by default: a mesh
        file from elsewhere may only name files in its own folder or below
        it, not ``../..`` or an absolute path, so reading it cannot read
        other files of the machine. (Formats read through trimesh are not
        covered.)

    Returns
    -------
    Mesh
        With per-vertex ``colors`` if the file has them, ``uv`` if every face
        has texture coordinates, and ``texture`` if the file names a readable
        image. Polygons are split into triangle fans. The mesh is returned as
        read: pass it to :func:`as_mesh` to check it (every surface method
        does).

    Raises
    ------
    TypeError
        If ``path`` is not a str or os.PathLike.
    FileNotFoundError
        If ``path`` does not exist or is a folder.
    ValueError
        If the file is not a mesh of its format or is cut short, has a NaN or
        infinite vertex, a face whose vertex index is past the vertex list,
        or names a file outside its folder without ``allow_outside``; the
        message names the file, the line (OBJ) or element (PLY), and what is
        wrong.
    ModuleNotFoundError
        For a format other than OBJ and PLY without trimesh installed.

    Warns
    -----
    UserWarning
        If a texture or material file the mesh names cannot be read (the mesh
        is read without it), or an OBJ uses more than one texture image.

    """
    path = as_path(path)
    allow_outside = check_bool(allow_outside, "allow_outside")
    if path.is_dir():
        raise FileNotFoundError(f"path {str(path)!r} is a folder, not a mesh file")
    if not path.is_file():
        raise FileNotFoundError(f"path {str(path)!r} does not exist or is not a file")
    suffix = path.suffix.lower()
    reader = {".obj": _read_obj, ".ply": _read_ply}.get(suffix)
    try:
        mesh = reader(path, allow_outside) if reader else _read_other(path)
        if len(mesh.faces) == 0:
            raise _Garbled(f"it holds no faces ({len(mesh.vertices)} vertices: a point cloud?); texsynth needs a "
                           "triangle mesh")
        return mesh
    except _Garbled as exc:
        raise ValueError(f"cannot read {str(path)!r} as a {suffix.lstrip('.').upper() or 'mesh'} mesh: {exc}"
                         ) from None
    except (TypeError, ValueError) as exc:  # arrays that do not make a Mesh (e.g. faces out of shape)
        raise ValueError(f"cannot read {str(path)!r} as a mesh: {exc}") from None


def write_mesh(path, mesh, *, overwrite=False):
    """Write a triangle mesh atomically.

    Examples
    --------
    >>> import tempfile, texsynth
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = texsynth.write_mesh(folder + "/ball.obj", texsynth.surface.sphere(42))
    ...     print(path.name, texsynth.read_mesh(path))
    ball.obj Mesh(42 vertices, 80 faces)

    Parameters
    ----------
    path : str or os.PathLike
        ``.obj``: text, vertex colours as ``v x y z r g b`` (RGB; grey is
        repeated, alpha dropped), ``vt`` and ``f v/vt``; a texture goes to
        ``<stem>.png`` and ``<stem>.mtl`` (``map_Kd``) beside it. ``.ply``:
        binary little-endian, double coordinates, colours as uchar ``red
        green blue [alpha]``, uv as a per-face ``texcoord`` list (as MeshLab
        and Blender write it), the texture as ``<stem>.png`` named by a
        ``comment TextureFile`` line. Any other suffix goes through trimesh
        (``pip install '.[mesh]'`` in a checkout; geometry and colours only).
    mesh : Mesh or (vertices, faces)
        The mesh; checked with :func:`as_mesh`.
    overwrite : bool
        Replace existing files (the mesh file and, with a texture, its
        ``.mtl`` and ``.png``). Off by default.

    Returns
    -------
    pathlib.Path
        The path of the mesh file.

    Raises
    ------
    FileExistsError
        If one of the files exists and ``overwrite`` is False (nothing is
        written then).
    FileNotFoundError
        If the folder of ``path`` does not exist.

    Notes
    -----
    Every file is written under a hidden temporary name beside its target and
    renamed when complete (:mod:`texsynth.io`), so a reader never sees half a
    file.
    """

    path = as_path(path)
    mesh = as_mesh(mesh, "mesh")
    overwrite = check_bool(overwrite, "overwrite")
    suffix = path.suffix.lower()
    if suffix == ".obj":
        _write_obj(path, mesh, overwrite)
    elif suffix == ".ply":
        _write_ply(path, mesh, overwrite)
    elif suffix == "":
        raise ValueError(f"path {str(path)!r} has no suffix; use .obj or .ply (or another format trimesh writes)")
    else:
        _write_other(path, mesh, overwrite)
    return path


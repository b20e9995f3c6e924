#!/usr/bin/python3
"""Headless mesh renderer: a software z-buffer rasterizer in numpy, PNG out.

usage:
  render.py MESH -o OUT.png [--view AZ,EL] [--size W,H] [--reference MESH] [--up x|y|z]
                            [--wire] [--flat] [--crease DEG] [--transparent] [--supersample S]
  render.py strip MESH [MESH ...] -o OUT.png [--csv STREAM.csv] [--count K] [--title T]
                            [same options as above but --reference]

Reads OBJ, OFF and PLY (ascii, binary little- and big-endian; what `meshlift decode`,
`meshlift stream -o` and draco_decoder write); polygons are fanned into triangles.

The camera is a perspective camera (30 degree field of view) looking at the centre of the bounding
box of a reference mesh (by default the mesh itself) from direction (azimuth, elevation) in
degrees around the up axis, at a distance where the bounding sphere fits, with the focal length
set so the reference's projection fills the image less a 5 % margin. Meshes rendered with the
same --reference are framed identically. Shading: see render().

`strip` renders several meshes (e.g. the DIR/prefix_<bytes>.ply files of `meshlift stream
IN.mlz --every N -o DIR`) with the camera of the last one (the one with most bytes when the names
carry byte counts) side by side, captioned with the bytes received and, given the `meshlift
stream --csv` file, bits per vertex and PSNR: how the model sharpens as it streams.

Exit codes as the meshlift CLI: 2 bad arguments, 3 unreadable or malformed input, 4 the output
cannot be written. Runs on Debian's /usr/bin/python3 with python3-numpy and python3-matplotlib.
"""
import argparse
import collections
import csv
import math
import os
import re
import sys

import numpy as np

EXIT_BAD_ARGUMENTS = 2
EXIT_BAD_INPUT = 3
EXIT_OUTPUT_ERROR = 4


class MeshReadError(Exception):
    """The file cannot be read as a mesh; the message names the reason."""


# ---------------------------------------------------------------------------------------------
# Readers: each returns (positions, triangles, polygon_edges) (PLY also its colours or None),
# checked into a Mesh by read_mesh.
# ---------------------------------------------------------------------------------------------

class Mesh(collections.namedtuple("Mesh", "positions triangles polygon_edges colours", defaults=(None,))):
    """positions (n, 3) float64; triangles (m, 3) int64; polygon_edges (m, 3) bool: whether the
    edge opposite corner i of a triangle is an edge of the polygon it was cut from (the wireframe
    draws those only, not the diagonals of fanned polygons); colours (n, 3) in [0, 1], the
    vertices' red, green, blue where a PLY file has them (as `meshlift decode` writes them), else
    None."""


def fan(k):
    """Corners and polygon edges of the fan (v0, v_i, v_i+1), i = 1..k-2, of a k-gon: the edge
    opposite corner 0 is always a polygon edge, the one opposite corner 1 (v0 v_i+1) only in the
    last triangle, the one opposite corner 2 (v0 v_i) only in the first."""
    return [((0, i, i + 1), (True, i + 1 == k - 1, i == 1)) for i in range(1, k - 1)]


def fan_triangles(polygons):
    """Triangles and polygon edges of each polygon given as a list of index lists."""
    triangles, edges = [], []
    for polygon in polygons:
        for corners, polygon_edges in fan(len(polygon)):
            triangles.append([polygon[c] for c in corners])
            edges.append(polygon_edges)
    return np.array(triangles, dtype=np.int64).reshape(-1, 3), np.array(edges, dtype=bool).reshape(-1, 3)


def all_edges(triangles):
    return np.ones(triangles.shape, dtype=bool)


def check_mesh(path, positions, triangles, edges, colours=None):
    if positions.shape[0] == 0:
        raise MeshReadError("%s: the mesh has no vertices" % path)
    if triangles.shape[0] == 0:
        raise MeshReadError("%s: the mesh has no faces (%d vertices): nothing to render" % (path, positions.shape[0]))
    if triangles.size and (triangles.min() < 0 or triangles.max() >= positions.shape[0]):
        bad = int(np.flatnonzero((triangles < 0).any(axis=1) | (triangles >= positions.shape[0]).any(axis=1))[0])
        raise MeshReadError("%s: face %d refers to a vertex outside 0..%d" % (path, bad, positions.shape[0] - 1))
    if not np.isfinite(positions).all():
        raise MeshReadError("%s: non-finite vertex coordinates" % path)
    return Mesh(positions, triangles, edges, colours)


def read_obj(path, text):
    positions, polygons = [], []
    for number, line in enumerate(text.splitlines(), 1):
        words = line.split()
        if not words:
            continue
        if words[0] == "v":
            if len(words) < 4:
                raise MeshReadError("%s:%d: vertex with fewer than 3 coordinates" % (path, number))
            positions.append(words[1:4])
        elif words[0] == "f":
            polygon = []
            for word in words[1:]:
                index = int(word.split("/", 1)[0])
                # OBJ indices are 1-based; negative ones count back from the last vertex read.
                polygon.append(index - 1 if index > 0 else len(positions) + index)
            polygons.append(polygon)
    try:
        positions = np.array(positions, dtype=np.float64).reshape(-1, 3)
    except ValueError as error:
        raise MeshReadError("%s: malformed vertex line (%s)" % (path, error))
    return (positions, *fan_triangles(polygons))


def read_off(path, text):
    lines = []
    for line in text.splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            lines.append(line)
    if not lines:
        raise MeshReadError("%s: file is empty" % path)
    header = lines[0].split()
    keyword = header[0]
    if not keyword.endswith("OFF") or "4" in keyword or "n" in keyword:
        raise MeshReadError("%s: not a 3D OFF file (first word '%s')" % (path, keyword[:20]))
    if len(header) > 1 and header[1] == "BINARY":
        raise MeshReadError("%s: binary OFF is not supported" % path)
    counts, at = header[1:], 1
    if len(counts) < 2:
        counts, at = lines[1].split(), 2
    try:
        vertex_count, face_count = int(counts[0]), int(counts[1])
    except (ValueError, IndexError):
        raise MeshReadError("%s: no vertex and face counts after '%s'" % (path, keyword))
    if vertex_count < 0 or face_count < 0 or at + vertex_count + face_count > len(lines):
        raise MeshReadError("%s: counts %d vertices and %d faces exceed the file's %d lines"
                            % (path, vertex_count, face_count, len(lines) - at))
    try:
        positions = np.array([line.split()[:3] for line in lines[at:at + vertex_count]], dtype=np.float64)
        positions = positions.reshape(-1, 3)
        face_words = [line.split() for line in lines[at + vertex_count:at + vertex_count + face_count]]
        if face_words and all(w[0] == "3" for w in face_words):
            triangles = np.array([w[1:4] for w in face_words], dtype=np.int64).reshape(-1, 3)
            edges = all_edges(triangles)
        else:
            polygons = [[int(x) for x in w[1:1 + int(w[0])]] for w in face_words]
            triangles, edges = fan_triangles(polygons)
    except ValueError as error:
        raise MeshReadError("%s: malformed vertex or face line (%s)" % (path, error))
    return positions, triangles, edges


PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
             "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
             "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}


def read_ply(path, data):
    """PLY 1.0 (ascii, binary_little_endian, binary_big_endian): the vertex element's x, y, z and
    the face element's vertex_indices (or vertex_index) list; other elements and properties are
    skipped by their declared types."""
    end = data.find(b"end_header")
    if not data.startswith(b"ply") or end < 0:
        raise MeshReadError("%s: not a PLY file (no 'ply' ... 'end_header')" % path)
    body_start = data.index(b"\n", end) + 1 if b"\n" in data[end:] else len(data)
    fmt, elements = None, []
    for line in data[:end].decode("ascii", "replace").splitlines()[1:]:
        words = line.split()
        if not words or words[0] in ("comment", "obj_info"):
            continue
        if words[0] == "format" and len(words) >= 2:
            fmt = words[1]
        elif words[0] == "element" and len(words) == 3:
            elements.append((words[1], int(words[2]), []))
        elif words[0] == "property" and elements:
            if words[1] == "list" and len(words) == 5 and words[2] in PLY_TYPES and words[3] in PLY_TYPES:
                elements[-1][2].append((words[4], PLY_TYPES[words[3]], PLY_TYPES[words[2]]))
            elif len(words) == 3 and words[1] in PLY_TYPES:
                elements[-1][2].append((words[2], PLY_TYPES[words[1]], None))
            else:
                raise MeshReadError("%s: malformed PLY property line '%s'" % (path, line[:80]))
        else:
            raise MeshReadError("%s: malformed PLY header line '%s'" % (path, line[:80]))
    if fmt not in ("ascii", "binary_little_endian", "binary_big_endian"):
        raise MeshReadError("%s: unknown PLY format '%s'" % (path, fmt))
    values = {}
    if fmt == "ascii":
        words = data[body_start:].split()
        at = 0
        for name, count, properties in elements:
            at = _ply_ascii_element(path, words, at, name, count, properties, values)
    else:
        order = "<" if fmt == "binary_little_endian" else ">"
        at = body_start
        for name, count, properties in elements:
            at = _ply_binary_element(path, data, at, order, name, count, properties, values)
    if "vertex" not in values:
        raise MeshReadError("%s: no vertex element with x, y, z" % path)
    triangles, edges = values.get("face", (np.zeros((0, 3), dtype=np.int64), np.zeros((0, 3), dtype=bool)))
    return values["vertex"], triangles, edges, values.get("colour")


def _ply_keep(name, properties, columns, polygons, values, path):
    """Stores the vertex positions and face triangles of one parsed element."""
    names = [p[0] for p in properties]
    if name == "vertex":
        if not all(axis in names for axis in "xyz"):
            raise MeshReadError("%s: the vertex element has no x, y, z properties" % path)
        values["vertex"] = np.stack([columns[names.index(axis)] for axis in "xyz"], axis=1).astype(np.float64)
        # Vertex colours: red, green, blue (or diffuse_red, ...), an integer type over its largest
        # value (uchar: 255).
        for rgb in (("red", "green", "blue"), ("diffuse_red", "diffuse_green", "diffuse_blue")):
            if all(c in names for c in rgb):
                types = [properties[names.index(c)][1] for c in rgb]
                largest = [float(np.iinfo(t).max) if np.dtype(t).kind in "iu" else 1.0 for t in types]
                values["colour"] = np.clip(np.stack([columns[names.index(c)] / m for c, m in zip(rgb, largest)],
                                                    axis=1), 0, 1)
                break
    elif name == "face" and polygons is not None:
        values["face"] = polygons


def _ply_face_list(properties):
    for i, (name, _, count_type) in enumerate(properties):
        if count_type and name in ("vertex_indices", "vertex_index"):
            return i
    return None


def _ply_ascii_element(path, words, at, name, count, properties, values):
    if not any(p[2] for p in properties):
        width = len(properties)
        if at + width * count > len(words):
            raise MeshReadError("%s: the %s element is cut short" % (path, name))
        block = np.array(words[at:at + width * count], dtype=np.float64).reshape(count, width)
        _ply_keep(name, properties, [block[:, i] for i in range(width)], None, values, path)
        return at + width * count
    face_list = _ply_face_list(properties)
    polygons = []
    try:
        for _ in range(count):
            for i, (_, _, count_type) in enumerate(properties):
                if count_type is None:
                    at += 1
                    continue
                n = int(words[at])
                if i == face_list:
                    polygons.append([int(w) for w in words[at + 1:at + 1 + n]])
                at += 1 + n
    except (IndexError, ValueError):
        raise MeshReadError("%s: the %s element is cut short or malformed" % (path, name))
    if at > len(words):
        raise MeshReadError("%s: the %s element is cut short" % (path, name))
    _ply_keep(name, properties, None, fan_triangles(polygons) if face_list is not None else None, values, path)
    return at


def _ply_binary_element(path, data, at, order, name, count, properties, values):
    if not any(p[2] for p in properties):
        dtype = np.dtype([("p%d" % i, order + p[1]) for i, p in enumerate(properties)])
        if at + dtype.itemsize * count > len(data):
            raise MeshReadError("%s: the %s element is cut short" % (path, name))
        block = np.frombuffer(data, dtype=dtype, count=count, offset=at)
        _ply_keep(name, properties, [block["p%d" % i] for i in range(len(properties))], None, values, path)
        return at + dtype.itemsize * count
    face_list = _ply_face_list(properties)
    # Fast path: every list has the length of the first item's lists, so the element is a fixed
    # record; checked after reading, else item by item.
    if count > 0:
        fields, offset, fixed = [], at, True
        for i, (_, value_type, count_type) in enumerate(properties):
            size = np.dtype(count_type or value_type).itemsize
            if offset + size > len(data):
                raise MeshReadError("%s: the %s element is cut short" % (path, name))
            if count_type is None:
                fields.append(("p%d" % i, order + value_type))
                offset += size
                continue
            n = int(np.frombuffer(data, dtype=order + count_type, count=1, offset=offset)[0])
            fields.append(("n%d" % i, order + count_type))
            fields.append(("p%d" % i, order + value_type, (n,)))
            offset += size + n * np.dtype(value_type).itemsize
        dtype = np.dtype(fields)
        if at + dtype.itemsize * count <= len(data):
            block = np.frombuffer(data, dtype=dtype, count=count, offset=at)
            for i, (_, _, count_type) in enumerate(properties):
                if count_type and not (block["n%d" % i] == block["n%d" % i][0]).all():
                    fixed = False
            if fixed:
                polygons = None
                if face_list is not None:
                    lists = block["p%d" % face_list].astype(np.int64).reshape(count, -1)
                    pieces = fan(lists.shape[1])
                    polygons = (np.concatenate([lists[:, corners] for corners, _ in pieces]).reshape(-1, 3),
                                np.concatenate([np.tile(e, (count, 1)) for _, e in pieces]).reshape(-1, 3)) \
                        if pieces else (np.zeros((0, 3), dtype=np.int64), np.zeros((0, 3), dtype=bool))
                _ply_keep(name, properties, None, polygons, values, path)
                return at + dtype.itemsize * count
    polygons = []
    for _ in range(count):
        for i, (_, value_type, count_type) in enumerate(properties):
            size = np.dtype(count_type or value_type).itemsize
            if at + size > len(data):
                raise MeshReadError("%s: the %s element is cut short" % (path, name))
            if count_type is None:
                at += size
                continue
            n = int(np.frombuffer(data, dtype=order + count_type, count=1, offset=at)[0])
            at += size
            value_size = np.dtype(value_type).itemsize
            if n < 0 or at + n * value_size > len(data):
                raise MeshReadError("%s: the %s element is cut short" % (path, name))
            if i == face_list:
                polygons.append(np.frombuffer(data, dtype=order + value_type, count=n, offset=at).tolist())
            at += n * value_size
    _ply_keep(name, properties, None, fan_triangles(polygons) if face_list is not None else None, values, path)
    return at


def read_mesh(path):
    """Mesh (positions, triangles, polygon_edges) of an OBJ, OFF or PLY file; MeshReadError with
    the reason if not."""
    extension = os.path.splitext(path)[1].lower()
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as error:
        raise MeshReadError("%s: cannot read the file: %s" % (path, error.strerror))
    if not data.strip():
        raise MeshReadError("%s: file is empty" % path)
    if extension == ".ply":
        mesh = read_ply(path, data)
    elif extension == ".off":
        mesh = read_off(path, data.decode("latin-1"))
    elif extension == ".obj":
        mesh = read_obj(path, data.decode("latin-1"))
    else:
        raise MeshReadError("%s: unknown mesh file extension '%s' (supported: obj, off, ply)" % (path, extension))
    return check_mesh(path, *mesh)


# ---------------------------------------------------------------------------------------------
# Camera
# ---------------------------------------------------------------------------------------------

UP_AXES = {"x": (np.array([1.0, 0, 0]), np.array([0, 0, 1.0])),
           "y": (np.array([0, 1.0, 0]), np.array([0, 0, 1.0])),
           "z": (np.array([0, 0, 1.0]), np.array([0, -1.0, 0]))}


class Camera:
    """Pinhole camera: u = cx + focal * x_c / z_c, v = cy - focal * y_c / z_c with (x_c, y_c, z_c)
    the point in the camera frame (right, up, forward); z_c is the distance along the view axis."""

    def __init__(self, eye, right, up, forward, focal, cx, cy, width, height):
        self.eye, self.right, self.up, self.forward = eye, right, up, forward
        self.focal, self.cx, self.cy, self.width, self.height = focal, cx, cy, width, height

    def to_camera(self, points):
        relative = points - self.eye
        return relative @ self.right, relative @ self.up, relative @ self.forward

    def project(self, points):
        """Screen (u, v) in pixels (origin top-left, pixel centres at half-integers) and depth z."""
        x, y, z = self.to_camera(points)
        safe = np.where(z > 0, z, 1.0)
        return self.cx + self.focal * x / safe, self.cy - self.focal * y / safe, z

    def scaled(self, factor):
        return Camera(self.eye, self.right, self.up, self.forward, self.focal * factor, self.cx * factor,
                      self.cy * factor, self.width * factor, self.height * factor)


def make_camera(reference_positions, width, height, azimuth=30.0, elevation=20.0, up_axis="y",
                field_of_view=30.0, margin=0.05):
    """Camera looking at the bounding-box centre of reference_positions from (azimuth, elevation)."""
    up, front = UP_AXES[up_axis]
    side = np.cross(up, front)
    low, high = reference_positions.min(axis=0), reference_positions.max(axis=0)
    centre = (low + high) / 2
    radius = max(np.linalg.norm(high - low) / 2, 1e-12)
    a, e = math.radians(azimuth), math.radians(elevation)
    direction = math.cos(e) * (math.cos(a) * front + math.sin(a) * side) + math.sin(e) * up
    # The bounding sphere fits in the field of view at this distance, so the eye is outside it.
    eye = centre + direction * radius / math.sin(math.radians(field_of_view) / 2)
    forward = -direction
    right = np.cross(forward, up)
    if np.linalg.norm(right) < 1e-9:  # looking straight along the up axis
        right = np.cross(forward, front)
    right /= np.linalg.norm(right)
    camera_up = np.cross(right, forward)
    camera = Camera(eye, right, camera_up, forward, 1.0, 0.0, 0.0, width, height)
    # Focal length and centre so the reference's projection fills the image less the margin.
    x, y, z = camera.to_camera(reference_positions)
    sx, sy = x / z, y / z
    span_x, span_y = max(sx.max() - sx.min(), 1e-12), max(sy.max() - sy.min(), 1e-12)
    focal = min(width * (1 - 2 * margin) / span_x, height * (1 - 2 * margin) / span_y)
    camera.focal = focal
    camera.cx = width / 2 - focal * (sx.max() + sx.min()) / 2
    camera.cy = height / 2 + focal * (sy.max() + sy.min()) / 2
    return camera


# ---------------------------------------------------------------------------------------------
# Rasterizer
# ---------------------------------------------------------------------------------------------

def rasterize(u, v, depth, triangles, width, height, fragment_budget=1 << 22):
    """Z-buffer rasterization of screen-space triangles.

    u, v: vertex screen coordinates (pixel centres at x + 0.5, y + 0.5); depth: vertex depth z > 0
    (triangles with a vertex at z <= 0 are skipped). Returns the front triangle index per pixel
    (-1 where empty), shape (height, width), and the interpolated 1/z (0 where empty).

    A pixel centre p is inside when its barycentrics b_i = E_i(p) / E(p0, p1, p2) are all >= 0,
    with the edge function E(a, b, p) = (b - a) x (p - a) (Pineda 1988); 1/z is affine in screen
    space (perspective-correct depth), so the nearest fragment has the largest b . (1/z).
    Candidates are all pixel centres of each triangle's bounding box, processed in batches of at
    most fragment_budget so a few huge triangles do not need more memory than many small ones.
    """
    tri_u, tri_v, tri_z = u[triangles], v[triangles], depth[triangles]
    area = (tri_u[:, 1] - tri_u[:, 0]) * (tri_v[:, 2] - tri_v[:, 0]) - \
           (tri_u[:, 2] - tri_u[:, 0]) * (tri_v[:, 1] - tri_v[:, 0])
    x_min = np.ceil(tri_u.min(axis=1) - 0.5)
    x_max = np.floor(tri_u.max(axis=1) - 0.5)
    y_min = np.ceil(tri_v.min(axis=1) - 0.5)
    y_max = np.floor(tri_v.max(axis=1) - 0.5)
    with np.errstate(invalid="ignore"):
        keep = (tri_z > 0).all(axis=1) & (np.abs(area) > 1e-12) & np.isfinite(area) & \
               (x_max >= 0) & (y_max >= 0) & (x_min <= width - 1) & (y_min <= height - 1)
    index = np.flatnonzero(keep)
    x_min = np.clip(x_min[index], 0, width - 1).astype(np.int64)
    x_max = np.clip(x_max[index], 0, width - 1).astype(np.int64)
    y_min = np.clip(y_min[index], 0, height - 1).astype(np.int64)
    y_max = np.clip(y_max[index], 0, height - 1).astype(np.int64)
    box_width = np.maximum(x_max - x_min + 1, 0)
    candidates = box_width * np.maximum(y_max - y_min + 1, 0)
    # Barycentric b_i = alpha_i * px + beta_i * py + gamma_i, from E(p_j, p_k, p) / area.
    U, V, A = tri_u[index], tri_v[index], area[index]
    coefficients = []
    for i, j, k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
        alpha = -(V[:, k] - V[:, j]) / A
        beta = (U[:, k] - U[:, j]) / A
        gamma = ((V[:, k] - V[:, j]) * U[:, j] - (U[:, k] - U[:, j]) * V[:, j]) / A
        coefficients.append((alpha, beta, gamma))
    inverse_z = 1.0 / tri_z[index]
    # 1/z = sum_i b_i / z_i, itself affine in (px, py).
    depth_plane = [sum(coefficients[i][c] * inverse_z[:, i] for i in range(3)) for c in range(3)]

    front = np.full(width * height, -1, dtype=np.int64)
    nearest = np.zeros(width * height)
    ends = np.cumsum(candidates)
    start = 0
    while start < len(index):
        # Triangles [start, stop) hold at most fragment_budget candidates (at least one triangle).
        limit = (ends[start - 1] if start else 0) + fragment_budget
        stop = max(int(np.searchsorted(ends, limit, side="right")), start + 1)
        counts = candidates[start:stop]
        total = int(counts.sum())
        if total == 0:
            start = stop
            continue
        local_triangle = np.repeat(np.arange(start, stop), counts)
        first = np.cumsum(counts) - counts
        offset = np.arange(total) - np.repeat(first, counts)
        widths = box_width[local_triangle]
        px = x_min[local_triangle] + offset % widths
        py = y_min[local_triangle] + offset // widths
        cx, cy = px + 0.5, py + 0.5
        inside = np.ones(total, dtype=bool)
        for alpha, beta, gamma in coefficients:
            inside &= alpha[local_triangle] * cx + beta[local_triangle] * cy + gamma[local_triangle] >= 0
        t = local_triangle[inside]
        pixel = py[inside] * width + px[inside]
        w = depth_plane[0][t] * cx[inside] + depth_plane[1][t] * cy[inside] + depth_plane[2][t]
        # Nearest fragment per pixel within the batch (largest 1/z; ties to the lower triangle
        # index, so the result does not depend on the batching), then against the buffer.
        order = np.lexsort((t, -w, pixel))
        pixel, w, t = pixel[order], w[order], t[order]
        head = np.ones(len(pixel), dtype=bool)
        head[1:] = pixel[1:] != pixel[:-1]
        pixel, w, t = pixel[head], w[head], t[head]
        better = w > nearest[pixel]
        nearest[pixel[better]] = w[better]
        front[pixel[better]] = index[t[better]]
        start = stop
    return front.reshape(height, width), nearest.reshape(height, width)


# ---------------------------------------------------------------------------------------------
# Shading
# ---------------------------------------------------------------------------------------------

ALBEDO = np.array([0.70, 0.75, 0.82])
WIRE_COLOUR = np.array([0.12, 0.14, 0.20])


def face_normals(positions, triangles):
    """Unnormalized face normals (p1 - p0) x (p2 - p0): length twice the area."""
    p = positions[triangles]
    return np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])


def corner_normals(positions, triangles, normals_of_faces, crease_degrees=40.0):
    """Normal at each triangle corner, shape (m, 3, 3): the angle-weighted mean of the unit normals
    of the faces around the corner's vertex that are within crease_degrees of this corner's face,
    n_c = sum over faces f at v with n_f . n_t >= cos(crease) of angle_f(v) * n_f
    (angle weights: Thuermer and Wuethrich 1998, independent of how polygons were cut into
    triangles; the crease angle as mesh viewers have it, so a cube stays a cube and fandisk's
    edges stay sharp while smooth regions are smooth). Zero sums fall back to the face normal.
    Shortcut: where every face at v is within crease/2 of the angle-weighted vertex normal, any two
    are within the crease of each other, so every corner at v gets that vertex normal exactly; the
    pairwise sum (valence^2 work, one pass per neighbour slot) runs at the other vertices only."""
    m = len(triangles)
    p = positions[triangles]
    unit = normals_of_faces / np.maximum(np.linalg.norm(normals_of_faces, axis=1, keepdims=True), 1e-300)
    angles = np.empty((m, 3))
    for corner in range(3):
        a = p[:, (corner + 1) % 3] - p[:, corner]
        b = p[:, (corner + 2) % 3] - p[:, corner]
        angles[:, corner] = np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), (a * b).sum(axis=1))
    vertex_of_corner = triangles.ravel()
    angle_of_corner = angles.ravel()
    unit_of_corner = np.repeat(unit, 3, axis=0)
    vertex = np.stack([np.bincount(vertex_of_corner, weights=angle_of_corner * unit_of_corner[:, axis],
                                   minlength=len(positions)) for axis in range(3)], axis=1)
    vertex /= np.maximum(np.linalg.norm(vertex, axis=1, keepdims=True), 1e-300)
    result = vertex[vertex_of_corner]
    half_crease = (unit_of_corner * result).sum(axis=1) < math.cos(math.radians(crease_degrees / 2))
    on_crease = np.bincount(vertex_of_corner, weights=half_crease, minlength=len(positions)) > 0
    active = np.flatnonzero(on_crease[vertex_of_corner])
    result[active] = 0
    # Corners grouped by vertex (CSR): the j-th corner at vertex v is by_vertex[first[v] + j].
    by_vertex = np.argsort(vertex_of_corner, kind="stable")
    valence = np.bincount(vertex_of_corner, minlength=len(positions))
    first = np.cumsum(valence) - valence
    cosine = math.cos(math.radians(crease_degrees))
    for slot in range(int(valence[on_crease].max()) if on_crease.any() else 0):
        active = active[valence[vertex_of_corner[active]] > slot]
        neighbour = by_vertex[first[vertex_of_corner[active]] + slot]
        face, own = neighbour // 3, active // 3
        near = (unit[face] * unit[own]).sum(axis=1) >= cosine
        result[active[near]] += angle_of_corner[neighbour[near], None] * unit[face[near]]
    length = np.linalg.norm(result, axis=1, keepdims=True)
    result = np.where(length > 1e-300, result / np.maximum(length, 1e-300), unit_of_corner)
    return result.reshape(m, 3, 3)


def render(positions, triangles, camera, wire=False, flat=False, transparent=False, supersample=2,
           polygon_edges=None, crease_degrees=40.0, colours=None):
    """RGBA image (height, width, 4) in [0, 1] of the mesh seen by camera.

    The albedo is a light grey-blue, or with `colours` ((n, 3) in [0, 1] per vertex) the vertices'
    colours interpolated with the perspective-correct barycentrics below.

    Shading (two-sided: a normal facing away from the eye is flipped): ambient + Lambert from a key
    and a fill light set relative to the camera, plus Blinn-Phong specular from the key light,
    colour = albedo * (k_a + k_d max(0, n.l_key) + k_f max(0, n.l_fill)) + k_s max(0, n.h)^s
    (Phong 1975, Blinn 1977). Normals are per-pixel: vertex normals interpolated with
    perspective-correct barycentrics (b_i / z_i) / sum_j (b_j / z_j), or face normals with flat.
    Edges whose faces meet at more than crease_degrees stay sharp (corner_normals).
    The wireframe overlay darkens pixels within about half a pixel of the visible triangle's edges
    (distance to edge i = b_i * |2 area| / |edge i| in screen space), only edges marked in
    polygon_edges (default: all). Supersampling S renders at S times the size and averages S x S
    blocks (premultiplied alpha).
    """
    s = max(int(supersample), 1)
    big = camera.scaled(s)
    width, height = int(big.width), int(big.height)
    u, v, z = big.project(positions)
    front, inverse_z = rasterize(u, v, z, triangles, width, height)
    covered = front >= 0
    rgb = np.ones((height, width, 3))
    alpha = covered.astype(np.float64)
    t = front[covered]
    if len(t):
        rows, columns = np.nonzero(covered)
        px, py = columns + 0.5, rows + 0.5
        corners = triangles[t]
        cu, cv, cz = u[corners], v[corners], z[corners]
        doubled_area = (cu[:, 1] - cu[:, 0]) * (cv[:, 2] - cv[:, 0]) - (cu[:, 2] - cu[:, 0]) * (cv[:, 1] - cv[:, 0])
        screen = np.empty((len(t), 3))
        for i, j, k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
            edge = (cu[:, k] - cu[:, j]) * (py - cv[:, j]) - (cv[:, k] - cv[:, j]) * (px - cu[:, j])
            screen[:, i] = edge / doubled_area
        perspective = screen / cz
        perspective /= perspective.sum(axis=1, keepdims=True)
        point = np.einsum("pi,pij->pj", perspective, positions[corners])
        normals_of_faces = face_normals(positions, triangles)
        if flat:
            normal = normals_of_faces[t]
        else:
            normal = np.einsum("pi,pij->pj", perspective, corner_normals(positions, triangles, normals_of_faces,
                                                                          crease_degrees)[t])
        normal = normal / np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
        to_eye = camera.eye - point
        to_eye /= np.maximum(np.linalg.norm(to_eye, axis=1, keepdims=True), 1e-300)
        normal *= np.where((normal * to_eye).sum(axis=1) < 0, -1.0, 1.0)[:, None]
        key = -0.45 * camera.right + 0.55 * camera.up - 0.70 * camera.forward
        fill = 0.60 * camera.right - 0.10 * camera.up - 0.80 * camera.forward
        key, fill = key / np.linalg.norm(key), fill / np.linalg.norm(fill)
        half = key + to_eye
        half /= np.maximum(np.linalg.norm(half, axis=1, keepdims=True), 1e-300)
        diffuse = 0.18 + 0.72 * np.maximum(normal @ key, 0) + 0.22 * np.maximum(normal @ fill, 0)
        specular = 0.18 * np.maximum((normal * half).sum(axis=1), 0) ** 40
        albedo = ALBEDO if colours is None else np.einsum("pi,pij->pj", perspective, colours[corners])
        colour = np.clip(albedo * diffuse[:, None] + specular[:, None], 0, 1)
        if wire:
            lengths = np.stack([np.hypot(cu[:, k] - cu[:, j], cv[:, k] - cv[:, j])
                                for j, k in ((1, 2), (2, 0), (0, 1))], axis=1)
            distance = screen * np.abs(doubled_area)[:, None] / np.maximum(lengths, 1e-12)
            if polygon_edges is not None:
                distance[~polygon_edges[t]] = np.inf
            distance = distance.min(axis=1)
            line = np.clip(1.0 - (distance - 0.5 * (s - 1)) / s, 0, 1)  # about one output pixel wide
            colour = colour * (1 - 0.85 * line[:, None]) + WIRE_COLOUR * 0.85 * line[:, None]
        rgb[covered] = colour
    if s > 1:
        h, w = height // s, width // s
        premultiplied = (rgb * alpha[..., None]).reshape(h, s, w, s, 3).mean(axis=(1, 3))
        alpha = alpha.reshape(h, s, w, s).mean(axis=(1, 3))
        rgb = np.divide(premultiplied, alpha[..., None], out=np.ones_like(premultiplied), where=alpha[..., None] > 0)
    if not transparent:
        rgb = rgb * alpha[..., None] + (1 - alpha[..., None])
        alpha = np.ones_like(alpha)
    return np.concatenate([np.clip(rgb, 0, 1), alpha[..., None]], axis=2)


# ---------------------------------------------------------------------------------------------
# Strip of streamed prefixes
# ---------------------------------------------------------------------------------------------

PREFIX_NAME = re.compile(r"prefix_0*(\d+)\.[A-Za-z]+$")


def prefix_bytes(path):
    """Bytes received encoded in a `meshlift stream -o` file name (prefix_<bytes>.ply), or None."""
    match = PREFIX_NAME.search(os.path.basename(path))
    return int(match.group(1)) if match else None


def read_stream_csv(path):
    """Rows of `meshlift stream --csv` keyed by bytes."""
    rows = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            try:
                rows[int(row["bytes"])] = row
            except (KeyError, ValueError):
                raise MeshReadError("%s: expected the columns of `meshlift stream --csv` (bytes, ...)" % path)
    return rows


def pick_meshes(paths, count):
    """count of the paths (ordered by bytes when their names carry them), the first and last
    included, the others nearest to geometrically spaced byte counts (a stream sharpens fastest
    in its first bytes)."""
    keyed = [(prefix_bytes(p), i, p) for i, p in enumerate(paths)]
    if all(k[0] is not None for k in keyed):
        keyed.sort()
    paths = [k[2] for k in keyed]
    if not count or count >= len(paths):
        return paths
    if count == 1:
        return paths[-1:]
    sizes = [k[0] for k in keyed]
    if all(b is not None and b > 0 for b in sizes):
        targets = np.geomspace(sizes[0], sizes[-1], count)
        chosen = sorted({int(np.argmin(np.abs(np.log(np.array(sizes, dtype=float) / t)))) for t in targets})
    else:
        chosen = []
    if len(chosen) < count:
        chosen = sorted(set(np.round(np.linspace(0, len(paths) - 1, count)).astype(int).tolist()))
    return [paths[i] for i in chosen]


def caption(path, positions, stream_rows):
    size = prefix_bytes(path)
    if size is None:
        return "%s\n%d vertices" % (os.path.basename(path), len(positions))
    lines = ["{:,} bytes".format(size)]
    row = stream_rows.get(size)
    if row:
        details = ["%.2f bpv" % float(row["bits_per_vertex"])]
        psnr = float(row.get("psnr_db", "nan"))
        if math.isfinite(psnr):
            details.append("%.1f dB" % psnr)
        lines.append(", ".join(details))
    lines.append("{:,} vertices".format(len(positions)))
    return "\n".join(lines)


def compose_strip(images, captions, output, title=None, transparent=False):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    height, width = images[0].shape[:2]
    dpi = 100
    caption_height = 62 + (26 if title else 0)
    figure = plt.figure(figsize=(width * len(images) / dpi, (height + caption_height) / dpi), dpi=dpi)
    total_height = height + caption_height
    for i, (image, text) in enumerate(zip(images, captions)):
        axes = figure.add_axes([i / len(images), (caption_height - (26 if title else 0)) / total_height,
                                1 / len(images), height / total_height])
        axes.imshow(image, interpolation="nearest")
        axes.set_axis_off()
        figure.text((i + 0.5) / len(images), (caption_height - (26 if title else 0)) / total_height - 0.01, text,
                    ha="center", va="top", fontsize=10, linespacing=1.3)
    if title:
        figure.text(0.5, 1 - 0.01, title, ha="center", va="top", fontsize=12)
    figure.savefig(output, dpi=dpi, transparent=transparent, facecolor="none" if transparent else "white")
    plt.close(figure)


# ---------------------------------------------------------------------------------------------
# Command line
# ---------------------------------------------------------------------------------------------

def pair(text, kind, name):
    try:
        first, second = (kind(x) for x in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError("%s expects two comma-separated numbers, got '%s'" % (name, text))
    return first, second


def add_common_options(parser, default_size):
    parser.add_argument("-o", "--output", required=True, help="PNG file to write")
    parser.add_argument("--view", default="30,20", type=lambda t: pair(t, float, "--view"),
                        help="azimuth,elevation in degrees around the up axis (default 30,20)")
    parser.add_argument("--size", default=default_size, type=lambda t: pair(t, int, "--size"),
                        help="image width,height in pixels (default %s)" % default_size)
    parser.add_argument("--up", default="y", choices=sorted(UP_AXES), help="the model's up axis (default y)")
    parser.add_argument("--wire", action="store_true", help="overlay the triangle edges (for coarse meshes)")
    parser.add_argument("--flat", action="store_true", help="face normals instead of smooth corner normals")
    parser.add_argument("--crease", type=float, default=40.0,
                        help="faces meeting at more than this angle in degrees keep a sharp edge (default 40)")
    parser.add_argument("--transparent", action="store_true", help="transparent instead of white background")
    parser.add_argument("--supersample", type=int, default=2, help="antialiasing factor per axis (default 2)")


def main(argv):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    strip = bool(argv) and argv[0] == "strip"
    parser = argparse.ArgumentParser(prog="render.py strip" if strip else "render.py",
                                     description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    if strip:
        parser.add_argument("meshes", nargs="+", help="meshes, e.g. DIR/prefix_*.ply")
        parser.add_argument("--csv", help="`meshlift stream --csv` file: bpv and PSNR for the captions")
        parser.add_argument("--count", type=int, default=0, help="render only this many of the meshes")
        parser.add_argument("--title", help="title above the strip")
        add_common_options(parser, "320,320")
        args = parser.parse_args(argv[1:])
    else:
        parser.add_argument("mesh")
        parser.add_argument("--reference", help="frame the camera on this mesh instead (same framing for a series)")
        add_common_options(parser, "800,800")
        args = parser.parse_args(argv)
    width, height = args.size
    if width < 1 or height < 1 or args.supersample < 1 or width * height * args.supersample ** 2 > 1 << 26:
        parser.error("--size and --supersample must be positive, at most 2^26 pixels rendered")
    try:
        if strip:
            paths = pick_meshes(args.meshes, args.count)
            rows = read_stream_csv(args.csv) if args.csv else {}
            meshes = [read_mesh(p) for p in paths]
            camera = make_camera(meshes[-1].positions, width, height, *args.view, up_axis=args.up)
            images = [render(m.positions, m.triangles, camera, args.wire, args.flat, args.transparent, args.supersample,
                             m.polygon_edges, args.crease, m.colours) for m in meshes]
            captions = [caption(path, m.positions, rows) for path, m in zip(paths, meshes)]
        else:
            mesh = read_mesh(args.mesh)
            reference = read_mesh(args.reference).positions if args.reference else mesh.positions
            camera = make_camera(reference, width, height, *args.view, up_axis=args.up)
            image = render(mesh.positions, mesh.triangles, camera, args.wire, args.flat, args.transparent,
                           args.supersample, mesh.polygon_edges, args.crease, mesh.colours)
    except MeshReadError as error:
        print("render.py: %s" % error, file=sys.stderr)
        return EXIT_BAD_INPUT
    except OSError as error:
        print("render.py: %s: %s" % (error.filename, error.strerror), file=sys.stderr)
        return EXIT_BAD_INPUT
    try:
        if strip:
            compose_strip(images, captions, args.output, args.title, args.transparent)
        else:
            plt.imsave(args.output, image)
    except (OSError, ValueError) as error:
        print("render.py: %s: cannot write the image: %s" % (args.output, error), file=sys.stderr)
        return EXIT_OUTPUT_ERROR
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

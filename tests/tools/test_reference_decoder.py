#!/usr/bin/env python3
"""Checks tools/reference_decoder.py (written from FORMAT.md alone) against `meshlift decode`.

    test_reference_decoder.py MESHLIFT [STREAM.mlz...] [--generate] [--cuts=N] [--every-byte]
                              [--truncate] [--damage]

`--generate` adds streams made here with `meshlift subdivide` and `meshlift encode` from two small
meshes with boundaries (a 5 x 5 grid whose interior vertices have valence 4 and 7, an open fan of
four triangles), their finer vertices moved pseudo-randomly: butterfly with the
mean-preserving update in local frames, Loop in x, y, z, linear without the update (`--no-update`:
the update is the default) in local frames, and the grid again with a colour per vertex (a COFF
input: a channel marked as the colour, FORMAT.md §3, whose bytes must agree within 1).
For each stream, and for prefixes of it (`--cuts=N`: N raw byte cuts spread over the file;
`--every-byte`: all of them; `--truncate`: also the files `meshlift truncate` rewrites from those
cuts; `--damage`: damaged copies, each chunk's checksum made right again where the damage is
inside a chunk, so that the codec's checks answer and not the container's), both decoders must
agree: the same §6 status when the C++ decoder refuses the input, else the same vertex count,
the same faces in the same order, and positions equal within
    |reference - C++| <= 2^-23 |C++| + 1e-12 · max |coordinate|.
Why not exact: `meshlift decode` writes positions as float32 (9 significant digits), the reference
decoder computes in double; the float32 rounding is the first term. The second covers values that
should be 0 and come out as ±1e-17 of a unit-size mesh in either decoder, because the two sum a
stencil's terms in different orders (doubles, 1e-16 relative).
Each whole stream must also get the status its version byte calls for, from both decoders: `ok` at
the current format version (reference_decoder.FORMAT_VERSION, 5: icosahedron_loop_L2_p12_v5.mlz,
the frames-and-channels golden), `unsupported_version` at an older one (FORMAT.md §1:
icosahedron_loop_L2_p12.mlz is version 1, the `_vN` goldens version N, up to `_v4`); a `_vN` name
must match the version byte, and the streams named on the command line must include one of the
current version.
Exit 0 when everything agrees, 1 otherwise; prints one line per disagreement and a summary.
"""

import math
import os
import re
import struct
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'tools'))
import reference_decoder  # noqa: E402

STATUS_PATTERN = re.compile(r': ([a-z_]+) \(error (\d+)\)')
VERSION_IN_NAME = re.compile(r'_v(\d+)\.mlz$')


def version_problems(path, data):
    """The whole-stream expectations FORMAT.md §1 sets by version: [(what, expected status)] and
    a list of problems with the stream itself (a `_vN` name that is not version N)."""
    if len(data) < 8 or data[:4] != reference_decoder.MAGIC:
        return None, ['%s: not a meshlift file' % path]
    version = data[4]
    problems = []
    match = VERSION_IN_NAME.search(os.path.basename(path))
    if match and int(match.group(1)) != version:
        problems.append('%s: named version %s, version byte %d' % (path, match.group(1), version))
    if version == reference_decoder.FORMAT_VERSION:
        return 'ok', problems
    if version < reference_decoder.FORMAT_VERSION:
        return 'unsupported_version', problems
    return None, problems + ['%s: version %d is newer than the reference decoder\'s %d'
                             % (path, version, reference_decoder.FORMAT_VERSION)]


def read_off(path, colours=None):
    """OFF or COFF (then `colours`, if a list, receives each vertex's bytes)."""
    with open(path) as f:
        tokens = f.read().split()
    if tokens[0] not in ('OFF', 'COFF'):
        raise ValueError('%s: not OFF' % path)
    coloured = tokens[0] == 'COFF'
    V, F = int(tokens[1]), int(tokens[2])
    i = 4
    positions = []
    for _ in range(V):
        positions.append((float(tokens[i]), float(tokens[i + 1]), float(tokens[i + 2])))
        i += 3
        if coloured:
            if colours is not None:
                colours.append(tuple(int(t) for t in tokens[i:i + 3]))
            i += 3
    faces = []
    for _ in range(F):
        if tokens[i] != '3':
            raise ValueError('%s: non-triangle face' % path)
        faces.append((int(tokens[i + 1]), int(tokens[i + 2]), int(tokens[i + 3])))
        i += 4
    return positions, faces


def cpp_decode(meshlift, path, workdir, max_bytes=None):
    """Returns ('ok', positions, faces, colours) or (status, None, None, None); colours are the
    bytes `meshlift decode` wrote (COFF), or []."""
    out = os.path.join(workdir, 'cpp.off')
    command = [meshlift, 'decode', path, '-o', out]
    if max_bytes is not None:
        command += ['--bytes', str(max_bytes)]
    run = subprocess.run(command, capture_output=True, text=True)
    if run.returncode != 0:
        match = STATUS_PATTERN.search(run.stderr)
        return (match.group(1) if match else 'exit %d: %s' % (run.returncode, run.stderr.strip()),
                None, None, None)
    colours = []
    positions, faces = read_off(out, colours)
    os.remove(out)
    return 'ok', positions, faces, colours


def reference_decode(data):
    """As cpp_decode, the colours as the bytes FORMAT.md §3 says a file stores, round(255 c)."""
    colours = []
    try:
        positions, faces = reference_decoder.decode(data, colours=colours)
    except reference_decoder.DecodeError as error:
        return error.status, None, None, None
    return 'ok', positions, faces, [tuple(int(math.floor(255 * min(1.0, max(0.0, x)) + 0.5)) for x in c)
                                    for c in colours]


def compare(expected, actual):
    """Returns (problem or None, largest position difference)."""
    status_c, pos_c, faces_c, colours_c = expected
    status_r, pos_r, faces_r, colours_r = actual
    if status_c != status_r:
        return 'status: C++ %s, reference %s' % (status_c, status_r), 0.0
    if status_c != 'ok':
        return None, 0.0
    if len(pos_c) != len(pos_r):
        return 'vertices: C++ %d, reference %d' % (len(pos_c), len(pos_r)), 0.0
    if faces_c != faces_r:
        return 'faces differ (C++ %d, reference %d)' % (len(faces_c), len(faces_r)), 0.0
    scale = max([abs(x) for p in pos_c for x in p] + [1e-300])
    largest = 0.0
    for v, (p, q) in enumerate(zip(pos_c, pos_r)):
        for x, y in zip(p, q):
            difference = abs(x - y)
            largest = max(largest, difference)
            if difference > 2.0 ** -23 * abs(x) + 1e-12 * scale:
                return 'vertex %d: C++ %r, reference %r' % (v, p, q), largest
    # Colours as bytes: a value the two sum in different orders may round the other way at .5.
    if len(colours_c) != len(colours_r):
        return 'colours: C++ %d, reference %d' % (len(colours_c), len(colours_r)), largest
    for v, (p, q) in enumerate(zip(colours_c, colours_r)):
        if any(abs(x - y) > 1 for x, y in zip(p, q)):
            return 'vertex %d colour: C++ %r, reference %r' % (v, p, q), largest
    return None, largest


def rebuild(header, chunks):
    """A file from (tag, payload) pairs, each with its length and a correct checksum (§2.1)."""
    out = bytearray(header)
    for tag, payload in chunks:
        out += tag
        n = len(payload)
        while True:   # §0.2 varint
            if n < 0x80:
                out.append(n)
                break
            out.append((n & 0x7F) | 0x80)
            n >>= 7
        out += payload + struct.pack('<I', reference_decoder.chunk_checksum(bytes(payload)))
    return bytes(out)


def damaged_copies(data):
    """(name, bytes) variants of a complete, valid stream whose chunks are HEAD, BASE, COEF..."""
    chunks = [(struct.pack('<I', c.tag), bytearray(c.payload))
              for c in reference_decoder.read_chunks(data)]
    head = chunks[0][1]

    def with_head(position, value):
        changed = bytearray(head)
        changed[position] = value
        return rebuild(data[:8], [(chunks[0][0], changed)] + chunks[1:])

    flipped = bytearray(data)
    flipped[-6] ^= 0x20
    base = bytearray(chunks[1][1])
    base[len(base) // 2] ^= 0x5A
    older = reference_decoder.FORMAT_VERSION - 1
    return [
        ('bad magic', b'MLZ\x1b' + data[4:]),
        ('version %d' % older, data[:4] + bytes([older]) + data[5:]),
        ('version %d' % (older + 2), data[:4] + bytes([older + 2]) + data[5:]),
        ('file header flags', data[:5] + b'\x01' + data[6:]),
        ('payload byte flipped', bytes(flipped)),
        ('unknown scheme', with_head(0, 3)),
        ('reserved HEAD flag', with_head(1, head[1] | 0x80)),
        ('13 levels', with_head(2, 13)),
        ('bit plane 32', with_head(3, 33)),
        ('BASE damaged', rebuild(data[:8], chunks[:1] + [(chunks[1][0], base)] + chunks[2:])),
        ('BASE missing', rebuild(data[:8], chunks[:1] + chunks[2:])),
        ('critical chunk XTRA', rebuild(data[:8], chunks + [(b'XTRA', b'?')])),
        ('ancillary chunk note', rebuild(data[:8], chunks + [(b'note', b'?')])),
    ]


def write_off(path, positions, faces, colours=None):
    with open(path, 'w') as out:
        out.write('%s\n%d %d 0\n' % ('COFF' if colours else 'OFF', len(positions), len(faces)))
        for v, p in enumerate(positions):
            out.write('%r %r %r' % tuple(p))
            out.write(' %d %d %d 255\n' % colours[v] if colours else '\n')
        for f in faces:
            out.write('3 %d %d %d\n' % tuple(f))


def generate_streams(meshlift, workdir):
    """Streams of meshes with boundaries and extraordinary vertices (the golden ones are closed
    icosahedra), encoded by the current encoder."""
    n = 4
    grid = [(i + 0.3 * j, 0.9 * j, 0.1 * ((i * 7 + j * 3) % 5)) for j in range(n + 1)
            for i in range(n + 1)]
    grid_faces = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            b, c, d = a + 1, a + n + 1, a + n + 2
            grid_faces += [(a, b, d), (a, d, c)] if (i + j) % 3 == 0 else [(a, b, c), (b, d, c)]
    fan = [(0.0, 0.0, 1.0)] + [(math.cos(2 * math.pi * k / 5), math.sin(2 * math.pi * k / 5),
                                0.2 * (k % 3)) for k in range(5)]
    fan_faces = [(0, k + 1, k + 2) for k in range(4)]
    seed = 12345
    streams = []
    for (name, positions, faces, scheme, options) in (
            ('grid', grid, grid_faces, 'butterfly', ['--update', '--frames', 'local']),
            ('grid', grid, grid_faces, 'loop', ['--frames', 'xyz']),
            ('fan', fan, fan_faces, 'linear', ['--no-update', '--frames', 'local']),
            ('coloured_grid', grid, grid_faces, 'butterfly', ['--update', '--frames', 'local'])):
        base = os.path.join(workdir, name + '.off')
        fine = os.path.join(workdir, name + '_fine.off')
        write_off(base, positions, faces)
        subprocess.run([meshlift, 'subdivide', base, '-o', fine, '--scheme', 'loop',
                        '--levels', '2'], check=True, capture_output=True)
        fine_positions, fine_faces = read_off(fine)
        moved = []
        for v, p in enumerate(fine_positions):
            if v >= len(positions):   # vertices are in level order: keep the base as it is
                offsets = []
                for _ in range(3):
                    seed = (seed * 1103515245 + 12345) % 2 ** 31
                    offsets.append((seed / 2 ** 31 - 0.5) * 0.04)
                p = tuple(x + o for x, o in zip(p, offsets))
            moved.append(p)
        # The coloured grid: a colour per vertex (bytes, COFF), a channel marked as the colour.
        colours = ([tuple((v * 37 + 80 * k) % 256 for k in range(3)) for v in range(len(moved))]
                   if name.startswith('coloured') else None)
        write_off(fine, moved, fine_faces, colours)
        stream = os.path.join(workdir, '%s_%s.mlz' % (name, scheme))
        subprocess.run([meshlift, 'encode', fine, '-o', stream, '--scheme', scheme, '--bits',
                        '14'] + options, check=True, capture_output=True)
        streams.append(stream)
    return streams


def cut_points(size, count, every_byte):
    if every_byte:
        return list(range(1, size + 1))
    if count <= 0:
        return []
    return sorted({round(size * (i + 1) / (count + 1)) for i in range(count)})


def main(argv):
    args = [a for a in argv if not a.startswith('--')]
    cuts = 0
    every_byte = '--every-byte' in argv
    with_truncate = '--truncate' in argv
    with_damage = '--damage' in argv
    for a in argv:
        if a.startswith('--cuts='):
            cuts = int(a.split('=', 1)[1])
    if len(args) < 1 or (len(args) < 2 and '--generate' not in argv):
        print(__doc__, file=sys.stderr)
        return 2
    meshlift, streams = args[0], args[1:]
    cases = failures = 0
    largest = 0.0
    statuses = {}
    current = 0   # streams named on the command line at the current format version
    named = len(streams)
    with tempfile.TemporaryDirectory() as workdir:
        if '--generate' in argv:
            streams += generate_streams(meshlift, workdir)
        for number, stream in enumerate(streams):
            with open(stream, 'rb') as f:
                data = f.read()
            expected_status, problems = version_problems(stream, data)
            if number < named and expected_status == 'ok':
                current += 1
            for (who, status) in (('C++', cpp_decode(meshlift, stream, workdir)[0]),
                                  ('reference', reference_decode(data)[0])):
                if expected_status is not None and status != expected_status:
                    problems.append('%s: version %d, %s decoder gives %s, expected %s'
                                    % (stream, data[4], who, status, expected_status))
            for problem in problems:
                failures += 1
                print(problem)
            todo = [(stream, None, data)]
            if with_damage and reference_decode(data)[0] == 'ok':
                for (what, damaged) in damaged_copies(data):
                    todo.append(('%s (%s)' % (stream, what), 'file', damaged))
            for n in cut_points(len(data), cuts, every_byte):
                todo.append((stream, n, data[:n]))
                if with_truncate and n >= 8:
                    rewritten = os.path.join(workdir, 'truncated.mlz')
                    run = subprocess.run([meshlift, 'truncate', stream, '--bytes', str(n),
                                          '-o', rewritten], capture_output=True)
                    if run.returncode == 0:
                        with open(rewritten, 'rb') as f:
                            todo.append(('%s (truncate --bytes %d)' % (stream, n), 'file',
                                         f.read()))
            for (name, n, payload) in todo:
                if n == 'file':
                    path = os.path.join(workdir, 'case.mlz')
                    with open(path, 'wb') as f:
                        f.write(payload)
                    expected = cpp_decode(meshlift, path, workdir)
                else:
                    expected = cpp_decode(meshlift, stream, workdir, n)
                actual = reference_decode(payload)
                problem, difference = compare(expected, actual)
                cases += 1
                statuses[expected[0]] = statuses.get(expected[0], 0) + 1
                largest = max(largest, difference)
                if problem:
                    failures += 1
                    print('%s%s: %s' % (name, '' if n in (None, 'file') else ' --bytes %d' % n,
                                        problem))
    if named and not current:
        failures += 1
        print('no stream named on the command line is of the current format version %d'
              % reference_decoder.FORMAT_VERSION)
    print('%d cases (%s), %d disagreements, largest position difference %.3g'
          % (cases, ', '.join('%s %d' % kv for kv in sorted(statuses.items())), failures, largest))
    return 1 if failures else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))

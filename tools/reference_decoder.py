#!/usr/bin/env python3
"""An independent reference decoder for meshlift streams (.mlz), format version 5.

Written from bitstream/FORMAT.md and docs/WAVELETS.md without the meshlift sources, to test the
format document's claim that a stranger can write a compatible decoder; what those two documents
leave out came from public references they cite: XXH3 from xxHash 0.8's xxhash.h, the modified
butterfly's extraordinary weights and boundary handling from OpenMesh's ModifiedButterFlyT, Loop's
beta_n from Loop 1987 (as OpenMesh's LoopT has it). Standard library only (runs on Debian's
/usr/bin/python3). Plain and slow on purpose: one function per section of the specification,
each naming the section it implements. (Written for version 2 by someone who had not seen the
sources; the version-3 base part, §5.1, was added from the document by its author, the
version-4 prediction (the mean of the parallelograms) from the new §5.1 by the author of that change.
The version-5 changes, the f32 centres and weights of §3 and §4's split vertices coded by walks
along the front with primed decision models, were added from the document alone, without the
sources.)

    reference_decoder.py IN.mlz -o OUT.off|OUT.obj [--bytes N] [--level K]

decodes the whole file or its first N bytes (FORMAT.md's truncation rules) and writes the mesh,
vertices in the stream's order. On bad input it prints `STATUS (error N): message` (§6) and exits
3, as `meshlift decode` does.
"""

import argparse
import math
import struct
import sys

MASK32 = 0xFFFFFFFF
MASK64 = 0xFFFFFFFFFFFFFFFF

# §6 Status codes (frozen numbers).
STATUS_CODES = {
    'ok': 0, 'truncated': 1, 'bad_magic': 2, 'unsupported_version': 3, 'corrupt': 4,
    'checksum_mismatch': 5, 'limit_exceeded': 6, 'reserved_bits_set': 7, 'io_error': 8,
}


class DecodeError(Exception):
    """A §6 status other than ok, with a sentence saying where."""

    def __init__(self, status, message):
        super().__init__(message)
        self.status = status
        self.message = message


# ---------------------------------------------------------------------------------------------
# §0 Conventions
# ---------------------------------------------------------------------------------------------

def read_u32(data, pos):
    """§0.1: little-endian u32."""
    return struct.unpack_from('<I', data, pos)[0]


def read_varint(data, pos):
    """§0.2: minimal unsigned LEB128 of at most 64 bits. Returns (value, next position)."""
    value = 0
    for i in range(10):
        if pos >= len(data):
            raise DecodeError('truncated', 'varint ends with the data')
        b = data[pos]
        pos += 1
        if i == 9 and b > 1:
            raise DecodeError('corrupt', 'varint longer than 64 bits')
        value |= (b & 0x7F) << (7 * i)
        if b & 0x80 == 0:
            if b == 0 and i > 0:
                raise DecodeError('corrupt', 'varint not minimal')
            return value, pos
    raise DecodeError('corrupt', 'varint longer than 64 bits')  # unreachable: caught at i == 9


# ---------------------------------------------------------------------------------------------
# §1 File header
# ---------------------------------------------------------------------------------------------

MAGIC = b'MLZ\x1a'
FORMAT_VERSION = 5


def read_file_header(data):
    """§1: the 8-byte file header, checked in the order the section gives."""
    for i in range(min(4, len(data))):
        if data[i] != MAGIC[i]:
            raise DecodeError('bad_magic', 'not a meshlift file (byte %d)' % i)
    if len(data) < 8:
        raise DecodeError('truncated', 'the data ends inside the 8-byte file header')
    if data[4] != FORMAT_VERSION:
        raise DecodeError('unsupported_version', 'format version %d' % data[4])
    if data[5] != 0:
        raise DecodeError('reserved_bits_set', 'file header flags are not zero')
    if data[6] != 0 or data[7] != 0:
        raise DecodeError('reserved_bits_set', 'file header reserved field is not zero')


# ---------------------------------------------------------------------------------------------
# §2.2 Checksum: XXH3_64bits, seed 0, default secret (xxHash 0.8), written from the public
# reference (xxhash.h: XXH3_len_*_64b, XXH3_hashLong_64b_internal, the scalar accumulate/scramble).
# ---------------------------------------------------------------------------------------------

XXH_PRIME32_1 = 0x9E3779B1
XXH_PRIME32_2 = 0x85EBCA77
XXH_PRIME32_3 = 0xC2B2AE3D
XXH_PRIME64_1 = 0x9E3779B185EBCA87
XXH_PRIME64_2 = 0xC2B2AE3D27D4EB4F
XXH_PRIME64_3 = 0x165667B19E3779F9
XXH_PRIME64_4 = 0x85EBCA77C2B2AE63
XXH_PRIME64_5 = 0x27D4EB2F165667C5

XXH3_SECRET = bytes.fromhex(
    'b8fe6c3923a44bbe7c01812cf721ad1cded46de9839097db7240a4a4b7b3671f'
    'cb79e64eccc0e578825ad07dccff7221b8084674f743248ee03590e6813a264c'
    '3c2852bb91c300cb88d0658b1b532ea371644897a20df94e3819ef46a9deacd8'
    'a8fa763fe39c343ff9dcbbc7c70b4f1d8a51e04bcdb45931c89f7ec9d9787364'
    'eac5ac8334d3ebc3c581a0fffa1363eb170ddd51b7f0da49d316552629d4689e'
    '2b16be587d47a1fc8ff8b8d17ad031ce45cb3a8f95160428afd7fbcabb4b407e')
XXH3_SECRET_SIZE_MIN = 136
XXH_STRIPE_LEN = 64
XXH_SECRET_CONSUME_RATE = 8


def _le64(b, pos):
    return struct.unpack_from('<Q', b, pos)[0]


def _le32(b, pos):
    return struct.unpack_from('<I', b, pos)[0]


def _rotl64(x, r):
    return ((x << r) | (x >> (64 - r))) & MASK64


def _swap64(x):
    return int.from_bytes(x.to_bytes(8, 'little'), 'big')


def _mul128_fold64(a, b):
    product = a * b
    return (product & MASK64) ^ (product >> 64)


def _xxh64_avalanche(h):
    h ^= h >> 33
    h = (h * XXH_PRIME64_2) & MASK64
    h ^= h >> 29
    h = (h * XXH_PRIME64_3) & MASK64
    h ^= h >> 32
    return h


def _xxh3_avalanche(h):
    h ^= h >> 37
    h = (h * 0x165667919E3779F9) & MASK64
    h ^= h >> 32
    return h


def _xxh3_rrmxmx(h, length):
    h ^= _rotl64(h, 49) ^ _rotl64(h, 24)
    h = (h * 0x9FB21C651E98DF25) & MASK64
    h ^= (h >> 35) + length
    h = (h * 0x9FB21C651E98DF25) & MASK64
    return h ^ (h >> 28)


def _xxh3_mix16(data, pos, secret_pos):
    s = XXH3_SECRET
    return _mul128_fold64(_le64(data, pos) ^ _le64(s, secret_pos),
                          _le64(data, pos + 8) ^ _le64(s, secret_pos + 8))


def xxh3_64(data):
    """XXH3_64bits(data) with seed 0 and the default 192-byte secret."""
    s = XXH3_SECRET
    n = len(data)
    if n == 0:
        return _xxh64_avalanche(_le64(s, 56) ^ _le64(s, 64))
    if n <= 3:
        combined = (data[0] << 16) | (data[n >> 1] << 24) | data[n - 1] | (n << 8)
        return _xxh64_avalanche(combined ^ (_le32(s, 0) ^ _le32(s, 4)))
    if n <= 8:
        input64 = _le32(data, n - 4) + (_le32(data, 0) << 32)
        return _xxh3_rrmxmx(input64 ^ (_le64(s, 8) ^ _le64(s, 16)), n)
    if n <= 16:
        low = _le64(data, 0) ^ (_le64(s, 24) ^ _le64(s, 32))
        high = _le64(data, n - 8) ^ (_le64(s, 40) ^ _le64(s, 48))
        acc = (n + _swap64(low) + high + _mul128_fold64(low, high)) & MASK64
        return _xxh3_avalanche(acc)
    if n <= 128:
        acc = (n * XXH_PRIME64_1) & MASK64
        if n > 32:
            if n > 64:
                if n > 96:
                    acc += _xxh3_mix16(data, 48, 96) + _xxh3_mix16(data, n - 64, 112)
                acc += _xxh3_mix16(data, 32, 64) + _xxh3_mix16(data, n - 48, 80)
            acc += _xxh3_mix16(data, 16, 32) + _xxh3_mix16(data, n - 32, 48)
        acc += _xxh3_mix16(data, 0, 0) + _xxh3_mix16(data, n - 16, 16)
        return _xxh3_avalanche(acc & MASK64)
    if n <= 240:
        acc = (n * XXH_PRIME64_1) & MASK64
        for i in range(8):
            acc += _xxh3_mix16(data, 16 * i, 16 * i)
        acc = _xxh3_avalanche(acc & MASK64)
        for i in range(8, n // 16):
            acc += _xxh3_mix16(data, 16 * i, 16 * (i - 8) + 3)
        acc += _xxh3_mix16(data, n - 16, XXH3_SECRET_SIZE_MIN - 17)
        return _xxh3_avalanche(acc & MASK64)
    return _xxh3_hash_long(data)


def _xxh3_accumulate_512(acc, data, pos, secret_pos):
    for i in range(8):
        value = _le64(data, pos + 8 * i)
        key = value ^ _le64(XXH3_SECRET, secret_pos + 8 * i)
        acc[i ^ 1] = (acc[i ^ 1] + value) & MASK64
        acc[i] = (acc[i] + (key & MASK32) * (key >> 32)) & MASK64


def _xxh3_scramble(acc, secret_pos):
    for i in range(8):
        a = acc[i]
        a ^= a >> 47
        a ^= _le64(XXH3_SECRET, secret_pos + 8 * i)
        acc[i] = (a * XXH_PRIME32_1) & MASK64


def _xxh3_hash_long(data):
    n = len(data)
    secret_size = len(XXH3_SECRET)
    acc = [XXH_PRIME32_3, XXH_PRIME64_1, XXH_PRIME64_2, XXH_PRIME64_3,
           XXH_PRIME64_4, XXH_PRIME32_2, XXH_PRIME64_5, XXH_PRIME32_1]
    stripes_per_block = (secret_size - XXH_STRIPE_LEN) // XXH_SECRET_CONSUME_RATE
    block_len = XXH_STRIPE_LEN * stripes_per_block
    blocks = (n - 1) // block_len
    for b in range(blocks):
        for s in range(stripes_per_block):
            _xxh3_accumulate_512(acc, data, b * block_len + s * XXH_STRIPE_LEN,
                                 s * XXH_SECRET_CONSUME_RATE)
        _xxh3_scramble(acc, secret_size - XXH_STRIPE_LEN)
    stripes = ((n - 1) - block_len * blocks) // XXH_STRIPE_LEN
    for s in range(stripes):
        _xxh3_accumulate_512(acc, data, blocks * block_len + s * XXH_STRIPE_LEN,
                             s * XXH_SECRET_CONSUME_RATE)
    _xxh3_accumulate_512(acc, data, n - XXH_STRIPE_LEN, secret_size - XXH_STRIPE_LEN - 7)
    result = (n * XXH_PRIME64_1) & MASK64
    for i in range(4):
        result += _mul128_fold64(acc[2 * i] ^ _le64(XXH3_SECRET, 11 + 16 * i),
                                 acc[2 * i + 1] ^ _le64(XXH3_SECRET, 11 + 16 * i + 8))
    return _xxh3_avalanche(result & MASK64)


def chunk_checksum(payload):
    """§2.2: the low 32 bits of XXH3_64bits(payload)."""
    return xxh3_64(payload) & MASK32


# ---------------------------------------------------------------------------------------------
# §2 Chunks
# ---------------------------------------------------------------------------------------------

MAX_CHUNK_BYTES = 1 << 30   # §8 container defaults
MAX_CHUNKS = 65536


class Chunk:
    def __init__(self, tag, payload, complete, offset, index):
        self.tag = tag
        self.payload = payload
        self.complete = complete
        self.offset = offset
        self.index = index

    def name(self):
        return ''.join(chr(c) if 32 <= c < 127 else '?' for c in struct.pack('<I', self.tag))


def read_chunks(data):
    """§2.1, §2.5: every chunk after the file header; the last one may be incomplete."""
    chunks = []
    pos = 8
    while pos < len(data):
        offset = pos
        where = ' (at byte %d, chunk %d)' % (offset, len(chunks))
        if len(chunks) == MAX_CHUNKS:
            raise DecodeError('limit_exceeded', 'more than %d chunks' % MAX_CHUNKS + where)
        if len(data) - pos < 4:
            chunks.append(Chunk(0, b'', False, offset, len(chunks)))
            break
        tag = read_u32(data, pos)
        pos += 4
        try:
            length, pos = read_varint(data, pos)
        except DecodeError as error:
            if error.status == 'truncated':
                chunks.append(Chunk(tag, b'', False, offset, len(chunks)))
                break
            raise DecodeError(error.status, 'malformed chunk length' + where)
        if length > MAX_CHUNK_BYTES:
            raise DecodeError('limit_exceeded', 'chunk of %d bytes' % length + where)
        if length > len(data) - pos:
            chunks.append(Chunk(tag, bytes(data[pos:]), False, offset, len(chunks)))
            break
        payload = bytes(data[pos:pos + length])
        pos += length
        if len(data) - pos < 4:
            chunks.append(Chunk(tag, payload, False, offset, len(chunks)))
            break
        if read_u32(data, pos) != chunk_checksum(payload):
            raise DecodeError('checksum_mismatch', 'chunk checksum does not match' + where)
        pos += 4
        chunks.append(Chunk(tag, payload, True, offset, len(chunks)))
    return chunks


TAG_HEAD = 0x44414548
TAG_BASE = 0x45534142
TAG_COEF = 0x46454F43


def classify_chunks(chunks):
    """§2.4 and the order rules of §3-§5: returns (HEAD chunk, BASE chunk, COEF payloads)."""
    # §2.5: an incomplete chunk with an empty payload carries nothing and is treated as absent.
    present = [c for c in chunks if c.complete or len(c.payload) > 0]
    if not present:
        raise DecodeError('truncated', 'the stream ends inside its header chunk')
    first = present[0]
    if first.tag != TAG_HEAD:
        raise DecodeError('corrupt', 'the first chunk (at byte 8) is %s, not HEAD' % first.name())
    if not first.complete:
        raise DecodeError('truncated', 'the stream ends inside its header chunk')
    base = None
    coefficients = []
    for chunk in present[1:]:
        if chunk.tag in (TAG_HEAD, TAG_BASE, TAG_COEF):
            # BASE is "the second chunk" literally: an ancillary chunk between HEAD and BASE
            # puts BASE out of place (what `meshlift decode` does), though §2.4 calls ancillary
            # chunks safe to skip.
            if chunk.tag == TAG_HEAD or (chunk.tag == TAG_BASE and chunk.index != 1) or \
                    (chunk.tag == TAG_COEF and base is None):
                raise DecodeError('corrupt', 'chunk %s out of place at byte %d'
                                  % (chunk.name(), chunk.offset))
            if chunk.tag == TAG_BASE:
                base = chunk
            else:
                coefficients.append(chunk.payload)
        elif ord('A') <= (chunk.tag & 0xFF) <= ord('Z'):
            raise DecodeError('unsupported_version', 'unknown critical chunk %s at byte %d'
                              % (chunk.name(), chunk.offset))
        # anything else is ancillary: skipped (§2.4)
    if base is None or not base.complete:
        raise DecodeError('truncated', 'the stream ends before its base mesh is complete')
    return first, base, b''.join(coefficients)


# ---------------------------------------------------------------------------------------------
# §3 Header chunk
# ---------------------------------------------------------------------------------------------

SCHEMES = ('linear', 'butterfly', 'loop')
MAX_LEVELS = 12
MAX_BASE_VERTICES = 1 << 22     # the CLI's DecodeLimits (docs/ERRORS.md)
MAX_BASE_FACES = 1 << 23
MAX_OUTPUT_VERTICES = 1 << 24
HUGE = 1e250


class Header:
    pass


def read_header(payload):
    """§3: the HEAD chunk's fields and their checks."""
    h = Header()
    pos = 0

    def need(n):
        if pos + n > len(payload):
            raise DecodeError('corrupt', 'header chunk too short')

    def number(fmt, size):
        nonlocal pos
        need(size)
        value = struct.unpack_from(fmt, payload, pos)[0]
        pos += size
        return value

    def f64():
        return number('<d', 8)

    def f32():
        """§3: IEEE binary32, little-endian, used as the binary64 of the same value."""
        return number('<f', 4)

    def u8():
        nonlocal pos
        need(1)
        value = payload[pos]
        pos += 1
        return value

    scheme, flags, levels, top_plus_one, base_plane = u8(), u8(), u8(), u8(), u8()
    if scheme > 2:
        raise DecodeError('corrupt', 'unknown wavelet scheme %d' % scheme)
    if flags & 0xF0:
        raise DecodeError('reserved_bits_set', 'reserved header flag bits set')
    if levels > MAX_LEVELS:
        raise DecodeError('limit_exceeded', 'header claims %d levels' % levels)
    if top_plus_one > 32:
        raise DecodeError('corrupt', 'header claims bit plane %d' % (top_plus_one - 1))
    if base_plane > top_plus_one or top_plus_one - base_plane > 29:
        raise DecodeError('corrupt', 'header claims base plane %d with top plane %d'
                          % (base_plane, top_plus_one - 1))
    h.scheme = SCHEMES[scheme]
    h.update = bool(flags & 1)
    h.local_frames = bool(flags & 2)
    h.extra_channels = bool(flags & 4)
    h.colour = bool(flags & 8)   # the first channel is the vertices' red, green, blue
    h.levels = levels
    h.top_plane = top_plus_one - 1
    h.base_plane = base_plane
    try:
        h.base_vertices, pos = read_varint(payload, pos)
        h.base_faces, pos = read_varint(payload, pos)
    except DecodeError:
        raise DecodeError('corrupt', 'header chunk too short or malformed counts')
    if h.base_vertices < 3 or h.base_faces < 1:
        raise DecodeError('corrupt', 'header claims an empty base mesh')
    if h.base_vertices > MAX_BASE_VERTICES or h.base_faces > MAX_BASE_FACES:
        raise DecodeError('limit_exceeded', 'header claims %d base vertices and %d base faces'
                          % (h.base_vertices, h.base_faces))
    h.step = f64()
    h.center = [f32(), f32(), f32()]
    h.weights = [f32() for _ in range(levels + 1)]
    h.tangent_shift = 0
    if h.local_frames:
        h.tangent_shift = u8()
        if h.tangent_shift > 16:
            raise DecodeError('corrupt', 'tangent shift %d' % h.tangent_shift)
    h.channels = []   # (components, step, centre values)
    if h.extra_channels:
        count = u8()
        if not 1 <= count <= 4:
            raise DecodeError('corrupt', 'channel count %d' % count)
        total = 0
        for _ in range(count):
            m = u8()
            total += m
            if m < 1 or total > 4:
                raise DecodeError('corrupt', 'channel components')
            step = f64()
            centre = [f32() for _ in range(m)]
            h.channels.append((m, step, centre))
    if h.colour and (not h.channels or h.channels[0][0] != 3):
        raise DecodeError('corrupt', 'the colour flag without a first channel of 3 components')
    if pos != len(payload):
        raise DecodeError('corrupt', 'header chunk has %d unexpected trailing bytes'
                          % (len(payload) - pos))
    steps = [h.step] + [step for (_, step, _) in h.channels]
    centres = h.center + [x for (_, _, centre) in h.channels for x in centre]
    for value in steps + h.weights:
        if not (math.isfinite(value) and value > 0):
            raise DecodeError('corrupt', 'header holds a non-finite or non-positive '
                              'quantization parameter')
    for value in centres:
        if not math.isfinite(value):
            raise DecodeError('corrupt', 'header holds a non-finite centre')
        if abs(value) > HUGE:
            raise DecodeError('corrupt', 'header centre too large')
    h.components = 3 + sum(m for (m, _, _) in h.channels)
    top = 2.0 ** (h.top_plane + 1)
    for j in range(levels + 1):
        for c in range(h.components):
            if top * component_step(h, j, c) / h.weights[j] > HUGE:
                raise DecodeError('corrupt', 'header step too large for its bit planes')
    if h.base_vertices > 3 * h.base_faces:   # §4
        raise DecodeError('corrupt', '%d base vertices cannot all lie on %d faces'
                          % (h.base_vertices, h.base_faces))
    return h


def component_step(h, level, c):
    """§5: the quantization step Δ_c of component c for a vertex of the given level."""
    if c < 3:
        if h.local_frames and level > 0 and c > 0:
            return h.step * 2.0 ** h.tangent_shift
        return h.step
    c -= 3
    for (m, step, _) in h.channels:
        if c < m:
            return step
        c -= m
    raise AssertionError('component out of range')


# ---------------------------------------------------------------------------------------------
# §7 Binary range coder (decoder side)
# ---------------------------------------------------------------------------------------------

PROB_BITS = 15
PROB_ONE = 1 << 15
PROB_MIN = 128
PROB_MAX = PROB_ONE - 128
HALF = 1 << 14
TOP = 1 << 24
COUNT_MAX = 15
SHIFT = [1 + int(math.floor(math.log2(c + 1))) for c in range(16)]


class Model:
    """§7.3: an adaptive bit model: probability of a 0 in units of 2^-15, and a count."""
    __slots__ = ('p', 'count', 'count_max')

    def __init__(self, count_max=COUNT_MAX, p=HALF, count=0):
        self.p = p
        self.count = count
        self.count_max = count_max

    def update(self, bit):
        s = SHIFT[self.count]
        if self.count < self.count_max:
            self.count += 1
        if bit == 0:
            self.p += (PROB_MAX - self.p) >> s
        else:
            self.p -= (self.p - PROB_MIN) >> s


class Exhausted(Exception):
    """§7.6: the symbol just decoded needed a byte beyond the input; it and all later are void."""


class RangeDecoder:
    """§7.2-§7.6; decode_bit and decode_direct raise Exhausted instead of returning untrusted
    values."""

    def __init__(self, data):
        self.data = data
        self.exhausted = False
        self.init_status = 'ok'
        if len(data) < 5:
            self.exhausted, self.init_status = True, 'truncated'
            return
        if data[0] != 0:
            self.exhausted, self.init_status = True, 'corrupt'
            return
        self.code = (data[1] << 24) | (data[2] << 16) | (data[3] << 8) | data[4]
        if self.code == MASK32:
            self.exhausted, self.init_status = True, 'corrupt'
            return
        self.range = MASK32
        self.position = 5

    def normalize(self):
        if self.range < TOP:
            if self.position == len(self.data):
                self.exhausted = True
                return False
            self.range = (self.range << 8) & MASK32
            self.code = ((self.code << 8) | self.data[self.position]) & MASK32
            self.position += 1
        return True

    def decode_bit(self, model):
        if self.exhausted or not self.normalize():
            raise Exhausted()
        bound = (self.range >> PROB_BITS) * model.p
        if self.code < bound:
            self.range = bound
            model.update(0)
            return 0
        self.code -= bound
        self.range -= bound
        model.update(1)
        return 1

    def decode_direct(self, n):
        value = 0
        for _ in range(n):
            if self.exhausted or not self.normalize():
                raise Exhausted()
            self.range >>= 1
            if self.code >= self.range:
                self.code -= self.range
                bit = 1
            else:
                bit = 0
            value = (value << 1) | bit
        return value


class IntegerCoder:
    """§4: adaptive Elias-gamma of value + 1, with its own length and mantissa models."""

    def __init__(self):
        self.length = [Model() for _ in range(33)]
        self.mantissa = [[Model() for _ in range(3)] for _ in range(33)]

    def decode(self, rc):
        n = 0
        while rc.decode_bit(self.length[n]) == 0:
            n += 1
            if n > 32:
                raise DecodeError('corrupt', 'integer longer than 32 bits in the base mesh')
        v = 1
        for i in range(n - 1, -1, -1):
            rank = n - 1 - i
            bit = rc.decode_bit(self.mantissa[n][rank]) if rank < 3 else rc.decode_direct(1)
            v = 2 * v + bit
        return v - 1


# ---------------------------------------------------------------------------------------------
# §4 Base mesh chunk
# ---------------------------------------------------------------------------------------------

NEW, RIGHT, LEFT, OTHER = 0, 1, 2, 3

# §4: the decision models start primed, p = 128·q and count = 4, with q from these tables
# (indexed [previous][k] like the models).
PRIME_BOUNDARY = [252, 253, 255, 244]
PRIME_RIGHT = [[128, 255, 128, 128, 128, 128],
               [128, 251, 250, 215, 152, 103],
               [128, 128, 253, 231, 155, 92],
               [128, 250, 254, 93, 76, 83]]
PRIME_LEFT = [[128, 128, 250, 211, 178, 103],
              [128, 251, 230, 224, 176, 100],
              [128, 128, 241, 234, 179, 106],
              [128, 255, 250, 176, 163, 120]]
PRIME_NEW_VERTEX = [[128, 128, 6, 1, 23, 29],
                    [128, 5, 77, 96, 28, 31],
                    [128, 128, 3, 21, 19, 27],
                    [128, 25, 28, 21, 37, 18]]
PRIME_START_NEW, PRIME_SPLIT_LEFT, PRIME_SPLIT_RIGHT = 1, 181, 236
PRIME_COUNT = 4
MAX_WALK = 64   # the encoder walks at most 64 steps: a decoded walk length is at most 62 (+ 2)


def primed(q):
    """§4, §7.3: a decision model primed with p = 128·q and count = 4."""
    return Model(p=128 * q, count=PRIME_COUNT)


def decode_base_mesh(payload, h):
    """§4: the face-by-face traversal. Returns the base faces (labels in first-use order)."""
    rc = RangeDecoder(payload)
    if rc.exhausted:
        raise DecodeError('corrupt', 'the BASE chunk is too short for %d faces' % h.base_faces)
    try:
        faces = _decode_traversal(rc, h.base_vertices, h.base_faces)
    except Exhausted:
        raise DecodeError('corrupt', 'the base mesh connectivity in the BASE chunk does not '
                          'decode to %d faces' % h.base_faces)
    return faces


def _decode_traversal(rc, V0, F0):
    boundary = [primed(q) for q in PRIME_BOUNDARY]
    right = [[primed(q) for q in row] for row in PRIME_RIGHT]
    left = [[primed(q) for q in row] for row in PRIME_LEFT]
    new_vertex = [[primed(q) for q in row] for row in PRIME_NEW_VERTEX]
    start_new = primed(PRIME_START_NEW)
    split_left = primed(PRIME_SPLIT_LEFT)
    split_right = primed(PRIME_SPLIT_RIGHT)
    index = IntegerCoder()
    vertex = IntegerCoder()
    walk_left = IntegerCoder()
    walk_right = IntegerCoder()

    faces = []
    coded = set()
    out_open = [[] for _ in range(V0)]
    in_open = [[] for _ in range(V0)]
    faces_at = [0] * V0
    gates = []
    seen = 0

    def add_face(a, b, c):
        if a == b or b == c or c == a:
            raise DecodeError('corrupt', 'base face with a repeated corner')
        for (u, w) in ((a, b), (b, c), (c, a)):
            if (u, w) in coded:
                raise DecodeError('corrupt', 'base mesh is not a manifold mesh: '
                                  'directed edge (%d, %d) twice' % (u, w))
        faces.append((a, b, c))
        faces_at[a] += 1
        faces_at[b] += 1
        faces_at[c] += 1
        for (u, w) in ((a, b), (b, c), (c, a)):
            coded.add((u, w))
            if (w, u) in coded:
                out_open[w].remove(u)
                in_open[u].remove(w)
            else:
                out_open[u].append(w)
                in_open[w].append(u)
                gates.append((u, w))

    def k(v):
        return min(faces_at[v], 5)

    def walk(v, coder, lists):
        """§4: n = coder's value + 2 steps along the front, each by the oldest open edge."""
        value = coder.decode(rc)
        if value > MAX_WALK - 2:
            raise DecodeError('corrupt', 'base mesh split walk of %d steps' % (value + 2))
        for _ in range(value + 2):
            if not lists[v]:
                raise DecodeError('corrupt', 'base mesh split walk leaves the front')
            v = lists[v][0]
        return v

    previous = OTHER
    while len(faces) < F0:
        gate = None
        while gates:
            a, b = gates.pop()
            if (b, a) not in coded:
                gate = (a, b)
                break
        if gate is None:
            corners = []
            for _ in range(3):
                if rc.decode_bit(start_new):
                    if seen >= V0:
                        raise DecodeError('corrupt', 'base mesh uses more than %d vertices' % V0)
                    corners.append(seen)
                    seen += 1
                else:
                    corner = seen - 1 - vertex.decode(rc)
                    if corner < 0:
                        raise DecodeError('corrupt', 'base mesh refers to an unseen vertex')
                    corners.append(corner)
            add_face(*corners)
            continue
        a, b = gate
        if rc.decode_bit(boundary[previous]):
            previous = OTHER
            continue
        c = None
        context = previous
        for (candidates, model, kind) in ((in_open[a], right[context][k(a)], RIGHT),
                                          (out_open[b], left[context][k(b)], LEFT)):
            if c is None and candidates and rc.decode_bit(model):
                i = index.decode(rc) if len(candidates) > 1 else 0
                if i >= len(candidates):
                    raise DecodeError('corrupt', 'base mesh candidate index out of range')
                c = candidates[i]
                previous = kind
        if c is None:
            if rc.decode_bit(new_vertex[context][k(b)]):
                if seen >= V0:
                    raise DecodeError('corrupt', 'base mesh uses more than %d vertices' % V0)
                c = seen
                seen += 1
                previous = NEW
            else:
                # a split: c is elsewhere on the front (a walk from b or a), or a label
                previous = OTHER
                if rc.decode_bit(split_left) == 0:
                    c = walk(b, walk_left, out_open)
                elif rc.decode_bit(split_right) == 0:
                    c = walk(a, walk_right, in_open)
                else:
                    c = seen - 1 - vertex.decode(rc)
                    if c < 0:
                        raise DecodeError('corrupt', 'base mesh refers to an unseen vertex')
        if c == a or c == b:
            raise DecodeError('corrupt', 'base face with a repeated corner')
        add_face(b, a, c)
    # §4: base vertices no face uses are not allowed (labels follow first use, so they would be
    # the last ones, from `seen` on).
    if seen != V0:
        raise DecodeError('corrupt', 'the base mesh leaves %d of its %d vertices on no face'
                          % (V0 - seen, V0))
    return faces


def check_manifold(faces, vertex_count):
    """§4: manifold and consistently oriented (each directed edge once, so each undirected edge
    has at most two faces of opposite orientation); no pinched vertex (one fan per vertex)."""
    third = {}
    for (a, b, c) in faces:
        for (u, w, x) in ((a, b, c), (b, c, a), (c, a, b)):
            if (u, w) in third:
                raise DecodeError('corrupt', 'inconsistent orientation at edge (%d, %d)' % (u, w))
            third[(u, w)] = x
    corners = [0] * vertex_count
    outgoing = [[] for _ in range(vertex_count)]
    for (u, w) in third:
        corners[u] += 1
        outgoing[u].append(w)
    for v in range(vertex_count):
        if not outgoing[v]:
            continue
        # Walk the fan of v face by face, (v, w, x) -> the face with v -> x; it must reach every
        # face at v. A boundary fan starts at the edge v -> w whose twin has no face.
        start = outgoing[v][0]
        for w in outgoing[v]:
            if (w, v) not in third:
                start = w
                break
        count, w = 0, start
        while (v, w) in third and count <= corners[v]:
            count += 1
            w = third[(v, w)]
            if w == start:
                break
        if count != corners[v]:
            raise DecodeError('corrupt', 'base mesh is not a manifold mesh: non-manifold '
                              'vertex %d' % v)


# §4 edge numbering and refinement -------------------------------------------------------------

class Level:
    """One level of the hierarchy: faces, edges (directed as §4 says) and each face's edges."""

    def __init__(self, vertex_count, faces, edges):
        self.vertex_count = vertex_count
        self.faces = faces
        self.edges = edges
        index = {}
        for e, (a, b) in enumerate(edges):
            index[(min(a, b), max(a, b))] = e
        self.face_edges = [tuple(index[(min(u, w), max(u, w))]
                                 for (u, w) in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0])))
                           for f in faces]


def number_base_edges(faces, vertex_count):
    """§4: sort (min, max, face) over the directed corner edges; each distinct undirected edge in
    that order gets the next number, directed as in its lowest-numbered face."""
    corner_edges = []
    for f, (a, b, c) in enumerate(faces):
        for (u, w) in ((a, b), (b, c), (c, a)):
            corner_edges.append((min(u, w), max(u, w), f, u, w))
    corner_edges.sort()
    edges = []
    last = None
    for (lo, hi, _, u, w) in corner_edges:
        if (lo, hi) != last:
            edges.append((u, w))
            last = (lo, hi)
    return Level(vertex_count, faces, edges)


def refine(level):
    """§4 Refinement: the odd vertex of edge e is V_j + e; edges 2e, 2e+1 and inner edges
    2E_j + 3f + i; faces 4f + i."""
    V, E = level.vertex_count, len(level.edges)
    edges = []
    for e, (a, b) in enumerate(level.edges):
        m = V + e
        edges.append((a, m))
        edges.append((m, b))
    faces = []
    for f, (c0, c1, c2) in enumerate(level.faces):
        m = [V + e for e in level.face_edges[f]]
        for i in range(3):
            edges.append((m[(i + 2) % 3], m[(i + 1) % 3]))
        c = (c0, c1, c2)
        for i in range(3):
            faces.append((c[i], m[i], m[(i + 2) % 3]))
        faces.append((m[0], m[1], m[2]))
    assert len(edges) == 2 * E + 3 * len(level.faces)
    return Level(V + E, faces, edges)


def build_hierarchy(base_faces, h):
    """All levels 0..L (after the §3 check of the refined vertex count)."""
    base = number_base_edges(base_faces, h.base_vertices)
    V, E, F = h.base_vertices, len(base.edges), len(base_faces)
    for _ in range(h.levels):
        V, E, F = V + E, 2 * E + 3 * F, 4 * F
        if V > MAX_OUTPUT_VERTICES:
            raise DecodeError('limit_exceeded', 'the stream refines to more than %d vertices'
                              % MAX_OUTPUT_VERTICES)
    levels = [base]
    for _ in range(h.levels):
        levels.append(refine(levels[-1]))
    return levels


# ---------------------------------------------------------------------------------------------
# §5 Coefficient stream
# ---------------------------------------------------------------------------------------------

def coding_forest(levels):
    """§5 Coding forest: children of every vertex, and the level each vertex first appears at."""
    L = len(levels) - 1
    total = levels[-1].vertex_count
    vertex_level = [0] * total
    for j in range(1, L + 1):
        for v in range(levels[j - 1].vertex_count, levels[j].vertex_count):
            vertex_level[v] = j
    children = [[] for _ in range(total)]
    if L == 0:
        return children, vertex_level
    base = levels[0]
    for e, (a, _) in enumerate(base.edges):
        children[a].append(base.vertex_count + e)
    for j in range(1, L):
        coarse, fine = levels[j - 1], levels[j]
        V_coarse, V_fine, E_coarse = coarse.vertex_count, fine.vertex_count, len(coarse.edges)
        for e in range(E_coarse):
            children[V_coarse + e] = [V_fine + 2 * e, V_fine + 2 * e + 1]
        for f, face_edges in enumerate(coarse.face_edges):
            for i, e in enumerate(face_edges):
                children[V_coarse + e].append(V_fine + 2 * E_coarse + 3 * f + i)
        for e in range(E_coarse):
            children[V_coarse + e].sort()
    return children, vertex_level


def base_predictions(faces, vertex_count):
    """§5.1 predict(v, c), as a recipe per base vertex: ('zero',), ('copy', a),
    ('midpoint', x, y) or ('parallelograms', [(x, y, d), ...]), from the base faces in §4's order."""
    first_face = {}          # vertex -> (face index, corner)
    faces_with_edge = {}     # undirected edge -> the faces that have both its corners
    corners_of = {}          # vertex -> [(face index, corner)] of every face with that corner
    for f, face in enumerate(faces):
        for i, v in enumerate(face):
            first_face.setdefault(v, (f, i))
            corners_of.setdefault(v, []).append((f, i))
            w = face[(i + 1) % 3]
            faces_with_edge.setdefault((min(v, w), max(v, w)), []).append(f)

    def parallelogram(f, i):
        v = faces[f][i]
        x, y = faces[f][(i + 1) % 3], faces[f][(i + 2) % 3]
        if x < v and y < v:
            for g in faces_with_edge[(min(x, y), max(x, y))]:
                if g != f:
                    d = [u for u in faces[g] if u != x and u != y][0]
                    if d < v:
                        return (x, y, d)
        return None

    recipes = []
    for v in range(vertex_count):
        found = [p for p in (parallelogram(f, i) for (f, i) in corners_of.get(v, [])) if p]
        if found:
            recipes.append(('parallelograms', found))
            continue
        if v in first_face:
            f, i = first_face[v]
            x, y = faces[f][(i + 1) % 3], faces[f][(i + 2) % 3]
            if x < v and y < v:
                recipes.append(('midpoint', x, y))
                continue
            if x < v:
                recipes.append(('copy', x))
                continue
            if y < v:
                recipes.append(('copy', y))
                continue
        recipes.append(('copy', v - 1) if v > 0 else ('zero',))
    return recipes


def predict(recipe, high, c):
    """§5.1: the prediction of one component, exact integers (// is floor division)."""
    kind = recipe[0]
    if kind == 'zero':
        return 0
    if kind == 'copy':
        return high[recipe[1]][c]
    if kind == 'midpoint':
        return (high[recipe[1]][c] + high[recipe[2]][c]) // 2
    found = recipe[1]
    return sum(high[x][c] + high[y][c] - high[d][c] for (x, y, d) in found) // len(found)


def decode_base_part(rc, h, faces):
    """§5.1: high[v][c] for every base vertex; a vertex cut short, and every later one, takes its
    prediction with a zero residual. Returns (high, exhausted)."""
    V0, K = h.base_vertices, h.components
    high = [[0] * K for _ in range(V0)]
    if h.base_plane > h.top_plane:
        return high, False
    recipes = base_predictions(faces, V0)
    magnitude = [IntegerCoder() for _ in range(K)]
    negative = [Model() for _ in range(K)]
    bound = 1 << (h.top_plane + 1 - h.base_plane)
    for v in range(V0):
        row = [0] * K
        try:
            for c in range(K):
                m = magnitude[c].decode(rc)
                r = -m if m != 0 and rc.decode_bit(negative[c]) else m
                row[c] = predict(recipes[v], high, c) + r
                if not -bound < row[c] < bound:
                    raise DecodeError('corrupt', 'a base part value out of range')
        except Exhausted:
            # A cut: this vertex and every later one take their prediction, clamped to the range.
            for u in range(v, V0):
                high[u] = [min(max(predict(recipes[u], high, c), 1 - bound), bound - 1) for c in range(K)]
            return high, True
        high[v] = row
    return high, False


class Coefficients:
    """Decoded bit-plane state per (vertex, component): `known` magnitude bits, lowest plane
    `low`, sign `state` (0 unknown, 1 positive, 2 negative)."""

    def __init__(self, vertex_count, components):
        self.known = [[0] * vertex_count for _ in range(components)]
        self.low = [[0] * vertex_count for _ in range(components)]
        self.state = [[0] * vertex_count for _ in range(components)]


def decode_coefficients(stream, h, levels):
    """§5.1 the base part, then §5.2 the bit planes: SPIHT per component with the contexts of
    versions 2 to 4; stops when the range decoder is exhausted (§7.6)."""
    children, vertex_level = coding_forest(levels)
    L = h.levels
    K = h.components
    total = levels[-1].vertex_count
    V0 = h.base_vertices
    coef = Coefficients(total, K)
    if h.top_plane < 0:
        return coef
    rc = RangeDecoder(stream)
    # §7.2 marks a stream whose first byte is not 0 (or whose code register is 0xFFFFFFFF)
    # "exhausted (corrupt)"; for the coefficient stream that is not an error status: like a
    # stream too short to start, it yields no symbols (what `meshlift decode` does).
    if rc.exhausted:
        return coef

    levels_count = 13
    lip_m = [[Model(7) for _ in range(K)] for _ in range(levels_count)]
    child_m = [[[[Model() for _ in range(4)] for _ in range(4)] for _ in range(K)]
               for _ in range(levels_count)]
    set_d_m = [[[Model(), Model()] for _ in range(K)] for _ in range(levels_count)]
    set_l_m = [[[Model(), Model()] for _ in range(K)] for _ in range(levels_count)]
    refine_m = [[Model() for _ in range(K)] for _ in range(levels_count)]
    sign_m = [[[Model(7) for _ in range(3)] for _ in range(K)] for _ in range(levels_count)]

    # L(v) is empty when v's children have no children: v is on level L - 1.
    def grandchildren_empty(v):
        return vertex_level[v] + 1 >= L

    high, cut = decode_base_part(rc, h, levels[0].faces)
    BP = h.base_plane
    ps = [[0] * total for _ in range(K)]
    known, low, state = coef.known, coef.low, coef.state
    LSP = [[v for v in range(V0) if BP <= h.top_plane and high[v][c] != 0] for c in range(K)]
    for c in range(K):
        for v in LSP[c]:
            state[c][v] = 2 if high[v][c] < 0 else 1
            known[c][v] = abs(high[v][c]) << BP
            low[c][v] = BP
    LIP = [[v for v in range(V0) if v not in set(LSP[c])] for c in range(K)]
    LIS = [[[v, 'A', False] for v in range(V0) if children[v]] for _ in range(K)]
    if cut:
        return coef

    def significant(u, c, n):
        negative = rc.decode_bit(sign_m[vertex_level[u]][c][ps[c][u]])
        state[c][u] = 2 if negative else 1
        LSP[c].append(u)
        known[c][u] = 1 << n
        low[c][u] = n

    try:
        for n in range(h.top_plane, -1, -1):
            for c in range(K):
                r = len(LSP[c])
                still = []
                for v in LIP[c]:
                    if n >= BP and v < V0:     # §5.2: a base vertex takes no decision above BP
                        still.append(v)
                    elif rc.decode_bit(lip_m[vertex_level[v]][c]):
                        significant(v, c, n)
                    else:
                        still.append(v)
                LIP[c] = still
                lis = LIS[c]
                kept = []
                i_entry = 0
                while i_entry < len(lis):
                    entry = lis[i_entry]
                    i_entry += 1
                    v, kind, implied = entry
                    s = 1 if state[c][v] != 0 else 0
                    t = state[c][v]
                    if kind == 'A':
                        if rc.decode_bit(set_d_m[vertex_level[v]][c][s]):
                            k = 0
                            kids = children[v]
                            m = len(kids)
                            no_grandchildren = grandchildren_empty(v)
                            for i, u in enumerate(kids):
                                ps[c][u] = t
                                if no_grandchildren and k == 0 and i == m - 1:
                                    bit = 1
                                else:
                                    bit = rc.decode_bit(
                                        child_m[vertex_level[u]][c][min(k, 3)][min(i, 3)])
                                if bit:
                                    significant(u, c, n)
                                    k += 1
                                else:
                                    LIP[c].append(u)
                            if not no_grandchildren:
                                lis.append([v, 'B', k == 0])
                        else:
                            kept.append(entry)
                    else:
                        if implied:
                            bit = 1
                        else:
                            bit = rc.decode_bit(set_l_m[vertex_level[v]][c][s])
                        if bit:
                            for u in children[v]:
                                if children[u]:
                                    lis.append([u, 'A', False])
                        else:
                            kept.append(entry)
                LIS[c] = kept
                for v in LSP[c][:r]:
                    if n >= BP and v < V0:
                        continue
                    bit = rc.decode_bit(refine_m[vertex_level[v]][c])
                    known[c][v] |= bit << n
                    low[c][v] = n
    except Exhausted:
        pass
    return coef


def dequantize(coef, h, vertex_level, component, vertex_count):
    """§5 Reconstruction: c = ±(known + 2^low / 2) · Δ_c / w_j; 0 where nothing is known."""
    known, low, state = coef.known[component], coef.low[component], coef.state[component]
    values = [0.0] * vertex_count
    for v in range(vertex_count):
        # a coefficient whose sign was not decoded yet (state 0) is still 0
        if known[v] == 0 or state[v] == 0:
            continue
        j = vertex_level[v]
        magnitude = (known[v] + 2.0 ** low[v] / 2) * component_step(h, j, component) / h.weights[j]
        values[v] = -magnitude if state[v] == 2 else magnitude
    return values


# §5 Local frames ----------------------------------------------------------------------------

def _dot(u, v):
    return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]


def _sub(u, v):
    return (u[0] - v[0], u[1] - v[1], u[2] - v[2])


def _cross(u, v):
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def _scale(s, v):
    return (s * v[0], s * v[1], s * v[2])


def rotate_details_to_xyz(level, geometry, details):
    """§5 Local frames: turn the (n, t1, t2) details of the odd vertices of level j + 1 into
    x, y, z, with frames from the level-j positions `geometry` (without the centre)."""
    x, y, z = geometry
    V = level.vertex_count
    normal_sum = [(0.0, 0.0, 0.0)] * V
    for (i0, i1, i2) in level.faces:
        p0 = (x[i0], y[i0], z[i0])
        p1 = (x[i1], y[i1], z[i1])
        p2 = (x[i2], y[i2], z[i2])
        cr = _cross(_sub(p1, p0), _sub(p2, p0))
        for v in (i0, i1, i2):
            s = normal_sum[v]
            normal_sum[v] = (s[0] + cr[0], s[1] + cr[1], s[2] + cr[2])
    dx, dy, dz = details
    for e, (a, b) in enumerate(level.edges):
        odd = V + e
        na, nb = normal_sum[a], normal_sum[b]
        n = (na[0] + nb[0], na[1] + nb[1], na[2] + nb[2])
        length = math.sqrt(_dot(n, n))
        pa = (x[a], y[a], z[a])
        pb = (x[b], y[b], z[b])
        d = _sub(pb, pa)
        if not (length > 1e-12 * _dot(d, d)) or not math.isfinite(length):
            continue   # identity frame
        n = _scale(1.0 / length, n)
        t1 = _sub(d, _scale(_dot(d, n), n))
        l1 = math.sqrt(_dot(t1, t1))
        if not (l1 > 1e-12 * math.sqrt(_dot(d, d))):
            if abs(n[0]) <= abs(n[1]) and abs(n[0]) <= abs(n[2]):
                axis = (1.0, 0.0, 0.0)
            elif abs(n[1]) <= abs(n[2]):
                axis = (0.0, 1.0, 0.0)
            else:
                axis = (0.0, 0.0, 1.0)
            t1 = _sub(axis, _scale(_dot(axis, n), n))
            l1 = math.sqrt(_dot(t1, t1))
        t1 = _scale(1.0 / l1, t1)
        t2 = _cross(n, t1)
        cn, c1, c2 = dx[odd], dy[odd], dz[odd]
        dx[odd] = cn * n[0] + c1 * t1[0] + c2 * t2[0]
        dy[odd] = cn * n[1] + c1 * t1[1] + c2 * t2[1]
        dz[odd] = cn * n[2] + c1 * t1[2] + c2 * t2[2]


# §5 Synthesis (docs/WAVELETS.md) -------------------------------------------------------------

def butterfly_weights(K):
    """Modified butterfly (Zorin, Schröder, Sweldens 1996) weights s_0..s_{K-1} on the ring of an
    extraordinary vertex of valence K, and the weight on the vertex itself."""
    if K == 3:
        return [5.0 / 12, -1.0 / 12, -1.0 / 12], 0.75
    if K == 4:
        return [3.0 / 8, 0.0, -1.0 / 8, 0.0], 0.75
    s = [(0.25 + math.cos(2 * math.pi * i / K) + 0.5 * math.cos(4 * math.pi * i / K)) / K
         for i in range(K)]
    return s, 0.75


def loop_beta(n):
    """Loop 1987: β_n = (1/n)(5/8 − (3/8 + ¼ cos(2π/n))²)."""
    return (5.0 / 8 - (3.0 / 8 + 0.25 * math.cos(2 * math.pi / n)) ** 2) / n


def sum_products(row, values):
    """Σ weight · value over a stencil row, left to right."""
    total = 0.0
    for (u, w) in row:
        total += w * values[u]
    return total


class Stencils:
    """The level j -> j + 1 rules (docs/WAVELETS.md, "Exact rules") as rows: `predict[e]` lists the
    (vertex, weight) pairs edge e's odd vertex adds to its detail; `update_first` (mean-preserving
    update, before the prediction) and `update_last` (Loop, after it) give each even vertex a
    (scale, [(odd vertex, weight)]) row."""

    def __init__(self, level, scheme, with_update):
        V = level.vertex_count
        third = {}   # third[(u, w)]: the third corner of the face with the directed edge u -> w
        for (a, b, c) in level.faces:
            third[(a, b)] = c
            third[(b, c)] = a
            third[(c, a)] = b
        neighbours = [[] for _ in range(V)]
        edge_of = {}
        for e, (a, b) in enumerate(level.edges):
            neighbours[a].append(b)
            neighbours[b].append(a)
            edge_of[(a, b)] = e
            edge_of[(b, a)] = e
        valence = [len(n) for n in neighbours]
        # boundary edges: one direction has no face
        on_boundary = [False] * V
        boundary_neighbours = [[] for _ in range(V)]
        for (a, b) in level.edges:
            if (a, b) not in third or (b, a) not in third:
                on_boundary[a] = on_boundary[b] = True
                boundary_neighbours[a].append(b)
                boundary_neighbours[b].append(a)
        self.predict = []
        for (a, b) in level.edges:
            c = third.get((a, b))
            d = third.get((b, a))
            interior = c is not None and d is not None
            if scheme == 'linear':
                row = [(a, 0.5), (b, 0.5)]
            elif scheme == 'loop':
                if interior:
                    row = [(a, 3.0 / 8), (b, 3.0 / 8), (c, 1.0 / 8), (d, 1.0 / 8)]
                else:
                    row = [(a, 0.5), (b, 0.5)]
            else:
                row = self._butterfly_row(a, b, c, d, third, valence, on_boundary,
                                          boundary_neighbours)
            self.predict.append(row)
        self.update_first = self.update_last = None
        if scheme == 'loop':
            self.update_last = []
            for v in range(V):
                if on_boundary[v]:
                    row = [(V + edge_of[(v, w)], 0.25) for w in boundary_neighbours[v]]
                    self.update_last.append((0.5, row))
                else:
                    n = valence[v]
                    w_n = 8 * loop_beta(n) / 5
                    s_n = 1 - n * w_n
                    self.update_last.append((s_n, [(V + edge_of[(v, w)], w_n)
                                                   for w in neighbours[v]]))
        elif with_update:
            # mean-preserving update (seed 003 eq. 5.9): λ_ℓ = 1 / (2 (1 + c_ℓ)), c_ℓ the
            # predictor's column sum; synthesis: even -= λ_ℓ Σ adjacent details.
            column = [0.0] * V
            for row in self.predict:
                for (u, w) in row:
                    column[u] += w
            self.update_first = []
            for v in range(V):
                lam = 1.0 / (2 * (1 + column[v]))
                self.update_first.append((1.0, [(V + edge_of[(v, w)], -lam)
                                                for w in neighbours[v]]))

    @staticmethod
    def _butterfly_row(a, b, c, d, third, valence, on_boundary, boundary_neighbours):
        if c is None or d is None:
            # boundary edge: 4-point rule (-1, 9, 9, -1)/16 along the boundary polyline
            a_other = [w for w in boundary_neighbours[a] if w != b][0]
            b_other = [w for w in boundary_neighbours[b] if w != a][0]
            return [(a, 9.0 / 16), (b, 9.0 / 16), (a_other, -1.0 / 16), (b_other, -1.0 / 16)]
        regular_a = valence[a] == 6 or on_boundary[a]
        regular_b = valence[b] == 6 or on_boundary[b]
        if regular_a and regular_b:
            row = [(a, 0.5), (b, 0.5), (c, 1.0 / 8), (d, 1.0 / 8)]
            # tips: the third vertices across the wing edges u -> w of the faces (a, b, c) and
            # (b, a, d); a missing one (a boundary wing edge, z the face's third corner) is
            # replaced by its reflection u + w - z
            for (u, w, z) in ((b, c, a), (c, a, b), (a, d, b), (d, b, a)):
                tip = third.get((w, u))
                if tip is not None:
                    row.append((tip, -1.0 / 16))
                else:
                    row += [(u, -1.0 / 16), (w, -1.0 / 16), (z, 1.0 / 16)]
            return row
        row = []
        count = 0
        for (centre, other) in ((a, b), (b, a)):
            if valence[centre] == 6 or on_boundary[centre]:
                continue
            count += 1
            s, self_weight = butterfly_weights(valence[centre])
            w = other
            for i in range(valence[centre]):
                row.append((w, s[i]))
                w = third[(w, centre)]
            row.append((centre, self_weight))
        return [(u, weight / count) for (u, weight) in row]

    def synthesize(self, values, V):
        """One level j -> j + 1 for one component, in place: `values[V + e]` holds the detail of
        edge e on entry and the odd vertex's value on exit."""
        if self.update_first is not None:
            self._update(self.update_first, values, V)
        for e, row in enumerate(self.predict):
            total = values[V + e]
            for (u, w) in row:
                total += w * values[u]
            values[V + e] = total
        if self.update_last is not None:
            self._update(self.update_last, values, V)

    @staticmethod
    def _update(rows, values, V):
        """Every even vertex from the odd values (rows read odd vertices only)."""
        values[:V] = [scale * values[v] + sum_products(row, values)
                      for v, (scale, row) in enumerate(rows)]


def synthesize(h, levels, coef, target_level):
    """§5: dequantize, then synthesize level by level (rotating details out of local frames
    first), then add the centres. Returns per-component value lists for level target_level."""
    total = levels[target_level].vertex_count
    vertex_level = [0] * total
    for j in range(1, target_level + 1):
        for v in range(levels[j - 1].vertex_count, levels[j].vertex_count):
            vertex_level[v] = j
    K = h.components
    values = [dequantize(coef, h, vertex_level, c, total) for c in range(K)]
    for j in range(target_level):
        level = levels[j]
        if h.local_frames:
            rotate_details_to_xyz(level, values[:3], values[:3])
        stencils = Stencils(level, h.scheme, h.update)
        for c in range(K):
            stencils.synthesize(values[c], level.vertex_count)
    centres = h.center + [x for (_, _, centre) in h.channels for x in centre]
    return [[x + centres[c] for x in values[c]] for c in range(K)]


# ---------------------------------------------------------------------------------------------
# Whole file
# ---------------------------------------------------------------------------------------------

def decode(data, level=None, colours=None):
    """Bytes (a whole file or a prefix) -> (positions [(x, y, z)], faces [(a, b, c)]). If `colours`
    is a list, it receives the vertices' colours [(r, g, b)] where flag bit 3 marks them (§3)."""
    read_file_header(data)
    chunks = read_chunks(data)
    head, base, stream = classify_chunks(chunks)
    h = read_header(head.payload)
    base_faces = decode_base_mesh(base.payload, h)
    check_manifold(base_faces, h.base_vertices)
    levels = build_hierarchy(base_faces, h)
    coef = decode_coefficients(stream, h, levels)
    target = h.levels if level is None else min(level, h.levels)
    values = synthesize(h, levels, coef, target)
    positions = list(zip(values[0], values[1], values[2]))
    if colours is not None and h.colour:
        colours.extend(zip(values[3], values[4], values[5]))
    return positions, levels[target].faces


def write_mesh(path, positions, faces):
    with open(path, 'w') as out:
        if path.lower().endswith('.obj'):
            for p in positions:
                out.write('v %r %r %r\n' % p)
            for f in faces:
                out.write('f %d %d %d\n' % (f[0] + 1, f[1] + 1, f[2] + 1))
        else:
            out.write('OFF\n%d %d 0\n' % (len(positions), len(faces)))
            for p in positions:
                out.write('%r %r %r\n' % p)
            for f in faces:
                out.write('3 %d %d %d\n' % f)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('input')
    parser.add_argument('-o', '--output', required=True, help='OUT.off or OUT.obj')
    parser.add_argument('--bytes', type=int, help='decode only the first N bytes')
    parser.add_argument('--level', type=int, help='stop at this level')
    args = parser.parse_args(argv)
    try:
        with open(args.input, 'rb') as f:
            data = f.read()
    except OSError as error:
        print('reference_decoder: %s: %s' % (args.input, error), file=sys.stderr)
        return 3
    if args.bytes is not None:
        data = data[:args.bytes]
    try:
        positions, faces = decode(data, args.level)
    except DecodeError as error:
        print('reference_decoder: %s: %s (error %d): %s'
              % (args.input, error.status, STATUS_CODES[error.status], error.message),
              file=sys.stderr)
        return 3
    try:
        write_mesh(args.output, positions, faces)
    except OSError as error:
        print('reference_decoder: %s: %s' % (args.output, error), file=sys.stderr)
        return 4
    return 0


if __name__ == '__main__':
    sys.exit(main())

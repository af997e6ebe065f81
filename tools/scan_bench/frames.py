"""Sequences, grids and decoded-point checks for the scan benchmark (tools/scan_bench).

A Sequence is a list of frames (x y z float32, metres, the file's finite points in file order),
with the ring/channel arrays where the files have them. Grids follow capz's for float32 PCD
frames (src/codec/grid_choice.cpp reserved_step, src/coding/quantiser.h): the step is
2 (B - r) (1 - 2^-30) with r half a float32 ulp at the largest |coordinate| + B, indices
round(x / step) half away from zero, decoded points float32(q step).
"""
import os
import struct

import numpy as np

import pcd

RING_FIELDS = ('ring', 'channel', 'laser_id', 'laser')


class Sequence:
    def __init__(self, name, files, frames, rings, nan_points):
        self.name, self.files, self.frames, self.rings = name, files, frames, rings
        self.nan_points = nan_points
        self.points = sum(len(f) for f in frames)
        self.file_bytes = sum(os.path.getsize(f) for f in files)

    @property
    def max_abs(self):
        return max(float(np.abs(f).max()) for f in self.frames if len(f))


def load(name, files, cache_dir=None):
    """Reads the PCD frames (cached as .npz under cache_dir)."""
    cache = os.path.join(cache_dir, name.replace('/', '_') + '.npz') if cache_dir else None
    if cache and os.path.exists(cache):
        z = np.load(cache, allow_pickle=True)
        frames = list(z['frames'])
        rings = None if z['rings'].shape == () else list(z['rings'])
        return Sequence(name, files, frames, rings, int(z['nan']))
    frames, rings, nan = [], [], 0
    for f in files:
        xyz, arrays = pcd.read_xyz(f)
        ok = np.isfinite(xyz).all(axis=1)
        nan += int((~ok).sum())
        frames.append(xyz[ok])
        ring = next((arrays[n] for n in RING_FIELDS if n in arrays), None)
        rings.append(None if ring is None else ring[ok].astype(np.int64))
    if any(r is None for r in rings) or len(np.unique(np.concatenate(rings))) < 2:
        rings = None
    if cache:
        fa = np.empty(len(frames), object)
        fa[:] = frames
        ra = np.array(None)
        if rings is not None:
            ra = np.empty(len(rings), object)
            ra[:] = rings
        np.savez(cache, frames=fa, rings=ra, nan=nan)
    return Sequence(name, files, frames, rings, nan)


def capz_step(bound, max_abs):
    _, e = np.frexp(max_abs + bound)
    reserve = 2.0 ** (int(e) - 25)
    return 2.0 * (bound - reserve) * (1.0 - 2.0 ** -30)


def quantise(xyz, step):
    v = xyz.astype(np.float64) / step
    return (np.sign(v) * np.floor(np.abs(v) + 0.5)).astype(np.int64)


def dequantise(q, step):
    return (q.astype(np.float64) * step).astype(np.float32)


def max_abs_error(orig, dec):
    """Largest per-coordinate error of decoded points in the original order."""
    if len(orig) == 0:
        return 0.0
    return float(np.abs(orig.astype(np.float64) - dec.astype(np.float64)).max())


def nn_error(orig, dec):
    """Per-coordinate (Chebyshev) Hausdorff distance between original and decoded points of a
    frame, for coders that reorder: the largest distance from a point of either set to the
    nearest of the other. A lower bound of the error under any pairing."""
    from scipy.spatial import cKDTree
    if len(orig) == 0 or len(dec) == 0:
        return 0.0 if len(orig) == len(dec) else float('inf')
    o, d = orig.astype(np.float64), dec.astype(np.float64)
    a, _ = cKDTree(d).query(o, p=np.inf)
    b, _ = cKDTree(o).query(d, p=np.inf)
    return float(max(a.max(), b.max()))


def same_multiset(a, b):
    """True when integer point sets a and b (n x 3) hold the same rows, duplicates counted."""
    if a.shape != b.shape:
        return False
    ka = a[np.lexsort(a.T[::-1])]
    kb = b[np.lexsort(b.T[::-1])]
    return bool((ka == kb).all())


# --- frame files shared with the C++ probes (frames_io.h) ---

def write_frames(path, frames):
    with open(path, 'wb') as f:
        for fr in frames:
            f.write(struct.pack('<I', len(fr)))
            f.write(np.ascontiguousarray(fr, '<f4').tobytes())


def read_frames(path):
    blob = open(path, 'rb').read()
    out, pos = [], 0
    while pos < len(blob):
        (n,) = struct.unpack_from('<I', blob, pos)
        pos += 4
        out.append(np.frombuffer(blob, '<f4', n * 3, pos).reshape(n, 3))
        pos += n * 12
    return out


# --- PLY ---

_PLY_TYPES = {'float': '<f4', 'float32': '<f4', 'double': '<f8', 'float64': '<f8', 'int': '<i4',
              'int32': '<i4', 'uint': '<u4', 'uint32': '<u4', 'short': '<i2', 'int16': '<i2',
              'ushort': '<u2', 'uint16': '<u2', 'char': '<i1', 'int8': '<i1', 'uchar': '<u1',
              'uint8': '<u1'}


def write_ply(path, xyz, dtype='<f4'):
    """Binary little-endian PLY of x y z (float32 or float64 by dtype)."""
    name = 'float' if np.dtype(dtype).itemsize == 4 else 'double'
    head = ('ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty %s x\n'
            'property %s y\nproperty %s z\nend_header\n' % (len(xyz), name, name, name))
    with open(path, 'wb') as f:
        f.write(head.encode('ascii'))
        f.write(np.ascontiguousarray(xyz, dtype).tobytes())


def read_ply_xyz(path):
    """x y z of a PLY's vertices (ascii or binary little/big endian), as float64."""
    blob = open(path, 'rb').read()
    end = blob.index(b'end_header') + len(b'end_header')
    end = blob.index(b'\n', end) + 1
    lines = blob[:end].decode('ascii').splitlines()
    fmt = next(l.split()[1] for l in lines if l.startswith('format'))
    props, count, in_vertex = [], 0, False
    for l in lines:
        w = l.split()
        if w[:1] == ['element']:
            in_vertex = w[1] == 'vertex'
            if in_vertex:
                count = int(w[2])
        elif w[:1] == ['property'] and in_vertex:
            props.append((w[-1], _PLY_TYPES[w[1]]))
    names = [p[0] for p in props]
    if fmt == 'ascii':
        vals = np.array(blob[end:].split()[:count * len(props)], np.float64)
        vals = vals.reshape(count, len(props))
        return vals[:, [names.index(c) for c in 'xyz']]
    order = '>' if fmt == 'binary_big_endian' else '<'
    dt = np.dtype([(n, order + t[1:]) for n, t in props])
    rec = np.frombuffer(blob, dt, count, end)
    return np.stack([rec[c].astype(np.float64) for c in 'xyz'], axis=1)

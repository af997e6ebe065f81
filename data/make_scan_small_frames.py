#!/usr/bin/env python3
"""Writes data/scan_small_ply/, data/scan_small_bin/, data/scan_small_nus/ and
data/scan_small_rec/: the first two
frames of data/scan_small/ (binary PCD, a cut of real RoboSense Helios 16P sweeps) as other tools
write PLY, KITTI .bin and nuScenes .pcd.bin frames, for the golden streams of format 1.1's
frame-file sources and their lossless residue (docs/FORMAT.md "Frame-file sources", "Lossless
frame-file streams"):

- scan_small_ply/NAME.ply: a script's binary_little_endian PLY: "ply", the format line, a comment
  line, `element vertex N`, `property float x|y|z|intensity` (intensity: the PCD's U1 value as a
  float), an empty face element (`element face 0`, `property list uchar int vertex_indices`),
  `end_header`, then the vertices, float32 little-endian;
- scan_small_bin/NAME.bin: float32 little-endian x y z intensity a point (what numpy's tofile of
  an (N, 4) float32 array writes), no header;
- scan_small_nus/NAME.pcd.bin: float32 little-endian x y z intensity ring a point, the ring the
  PCD's U2 channel as a float (nuScenes' layout and name: numpy's tofile of an (N, 5) array);
- scan_small_rec/NAME.bin: a record of another layout, as a C struct written out would give it
  (`--bin-fields "x y z intensity:U1 _:U1 ring:U2 t:U4"`, 20 bytes a point): float32 x y z, the
  PCD's U1 intensity, a zero padding byte, its U2 channel and its U4 time_stamp.

File names are the PCD frames' with the extension changed. Deterministic, standard library only.

usage: python3 data/make_scan_small_frames.py
"""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
CODES = {('F', 4): 'f', ('F', 8): 'd', ('U', 1): 'B', ('U', 2): 'H', ('U', 4): 'I',
         ('I', 1): 'b', ('I', 2): 'h', ('I', 4): 'i'}


def read_binary_pcd(path):
    """Rows of (x, y, z, intensity, channel, time_stamp) of a binary PCD frame."""
    b = open(path, 'rb').read()
    head, pos = {}, 0
    while True:
        e = b.index(b'\n', pos)
        line = b[pos:e].decode('ascii')
        pos = e + 1
        if line.startswith('#'):
            continue
        key, _, rest = line.partition(' ')
        head[key] = rest.split()
        if key == 'DATA':
            break
    fmt = '<' + ''.join(CODES[(t, int(s))] * int(c) for t, s, c in
                        zip(head['TYPE'], head['SIZE'], head['COUNT']))
    step = struct.calcsize(fmt)
    names = head['FIELDS']
    cols = [names.index(n) for n in ('x', 'y', 'z', 'intensity', 'channel', 'time_stamp')]
    n = int(head['POINTS'][0])
    return [tuple(float(v[c]) for c in cols)
            for v in (struct.unpack_from(fmt, b, pos + i * step) for i in range(n))]


def main():
    src = os.path.join(HERE, 'scan_small')
    ply_dir, bin_dir = os.path.join(HERE, 'scan_small_ply'), os.path.join(HERE, 'scan_small_bin')
    nus_dir, rec_dir = os.path.join(HERE, 'scan_small_nus'), os.path.join(HERE, 'scan_small_rec')
    for d in (ply_dir, bin_dir, nus_dir, rec_dir):
        os.makedirs(d, exist_ok=True)
    for name in sorted(os.listdir(src))[:2]:
        rows = read_binary_pcd(os.path.join(src, name))
        stem = os.path.splitext(name)[0]
        body = b''.join(struct.pack('<4f', *r[:4]) for r in rows)
        head = ('ply\nformat binary_little_endian 1.0\ncomment made by make_scan_small_frames.py\n'
                'element vertex %d\nproperty float x\nproperty float y\nproperty float z\n'
                'property float intensity\nelement face 0\n'
                'property list uchar int vertex_indices\nend_header\n' % len(rows))
        with open(os.path.join(ply_dir, stem + '.ply'), 'wb') as f:
            f.write(head.encode('ascii') + body)
        with open(os.path.join(bin_dir, stem + '.bin'), 'wb') as f:
            f.write(body)
        with open(os.path.join(nus_dir, stem + '.pcd.bin'), 'wb') as f:
            f.write(b''.join(struct.pack('<5f', *r[:5]) for r in rows))
        with open(os.path.join(rec_dir, stem + '.bin'), 'wb') as f:
            f.write(b''.join(struct.pack('<3fBBHI', r[0], r[1], r[2], int(r[3]), 0, int(r[4]),
                                         int(r[5])) for r in rows))


if __name__ == '__main__':
    main()

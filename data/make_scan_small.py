#!/usr/bin/env python3
"""Writes data/scan_small/: a cut of the four consecutive RoboSense Helios 16P sweeps in
../shared/data/scan/robosense-helios16p (tier4/nebula's test data, Apache-2.0: data/README.md),
small enough to bundle, as binary PCD frames of their own point counts (a ragged take, format
1.1: the golden streams of tests/golden/streams/scan_small.*).

Per frame, the points of firing columns FIRST .. FIRST + COLUMNS - 1 (a column is a run of points
whose channel numbers do not rise: the sensor fires its lasers from the top channel down, and a
column starts where the channel number goes up again), in the file's order, every field kept
(x y z intensity return_type channel azimuth elevation distance time_stamp), each value the one
the ascii source printed (its float32 fields are the float32 nearest the printed text, which is
the float32 the driver wrote). A beam without a return is missing from the source, not NaN, so
the frames' counts differ (about 2,000 points each) and none holds a NaN point. The header keeps
the source's FIELDS, SIZE, TYPE, COUNT and VIEWPOINT; WIDTH and POINTS are the cut's count,
HEIGHT 1, DATA binary. File names are the source's. Deterministic, standard library only.

usage: python3 data/make_scan_small.py [SRC_DIR [OUT_DIR]] [--first 600] [--columns 150]
"""
import argparse
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_SRC = os.path.join(HERE, '..', '..', 'shared', 'data', 'scan', 'robosense-helios16p')

# PCD TYPE and SIZE to a struct code (little-endian).
CODES = {('F', 4): 'f', ('F', 8): 'd', ('U', 1): 'B', ('U', 2): 'H', ('U', 4): 'I',
         ('I', 1): 'b', ('I', 2): 'h', ('I', 4): 'i'}


def read_ascii_pcd(path):
    """(header lines before DATA as (key, rest) pairs, rows of value strings)."""
    lines = open(path).read().splitlines()
    header, rows = [], []
    for i, l in enumerate(lines):
        if l.startswith('#'):
            continue
        key, _, rest = l.partition(' ')
        if key == 'DATA':
            if rest.strip() != 'ascii':
                raise SystemExit('%s: DATA %s, expected ascii' % (path, rest))
            rows = [r.split() for r in lines[i + 1:] if r.strip()]
            break
        header.append((key, rest))
    return header, rows


def cut(rows, channel, first, columns):
    """The rows of firing columns [first, first + columns), in order."""
    out, col, prev = [], 0, None
    for r in rows:
        c = int(r[channel])
        if prev is not None and c > prev:
            col += 1
        prev = c
        if first <= col < first + columns:
            out.append(r)
    return out


def write_binary_pcd(path, header, rows):
    h = dict(header)
    fields, sizes, types = h['FIELDS'].split(), h['SIZE'].split(), h['TYPE'].split()
    if any(c != '1' for c in h['COUNT'].split()):
        raise SystemExit('COUNT > 1 is not expected in the Helios source')
    fmt = '<' + ''.join(CODES[(t, int(s))] for t, s in zip(types, sizes))
    conv = [float if t == 'F' else int for t in types]
    text = ['# .PCD v0.7 - Point Cloud Data file format']
    for key, rest in header:
        if key in ('WIDTH', 'POINTS'):
            rest = str(len(rows))
        elif key == 'HEIGHT':
            rest = '1'
        text.append(key + ' ' + rest)
    text.append('DATA binary')
    body = b''.join(struct.pack(fmt, *(f(v) for f, v in zip(conv, r))) for r in rows)
    with open(path, 'wb') as out:
        out.write(('\n'.join(text) + '\n').encode('ascii') + body)
    return fields


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('src', nargs='?', default=DEFAULT_SRC)
    ap.add_argument('out', nargs='?', default=os.path.join(HERE, 'scan_small'))
    ap.add_argument('--first', type=int, default=600)
    ap.add_argument('--columns', type=int, default=150)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    for name in sorted(n for n in os.listdir(a.src) if n.endswith('.pcd')):
        header, rows = read_ascii_pcd(os.path.join(a.src, name))
        channel = dict(header)['FIELDS'].split().index('channel')
        kept = cut(rows, channel, a.first, a.columns)
        write_binary_pcd(os.path.join(a.out, name), header, kept)
        print('%s: %d of %d points' % (name, len(kept), len(rows)))


if __name__ == '__main__':
    main()

#!/usr/bin/env python3
"""Builds a preset dictionary for META coding 3 (docs/FORMAT.md 5.8) from C3D files.

  make_meta_dict.py OUT.bin [--min-files K] [--list] FILE.c3d ...

The dictionary is parameter records of C3D parameter sections, each as the file holds it from
its name to the end of its description (the two bytes before the name, the name's length and
its group number, are left out: group numbers differ between files). A record is kept when at
least K of the files (default 2) hold the same bytes, so what one take says alone (its subject,
its own labels) stays out and what vendors' software writes in every take goes in. Records are
taken file by file, the largest parameter section first, each record once; the files' runs of
records are then written in reverse, so the records of the largest sections, which most files
share, end nearest to the data the dictionary precedes (LZMA's distances are cheaper there).

The dictionary that format 8.0 names (docs/format/meta-dict-1.bin) was made with

  find ../shared/data/c3d -iname '*.c3d' -print0 | sort -z |
    xargs -0 tools/make_meta_dict.py docs/format/meta-dict-1.bin --min-files 2

from the shared C3D files (../shared/data/README). It is part of the format: changing it makes
another dictionary number, never a new meta-dict-1.bin. --list prints the files and how many of
their records went in; tools/meta_dict_eval.sh measures a dictionary on files it was not made
from.
"""
import collections
import struct
import sys


def parameter_section(path):
    """The parameter section's bytes (its 4-byte header and the records), or b'' if none."""
    with open(path, 'rb') as f:
        data = f.read()
    if len(data) < 512 or data[0] < 1:
        return b''
    start = (data[0] - 1) * 512
    if start + 4 > len(data):
        return b''
    blocks = max(data[start + 2], 1)
    return data[start:start + 512 * blocks]


def records(section):
    """Each parameter or group record's bytes after its first two, in file order."""
    out = []
    i = 4
    n = len(section)
    while i + 2 < n:
        name_len = section[i]
        if name_len > 127:
            name_len = 256 - name_len  # a locked record: negative length
        if name_len == 0:
            break
        j = i + 2 + name_len
        if j + 2 > n:
            break
        (offset,) = struct.unpack_from('<H', section, j)
        end = j + offset if offset else n
        if end > n or end <= j:
            break
        out.append(section[i + 2:end])
        if offset == 0:
            break
        i = end
    return out


def build(paths, min_files, show):
    sections = [(p, parameter_section(p)) for p in paths]
    sections = [(p, s) for p, s in sections if s]
    count = collections.Counter()
    for _, s in sections:
        for r in set(records(s)):
            count[r] += 1
    seen = set()
    runs = []
    for p, s in sorted(sections, key=lambda ps: (-len(ps[1]), ps[0])):
        run = []
        for r in records(s):
            if count[r] >= min_files and r not in seen:
                seen.add(r)
                run.append(r)
        if show:
            print(f'{len(run):5d} records  {p}')
        if run:
            runs.append(b''.join(run))
    runs.reverse()
    return b''.join(runs)


def main(argv):
    if len(argv) < 2:
        sys.exit(__doc__)
    out = argv[0]
    min_files = 2
    show = False
    paths = []
    i = 1
    while i < len(argv):
        if argv[i] == '--min-files':
            min_files = int(argv[i + 1])
            i += 2
            continue
        if argv[i] == '--list':
            show = True
        else:
            paths.append(argv[i])
        i += 1
    d = build(paths, min_files, show)
    with open(out, 'wb') as f:
        f.write(d)
    print(f'{out}: {len(d)} bytes from {len(paths)} files', file=sys.stderr)


if __name__ == '__main__':
    main(sys.argv[1:])

"""PCD frame reading for the scan benchmark (tools/scan_bench): the three encodings (ascii,
binary, binary_compressed with LZF), `_` padding fields, COUNT > 1. numpy only.

read_pcd(path) -> (fields, arrays): fields is a list of (name, size, type, count) and arrays a
dict name -> numpy array of shape (points,) or (points, count). write_xyz_pcd writes a binary
PCD of x y z float32 (the geometry-only frames the harness gives capz).
"""
import numpy as np

_TYPES = {('F', 4): '<f4', ('F', 8): '<f8', ('U', 1): '<u1', ('U', 2): '<u2', ('U', 4): '<u4',
          ('U', 8): '<u8', ('I', 1): '<i1', ('I', 2): '<i2', ('I', 4): '<i4', ('I', 8): '<i8'}


def lzf_decompress(src, out_len):
    """LZF (liblzf's format, as PCL writes it): literal runs and back references."""
    out = bytearray(out_len)
    i = o = 0
    n = len(src)
    while i < n:
        c = src[i]
        i += 1
        if c < 32:  # literal run of c + 1 bytes
            run = c + 1
            out[o:o + run] = src[i:i + run]
            i += run
            o += run
            continue
        length = c >> 5
        if length == 7:
            length += src[i]
            i += 1
        ref = o - ((c & 0x1f) << 8) - src[i] - 1
        i += 1
        length += 2
        if ref < 0:
            raise ValueError('LZF back reference before the start')
        if ref + length <= o:
            out[o:o + length] = out[ref:ref + length]
            o += length
        else:  # overlapping copy, byte by byte
            for k in range(length):
                out[o] = out[ref + k]
                o += 1
    if o != out_len:
        raise ValueError('LZF data gives %d bytes, header says %d' % (o, out_len))
    return bytes(out)


def _header(blob, path):
    hdr = {}
    pos = 0
    while True:
        end = blob.index(b'\n', pos)
        line = blob[pos:end].decode('ascii', 'replace').strip()
        pos = end + 1
        if not line or line.startswith('#'):
            continue
        key, _, rest = line.partition(' ')
        hdr[key.upper()] = rest.split()
        if key.upper() == 'DATA':
            return hdr, pos
        if pos >= len(blob):
            raise ValueError('%s: no DATA line' % path)


def read_pcd(path):
    blob = open(path, 'rb').read()
    hdr, pos = _header(blob, path)
    names = hdr['FIELDS']
    sizes = [int(s) for s in hdr['SIZE']]
    types = hdr['TYPE']
    counts = [int(c) for c in hdr.get('COUNT', ['1'] * len(names))]
    points = int(hdr['POINTS'][0])
    fields = list(zip(names, sizes, types, counts))
    dtype = np.dtype([('%s_%d' % (n, k) if n == '_' else n, _TYPES[(t, s)], (c,))
                      for k, (n, s, t, c) in enumerate(fields)])
    data = hdr['DATA'][0].lower()
    if data == 'ascii':
        text = blob[pos:].split()
        vals = np.array(text[:points * sum(counts)], dtype=np.float64).reshape(points, -1)
        rec = np.zeros(points, dtype)
        col = 0
        for name in dtype.names:
            c = dtype[name].shape[0]
            rec[name] = vals[:, col:col + c].astype(dtype[name].base)
            col += c
    elif data == 'binary':
        rec = np.frombuffer(blob, dtype, points, pos)
    elif data == 'binary_compressed':
        csize, usize = np.frombuffer(blob, '<u4', 2, pos)
        raw = lzf_decompress(blob[pos + 8:pos + 8 + int(csize)], int(usize))
        rec = np.zeros(points, dtype)
        off = 0
        for name in dtype.names:  # field by field (structure of arrays)
            d = dtype[name]
            nbytes = d.itemsize * points
            rec[name] = np.frombuffer(raw, d.base, points * d.shape[0], off).reshape(points, -1)
            off += nbytes
    else:
        raise ValueError('%s: unknown DATA %s' % (path, data))
    arrays = {}
    for name in dtype.names:
        a = np.asarray(rec[name])
        arrays[name] = a[:, 0] if a.shape[1] == 1 else a
    return fields, arrays


def read_xyz(path):
    """x y z as float32 (points x 3) and the file's other arrays."""
    _, arrays = read_pcd(path)
    xyz = np.stack([arrays['x'], arrays['y'], arrays['z']], axis=1).astype(np.float32)
    return xyz, arrays


def write_xyz_pcd(path, xyz):
    xyz = np.ascontiguousarray(xyz, dtype='<f4')
    head = ('VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH %d\nHEIGHT 1\n'
            'VIEWPOINT 0 0 0 1 0 0 0\nPOINTS %d\nDATA binary\n' % (len(xyz), len(xyz)))
    with open(path, 'wb') as f:
        f.write(head.encode('ascii'))
        f.write(xyz.tobytes())

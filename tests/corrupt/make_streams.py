#!/usr/bin/env python3
"""Hand-crafts the corrupt .capz streams in streams/ from a valid one (docs/FORMAT.md).
Run from tests/corrupt: python3 make_streams.py VALID.capz   (committed outputs; rerun only when
the format changes; VALID.capz is ../golden/streams/Capture0004.c3d.grid1mm.v1.0.capz, format 1.0)
Each file's name says what is wrong; test_corrupt.cpp expects every one to be rejected cleanly."""
import struct, sys, zlib, os

def crc32c(data):
    crc = 0xFFFFFFFF
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = (crc >> 1) ^ (0x82F63B78 if crc & 1 else 0)
    return crc ^ 0xFFFFFFFF

def chunks(b):
    off = 15
    out = []
    while off < len(b):
        t = b[off:off+4]; n = struct.unpack('<I', b[off+4:off+8])[0]
        out.append((off, t, n))
        off += 12 + n
    return out

def rechunk(t, payload):
    return t + struct.pack('<I', len(payload)) + payload + struct.pack('<I', crc32c(t + payload))

def with_version(b, major, minor):
    """b with version major.minor in its file header, the header's CRC made right."""
    h = b[:9] + bytes([major, minor])
    return h + struct.pack('<I', crc32c(h)) + b[15:]

src = open(sys.argv[1], 'rb').read()
assert src[9:11] == bytes([1, 0]), 'a format 1.0 stream is needed'
cs = chunks(src)
out = {}
out['empty.capz'] = b''
out['text_file.capz'] = b'hello, this is not a capz file\n'
out['magic_only.capz'] = src[:9]
out['crlf_converted_magic.capz'] = src[:5] + b'\r\r\n' + src[7:]
out['future_major_version.capz'] = with_version(src, 2, 0)  # capz reads 1.x
out['major_version_zero.capz'] = with_version(src, 0, 0)
out['version_bytes_bad_crc.capz'] = src[:9] + bytes([1, 1]) + src[11:]
# The pre-release magic (capz 0.1.0 and earlier, formats 1.0-9.3): refused as unsupported.
out['prerelease_magic.capz'] = src[:1] + b'capz' + src[5:9] + bytes([9, 3]) + src[11:]
out['truncated_half.capz'] = src[:len(src)//2]
out['truncated_last_byte.capz'] = src[:-1]
out['truncated_after_meta.capz'] = src[:cs[2][0]]
out['trailing_garbage.capz'] = src + b'\0' * 7
# bad CRCs
off, t, n = cs[0]
b = bytearray(src); b[off + 8] ^= 1; out['head_bad_crc.capz'] = bytes(b)
posw = [c for c in cs if c[1] == b'POSW'][0]
b = bytearray(src); b[posw[0] + 8 + posw[2]//2] ^= 0x10; out['posw_bad_crc.capz'] = bytes(b)
# chunk length past the end of the file
b = bytearray(src); b[posw[0]+4:posw[0]+8] = struct.pack('<I', 0x7FFFFFF0); out['posw_length_past_end.capz'] = bytes(b)
# HEAD with valid CRC but lying counts
head = bytearray(src[cs[0][0]+8:cs[0][0]+8+cs[0][2]])
def with_head(h):
    return src[:15] + rechunk(b'HEAD', bytes(h)) + src[cs[0][0] + 12 + cs[0][2]:]
h = bytearray(head); h[0:8] = struct.pack('<Q', 1 << 39); out['head_huge_frame_count.capz'] = with_head(h)
h = bytearray(head); h[8:12] = struct.pack('<I', 0xFFFFFFFF); out['head_huge_point_count.capz'] = with_head(h)
h = bytearray(head); h[12:16] = struct.pack('<I', 0); out['head_zero_window.capz'] = with_head(h)
h = bytearray(head); h[17] = 9; out['head_unknown_mode.capz'] = with_head(h)
h = bytearray(head); h[20:28] = struct.pack('<d', float('nan')); out['head_nan_step.capz'] = with_head(h)
h = bytearray(head); h[18] = 200; out['head_unknown_codec.capz'] = with_head(h)
h = bytearray(head); h[0:8] = struct.pack('<Q', struct.unpack('<Q', head[0:8])[0] + 1); out['head_one_frame_more.capz'] = with_head(h)
# META replaced by garbage with a valid CRC
m = cs[1]
out['meta_garbage.capz'] = src[:m[0]] + rechunk(b'META', b'\xff' * 40) + src[m[0] + 12 + m[2]:]
# chunks swapped: META first
out['meta_before_head.capz'] = src[:15] + src[m[0]:m[0]+12+m[2]] + src[cs[0][0]:cs[0][0]+12+cs[0][2]] + src[m[0]+12+m[2]:]
# POSW payload: residual block replaced by zeros (valid CRC)
pp = bytearray(src[posw[0]+8:posw[0]+8+posw[2]])
tail = len(pp) // 2
pp[tail:] = b'\0' * (len(pp) - tail)
out['posw_zeroed_residuals.capz'] = src[:posw[0]] + rechunk(b'POSW', bytes(pp)) + src[posw[0]+12+posw[2]:]
# POSW claims another window
pp = bytearray(src[posw[0]+8:posw[0]+8+posw[2]]); pp[0] = 5
out['posw_wrong_window.capz'] = src[:posw[0]] + rechunk(b'POSW', bytes(pp)) + src[posw[0]+12+posw[2]:]
# INDX with an offset into the middle of a chunk
ix = cs[-1]
ip = bytearray(src[ix[0]+8:ix[0]+8+ix[2]])
ip[1:9] = struct.pack('<Q', struct.unpack('<Q', ip[1:9])[0] + 3)
out['indx_bad_offset.capz'] = src[:ix[0]] + rechunk(b'INDX', bytes(ip))
# INDX removed
out['indx_missing.capz'] = src[:ix[0]]
# A 1.1 stream with a critical chunk type 1.0 does not know, after META (FORMAT.md 2): refused
# as unsupported, naming the chunk (the INDX offsets moved with it).
extra = rechunk(b'SCAN', b'\x01\x02\x03')
at = m[0] + 12 + m[2]
ip = bytearray(src[ix[0]+8:ix[0]+8+ix[2]])
count, pos = 0, 0
while True:  # the window count, a varint
    count |= (ip[pos] & 0x7F) << (7 * pos)
    pos += 1
    if not ip[pos - 1] & 0x80:
        break
for w in range(count):
    o = pos + 16 * w
    ip[o:o+8] = struct.pack('<Q', struct.unpack('<Q', ip[o:o+8])[0] + len(extra))
body = src[:at] + extra + src[at:ix[0]] + rechunk(b'INDX', bytes(ip))
out['unknown_critical_chunk.capz'] = with_version(body, 1, 1)
os.makedirs('streams', exist_ok=True)
for k, v in out.items():
    open(os.path.join('streams', k), 'wb').write(v)
print(len(out), 'streams')

"""The scan benchmark's peers (tools/scan_bench): each runner codes one sequence at one bound
(or losslessly), decodes it, measures the error on the decoded points and returns a Result.
Times are the CPU seconds (user + system) of the peer's processes, or of the probe's own coding
loops where a peer has no command line (Cloudini, PCL), one thread each.
"""
import filecmp
import glob
import os
import resource
import shutil
import subprocess

import numpy as np

import frames as fr
import laser_table

# MPEG's common test conditions for the octree (cfg/octree-*-ctc-*.yaml): without these the
# neighbour contexts are off.
CTC_OCTREE = ['--neighbourAvailBoundaryLog2=8', '--intra_pred_max_node_size_log2=6',
              '--inferredDirectCodingMode=1']
GRID = ['--inputScale=1', '--positionQuantizationScale=1', '--mergeDuplicatedPoints=0']


class Result(dict):
    """bytes, max_error, enc_s, dec_s, check (how the error was measured), ok, note, config."""


def run(cmd, cwd=None):
    """Runs cmd; returns (completed process, CPU seconds of it and its children)."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return p, (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


def _fresh(path):
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(path)
    return path


def _fail(p, what):
    msg = (p.stderr or p.stdout or '').strip().splitlines()
    return Result(ok=False, note='%s failed (exit %d): %s' % (what, p.returncode,
                                                             msg[-1][:160] if msg else ''))


# --- G-PCC (TMC13) ---

def write_grid_plys(qframes, folder):
    """Integer grid frames as binary PLY (float32 holds these integers exactly)."""
    _fresh(folder)
    for k, q in enumerate(qframes):
        fr.write_ply(os.path.join(folder, 'f%04d.ply' % k), q.astype(np.float32))


def tmc13(seq, qframes, step, tmc3, ply_dir, work, options, config):
    """Codes the integer frames in ply_dir as one TMC13 stream (frames in order), decodes it and
    checks the decoded grid against the input, frame by frame, as multisets."""
    _fresh(work)
    n = len(qframes)
    stream = os.path.join(work, 'seq.bin')
    # The sequence's box over all frames: by default TMC13 takes the first frame's, and clamps
    # later frames' points that fall outside it.
    allq = np.concatenate(qframes)
    lo, hi = allq.min(axis=0), allq.max(axis=0)
    options = ['--autoSeqBbox=0', '--seqOrigin=%d,%d,%d' % tuple(lo),
               '--seqSizeWhd=%d,%d,%d' % tuple(hi - lo + 1)] + options
    enc = [tmc3, '--mode=0', '--uncompressedDataPath=' + os.path.join(ply_dir, 'f%04d.ply'),
           '--firstFrameNum=0', '--frameCount=%d' % n, '--compressedStreamPath=' + stream
           ] + GRID + options
    p, enc_s = run(enc)
    if p.returncode != 0 or not os.path.exists(stream):
        return _fail(p, 'tmc3 encode')
    dec = [tmc3, '--mode=1', '--compressedStreamPath=' + stream, '--firstFrameNum=0',
           '--reconstructedDataPath=' + os.path.join(work, 'd%04d.ply'), '--outputBinaryPly=1']
    p, dec_s = run(dec)
    if p.returncode != 0:
        return _fail(p, 'tmc3 decode')
    exact, err = True, 0.0
    for k, q in enumerate(qframes):
        path = os.path.join(work, 'd%04d.ply' % k)
        d = fr.read_ply_xyz(path) if os.path.exists(path) else np.zeros((0, 3))
        dq = np.rint(d).astype(np.int64)
        if fr.same_multiset(dq, q) and np.abs(d - dq).max(initial=0) == 0:
            err = max(err, fr.max_abs_error(seq.frames[k], fr.dequantise(q, step)))
        else:
            exact = False
            err = max(err, fr.nn_error(seq.frames[k], fr.dequantise(dq, step)))
    return Result(ok=exact, bytes=os.path.getsize(stream), max_error=err, enc_s=enc_s,
                  dec_s=dec_s, check='decoded grid == input grid' if exact else
                  'GRID DIFFERS: nearest decoded point', config=config,
                  note='' if exact else 'decoded grid differs from the input grid')


def gpcc_configs(seq, step):
    """(peer name, config text, TMC13 options) of the G-PCC configurations measured."""
    # randomAccessPeriod defaults to 1 (every frame intra): one random access point per
    # sequence lets every later frame be predicted from the one before.
    inter = ['--interPredictionEnabled=1', '--randomAccessPeriod=%d' % len(seq.frames)]
    out = [('gpcc-octree', 'octree, CTC options, each frame intra', CTC_OCTREE + ['--geomTreeType=0'])]
    table = laser_table.infer(seq.frames, seq.rings)
    ang = laser_table.tmc13_options(table, step) + ['--predGeomAzimuthSortPrecision=1024']
    src = 'ring field' if seq.rings is not None else 'clustered'
    out.append(('gpcc-angular', 'predictive tree, angular, %d lasers (%s), file order'
                % (len(table), src), ang + ['--predGeomSort=0']))
    out.append(('gpcc-angular-az', 'predictive tree, angular, %d lasers (%s), azimuth sort'
                % (len(table), src), ang + ['--predGeomSort=2']))
    if len(seq.frames) > 1:
        out.append(('gpcc-octree-inter', 'octree, CTC options, inter over the sequence',
                    CTC_OCTREE + ['--geomTreeType=0'] + inter))
    # The octree with the same laser table (angular contexts), as MPEG's test conditions run
    # it on LiDAR sequences.
    keep = ('--angularEnabled', '--numLasers', '--lasersTheta', '--lasersZ',
            '--lasersNumPhiPerTurn', '--lidarHeadPosition')
    oct_ang = CTC_OCTREE + ['--geomTreeType=0', '--planarBufferDisabled=1'] + [
        o for o in laser_table.tmc13_options(table, step) if o.split('=')[0] in keep]
    out.append(('gpcc-octree-angular', 'octree, CTC options, angular, %d lasers (%s), each '
                'frame intra' % (len(table), src), oct_ang))
    # Angular octree with inter is left out: this TMC13's decoder crashed on its streams
    # (pandar64-factory20 and robosense-helios16p, 1 mm and 1 cm; docs/bench/SCANS.md).
    return out


# --- Draco ---

def _draco_bits(xyz, bound):
    rng = float(np.ptp(xyz.astype(np.float64), axis=0).max()) if len(xyz) else 1.0
    bits = 1
    while bits < 30 and rng / ((1 << bits) - 1) / 2 > bound * (1 - 1e-6):
        bits += 1
    return bits


def draco(seq, bound, work, level=10):
    """draco_encoder -point_cloud per frame, quantisation bits chosen per frame from its
    bounding box (Draco's step is the largest extent over 2^bits - 1), raised by one where the
    decoded frame misses the bound. Error by nearest decoded point (Draco reorders)."""
    _fresh(work)
    total = enc_s = dec_s = err = 0.0
    qps = []
    for k, xyz in enumerate(seq.frames):
        src = os.path.join(work, 'f%04d.ply' % k)
        fr.write_ply(src, xyz)
        bits = _draco_bits(xyz, bound)
        for _ in range(3):
            drc, out = os.path.join(work, 'f%04d.drc' % k), os.path.join(work, 'd%04d.ply' % k)
            p, e = run(['draco_encoder', '-point_cloud', '-i', src, '-o', drc, '-qp', str(bits),
                        '-cl', str(level)])
            if p.returncode != 0:
                return _fail(p, 'draco_encoder')
            p, d = run(['draco_decoder', '-i', drc, '-o', out])
            if p.returncode != 0:
                return _fail(p, 'draco_decoder')
            e_k = fr.nn_error(xyz, fr.read_ply_xyz(out).astype(np.float32))
            if e_k <= bound or bits >= 30:
                break
            bits += 1
        total += os.path.getsize(drc)
        enc_s += e
        dec_s += d
        err = max(err, e_k)
        qps.append(bits)
    return Result(ok=True, bytes=int(total), max_error=err, enc_s=enc_s, dec_s=dec_s,
                  check='nearest decoded point', config='-point_cloud -cl %d -qp %d..%d'
                  % (level, min(qps), max(qps)))


# --- Cloudini and PCL (our probes) ---

def _probe(cmd, seq, out_path):
    import json
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        return None, p
    return json.loads(p.stdout.strip().splitlines()[-1]), fr.read_frames(out_path)


def cloudini(seq, bound, frames_path, probe, work):
    """Cloudini's encoder at resolution 2 B (its max error is half the resolution), in order."""
    _fresh(work)
    out = os.path.join(work, 'dec.frames')
    js, dec = _probe([probe, frames_path, repr(2 * bound), out], seq, out)
    if js is None:
        return _fail(dec, 'scan_cloudini')
    err = max(fr.max_abs_error(o, d) for o, d in zip(seq.frames, dec))
    return Result(ok=True, bytes=js['bytes'], max_error=err, enc_s=js['encode_s'],
                  dec_s=js['decode_s'], check='in order', config='resolution %g m, zstd, '
                  'one thread' % (2 * bound))


def pcl_octree(seq, bound, frames_path, probe, work, iframe=30):
    """PCL's octree coder, point resolution B (then 0.99 B, 0.9 B, 0.5 B until the bound holds
    by nearest decoded point), octree resolution 16 x that."""
    _fresh(work)
    out = os.path.join(work, 'dec.frames')
    for f in (1.0, 0.99, 0.9, 0.5):
        js, dec = _probe([probe, frames_path, repr(f * bound), str(iframe), out], seq, out)
        if js is None:
            return _fail(dec, 'scan_pcl_octree')
        err = max(fr.nn_error(o, d) for o, d in zip(seq.frames, dec))
        if err <= bound:
            break
    return Result(ok=True, bytes=js['bytes'], max_error=err, enc_s=js['encode_s'],
                  dec_s=js['decode_s'], check='nearest decoded point',
                  config='point res %g m, octree res 16x, I-frame every %d' % (f * bound, iframe))


# --- general-purpose compressors of the frame files (lossless) ---

def file_compressor(files, name, work):
    """xz -9e or zstd -19 (one thread) of each frame file; returns bytes and times."""
    _fresh(work)
    enc, dec = {'xz': (['xz', '-9e', '-T1', '-c'], ['xz', '-d', '-T1', '-c']),
                'zstd': (['zstd', '-19', '-q', '-c'], ['zstd', '-d', '-q', '-c'])}[name]
    total = enc_s = dec_s = 0.0
    for k, f in enumerate(files):
        out = os.path.join(work, 'f%04d.%s' % (k, name))
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        with open(out, 'wb') as o:
            subprocess.run(enc + [f], stdout=o, check=True)
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        with open(os.devnull, 'wb') as o:
            subprocess.run(dec + [out], stdout=o, check=True)
        r2 = resource.getrusage(resource.RUSAGE_CHILDREN)
        enc_s += r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime
        dec_s += r2.ru_utime - r1.ru_utime + r2.ru_stime - r1.ru_stime
        total += os.path.getsize(out)
    return Result(ok=True, bytes=int(total), max_error=0.0, enc_s=enc_s, dec_s=dec_s,
                  check='lossless', config=' '.join(enc[1:-1]))


# --- capz ---

def _capz_round(capz_bin, src, work, opts):
    """capz compress of src with opts, one thread, then decompress to work/dec: (archive path,
    output path, encode CPU s, decode CPU s), or a failed Result."""
    _fresh(work)
    arc = os.path.join(work, 'seq.capz')
    p, enc_s = run([capz_bin, 'compress', src, '-o', arc, '-T', '1', '-q'] + opts)
    if p.returncode != 0:
        return _fail(p, 'capz compress ' + ' '.join(opts))
    out = os.path.join(work, 'dec')
    p, dec_s = run([capz_bin, 'decompress', arc, '-o', out, '-T', '1', '-q'])
    if p.returncode != 0:
        return _fail(p, 'capz decompress')
    return arc, out, enc_s, dec_s


def capz(seq, bound, xyz_dir, capz_bin, work, order='kept'):
    """capz compress of the x y z frames at the bound, one thread, the points' order kept or
    (order 'any') as the encoder finds cheapest; the error by the decoded point in order, or by
    the nearest decoded point when the order changed."""
    opts = ['--max-error', '%gm' % bound, '--units', 'm']
    opts += ['--point-order', 'any'] if order == 'any' else []
    done = _capz_round(capz_bin, xyz_dir, work, opts)
    if isinstance(done, Result):
        return done
    arc, out, enc_s, dec_s = done
    import pcd
    dec = [pcd.read_xyz(f)[0] for f in sorted(glob.glob(os.path.join(out, '*.pcd')))]
    same = len(dec) == len(seq.frames) and all(
        len(a) == len(b) for a, b in zip(seq.frames, dec))
    # In order when the kept order came back, or `any` left every point within the bound of its
    # own; else by the nearest decoded point.
    err = max((fr.max_abs_error(a, b) for a, b in zip(seq.frames, dec)), default=0.0) \
        if same else float('inf')
    in_order = same and (order != 'any' or err <= bound)
    if same and not in_order:
        err = max(fr.nn_error(a, b) for a, b in zip(seq.frames, dec))
    return Result(ok=True, bytes=os.path.getsize(arc), max_error=err, enc_s=enc_s,
                  dec_s=dec_s, check='in order' if in_order else 'nearest decoded point',
                  config=' '.join(opts + ['-T 1']))


def capz_lossless(files, capz_bin, work):
    """capz compress --lossless of the frame files as given (all fields; the folder, or the
    file of a one-frame sequence), decompressed and compared byte for byte with each file."""
    src = files[0] if len(files) == 1 else os.path.dirname(files[0])
    done = _capz_round(capz_bin, src, work, ['--lossless'])
    if isinstance(done, Result):
        return done
    arc, out, enc_s, dec_s = done
    got = out if os.path.isfile(out) else None
    for f in files:
        g = got or os.path.join(out, os.path.basename(f))
        if not os.path.exists(g) or not filecmp.cmp(f, g, shallow=False):
            return Result(ok=False, note='capz --lossless: %s not given back byte for byte' % f)
    return Result(ok=True, bytes=os.path.getsize(arc), max_error=0.0, enc_s=enc_s,
                  dec_s=dec_s, check='lossless', config='--lossless -T 1')

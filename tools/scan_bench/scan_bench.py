#!/usr/bin/python3
"""Scan sequences against their peers (issue #37 item 7): one row per sequence, bound and peer.

  tools/scan_bench/scan_bench.py --capz BUILD/capz [--peers /work/build-peers]
      [--data ../shared/data/scan] [--work DIR] [--bounds 0.001,0.01] [--only NAME,...]
      [--skip PEER,...] [--tsv docs/bench/scan_peers_DATE.tsv] [--plot docs/img/scan_rd.png]
      [--md FILE]

Sequences: pandar64-factory20 (20 sweeps), robosense-e1, robosense-helios16p, and each file of
single/ as a one-frame sequence; the finite points of each frame in file order (x y z float32,
metres). Peers (tools/scan_bench/build_peers.sh builds TMC13 and the Cloudini probe; Draco is
Debian's draco; the PCL probe is build/tools/scan_pcl_octree):
  gpcc-octree        TMC13 octree, MPEG's test-condition options, every frame intra
  gpcc-angular[-az]  TMC13 angular predictive tree, laser table from laser_table.py, file order
                     (predGeomSort=0) or azimuth sort (=2)
  gpcc-octree-inter  TMC13 octree with inter prediction over the sequence
                     (each G-PCC run codes the integers round(x / step) of capz's grid at
                     inputScale 1, duplicates kept; its decoded grid is checked against them)
  cloudini           Cloudini's per-cloud encoder at resolution 2 B
  draco              draco_encoder -point_cloud, quantisation bits meeting B per frame
  pcl-octree         PCL's OctreePointCloudCompression, point resolution B
  capz               capz compress of the x y z frames (binary PCD) at --max-error B, -T 1,
                     the points' order kept (the default)
  capz-any           the same with --point-order any
  capz-lossless      capz compress --lossless of the frame files as given (all fields), every
                     file given back byte for byte
  xz-9e, zstd-19     of the frame files as given (all fields; lossless), and xz-9e-xyz of the
                     x y z binary PCD frames capz reads (geometry only, lossless)
Bits per point: 8 x bytes / points over all frames (geometry only, except xz-9e and zstd-19 of
the files). Max error: largest per-coordinate error on the decoded points against the float32
originals, in metres (by the decoded grid, in order, or by the nearest decoded point for coders
that reorder). Speeds: points and MB of x y z float32 input (12 B a point; the files' bytes for
xz-9e/zstd-19) per CPU second, one thread.
"""
import argparse
import datetime
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import frames as fr  # noqa: E402
import pcd  # noqa: E402
import peers  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
COLUMNS = ['sequence', 'frames', 'points', 'bound_m', 'peer', 'config', 'bytes',
           'bits_per_point', 'max_error_m', 'bound_held', 'check', 'enc_cpu_s', 'dec_cpu_s',
           'enc_Mpoints_s', 'dec_Mpoints_s', 'enc_MB_s', 'dec_MB_s', 'note']


def sequences(data):
    out = []
    for name in ('pandar64-factory20', 'robosense-e1', 'robosense-helios16p'):
        d = os.path.join(data, name)
        out.append((name, sorted(os.path.join(d, f) for f in os.listdir(d) if f.endswith('.pcd'))))
    single = os.path.join(data, 'single')
    for f in sorted(os.listdir(single)):
        if f.endswith('.pcd'):
            out.append(('single/' + f[:-4], [os.path.join(single, f)]))
    return out


def row(seq, bound, peer, r, input_mb):
    d = {'sequence': seq.name, 'frames': len(seq.frames), 'points': seq.points,
         'bound_m': '%g' % bound if bound else 'lossless', 'peer': peer,
         'config': r.get('config', ''), 'note': r.get('note', '')}
    if 'bytes' not in r:
        d['note'] = ('not yet: ' if r.get('not_yet') else '') + d['note']
        return d
    mb = input_mb if input_mb else seq.points * 12 / 1e6
    d.update(bytes=r['bytes'], bits_per_point='%.4f' % (8.0 * r['bytes'] / seq.points),
             max_error_m='%.6g' % r['max_error'],
             bound_held=('yes' if r['max_error'] <= bound else 'NO') if bound else 'lossless',
             check=r['check'], enc_cpu_s='%.4f' % r['enc_s'], dec_cpu_s='%.4f' % r['dec_s'],
             enc_Mpoints_s='%.3f' % (seq.points / 1e6 / max(r['enc_s'], 1e-9)),
             dec_Mpoints_s='%.3f' % (seq.points / 1e6 / max(r['dec_s'], 1e-9)),
             enc_MB_s='%.2f' % (mb / max(r['enc_s'], 1e-9)),
             dec_MB_s='%.2f' % (mb / max(r['dec_s'], 1e-9)))
    if not r.get('ok', True):
        d['bound_held'] = 'NO'
    return d


def bench_sequence(name, files, a, out):
    work = os.path.join(a.work, name.replace('/', '_'))
    os.makedirs(work, exist_ok=True)
    seq = fr.load(name, files, a.work)
    print('== %s: %d frames, %d points (%d NaN points left out)' % (name, len(seq.frames),
          seq.points, seq.nan_points), file=sys.stderr, flush=True)
    frames_path = os.path.join(work, 'xyz.frames')
    fr.write_frames(frames_path, seq.frames)
    xyz_dir = os.path.join(work, 'xyz_pcd')
    peers._fresh(xyz_dir)
    xyz_files = []
    for k, f in enumerate(seq.frames):
        xyz_files.append(os.path.join(xyz_dir, os.path.basename(files[k])))
        pcd.write_xyz_pcd(xyz_files[-1], f)

    def emit(bound, peer, r, input_mb=None):
        out.append(row(seq, bound, peer, r, input_mb))
        d = out[-1]
        print('  %-8s %-18s %8s bpp  err %-10s %s %s' % (d['bound_m'], peer,
              d.get('bits_per_point', '-'), d.get('max_error_m', '-'), d.get('bound_held', ''),
              d['note'][:90]), file=sys.stderr, flush=True)

    for bound in a.bounds:
        step = fr.capz_step(bound, seq.max_abs)
        qframes = [fr.quantise(f, step) for f in seq.frames]
        bw = os.path.join(work, 'b%g' % bound)
        if 'gpcc' not in a.skip:
            ply_dir = os.path.join(bw, 'grid_ply')
            peers.write_grid_plys(qframes, ply_dir)
            for peer, config, opts in peers.gpcc_configs(seq, step):
                if peer in a.skip:
                    continue
                r = peers.tmc13(seq, qframes, step, a.tmc3, ply_dir, os.path.join(bw, peer),
                                opts, config + '; step %.9g m' % step)
                emit(bound, peer, r)
        if 'cloudini' not in a.skip:
            emit(bound, 'cloudini', peers.cloudini(seq, bound, frames_path, a.cloudini,
                                                   os.path.join(bw, 'cloudini')))
        if 'draco' not in a.skip:
            emit(bound, 'draco', peers.draco(seq, bound, os.path.join(bw, 'draco')))
        if 'pcl-octree' not in a.skip:
            emit(bound, 'pcl-octree', peers.pcl_octree(seq, bound, frames_path, a.pcl,
                                                       os.path.join(bw, 'pcl')))
        if 'capz' not in a.skip:
            emit(bound, 'capz', peers.capz(seq, bound, xyz_dir, a.capz, os.path.join(bw, 'capz')))
        if 'capz-any' not in a.skip:
            emit(bound, 'capz-any', peers.capz(seq, bound, xyz_dir, a.capz,
                                               os.path.join(bw, 'capz-any'), order='any'))
    if 'capz-lossless' not in a.skip:
        emit(0, 'capz-lossless', peers.capz_lossless(files, a.capz, os.path.join(work, 'capzl')),
             seq.file_bytes / 1e6)
    if 'xz' not in a.skip:
        emit(0, 'xz-9e', peers.file_compressor(files, 'xz', os.path.join(work, 'xz')),
             seq.file_bytes / 1e6)
        emit(0, 'zstd-19', peers.file_compressor(files, 'zstd', os.path.join(work, 'zstd')),
             seq.file_bytes / 1e6)
        emit(0, 'xz-9e-xyz', peers.file_compressor(xyz_files, 'xz', os.path.join(work, 'xzx')))


def write_tsv(path, rows):
    with open(path, 'w') as f:
        f.write('\t'.join(COLUMNS) + '\n')
        for r in rows:
            f.write('\t'.join(str(r.get(c, '')) for c in COLUMNS) + '\n')


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--capz', required=True)
    ap.add_argument('--peers', default='/work/build-peers')
    ap.add_argument('--pcl', help='scan_pcl_octree (default: next to --capz, tools/)')
    ap.add_argument('--data', default=os.path.join(ROOT, '..', 'shared', 'data', 'scan'))
    ap.add_argument('--work', default='/tmp/scan_bench')
    ap.add_argument('--bounds', default='0.001,0.01')
    ap.add_argument('--only', default='')
    ap.add_argument('--skip', default='')
    date = datetime.date.today().isoformat()
    ap.add_argument('--tsv', default=os.path.join(ROOT, 'docs', 'bench',
                                                  'scan_peers_%s.tsv' % date))
    ap.add_argument('--plot', default='')
    ap.add_argument('--md', default='')
    a = ap.parse_args()
    a.bounds = [float(b) for b in a.bounds.split(',')]
    a.skip = set(s for s in a.skip.split(',') if s)
    a.capz = os.path.abspath(a.capz)
    a.tmc3 = os.path.join(a.peers, 'tmc13', 'tmc3', 'tmc3')
    a.cloudini = os.path.join(a.peers, 'scan_cloudini')
    a.pcl = a.pcl or os.path.join(os.path.dirname(os.path.abspath(a.capz)), 'tools',
                                  'scan_pcl_octree')
    os.makedirs(a.work, exist_ok=True)
    only = set(s for s in a.only.split(',') if s)
    rows = []
    for name, files in sequences(a.data):
        if only and name not in only:
            continue
        bench_sequence(name, files, a, rows)
        write_tsv(a.tsv, rows)
    import report
    if a.plot:
        report.plot(rows, a.plot)
    if a.md:
        with open(a.md, 'w') as f:
            f.write(report.markdown(rows))


if __name__ == '__main__':
    main()

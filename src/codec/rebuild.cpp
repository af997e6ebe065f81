// Rebuilding the original file from a .capz (capz/original.h; docs/FORMAT.md 7, 14): the decoded
// take, read one window at a time, plus the residue chunks. Memory: one window, the residue's
// head and tail.
#include <filesystem>
#include <functional>
#include <memory>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "codec/capz_source.h"
#include "coding/bytes.h"
#include "core/atomic_file.h"
#include "core/hash.h"
#include "io/frame_files.h"
#include "io/pcd_folder.h"
#include "io/residue/c3d_residue.h"
#include "io/residue/pcd_residue.h"
#include "io/residue/trc_residue.h"

namespace capz {
namespace {

using Write = std::function<void(const uint8_t*, size_t)>;
// A PCD folder's frame files, one at a time: its name and bytes.
using FrameWrite = std::function<void(const std::string&, const std::vector<uint8_t>&)>;

struct Record {
  OriginalInfo info;
  Digest128 hash{};
  std::vector<uint8_t> file_part;
  bool c3d = false, pcd = false;
};

std::vector<uint8_t> chunk_payload(StreamBytes& b, const ParsedStream& ps, const char* type,
                                   const std::string& name) {
  const auto it = ps.file_chunks.find(type);
  if (it == ps.file_chunks.end()) return {};
  const Chunk c = chunk_at(b, it->second.first, name);
  return std::vector<uint8_t>(c.payload, c.payload + c.size);
}

Record read_record(StreamBytes& b, const ParsedStream& ps, const std::string& name) {
  Record r;
  if (!ps.file_chunks.count("HASH")) return r;
  const std::vector<uint8_t> h = chunk_payload(b, ps, "HASH", name);
  ByteReader in(h.data(), h.size(), name + ": HASH");
  r.info.hashed = true;
  r.info.size = in.u64();
  for (uint8_t& x : r.hash) x = in.u8();
  if (in.remaining() != 0) fail(ErrorCode::kCorrupt, name, "HASH: bytes left over");
  r.info.hash_hex = digest_hex(r.hash);
  const Format f = ps.h.source_format;
  r.c3d = f == Format::kC3D;
  r.pcd = is_frame_files(f);
  const char* type = r.c3d ? "C3DR" : f == Format::kTRC ? "TRCR" : r.pcd ? "PCDR" : nullptr;
  if (type && ps.file_chunks.count(type)) {
    r.file_part = chunk_payload(b, ps, type, name);
    r.info.residue = true;
    r.info.exact = ps.h.lossless;
    r.info.windows_at_bound = !r.pcd;  // PCDP: lossless archives only
    if (r.pcd && !r.info.exact)
      fail(ErrorCode::kCorrupt, name, "PCDR in an archive that is not lossless");
  }
  return r;
}

// Window w's residue payload (C3DP / TRCP, after its window index); empty when it has none.
std::vector<uint8_t> window_payload(StreamBytes& b, const ParsedStream& ps, size_t w,
                                    const char* type, const std::string& name) {
  const IndexEntry& e = ps.index[w];
  size_t off = static_cast<size_t>(e.offset);
  const size_t end = off + static_cast<size_t>(e.bytes);
  while (off < end) {
    const Chunk c = chunk_at(b, off, name);
    if (c.end > end) fail(ErrorCode::kCorrupt, name, "a chunk runs past its window");
    if (c.type == type) {
      ByteReader in(c.payload, c.size, name + ": " + type);
      if (in.varint() != w)
        fail(ErrorCode::kCorrupt, name, std::string(type) + " of the wrong window");
      const size_t at = in.offset();
      return std::vector<uint8_t>(c.payload + at, c.payload + c.size);
    }
    off = c.end;
  }
  return {};
}

// A folder's frame files (PCD, PLY, .bin) rebuilt (FORMAT.md 7.3, 14.3, "Lossless frame-file
// streams"), each handed to `frame` after its size
// and hash are checked; `out` sees every byte, in order.
void rebuild_pcd(const std::string& path, StreamBytes& raw, CapzSource& src, const Record& r,
                 const Write& out, const FrameWrite& frame) {
  const ParsedStream& ps = src.parsed();
  const Take& t = ps.take;
  if (!t.pcd || t.pcd->frame_names.size() != t.frames ||
      (t.format == Format::kPCDFolder
           ? pcd_output_names(t)
           : frame_output_names(t, frame_extension(t.format))) != t.pcd->frame_names)
    fail(ErrorCode::kCorrupt, path, "PCDR in an archive without one valid name per frame file");
  // A ragged stream's PCDR is described against its META take (FORMAT.md "Lossless ragged
  // streams": the reference's dictionary has WIDTH 0 and POINTS 0), also when the source reads
  // a stream of one ragged frame as the fixed frame of its file (capz_source.h), its blocks
  // fixed (regenerated as wide as their points, pcd_residue.h).
  residue::PCDResidueDecoder dec(r.file_part.data(), r.file_part.size(),
                                 ps.h.ragged ? ps.take : src.header(), path);
  const size_t W = ps.h.window_frames;
  FrameBlock block;
  std::vector<uint8_t> bytes;
  for (size_t w = 0, f0 = 0; f0 < t.frames; ++w, f0 += W) {
    src.read(f0, W, &block);
    // Never empty when present (a record per frame): empty means absent.
    const std::vector<uint8_t> p = window_payload(raw, ps, w, "PCDP", path);
    if (p.empty()) fail(ErrorCode::kCorrupt, path, "window " + std::to_string(w) + " has no PCDP");
    ByteReader in(p.data(), p.size(), path + ": PCDP");
    for (size_t k = 0; k < block.frames; ++k) {
      const std::string& name = t.pcd->frame_names[f0 + k];
      dec.frame(block, k, in, name, &bytes);
      out(bytes.data(), bytes.size());
      frame(name, bytes);
    }
    if (!in.at_end())
      fail(ErrorCode::kCorrupt, path, "PCDP of window " + std::to_string(w) + ": bytes left over");
  }
}

// A C3D or TRC file rebuilt from the record's residue (its head, the frames' windows, a C3D's
// regenerated rotation section, its tail), every byte handed to `out` in order.
void rebuild_c3d_trc(const std::string& path, StreamBytes& raw, CapzSource& src, const Record& r,
                     const Write& out) {
  const ParsedStream& ps = src.parsed();
  const Take& t = ps.take;
  static const std::vector<C3DGroup> kNone;
  std::unique_ptr<residue::C3DResidueDecoder> c3d;
  std::unique_ptr<residue::TRCResidueDecoder> trc;
  if (r.c3d) {
    c3d.reset(new residue::C3DResidueDecoder(r.file_part.data(), r.file_part.size(),
                                             t.c3d ? t.c3d->groups : kNone, path, r.info.size));
    out(c3d->head().data(), c3d->head().size());
  } else {
    trc.reset(new residue::TRCResidueDecoder(r.file_part.data(), r.file_part.size(), t, path,
                                             r.info.size));
    out(trc->head().data(), trc->head().size());
  }
  const size_t W = ps.h.window_frames;
  FrameBlock block;
  std::vector<uint8_t> bytes;
  // A regenerated rotation section follows every frame: its windows are read again, after the
  // frames' (whose pass is left out when they have no bytes).
  const bool rotations = c3d && c3d->layout().rotations;
  const bool frames_pass = !rotations || c3d->layout().per_frame > 0;
  for (size_t w = 0, f0 = 0; frames_pass && f0 < t.frames; ++w, f0 += W) {
    src.read(f0, W, &block);
    // At every target from 5.0 on (a 4.0 stream has them when lossless only).
    const std::vector<uint8_t> p = window_payload(raw, ps, w, r.c3d ? "C3DP" : "TRCP", path);
    bytes.clear();
    if (c3d)
      c3d->window(block, p.data(), p.size(), &bytes);
    else
      trc->window(block, p.data(), p.size(), &bytes, ps.h.lossless);
    out(bytes.data(), bytes.size());
  }
  if (rotations) {
    out(c3d->gap().data(), c3d->gap().size());
    for (size_t w = 0, f0 = 0; f0 < t.frames; ++w, f0 += W) {
      src.read(f0, W, &block);
      const std::vector<uint8_t> p = window_payload(raw, ps, w, "C3DP", path);
      bytes.clear();
      c3d->rotation_window(block, p.data(), p.size(), &bytes);
      out(bytes.data(), bytes.size());
    }
  }
  if (c3d)
    out(c3d->tail().data(), c3d->tail().size());
  else
    trc->finish();
}

// The rebuild, handed to `write` in order (a PCD folder's: to `frame`, file by file); checks the
// size, and the hash when lossless.
void rebuild(const std::string& path, const Write& write, const DecompressOptions& opts = {},
             const FrameWrite& frame = nullptr) {
  std::unique_ptr<StreamBytes> raw(new FileBytes(path));
  CapzSource src(std::unique_ptr<StreamBytes>(new FileBytes(path)), path, true, opts.threads,
                 opts.memory_limit);
  const ParsedStream& ps = src.parsed();
  const Record r = read_record(*raw, ps, path);
  if (!can_rebuild(r.info, r.c3d))
    fail(ErrorCode::kInvalidParameter, path, "the archive holds no residue to rebuild from");
  Hasher hasher;
  uint64_t n = 0;
  const Write out = [&](const uint8_t* p, size_t k) {
    hasher.update(p, k);
    n += k;
    write(p, k);
  };
  if (r.pcd) {
    rebuild_pcd(
        path, *raw, src, r, out,
        frame ? frame : [](const std::string&, const std::vector<uint8_t>&) {});
    if (n != r.info.size || hasher.digest() != r.hash)
      fail(ErrorCode::kCorrupt, path,
           "the rebuilt frame files (" + std::to_string(n) + " bytes, XXH3-128 " +
               digest_hex(hasher.digest()) + ") differ from the recorded " +
               std::to_string(r.info.size) + " bytes, " + r.info.hash_hex);
    return;
  }
  rebuild_c3d_trc(path, *raw, src, r, out);
  // A TRC at a bound prints its own coordinates: its size is its own.
  if ((r.c3d || r.info.exact) && n != r.info.size)
    fail(ErrorCode::kCorrupt, path,
         "the rebuilt original has " + std::to_string(n) + " bytes, the archive records " +
             std::to_string(r.info.size));
  if (r.info.exact && hasher.digest() != r.hash)
    fail(ErrorCode::kCorrupt, path,
         "the rebuilt original's XXH3-128 " + digest_hex(hasher.digest()) +
             " differs from the recorded " + r.info.hash_hex);
}

}  // namespace

OriginalInfo original_info(const std::string& capz_path) {
  FileBytes b(capz_path);
  const ParsedStream ps = parse_stream(b, capz_path);
  return read_record(b, ps, capz_path).info;
}

bool can_rebuild(const OriginalInfo& info, bool c3d) {
  return info.hashed && info.residue && (info.exact || c3d || info.windows_at_bound);
}

void rebuild_original(const std::string& capz_path, const std::string& out, bool overwrite,
                      const DecompressOptions& opts) {
  Format f = Format::kC3D;
  size_t frames = 0;
  {
    FileBytes b(capz_path);
    const ParsedStream ps = parse_stream(b, capz_path);
    f = ps.h.source_format;
    frames = ps.take.frames;
  }
  const std::string ext = frame_extension(f);
  if (!ext.empty() && frames == 1 && single_frame_output(out, ext)) {
    AtomicFile file(out, overwrite);  // a one-frame take: that one file
    rebuild(
        capz_path, [&](const uint8_t* p, size_t n) { file.write(p, n); }, opts);
    file.commit();
    return;
  }
  if (!ext.empty()) {  // a folder of frame files, renamed into place once every file has checked
    const std::string path = without_trailing_slashes(out);
    if (f == Format::kPCDFolder)
      check_replaceable_pcd_dir(path, overwrite);
    else
      check_replaceable_frame_dir(path, ext, overwrite);
    AtomicDir dir(path, overwrite, frames_go_beside);
    rebuild(
        capz_path, [](const uint8_t*, size_t) {}, opts,
        [&](const std::string& name, const std::vector<uint8_t>& bytes) {
          write_file((std::filesystem::path(dir.temp_dir()) / name).string(), bytes, true);
        });
    dir.commit();
    return;
  }
  AtomicFile file(out, overwrite);
  rebuild(
      capz_path, [&](const uint8_t* p, size_t n) { file.write(p, n); }, opts);
  file.commit();
}

void test_original(const std::string& capz_path, const DecompressOptions& opts) {
  rebuild(
      capz_path, [](const uint8_t*, size_t) {}, opts);
}

std::string rebuilds_file(const std::string& capz_path, const std::string& original,
                          const DecompressOptions& opts) {
  FileBytes b(capz_path);
  const ParsedStream ps = parse_stream(b, capz_path);
  const Record r = read_record(b, ps, capz_path);
  if (!r.info.exact) return "the archive cannot rebuild the original byte for byte";
  test_original(capz_path, opts);  // the rebuilt bytes hash as recorded
  Digest128 now{};
  if (r.pcd) {  // frame files: concatenated in frame order
    Hasher h;
    const Format fmt = ps.h.source_format;
    FrameFiles files;
    std::error_code ec;  // a PCD folder, or one file (a one-frame take) as PLY and .bin
    if (fmt == Format::kPCDFolder && std::filesystem::is_directory(original, ec)) {
      files.dir = original;
      files.names = list_pcd_frames(original);
    } else {
      files = list_frame_files(original, frame_extension(fmt));
    }
    for (size_t i = 0; i < files.names.size(); ++i) {
      const std::vector<uint8_t> f = read_file(files.path(i));
      h.update(f.data(), f.size());
    }
    now = h.digest();
  } else {
    now = hash128_file(original);
  }
  if (r.hash != now) return "the recorded hash is not the input's";
  return "";
}

}  // namespace capz

// The encoder's side of byte-exact archives (docs/FORMAT.md 7, 14): for a source read from an
// original C3D or TRC file (or, lossless only, a PCD folder: HASH over its frame files, PCDR and
// per window PCDP, each frame file compared in memory with the writer's bytes), the HASH chunk
// (size and XXH3-128 of the file), the file-level residue (C3DR / TRCR) and each window's residue
// (C3DP / TRCP) at every target. With the self-check of a lossless stream it rebuilds the original
// window by window, as the decoder will, from the frames the archive gives back, compares each
// window's bytes with the file's and, at the end, the rebuilt size and hash with the original's.
// Memory: one window of the original.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/stream.h"
#include "core/hash.h"
#include "core/input_file.h"
#include "io/residue/c3d_residue.h"
#include "io/residue/pcd_residue.h"
#include "io/residue/trc_residue.h"

namespace capz {

// The original file (FrameSource::original_file) an archive of `source` under `opts` gives back,
// or "" when it can give none: opts.drop_fields leaves the source's point fields out, and
// opts.attr_error keeps some within a bound, so its frame files cannot come back byte for byte
// (`--lossless --drop-fields` keeps the positions' bits alone, `--lossless --attr-error` the
// positions' bits and the fields within their bounds: docs/CLI.md).
std::string residue_original(const FrameSource& source, const CompressOptions& opts);

class ResidueWriter {
 public:
  // nullptr unless `path` (residue_original) is an original C3D or TRC file or a PCD folder,
  // for a take `header` read from it (the header must outlive the writer).
  static std::unique_ptr<ResidueWriter> open(const std::string& path, const Take& header,
                                             bool check);
  ResidueWriter(const std::string& path, const Take& header, bool check);
  ~ResidueWriter();

  // Appends HASH and C3DR or TRCR (after META). `exact`: the stream is lossless (HEAD flag bit
  // 0), whatever target gave it (a bound coarser than an int16 C3D's step gives it too).
  void file_chunks(std::vector<uint8_t>* buf, bool exact);
  // Appends window w's residue chunk for `block` (the frames as read): C3DP (left out when empty)
  // or TRCP, at every target. With the check of an exact stream, `back` (the frames
  // the archive gives back for the window) rebuilds the window's bytes, which must equal the
  // original's. Throws Error(kInternal).
  void window_chunk(size_t w, const FrameBlock& block, const FrameBlock* back,
                    std::vector<uint8_t>* buf);
  // With the check of an exact stream: the rebuilt file's size and hash equal the original's.
  void finish();
  // Bytes of the chunks written so far: all, and HASH + C3DR/TRCR alone.
  size_t bytes() const { return bytes_; }
  size_t file_bytes() const { return file_bytes_; }
  // At a bound: samples marked absent whose coordinates were not kept (C3DResidueEncoder).
  size_t dropped_coordinates() const { return c3d_ ? c3d_->dropped_coordinates() : 0; }

 private:
  // known: known_size bytes of the original from offset known_at, when the caller has them
  // (else read).
  void check_bytes(size_t w, const std::vector<uint8_t>& rebuilt, const uint8_t* known = nullptr,
                   size_t known_size = 0, uint64_t known_at = 0);
  void check_rotations(size_t w, const FrameBlock& back, const std::vector<uint8_t>& payload);
  void pcd_file_chunks(std::vector<uint8_t>* buf);
  void pcd_window_chunk(size_t w, const FrameBlock& block, const FrameBlock* back,
                        std::vector<uint8_t>* buf);
  [[noreturn]] void failed(const std::string& what) const;

  std::string path_;
  const Take& header_;
  bool exact_ = false, check_;
  uint64_t size_ = 0;
  Digest128 hash_{};
  std::unique_ptr<residue::C3DResidueEncoder> c3d_;
  std::unique_ptr<residue::TRCResidueEncoder> trc_;
  // A PCD folder (lossless only): each frame file's name, size and hash.
  bool pcd_ = false;
  std::unique_ptr<residue::PCDResidueEncoder> pcd_enc_;
  std::unique_ptr<residue::PCDResidueDecoder> pcd_back_;
  std::vector<std::string> names_;
  std::vector<uint64_t> sizes_;
  std::vector<Digest128> hashes_;
  std::vector<uint8_t> file_part_;
  // The self-check's rebuild.
  std::unique_ptr<residue::C3DResidueDecoder> c3d_back_;
  std::unique_ptr<residue::TRCResidueDecoder> trc_back_;
  std::unique_ptr<InputFile> orig_;
  std::vector<uint8_t> orig_bytes_;  // check_bytes' scratch
  Hasher rebuilt_hash_;
  uint64_t rebuilt_ = 0, rotations_checked_ = 0;
  size_t bytes_ = 0, file_bytes_ = 0;
};

}  // namespace capz

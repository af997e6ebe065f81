// The encoder driver: a frame source to .capz bytes under CompressOptions (docs/FORMAT.md).
// Two passes over the source: a scan that chooses the grid (grid_choice.h), then each window is
// quantised, predicted and coded (coding/positions.h, mask.h, c3d_words.h, analog/), checked by
// running THE decoder (decoder.h) on the chunks it wrote, and handed to a StreamOut.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/stream.h"
#include "core/atomic_file.h"

namespace capz {

// Knobs that change how the encoder works but never what it writes.
struct EncoderTuning {
  // The KG search (kg_error with codec none) tries about 26 grid steps; the first pass keeps
  // the take's valid coordinates in memory for them when they take at most this many bytes,
  // else the search reads the source once per step. Either way it finds the same step.
  size_t kg_cache_bytes = size_t{64} << 20;
  // META in coding 0 (encode_meta_raw), no coding tried: a stream whose size less META's
  // payload bounds from below the stream's size with META coded (INDX's offsets are fixed width).
  bool meta_raw = false;
  // ATTR chunks with an empty payload (their window index only), the fields not coded: no other
  // chunk depends on ATTR's bytes (the fields are still quantised as for the coding, which a
  // residue reads), so with meta_raw the stream's size less META's payload bounds from below the
  // size of the stream with its fields and META coded.
  bool attr_empty = false;
  // POSW's residual block cut to its raw bits' bytes (encode_positions_bound), nothing entropy
  // coded: with meta_raw, the stream's size less META's payload bounds from below the size of
  // the stream coded whole, META and all (and, with attr_empty, its fields too).
  bool positions_bound = false;
  // ATTR's LZMA transforms estimated on a sample before any is coded in full
  // (encode_attributes' estimate and estimate_split): a trial's size within a few per mille of
  // the stream's, for the choice between POSW and the scan coder (compress.cpp), never a
  // stream's bytes.
  bool attr_estimate = false;
};

// Where the encoder puts the stream: appended to memory, or written to a file as it goes.
class StreamOut {
 public:
  explicit StreamOut(std::vector<uint8_t>* mem) : mem_(mem) {}
  explicit StreamOut(AtomicFile* file) : file_(file) {}
  // Appends buf and clears it.
  void flush(std::vector<uint8_t>* buf);
  size_t size() const { return size_; }

 private:
  std::vector<uint8_t>* mem_ = nullptr;
  AtomicFile* file_ = nullptr;
  size_t size_ = 0;
};

// Thrown by encode_source when a transform-output window misses the KG target; the caller then
// encodes again with allow_transform_output = false (through the grid).
struct TransformMissedTarget {};

// Encodes the whole source into *out. allow_transform_output = false: a KG target with a
// transform goes through the grid. Throws Error(kInvalidParameter) for an impossible target,
// Error(kInternal) when the self-check fails.
void encode_source(FrameSource& source, const CompressOptions& opts, const EncoderTuning& tuning,
                   StreamOut* out, CompressStats* stats, bool allow_transform_output = true);

class TransformCodec;
// The --codec-opt keys meant for `codec`: a key "name.key" goes to the codec called name only
// (a name that is no codec is an error); a bare key goes to whichever codec was chosen.
std::map<std::string, std::string> options_for(const TransformCodec& codec,
                                               const std::map<std::string, std::string>& all);

// compress() with explicit tuning (tests compare tunings; the public API keeps the defaults).
std::vector<uint8_t> compress_tuned(const Take& take, const CompressOptions& opts,
                                    const EncoderTuning& tuning, CompressStats* stats = nullptr);

}  // namespace capz

// Representation of one analog channel in one window (docs/format-drafts/analog.md A.2).
//
// A channel's n samples (doubles, exactly as the take stores them) become:
//   - a gap list: the indices of non-finite samples (NaN, Inf) and their 64-bit patterns; for
//     coding, each is replaced by the previous finite sample (the first finite one before any);
//   - then one kind for the filled samples:
//       kConst    every sample has the same bit pattern (8 bytes, nothing per sample);
//       kInt      integers with |x| <= kMaxSample, no -0.0: the integers themselves;
//       kScaled   x == R(k * s + o) for integers k (R = rounding to float32 when every sample is
//                 a float32, else none), a few exceptions stored whole: the k;
//       kRank     few distinct values: a sorted table and each sample's rank;
//       kFloat32  / kFloat64: the values, coded by the float predictor (analog_float.h).
// Kinds kInt, kScaled and kRank feed `ints` to the integer pipeline (LPC, cascade).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "coding/analog/analog_layout.h"
#include "coding/bytes.h"

namespace capz {
namespace analog {

struct Interp;  // analog_interp.h
struct Hold;    // analog_hold.h

enum class Kind : uint8_t {
  kConst = 0,
  kInt = 1,
  kScaled = 2,
  kRank = 3,
  kFloat32 = 4,
  kFloat64 = 5
};
constexpr int kKinds = 6;
inline bool is_integer_kind(Kind k) {
  return k == Kind::kInt || k == Kind::kScaled || k == Kind::kRank;
}

// What the file says about a channel; only ever a hint (the encoder verifies everything).
// The scaling of the previous kind 2 channel of a window (FORMAT.md 11.7): from 9.2 on a kind 2
// header may say "the same" instead of repeating round, s and o.
struct ScaledShare {
  bool have = false;  // an earlier channel of the window has kind 2
  bool round_f32 = false;
  double step = 0, offset = 0;
};

struct ChannelHint {
  double scale = 0;   // a candidate step of the stored values (0 = none)
  double offset = 0;  // a candidate offset, in stored units
  // Lossy analog (FORMAT.md 16.3): the encoder moved the samples onto lattice_offset + k *
  // lattice_step (0: it did not). That scaled fit is tried first and, when it holds, is the
  // only candidate.
  double lattice_step = 0, lattice_offset = 0;
  // The window's previous kind 2 channel's scaling (FORMAT.md 11.7): a fit whose step is within
  // 1e-6 of its step tries it too, and takes it when it leaves no more exceptions.
  ScaledShare share;
};

struct ChannelRepr {
  Kind kind = Kind::kConst;
  std::vector<uint32_t> gap_index;  // increasing
  std::vector<uint64_t> gap_bits;   // bit pattern of each gap sample
  uint64_t const_bits = 0;          // kConst
  bool round_f32 = false;           // kScaled: R = float32 rounding
  double step = 0, offset = 0;      // kScaled
  std::vector<uint32_t> exc_index;  // kScaled exceptions: increasing sample indices
  std::vector<int64_t> exc_delta;   // their ordered bits minus those of R(k * s + o) (float32
                                    // patterns when round_f32), wrapping
  std::vector<double> table;        // kRank: distinct values in increasing ordered-bits order
  std::vector<int32_t> ints;        // integer kinds: n values, |v| <= kMaxSample
  std::vector<double> filled;       // float kinds: the n samples with gaps filled
};

// Monotone map of double bit patterns to unsigned integers (-0.0 just below +0.0).
inline uint64_t ordered_bits(uint64_t b) {
  return (b >> 63) ? ~b : b | (uint64_t{1} << 63);
}
inline uint64_t from_ordered_bits(uint64_t o) {
  return (o >> 63) ? o & ~(uint64_t{1} << 63) : ~o;
}
inline uint64_t bits_of(double v) {
  uint64_t b;
  std::memcpy(&b, &v, 8);
  return b;
}
inline double from_bits(uint64_t b) {
  double v;
  std::memcpy(&v, &b, 8);
  return v;
}
// y rounded to float32 (nearest even) and widened; finite values beyond the float range become
// +-FLT_MAX first, so the conversion is always defined.
inline double round_to_float32(double y) {
  constexpr double kMax = std::numeric_limits<float>::max();
  if (y > kMax && y <= std::numeric_limits<double>::max()) y = kMax;
  if (y < -kMax && y >= -std::numeric_limits<double>::max()) y = -kMax;
  return static_cast<double>(static_cast<float>(y));
}
// True when v is a float32 value (widened), bit for bit.
inline bool is_float32(double v) {
  return bits_of(round_to_float32(v)) == bits_of(v);
}
// Ordered 32-bit pattern of a float32 value v (widened to double), and back.
inline uint32_t ordered_f32(double v) {
  const float f = static_cast<float>(v);
  uint32_t b;
  std::memcpy(&b, &f, 4);
  return (b >> 31) ? ~b : b | 0x80000000u;
}
inline double from_ordered_f32(uint32_t o) {
  const uint32_t b = (o >> 31) ? o & 0x7FFFFFFFu : ~o;
  float f;
  std::memcpy(&f, &b, 4);
  return f;
}
// v moved by d units of its ordered pattern: float32 patterns when f32, else double; wrapping.
double apply_ordered_delta(double v, int64_t d, bool f32);

// The representations worth trying for samples col[0], col[stride], ... (n of them), the
// preferred one first: a single one for kConst; for integers kScaled (step the integers'
// greatest common step, when above 1) and kInt; else kScaled when a fit exists, kRank when the
// table is small enough, and always the float kind (the window codec codes each and keeps the
// smallest).
std::vector<ChannelRepr> candidate_representations(const double* col, size_t stride, size_t n,
                                                   const ChannelHint& hint);

// The lattice the lossless coder finds for the samples (gaps skipped): for integers their
// greatest common step and the offset below it (step 1 and offset 0 when that step is 1), else
// the step and offset of the scaled fit (kScaled) when there is one. False when the samples are
// on no lattice (or constant).
bool sample_lattice(const double* col, size_t stride, size_t n, const ChannelHint& hint,
                    double* step, double* offset);
// The first of candidate_representations.
ChannelRepr choose_representation(const double* col, size_t stride, size_t n,
                                  const ChannelHint& hint);

// What a stream's version lets a channel header carry (FORMAT.md 11.3, 11.7, 11.4, 11.5): the
// writer asserts it (an encoder that asks for more is a bug), the reader rejects the rest as
// corrupt.
struct HeaderRules {
  size_t S = 0;  // 7.x streams on: analog samples a point frame, repeat lists (bit 5); 0: none
  bool lattice = false;  // 8.0 on: a kRank table may be coded against a lattice (table flag bit 1)
  bool interp = false;   // 9.0 on: an interpolation field (bit 6)
  bool hold = false;     // 9.2 on: a hold field (bit 7)
  bool share = false;    // 9.2 on: bit 4 with kind 2 names the previous kind 2 scaling
};
// What one channel's header leaves for the next ones of the window: the last constant (bit 4
// with kind 0; 0 before any) and the last kind 2 scaling (9.6; none before any).
struct HeaderState {
  uint64_t last_const = 0;
  ScaledShare share;
};

// The kind byte's low 3 bits are the kind; bit 3 says a gap list follows; bit 4 says the value
// is the state's last constant (kind 0) or its scaling the state's (kind 2, rules.share); bits
// 5, 6 and 7 say a repeat list, an interpolation or a hold field follows (at most one, as
// `kept` has), and r then describes the channel's kept samples. The header carries everything
// but the per-sample numbers (ints or float samples), which the entropy stage codes. kConst and
// kScaled channels update *state. Throws Error(kInternal) when `kept` has a field the rules do
// not allow.
void write_repr_header(const ChannelRepr& r, const KeptRows& kept, const HeaderRules& rules,
                       HeaderState* state, ByteWriter* w);
// Reads a header for a channel of n samples; sizes are bounded by the bytes left in `in`. *kept
// gets the channel's layout (all() without a field), and r then describes kept->count(n, S)
// samples. Fields the rules do not allow are corrupt.
ChannelRepr read_repr_header(ByteReader* in, size_t n, const HeaderRules& rules, HeaderState* state,
                             KeptRows* kept);

// Writes the n samples to col[0], col[stride], ... from the header and `ints` / `filled`.
// Throws Error(kCorrupt) naming `what` when a rank is outside the table.
void reconstruct(const ChannelRepr& r, size_t n, double* col, size_t stride,
                 const std::string& what);

}  // namespace analog
}  // namespace capz

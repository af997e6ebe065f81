// An analog channel's representation (docs/FORMAT.md 11.2): its header read and the samples
// rebuilt from the coded numbers; the encoder's choice and the header writer are
// analog_repr_encode.cpp.
#include "coding/analog/analog_repr.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>

#include "capz/error.h"
#include "coding/analog/analog_hold.h"
#include "coding/analog/analog_interp.h"
#include "coding/analog/analog_lpc.h"
#include "coding/analog/analog_repeat.h"
#include "coding/analog/analog_scaled.h"
#include "coding/analog/analog_table.h"

namespace capz {
namespace analog {

double apply_ordered_delta(double v, int64_t d, bool f32) {
  if (f32) return from_ordered_f32(static_cast<uint32_t>(static_cast<int64_t>(ordered_f32(v)) + d));
  return from_bits(from_ordered_bits(ordered_bits(bits_of(v)) + static_cast<uint64_t>(d)));
}

namespace {

void read_gaps(ByteReader* in, size_t n, ChannelRepr* r) {
  r->gap_index = read_runs(in, n, "gap");
  const uint64_t npat = in->count(8, "analog gap patterns");
  if (npat == 0 || npat > r->gap_index.size())
    throw Error(ErrorCode::kCorrupt, in->what() + ": bad number of analog gap patterns");
  std::vector<uint64_t> pats(npat);
  for (uint64_t& p : pats) p = in->u64();
  r->gap_bits.assign(r->gap_index.size(), pats[0]);
  if (npat > 1)
    for (uint64_t& b : r->gap_bits) {
      const uint64_t k = in->varint();
      if (k >= npat) throw Error(ErrorCode::kCorrupt, in->what() + ": analog gap pattern index");
      b = pats[k];
    }
}

// The rows the header byte's bits 6 (interpolated), 7 (held) and 5 (repeated frames) leave out
// of the n samples, read into kept; returns how many samples are coded.
size_t read_kept_rows(ByteReader* in, int byte, size_t n, const HeaderRules& rules,
                      KeptRows* kept) {
  *kept = KeptRows();
  if (byte & 64) {
    kept->interp = read_interp(in, n);
    n = interp_kept_count(n, kept->interp);
  }
  if (byte & 128) {
    kept->hold = read_hold(in, n);
    n = hold_kept_count(n, kept->hold);
  }
  if (byte & 32) {  // FORMAT.md 11.3: only in 7.x streams (S > 0)
    const size_t S = rules.S;
    if (S == 0 || n % S != 0)
      throw Error(
          ErrorCode::kCorrupt,
          in->what() + ": analog repeat list in a window without frames (no samples per frame)");
    kept->repeats = read_repeats(in, n / S);
    n -= S * kept->repeats.size();
  }
  return n;
}

// A scaled channel's header (kind 2, n coded samples): its scaling, or with bit 4 of the header
// byte the previous channel's (FORMAT.md 11.7), then its exceptions.
void read_scaled(ByteReader* in, int byte, size_t n, HeaderState* state, ChannelRepr* r) {
  if (byte & 16) {  // FORMAT.md 11.7
    const ScaledShare& share = state->share;
    if (!share.have)
      throw Error(ErrorCode::kCorrupt,
                  in->what() + ": analog scaling shared with no earlier channel");
    r->round_f32 = share.round_f32;
    r->step = share.step;
    r->offset = share.offset;
  } else {
    const int f = in->u8();
    if (f > 1) throw Error(ErrorCode::kCorrupt, in->what() + ": bad analog rounding flag");
    r->round_f32 = f == 1;
    r->step = in->f64();
    r->offset = in->f64();
  }
  state->share = ScaledShare{true, r->round_f32, r->step, r->offset};
  const uint64_t ne = in->count(2, "analog exceptions");
  uint64_t prev = 0;
  for (uint64_t e = 0; e < ne; ++e) {
    const uint64_t i = prev + in->varint();
    if (i >= n) throw Error(ErrorCode::kCorrupt, in->what() + ": analog exception past the window");
    r->exc_index.push_back(static_cast<uint32_t>(i));
    r->exc_delta.push_back(in->svarint());
    prev = i + 1;
  }
}

}  // namespace

ChannelRepr read_repr_header(ByteReader* in, size_t n, const HeaderRules& rules, HeaderState* state,
                             KeptRows* kept) {
  ChannelRepr r;
  const int byte = in->u8();
  // At most one of bits 5-7 (FORMAT.md 7.2, 9.2, 9.4), and neither 6 nor 7 with kind 0.
  const int layouts = ((byte >> 5) & 1) + ((byte >> 6) & 1) + ((byte >> 7) & 1);
  // Bit 4 names kind 0's previous constant, or kind 2's previous scaling (9.6).
  const bool same_ok = (byte & 7) == 0 || (byte & 7) == static_cast<int>(Kind::kScaled);
  if ((byte & 7) >= kKinds || ((byte & 16) && !same_ok) || layouts > 1 ||
      ((byte & 192) && (byte & 7) == 0))
    throw Error(ErrorCode::kCorrupt,
                in->what() + ": unknown analog channel kind " + std::to_string(byte));
  n = read_kept_rows(in, byte, n, rules, kept);
  r.kind = static_cast<Kind>(byte & 7);
  if (byte & 8) read_gaps(in, n, &r);
  switch (r.kind) {
    case Kind::kConst:
      r.const_bits = (byte & 16) ? state->last_const : __builtin_bswap64(in->varint());
      state->last_const = r.const_bits;
      break;
    case Kind::kScaled:
      read_scaled(in, byte, n, state, &r);
      break;
    case Kind::kRank:
      r.table = read_value_table(in, n);
      break;
    default:
      break;
  }
  return r;
}

void reconstruct(const ChannelRepr& r, size_t n, double* col, size_t stride,
                 const std::string& what) {
  switch (r.kind) {
    case Kind::kConst:
      for (size_t i = 0; i < n; ++i) col[i * stride] = from_bits(r.const_bits);
      break;
    case Kind::kInt:
      for (size_t i = 0; i < n; ++i) col[i * stride] = r.ints[i];
      break;
    case Kind::kScaled: {
      for (size_t i = 0; i < n; ++i)
        col[i * stride] = scaled_value(r.ints[i], r.step, r.offset, r.round_f32);
      for (size_t e = 0; e < r.exc_index.size(); ++e) {
        double* p = &col[r.exc_index[e] * stride];
        *p = apply_ordered_delta(*p, r.exc_delta[e], r.round_f32);
      }
      break;
    }
    case Kind::kRank:
      for (size_t i = 0; i < n; ++i) {
        const int32_t k = r.ints[i];
        if (k < 0 || static_cast<size_t>(k) >= r.table.size())
          throw Error(ErrorCode::kCorrupt, what + ": analog rank outside its table");
        col[i * stride] = r.table[k];
      }
      break;
    default:
      for (size_t i = 0; i < n; ++i) col[i * stride] = r.filled[i];
      break;
  }
  for (size_t g = 0; g < r.gap_index.size(); ++g)
    col[r.gap_index[g] * stride] = from_bits(r.gap_bits[g]);
}

}  // namespace analog
}  // namespace capz

// An analog channel's representations (docs/FORMAT.md 11.2) as the encoder finds them: gaps
// filled, distinct values ranked, integer steps, scaled fits and lattices; the candidates of a
// channel and its header written. The reader is analog_repr.cpp.
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
#include "coding/analog/analog_repr.h"
#include "coding/analog/analog_round.h"
#include "coding/analog/analog_scaled.h"
#include "coding/analog/analog_scratch.h"
#include "coding/analog/analog_simd.h"
#include "coding/analog/analog_table.h"

namespace capz {
namespace analog {

namespace {

constexpr uint64_t kNegZero = uint64_t{1} << 63;

// Replaces non-finite samples by the previous finite one (the first finite one before any),
// recording them in r->gap_index / gap_bits.
std::vector<double> fill_gaps(const double* col, size_t stride, size_t n, ChannelRepr* r) {
  std::vector<double> v(n);
  double first = 0;
  for (size_t i = 0; i < n; ++i)
    if (std::isfinite(col[i * stride])) {
      first = col[i * stride];
      break;
    }
  double last = first;
  for (size_t i = 0; i < n; ++i) {
    const double x = col[i * stride];
    if (std::isfinite(x)) {
      last = x;
    } else {
      r->gap_index.push_back(static_cast<uint32_t>(i));
      r->gap_bits.push_back(bits_of(x));
    }
    v[i] = last;
  }
  return v;
}

constexpr size_t kMaxTable = 65536;

// Rough coded sizes in bits, to choose between ranks and float coding: the table (about 3 bytes
// an entry for float32, 5 for float64) plus unpredicted ranks, against the float coder's bit
// lengths of previous-sample residuals plus 2 bits a sample for the lengths themselves.
double rank_bits(size_t m, size_t n, bool f32) {
  return static_cast<double>(m) * (f32 ? 24 : 40) +
         static_cast<double>(n) * std::log2(static_cast<double>(m));
}
double float_bits(const std::vector<double>& v, bool f32) {
  double bits = 0;
  for (size_t i = 1; i < v.size(); ++i) {
    const int64_t d = exception_delta(v[i], v[i - 1], f32);
    const uint64_t u = (static_cast<uint64_t>(d) << 1) ^ static_cast<uint64_t>(d >> 63);
    bits += 2 + (u == 0 ? 0 : 64 - __builtin_clzll(u));
  }
  return bits;
}

bool all_integers(const std::vector<double>& v) {
  for (double x : v)
    if (!(std::fabs(x) <= kMaxSample) || x != std::floor(x) || bits_of(x) == kNegZero) return false;
  return true;
}

// Keys of float32 values (ordered double patterns, whose low bits are all ones for negative
// values) sort as their 32-bit ordered float patterns: the same order, one to one. When the
// keys' varying bits and an index of ibits bits do not fit one word and every key is a float32,
// *f32_keys receives those patterns and is returned with *diff updated; else keys.
const std::vector<uint64_t>* narrowed_keys(const std::vector<uint64_t>& keys, int ibits,
                                           std::vector<uint64_t>* f32_keys, uint64_t* diff) {
  const size_t n = keys.size();
  if (!*diff || 64 - __builtin_clzll(*diff) - __builtin_ctzll(*diff) + ibits <= 64) return &keys;
  f32_keys->resize(n);
  for (size_t i = 0; i < n; ++i) {
    const double v = from_bits(from_ordered_bits(keys[i]));
    if (!is_float32(v)) return &keys;
    (*f32_keys)[i] = ordered_f32(v);
  }
  *diff = 0;
  for (size_t i = 1; i < n; ++i) *diff |= (*f32_keys)[i] ^ (*f32_keys)[0];
  return f32_keys;
}

// sort_unique when the varying bits (width of them from bit lo of sk's keys) and the index fit
// one 64-bit word: each key packed as (its varying bits, its index), sorted alone in digits of
// up to 11 bits.
void sort_unique_packed(const std::vector<uint64_t>& sk, int lo, int width, int ibits,
                        std::vector<uint64_t>* keys, std::vector<int32_t>* ranks) {
  const size_t n = keys->size();
  const uint64_t vmask = width == 64 ? ~uint64_t{0} : (uint64_t{1} << width) - 1;
  const uint64_t imask = (uint64_t{1} << ibits) - 1;  // ibits < 64 here (n <= 2^32)
  // The two arrays of the passes: a per-thread buffer (not zeroed: every entry is written).
  uint64_t* a = scratch<uint64_t, Scratch::kRankKeys>(2 * n);
  uint64_t* b = a + n;
  for (size_t i = 0; i < n; ++i) a[i] = (((sk[i] >> lo) & vmask) << ibits) | i;
  const int digit = n >= 2048 ? 11 : 8;
  const size_t nd = size_t{1} << digit;
  const uint64_t dmask = nd - 1;
  // Each pass counts and moves the first half of a (c0) and the rest (c1) side by side: two
  // chains of counter increments, not one through memory whenever neighbouring keys share a
  // digit (as a slowly varying signal's high digits do). In each bucket the first half's keys
  // go before the rest's, each half in its order: the same stable pass as one sweep.
  std::vector<uint32_t> count(2 * nd);  // n is a window channel's length, far below 2^32
  uint32_t* c0 = count.data();
  uint32_t* c1 = c0 + nd;
  const size_t h = n / 2;
  for (int sh = ibits; sh < ibits + width; sh += digit) {
    std::fill(count.begin(), count.end(), 0);
    for (size_t i = 0; i < h; ++i) {
      ++c0[(a[i] >> sh) & dmask];
      ++c1[(a[h + i] >> sh) & dmask];
    }
    if (n & 1) ++c1[(a[n - 1] >> sh) & dmask];
    const size_t d0 = (a[0] >> sh) & dmask;
    if (c0[d0] + c1[d0] == n) continue;  // one digit in every key: the pass moves nothing
    for (size_t d = 0, at = 0; d < nd; ++d) {
      const uint32_t k0 = c0[d], k1 = c1[d];
      c0[d] = static_cast<uint32_t>(at);
      c1[d] = static_cast<uint32_t>(at + k0);
      at += k0 + k1;
    }
    for (size_t i = 0; i < h; ++i) {
      const uint64_t x = a[i], y = a[h + i];
      b[c0[(x >> sh) & dmask]++] = x;
      b[c1[(y >> sh) & dmask]++] = y;
    }
    if (n & 1) b[c1[(a[n - 1] >> sh) & dmask]++] = a[n - 1];
    std::swap(a, b);
  }
  // The distinct keys into b (free now) in order, a new one where the varying bits change.
  size_t m = 0;
  uint64_t prev = n ? ~(a[0] >> ibits) : 0;
  for (size_t j = 0; j < n; ++j) {
    const uint64_t v = a[j] >> ibits;
    m += v != prev;
    prev = v;
    const size_t i = static_cast<size_t>(a[j] & imask);
    b[m - 1] = (*keys)[i];
    (*ranks)[i] = static_cast<int32_t>(m - 1);
  }
  keys->assign(b, b + m);
}

// sort_unique otherwise: keys and indices move side by side, a byte a pass.
void sort_unique_wide(std::vector<uint64_t>* keys, std::vector<int32_t>* ranks) {
  const size_t n = keys->size();
  std::vector<uint64_t> a = *keys, b(n);
  std::vector<uint32_t> ia(n), ib(n);
  for (size_t i = 0; i < n; ++i) ia[i] = static_cast<uint32_t>(i);
  uint64_t diff = 0;
  for (size_t i = 1; i < n; ++i) diff |= a[i] ^ a[0];
  for (int d = 0; d < 8; ++d) {
    const int sh = 8 * d;
    if (((diff >> sh) & 0xFF) == 0) continue;
    size_t count[257] = {0};
    for (size_t i = 0; i < n; ++i) ++count[((a[i] >> sh) & 0xFF) + 1];
    for (int k = 0; k < 256; ++k) count[k + 1] += count[k];
    for (size_t i = 0; i < n; ++i) {
      const size_t to = count[(a[i] >> sh) & 0xFF]++;
      b[to] = a[i];
      ib[to] = ia[i];
    }
    a.swap(b);
    ia.swap(ib);
  }
  keys->clear();
  for (size_t i = 0; i < n; ++i) {
    if (keys->empty() || keys->back() != a[i]) keys->push_back(a[i]);
    (*ranks)[ia[i]] = static_cast<int32_t>(keys->size() - 1);
  }
}

// Sorts *keys and drops repeats (as std::sort and std::unique would); (*ranks)[i] receives the
// position of the i-th original key in the result. LSD radix sort, stable, on the bits that
// are not the same in every key: when those bits and the index fit one 64-bit word together,
// each key is packed as (its varying bits, its index) and sorted alone; else keys and indices
// move side by side. Keys equal in their varying bits are equal, so either way equal keys end
// up adjacent and share a rank.
void sort_unique(std::vector<uint64_t>* keys, std::vector<int32_t>* ranks) {
  const size_t n = keys->size();
  uint64_t diff = 0;
  for (size_t i = 1; i < n; ++i) diff |= (*keys)[i] ^ (*keys)[0];
  const int ibits = n > 1 ? 64 - __builtin_clzll(static_cast<uint64_t>(n - 1)) : 0;
  ranks->resize(n);
  std::vector<uint64_t> f32_keys;
  const std::vector<uint64_t>* sk = narrowed_keys(*keys, ibits, &f32_keys, &diff);
  const int lo = diff ? __builtin_ctzll(diff) : 0;
  const int width = diff ? 64 - __builtin_clzll(diff) - lo : 0;
  if (width + ibits <= 64)
    sort_unique_packed(*sk, lo, width, ibits, keys, ranks);
  else
    sort_unique_wide(keys, ranks);
}

// Distinct values of v in increasing order of their ordered bits: ord (the ordered patterns)
// and the values.
void distinct_sorted(const std::vector<double>& v, std::vector<uint64_t>* ord,
                     std::vector<double>* sorted) {
  const size_t n = v.size();
  ord->resize(n);
  for (size_t i = 0; i < n; ++i) (*ord)[i] = ordered_bits(bits_of(v[i]));
  std::vector<int32_t> ranks;
  sort_unique(ord, &ranks);
  sorted->resize(ord->size());
  for (size_t i = 0; i < ord->size(); ++i) (*sorted)[i] = from_bits(from_ordered_bits((*ord)[i]));
}

bool all_float32(const std::vector<double>& v) {
  for (double x : v)
    if (!is_float32(x)) return false;
  return true;
}

// The integers' common step: the greatest common divisor g of their distances from the first
// (0 when all are equal), and the offset o = v[0] mod g in [0, g), so that every v == o + k g.
// Stops at g = 1, which most channels reach within a few samples.
uint64_t integer_step(const std::vector<double>& v, double* offset) {
  uint64_t g = 0;
  const int64_t v0 = static_cast<int64_t>(v.empty() ? 0.0 : v[0]);
  for (size_t i = 1; i < v.size() && g != 1; ++i) {
    const int64_t d = static_cast<int64_t>(v[i]) - v0;
    g = std::gcd(g, static_cast<uint64_t>(d < 0 ? -d : d));
  }
  if (g > 1) {
    const int64_t gi = static_cast<int64_t>(g);
    *offset = static_cast<double>(((v0 % gi) + gi) % gi);
  }
  return g;
}

}  // namespace

bool sample_lattice(const double* col, size_t stride, size_t n, const ChannelHint& hint,
                    double* step, double* offset) {
  ChannelRepr r;
  const std::vector<double> v = fill_gaps(col, stride, n, &r);
  if (n < 2) return false;
  if (all_integers(v)) {
    double o = 0;  // integer_step sets it only for a step above 1
    const uint64_t g = integer_step(v, &o);
    *step = g > 1 ? static_cast<double>(g) : 1.0;
    *offset = o;
    return true;
  }
  std::vector<uint64_t> ord;
  std::vector<double> sorted;
  distinct_sorted(v, &ord, &sorted);
  if (sorted.size() < 2 || !find_scaled(v, sorted, all_float32(v), hint, &r)) return false;
  *step = r.step;
  *offset = r.offset;
  return true;
}

std::vector<ChannelRepr> candidate_representations(const double* col, size_t stride, size_t n,
                                                   const ChannelHint& hint) {
  ChannelRepr r;
  std::vector<double> v = fill_gaps(col, stride, n, &r);
  bool constant = true;
  for (size_t i = 1; i < n && constant; ++i) constant = bits_of(v[i]) == bits_of(v[0]);
  if (constant) {
    r.kind = Kind::kConst;
    r.const_bits = n ? bits_of(v[0]) : 0;
    return {r};
  }
  if (hint.lattice_step > 0) {  // lossy analog: the encoder put the samples on this lattice
    ChannelRepr scaled = r;
    if (fit_scaled(v, hint.lattice_step, hint.lattice_offset, all_float32(v), n_max_exc(n),
                   &scaled)) {
      scaled.kind = Kind::kScaled;
      return {scaled};
    }
  }
  if (all_integers(v)) {
    // Integers that share a step g > 1 (EMG counts stored times 20, say) are also offered as
    // kScaled with step g, whose k are g times smaller; the window codec keeps the smaller.
    std::vector<ChannelRepr> out;
    double o = 0;
    const uint64_t g = integer_step(v, &o);
    ChannelRepr scaled = r;
    if (g > 1 && fit_scaled(v, static_cast<double>(g), o, all_float32(v), 0, &scaled)) {
      scaled.kind = Kind::kScaled;
      out.push_back(std::move(scaled));
    }
    r.kind = Kind::kInt;
    r.ints.resize(n);
    for (size_t i = 0; i < n; ++i) r.ints[i] = static_cast<int32_t>(v[i]);
    out.push_back(std::move(r));
    return out;
  }
  const bool f32 = all_float32(v);
  std::vector<uint64_t> ord(n);
  for (size_t i = 0; i < n; ++i) ord[i] = ordered_bits(bits_of(v[i]));
  std::vector<int32_t> ranks;
  sort_unique(&ord, &ranks);
  std::vector<double> sorted(ord.size());
  for (size_t i = 0; i < ord.size(); ++i) sorted[i] = from_bits(from_ordered_bits(ord[i]));
  std::vector<ChannelRepr> out;
  ChannelRepr scaled = r;
  if (find_scaled(v, sorted, f32, hint, &scaled)) {
    scaled.kind = Kind::kScaled;
    out.push_back(std::move(scaled));
  }
  // (float_bits, a pass over the samples, only where the choice depends on it)
  if (ord.size() <= kMaxTable &&
      (ord.size() <= n / 2 || rank_bits(ord.size(), n, f32) < float_bits(v, f32))) {
    ChannelRepr rank = r;
    rank.kind = Kind::kRank;
    rank.table = sorted;
    rank.ints = std::move(ranks);
    out.push_back(std::move(rank));
  }
  r.kind = f32 ? Kind::kFloat32 : Kind::kFloat64;
  r.filled = std::move(v);
  out.push_back(std::move(r));
  return out;
}

ChannelRepr choose_representation(const double* col, size_t stride, size_t n,
                                  const ChannelHint& hint) {
  return std::move(candidate_representations(col, stride, n, hint).front());
}

void write_repr_header(const ChannelRepr& r, const KeptRows& kept, const HeaderRules& rules,
                       HeaderState* state, ByteWriter* w) {
  const bool rep = !kept.repeats.empty(), inter = kept.interp.period != 0,
             held = kept.hold.period != 0;
  if ((rep && rules.S == 0) || rep + inter + held > 1)
    throw Error(ErrorCode::kInternal, "analog channel layout not allowed in this format version");
  const bool gaps = !r.gap_index.empty();
  const ScaledShare& share = state->share;
  const bool same_scaling =
      share.have && r.kind == Kind::kScaled && share.round_f32 == r.round_f32 &&
      bits_of(share.step) == bits_of(r.step) && bits_of(share.offset) == bits_of(r.offset);
  const bool same = (r.kind == Kind::kConst && r.const_bits == state->last_const) || same_scaling;
  w->u8(static_cast<uint8_t>(static_cast<int>(r.kind) | (gaps ? 8 : 0) | (same ? 16 : 0) |
                             (rep ? 32 : 0) | (inter ? 64 : 0) | (held ? 128 : 0)));
  if (rep) write_runs(kept.repeats, w);
  if (inter) write_interp(kept.interp, w);
  if (held) write_hold(kept.hold, w);
  if (gaps) {
    // Runs of consecutive gap samples; then the distinct bit patterns and, when several, each
    // sample's index.
    write_runs(r.gap_index, w);
    std::vector<uint64_t> pats;
    for (uint64_t b : r.gap_bits)
      if (std::find(pats.begin(), pats.end(), b) == pats.end()) pats.push_back(b);
    w->varint(pats.size());
    for (uint64_t b : pats) w->u64(b);
    if (pats.size() > 1)
      for (uint64_t b : r.gap_bits)
        w->varint(static_cast<uint64_t>(std::find(pats.begin(), pats.end(), b) - pats.begin()));
  }
  switch (r.kind) {
    case Kind::kConst:
      if (!same) w->varint(__builtin_bswap64(r.const_bits));
      state->last_const = r.const_bits;
      break;
    case Kind::kScaled: {
      if (!same_scaling) {
        w->u8(r.round_f32 ? 1 : 0);
        w->f64(r.step);
        w->f64(r.offset);
      }
      state->share = ScaledShare{true, r.round_f32, r.step, r.offset};
      w->varint(r.exc_index.size());
      uint32_t prev = 0;
      for (size_t e = 0; e < r.exc_index.size(); ++e) {
        w->varint(r.exc_index[e] - prev);
        w->svarint(r.exc_delta[e]);
        prev = r.exc_index[e] + 1;
      }
      break;
    }
    case Kind::kRank:
      write_value_table(r.table, w);
      break;
    default:
      break;
  }
}

}  // namespace analog
}  // namespace capz

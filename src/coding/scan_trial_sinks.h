// The scan geometry encoder's symbol sinks (scan_encode.cpp): coding into the block, the
// estimate of a trial's bits (CostSink, Tally), the recording of a frame's symbols for a trial
// (RecordSink), and the encoding side of scan_loop.h's Io (EncodeIo, RecordIo). Encoder only.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/entropy.h"
#include "coding/scan_geometry.h"
#include "coding/scan_shared.h"
#include "coding/scan_table.h"

namespace capz {
namespace scan_sinks {

// Codes into the block.
struct PutSink {
  IntEncoder* enc;
  void put(uint32_t u, int ctx) { scan::put_value(*enc, u, ctx); }
};
// The bits the block would take: each context's tokens under adaptive counts (about what the
// range coder's models learn) plus the raw bits below the token, summed symbol by symbol. The
// exact estimate: its comparisons decide the coding of a frame (spherical_wins).
class CostSink {
 public:
  CostSink() : counts_(scan::kContexts * 64, 0), totals_(scan::kContexts, 0) {}
  void put(uint32_t u, int ctx) {
    int extra;
    const int tok = token_of(u, &extra);
    uint32_t& c = counts_[static_cast<size_t>(ctx) * 64 + static_cast<size_t>(tok)];
    uint32_t& t = totals_[static_cast<size_t>(ctx)];
    bits += extra + std::log2((t + 16.0) / (c + 0.25));
    ++c, ++t;
  }
  double bits = 0;

 private:
  std::vector<uint32_t> counts_, totals_;
};

// One symbol as coded: the value and its context.
struct Sym {
  uint32_t u, ctx;
};

// What CostSink's sum depends on: the symbols' count, raw bits and tokens per context. Its sum
// of log2((t + 16) / (c + 0.25)) over a context's symbols is, in real numbers, the sum of
// log2(t + 16) for t below the context's total less, per token, the sum of log2(c + 0.25) for c
// below the token's count: the estimate below, which needs no logarithm per symbol.
class Tally {
 public:
  Tally() : counts_(scan::kContexts * 64, 0), totals_(scan::kContexts, 0) {}
  void clear() {
    std::fill(counts_.begin(), counts_.end(), 0u);
    std::fill(totals_.begin(), totals_.end(), 0u);
    extra_ = symbols_ = 0;
  }
  __attribute__((always_inline)) void put(uint32_t u, int ctx) {
    int extra;
    const int tok = token_of(u, &extra);
    ++counts_[static_cast<size_t>(ctx) * 64 + static_cast<size_t>(tok)];
    ++totals_[static_cast<size_t>(ctx)];
    extra_ += static_cast<uint64_t>(extra);
    ++symbols_;
  }
  uint64_t symbols() const { return symbols_; }
  // Adds o's symbols to these.
  void add(const Tally& o) {
    for (size_t i = 0; i < counts_.size(); ++i) counts_[i] += o.counts_[i];
    for (size_t i = 0; i < totals_.size(); ++i) totals_[i] += o.totals_[i];
    extra_ += o.extra_;
    symbols_ += o.symbols_;
  }
  // CostSink's bits in real numbers, computed in binary64 from prefix sums of logarithms.
  double estimate(std::vector<double>* log_t, std::vector<double>* log_c) const {
    double bits = static_cast<double>(extra_);
    for (size_t ctx = 0; ctx < totals_.size(); ++ctx) {
      if (totals_[ctx] == 0) continue;
      bits += prefix(log_t, 16.0, totals_[ctx]);
      for (size_t tok = 0; tok < 64; ++tok) bits -= prefix(log_c, 0.25, counts_[ctx * 64 + tok]);
    }
    return bits;
  }

 private:
  // sum of log2(j + offset) for j < n, from the table of such sums (grown as needed).
  static double prefix(std::vector<double>* sums, double offset, uint32_t n) {
    if (sums->empty()) sums->push_back(0.0);
    if (sums->size() <= n) sums->reserve(std::max<size_t>(2 * sums->size(), size_t{n} + 1));
    while (sums->size() <= n) {
      const double j = static_cast<double>(sums->size() - 1);
      sums->push_back(sums->back() + std::log2(j + offset));
    }
    return (*sums)[n];
  }
  std::vector<uint32_t> counts_, totals_;
  uint64_t extra_ = 0, symbols_ = 0;
};

// A symbol of the second of x y from the hypotenuse, the alternative to syms[at] (from the
// azimuth).
struct AltSym {
  size_t at;
  Sym sym;
};

// Room for n values of a trivial type, left uninitialised (only the pages written are touched)
// and kept while large enough: a trial's symbols, about 50 bytes a point of a frame.
template <class T>
class Room {
 public:
  // At least n values; those held before are lost when it grows (to twice its size at least, as
  // a vector's capacity does: each new block is fresh pages to touch).
  T* reserve(size_t n) {
    if (n > size_) {
      size_ = std::max(n, 2 * size_);
      buf_.reset();
      buf_.reset(new T[size_]);  // default-initialised: no writes
    }
    return buf_.get();
  }
  T* data() const { return buf_.get(); }

 private:
  std::unique_ptr<T[]> buf_;
  size_t size_ = 0;
};

[[noreturn]] __attribute__((noinline, cold)) inline void trial_overflow() {
  fail(ErrorCode::kInternal, "scan geometry", "a trial's symbols overflow");
}

// Records a frame's symbols and tallies them, the second of x y both ways (scan_loop.h's
// BothSeconds): the azimuth's symbols into syms and `azimuth`, the hypotenuse's into alts and
// `hypot` (each told by its contexts), every other symbol into syms and `tally`. The arrays
// have room for the frame (at most 7 symbols and one alternative a point).
// A trial's symbol of context ctx: the hypotenuse's second of x y (an alternative, tallied in
// `hypot`), the azimuth's (tallied in `azimuth`), or another (in `tally`).
inline bool hypot_context(int ctx) {
  return ctx >= scan::kCtxAxis2 && ctx < scan::kCtxZFrac;
}
inline bool azimuth_context(int ctx) {
  return ctx >= scan::kCtxY && ctx < scan::kCtxZ;
}

struct RecordSink {
  Sym *syms, *next, *end;
  AltSym* alt;
  Tally *tally, *azimuth, *hypot;
  __attribute__((always_inline)) void put(uint32_t u, int ctx) {
    const Sym y{u, static_cast<uint32_t>(ctx)};
    if (__builtin_expect(next == end, 0)) trial_overflow();
    if (hypot_context(ctx)) {
      *alt++ = AltSym{static_cast<size_t>(next - syms), y};
      hypot->put(u, ctx);
      return;
    }
    *next++ = y;
    (azimuth_context(ctx) ? azimuth : tally)->put(u, ctx);
  }
};

// RecordSink's tallies without its records: a trial coded again, recorded, if it wins (the
// second trial of a frame too large to hold two trials' records, scan_encode.cpp).
struct TallySink {
  Tally *tally, *azimuth, *hypot;
  __attribute__((always_inline)) void put(uint32_t u, int ctx) {
    (hypot_context(ctx) ? hypot : azimuth_context(ctx) ? azimuth : tally)->put(u, ctx);
  }
};

// The encoding side of scan::code_frame: the actual values are the window's.
template <class Sink>
class EncodeIo {
 public:
  EncodeIo(Sink* sink, const ScanGeometry& g, const scan::Placement& placed)
      : sink_(sink), g_(g), polar_(placed.polar.data()), fire_(placed.fire.data()) {}
  // (The sink codes each value as its context says: scan::value_kind.)
  __attribute__((always_inline)) int32_t sym(int32_t actual, int32_t pred, int ctx) {
    sink_->put(zigzag(wrap_sub(actual, pred)), ctx);
    return actual;
  }
  __attribute__((always_inline)) int32_t sym_plain(int32_t actual, int32_t pred, int ctx) {
    return sym(actual, pred, ctx);
  }
  __attribute__((always_inline)) uint32_t ring(uint32_t d, uint32_t, int ctx) {
    sink_->put(d, ctx);
    return d;
  }
  __attribute__((always_inline)) bool flag(bool v, int ctx) {
    sink_->put(v ? 1u : 0u, ctx);
    return v;
  }
  scan::Polar polar(size_t i) const { return polar_[i]; }
  // (Called only on a table with slots, whose placement has every point's firing.)
  scan::Fire fire(size_t i) const { return fire_[i]; }
  const int32_t* actual(size_t i) const { return &g_.q[3 * i]; }
  bool actual_valid(size_t i) const { return g_.valid[i] != 0; }

 private:
  Sink* sink_;
  const ScanGeometry& g_;
  const scan::Polar* polar_;
  const scan::Fire* fire_;
};

// The encoder's spherical trial: codes the second of x y both ways (scan_loop.h).
struct RecordIo : EncodeIo<RecordSink> {
  using EncodeIo<RecordSink>::EncodeIo;
  static constexpr bool kBothSeconds = true;
};
struct TallyIo : EncodeIo<TallySink> {
  using EncodeIo<TallySink>::EncodeIo;
  static constexpr bool kBothSeconds = true;
};

}  // namespace scan_sinks
}  // namespace capz

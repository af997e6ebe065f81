// The scan geometry encoder (docs/FORMAT.md "Scans (format 1.1)").
#include <cmath>
#include <string>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/scan_geometry.h"
#include "coding/scan_shared.h"
#include "coding/scan_table.h"

namespace capz {

namespace scan {

void write_header(const ScanGeometry& g, const std::vector<uint8_t>& flags, const Table& t,
                  std::vector<uint8_t>* out) {
  ByteWriter w;
  w.varint(g.counts.size());
  for (uint32_t n : g.counts) w.varint(n);
  w.bytes(flags);
  w.varint(t.rings());
  if (t.rings() > 0) {
    w.f32(t.step);
    w.varint(t.columns);
    for (size_t k = 0; k < t.rings(); ++k) {
      w.f32(t.azimuth0[k]);
      w.f32(t.slope[k]);
      w.f32(t.z0[k]);
    }
  }
  out->insert(out->end(), w.buffer().begin(), w.buffer().end());
}

}  // namespace scan

namespace {

// Codes into the block.
struct PutSink {
  IntEncoder* enc;
  void put(uint32_t u, int ctx) { enc->put(u, ctx); }
};
// Estimates the bits the block would take: each context's tokens under adaptive counts (about
// what the range coder's models learn) plus the raw bits below the token.
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

// The encoding side of scan::code_frame: the actual values are the window's.
template <class Sink>
class EncodeIo {
 public:
  EncodeIo(Sink* sink, const ScanGeometry& g, const std::vector<scan::Polar>& polar)
      : sink_(sink), g_(g), polar_(polar) {}
  int32_t sym(int32_t actual, int32_t pred, int ctx) {
    sink_->put(zigzag(wrap_sub(actual, pred)), ctx);
    return actual;
  }
  uint32_t ring(uint32_t d, uint32_t, int ctx) {
    sink_->put(d, ctx);
    return d;
  }
  bool flag(bool v, int ctx) {
    sink_->put(v ? 1u : 0u, ctx);
    return v;
  }
  scan::Polar polar(size_t i) const { return polar_[i]; }
  const int32_t* actual(size_t i) const { return &g_.q[3 * i]; }
  bool actual_valid(size_t i) const { return g_.valid[i] != 0; }

 private:
  Sink* sink_;
  const ScanGeometry& g_;
  const std::vector<scan::Polar>& polar_;
};

uint8_t validity(const ScanGeometry& g, size_t first, size_t n) {
  size_t v = 0;
  for (size_t i = first; i < first + n; ++i) v += g.valid[i] != 0;
  return v == n ? scan::kAllValid : v == 0 ? scan::kNoneValid : scan::kSomeValid;
}

// Bits of frame [first, first + n) under `flags`, from the state st (left unchanged).
double frame_cost(const scan::State& st, uint8_t flags, const ScanGeometry& g,
                  const std::vector<scan::Polar>& polar, size_t first, size_t n,
                  std::vector<int32_t>* q, std::vector<uint8_t>* v) {
  CostSink sink;
  EncodeIo<CostSink> io(&sink, g, polar);
  scan::State trial = st.trial();
  scan::code_frame(io, trial, flags, first, n, q->data(), v->data());
  return sink.bits;
}

// The payload under one table: per frame the cheaper of spherical and Cartesian coding.
std::vector<uint8_t> encode_with(const ScanGeometry& g, const scan::Table& t,
                                 const std::vector<scan::Polar>& polar) {
  const size_t frames = g.counts.size();
  std::vector<uint8_t> flags(frames);
  IntEncoder enc(scan::kContexts);
  PutSink sink{&enc};
  EncodeIo<PutSink> io(&sink, g, polar);
  scan::State st(t);
  std::vector<int32_t> q;
  std::vector<uint8_t> v;
  size_t first = 0;
  for (size_t f = 0; f < frames; ++f) {
    const size_t n = g.counts[f];
    q.resize(3 * n);
    v.resize(n);
    flags[f] = validity(g, first, n);
    if (t.rings() > 0 && flags[f] != scan::kNoneValid && scan::spherical_ok(g, first, n)) {
      const uint8_t sph = static_cast<uint8_t>(flags[f] | scan::kSpherical);
      if (frame_cost(st, sph, g, polar, first, n, &q, &v) <
          frame_cost(st, flags[f], g, polar, first, n, &q, &v))
        flags[f] = sph;
    }
    scan::code_frame(io, st, flags[f], first, n, q.data(), v.data());
    first += n;
  }
  std::vector<uint8_t> out;
  scan::write_header(g, flags, t, &out);
  const std::vector<uint8_t> body = enc.finish();
  out.insert(out.end(), body.begin(), body.end());
  return out;
}

}  // namespace

std::vector<uint8_t> encode_scan_geometry(const ScanGeometry& g, const ScanHints& hints) {
  size_t total = 0;
  for (uint32_t n : g.counts) total += n;
  if (g.valid.size() != total || g.q.size() != 3 * total)
    fail(ErrorCode::kInternal, "scan geometry", "the points disagree with the frames' counts");
  // The table's azimuth step as found, and finer ones for azimuths off that step: the smallest
  // payload wins.
  std::vector<uint8_t> best;
  for (double divisor : {1.0, 4.0, 16.0}) {
    std::vector<scan::Polar> polar;
    const scan::Table t = scan::infer_table(g, hints, divisor, &polar);
    std::vector<uint8_t> out = encode_with(g, t, polar);
    if (best.empty() || out.size() < best.size()) best.swap(out);
    if (t.rings() == 0) break;
  }
  return best;
}

}  // namespace capz

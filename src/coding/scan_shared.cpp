// The scan geometry coder's shared parts: header, table, trigonometry, state
// (docs/FORMAT.md "Scans (format 1.1)").
#include "coding/scan_shared.h"

#include <cmath>

#include "capz/error.h"
#include "coding/bytes.h"

namespace capz {
namespace scan {

namespace {

// Taylor series of sin and cos on |r| <= pi/4 (terms to r^17 and r^16) in Horner form:
// sin r = r + r r2 P_s(r2), cos r = 1 + r2 P_c(r2), the coefficients from the highest term.
constexpr double kSinTerms[8] = {
    1.0 / 355687428096000.0, -1.0 / 1307674368000.0, 1.0 / 6227020800.0, -1.0 / 39916800.0,
    1.0 / 362880.0,          -1.0 / 5040.0,          1.0 / 120.0,        -1.0 / 6.0};
constexpr double kCosTerms[8] = {
    1.0 / 20922789888000.0, -1.0 / 87178291200.0, 1.0 / 479001600.0, -1.0 / 3628800.0,
    1.0 / 40320.0,          -1.0 / 720.0,         1.0 / 24.0,        -0.5};
double horner(const double (&c)[8], double r2) {
  double p = c[0];
  for (int i = 1; i < 8; ++i) p = p * r2 + c[i];
  return p;
}

void check_finite(float v, ByteReader* r) {
  if (!std::isfinite(v)) fail(ErrorCode::kCorrupt, r->what(), "laser table value is not finite");
}

}  // namespace

void det_sincos(double a, double* s, double* c) {
  // a = k pi/2 + r, |r| <= pi/4 (about; exactness does not matter, only the same bits).
  const double kHalfPiHi = 1.5707963267948966;
  const double kHalfPiLo = 6.123233995736766e-17;
  const double k = std::floor(a * (1.0 / kHalfPiHi) + 0.5);
  const double r = (a - k * kHalfPiHi) - k * kHalfPiLo;
  const double q = k - 4.0 * std::floor(k * 0.25);  // 0, 1, 2 or 3
  const double r2 = r * r;
  const double ps = r + r * r2 * horner(kSinTerms, r2), pc = 1.0 + r2 * horner(kCosTerms, r2);
  if (q == 0.0) {
    *s = ps, *c = pc;
  } else if (q == 1.0) {
    *s = pc, *c = -ps;
  } else if (q == 2.0) {
    *s = -ps, *c = -pc;
  } else {
    *s = -pc, *c = ps;
  }
}

int32_t round_clamp(double v) {
  if (!(v == v)) return 0;
  if (v >= 2147483647.0) return INT32_MAX;
  if (v <= -2147483648.0) return INT32_MIN;
  return static_cast<int32_t>(std::floor(v + 0.5));
}

Header read_header(const uint8_t* data, size_t size, const std::string& what, size_t max_points) {
  ByteReader r(data, size, what);
  Header h;
  const size_t frames = static_cast<size_t>(r.count(2, "frame count"));
  h.counts.resize(frames);
  uint64_t total = 0;
  for (uint32_t& n : h.counts) {
    const uint64_t v = r.varint();
    total += v;
    if (v > UINT32_MAX || total > max_points)
      fail(ErrorCode::kCorrupt, what,
           "the frames' point counts exceed " + std::to_string(max_points) + " points");
    n = static_cast<uint32_t>(v);
  }
  const uint8_t* f = r.bytes(frames);
  h.flags.assign(f, f + frames);
  const uint64_t rings = r.varint();
  if (rings > kMaxRings) fail(ErrorCode::kCorrupt, what, "more than 1024 rings in the laser table");
  Table& t = h.table;
  if (rings > 0) {
    t.step = r.f32();
    check_finite(t.step, &r);
    const uint64_t cols = r.varint();
    if (t.step == 0.0f || cols == 0 || cols * rings > kMaxMapCells)
      fail(ErrorCode::kCorrupt, what, "laser table with a zero step or too many columns");
    t.columns = static_cast<uint32_t>(cols);
    for (uint64_t k = 0; k < rings; ++k) {
      t.azimuth0.push_back(r.f32());
      t.slope.push_back(r.f32());
      t.z0.push_back(r.f32());
      check_finite(t.azimuth0.back(), &r);
      check_finite(t.slope.back(), &r);
      check_finite(t.z0.back(), &r);
    }
  }
  uint64_t coded = 0;  // points that code at least one symbol
  for (size_t i = 0; i < frames; ++i) {
    const uint8_t fl = h.flags[i];
    if ((fl & ~kFrameFlagMask) != 0 || (fl & 3) == 3)
      fail(ErrorCode::kCorrupt, what, "frame " + std::to_string(i) + " has unknown flags");
    if ((fl & kSpherical) && rings == 0)
      fail(ErrorCode::kCorrupt, what, "a spherical frame without a laser table");
    if ((fl & 3) != kNoneValid) coded += h.counts[i];
  }
  h.body = r.offset();
  if (coded > kMaxSymbolsPerByte * (size - h.body))
    fail(ErrorCode::kCorrupt, what, "more points than the coded bytes can hold");
  return h;
}

State::State(const Table& t)
    : ring(t.rings()), succ(t.rings()), t_(&t), maps_(std::make_shared<Maps>()) {
  for (size_t k = 0; k < succ.size(); ++k) succ[k] = static_cast<uint32_t>((k + 1) % succ.size());
  const size_t cells = t.rings() * t.columns;
  maps_->prev.assign(cells, 0);
  maps_->cur.assign(cells, 0);
  maps_->prev_set.assign(cells, 0);
  maps_->cur_set.assign(cells, 0);
}

void State::end_frame() {
  if (trial_) return;
  maps_->prev.swap(maps_->cur);
  maps_->prev_set.swap(maps_->cur_set);
  std::fill(maps_->cur_set.begin(), maps_->cur_set.end(), uint8_t{0});
}

size_t State::cell(uint32_t k, int32_t col) const {
  const int64_t c = static_cast<int64_t>(col) % t_->columns;
  return static_cast<size_t>(k) * t_->columns + static_cast<size_t>(c < 0 ? c + t_->columns : c);
}

bool State::map_prev(uint32_t k, int32_t col, int32_t* range) const {
  const size_t i = cell(k, col);
  if (!maps_->prev_set[i]) return false;
  *range = maps_->prev[i];
  return true;
}

void State::map_set(uint32_t k, int32_t col, int32_t range) {
  if (trial_) return;
  const size_t i = cell(k, col);
  maps_->cur[i] = range;
  maps_->cur_set[i] = 1;
}

}  // namespace scan
}  // namespace capz

// The scaled representation's fit (docs/FORMAT.md 11.7 kind 2, 16.3): the step and offset
// that describe a channel's samples as k * s + o (rounded to float32 when they are float32),
// found from the data and the C3D hint, and the exceptions it leaves. Encoder side (the decoder
// shares only scaled_value, in the header). Built with -ffp-contract=off.
#include "coding/analog/analog_scaled.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

#include "coding/analog/analog_round.h"
#include "coding/analog/analog_scratch.h"
#include "coding/analog/analog_simd.h"

namespace capz {
namespace analog {

namespace {

// fit_scaled's loop W samples a step, from sample i while W are left: returns where it stopped,
// or SIZE_MAX when the fit fails there. A step whose W quotients all round without a division
// (|k| < 2^23 then) computes scaled_value lane by lane with the same operations (the product
// rounded before the sum, then round_to_float32; k + 0 is k with a zero's sign dropped, as
// scaled_value's int64 k has none); any other step goes sample by sample through `one`.
// Always inlined, so that it is compiled for its caller's target (AVX2 for W = 4).
template <int W>
struct FitLanes;
template <>
struct FitLanes<2> {
  typedef double D __attribute__((vector_size(16)));
  typedef float F __attribute__((vector_size(8)));
  typedef long long M __attribute__((vector_size(16)));
};
template <>
struct FitLanes<4> {
  typedef double D __attribute__((vector_size(32)));
  typedef float F __attribute__((vector_size(16)));
  typedef long long M __attribute__((vector_size(32)));
};
template <int W, typename One>
__attribute__((always_inline)) inline size_t fit_scaled_lanes(const std::vector<double>& v,
                                                              size_t i, double s, double o,
                                                              bool f32, size_t max_exc,
                                                              const QuotientRounder& round_quotient,
                                                              const One& one, ChannelRepr* r) {
  typedef typename FitLanes<W>::D D;
  typedef typename FitLanes<W>::F F;
  typedef typename FitLanes<W>::M M;
  constexpr double kMax = std::numeric_limits<float>::max();
  constexpr double kDMax = std::numeric_limits<double>::max();
  const size_t n = v.size();
  for (; i + W <= n; i += W) {
    D x, k;
    std::memcpy(&x, v.data() + i, sizeof x);
    const D d = x - o;
    if (round_quotient.lanes<D, M>(d, &k)) {
      D y = (k + 0.0) * s + o;
      if (f32) {
        y = ((y > kMax) & (y <= kDMax)) ? kMax : y;
        y = ((y < -kMax) & (y >= -kDMax)) ? -kMax : y;
        y = __builtin_convertvector(__builtin_convertvector(y, F), D);
      }
      M yb, xb;
      std::memcpy(&yb, &y, sizeof yb);
      std::memcpy(&xb, &x, sizeof xb);
      for (int l = 0; l < W; ++l) {
        r->ints[i + l] = static_cast<int32_t>(k[l]);
        if (yb[l] == xb[l]) continue;
        if (r->exc_index.size() == max_exc) return SIZE_MAX;
        r->exc_index.push_back(static_cast<uint32_t>(i + l));
        r->exc_delta.push_back(exception_delta(x[l], y[l], f32));
      }
      continue;
    }
    for (int l = 0; l < W; ++l)
      if (!one(i + l)) return SIZE_MAX;
  }
  return i;
}

#if defined(__x86_64__) || defined(__i386__)
template <typename One>
__attribute__((target("avx2"))) size_t fit_scaled_avx2(const std::vector<double>& v, double s,
                                                       double o, bool f32, size_t max_exc,
                                                       const QuotientRounder& round_quotient,
                                                       const One& one, ChannelRepr* r) {
  return fit_scaled_lanes<4>(v, 0, s, o, f32, max_exc, round_quotient, one, r);
}
#endif

}  // namespace

// The scaled fit for step s and offset o: the k and the exceptions; false when more than
// max_exc samples would be exceptions or a k is out of range. Four samples a step (AVX2), or
// two, where the quotients round without a division (fit_scaled_lanes); else sample by sample.
bool fit_scaled(const std::vector<double>& v, double s, double o, bool f32, size_t max_exc,
                ChannelRepr* r) {
  if (!(s > 0) || !std::isfinite(s) || !std::isfinite(o)) return false;
  const size_t n = v.size();
  r->ints.resize(n);
  r->exc_index.clear();
  r->exc_delta.clear();
  const QuotientRounder round_quotient(s);
  auto one = [&](size_t i) {
    const double kd = round_quotient(v[i] - o);
    if (!(std::fabs(kd) <= static_cast<double>(kMaxScaledK))) return false;
    const int64_t k = static_cast<int64_t>(kd);
    r->ints[i] = static_cast<int32_t>(k);
    const uint64_t want = bits_of(v[i]), got = bits_of(scaled_value(k, s, o, f32));
    if (want != got) {
      if (r->exc_index.size() == max_exc) return false;
      r->exc_index.push_back(static_cast<uint32_t>(i));
      r->exc_delta.push_back(exception_delta(v[i], from_bits(got), f32));
    }
    return true;
  };
  size_t i = 0;
#if defined(__x86_64__) || defined(__i386__)
  if (avx2_enabled()) i = fit_scaled_avx2(v, s, o, f32, max_exc, round_quotient, one, r);
#endif
  if (i != SIZE_MAX) i = fit_scaled_lanes<2>(v, i, s, o, f32, max_exc, round_quotient, one, r);
  if (i == SIZE_MAX) return false;
  if (i < n && !one(i)) return false;
  r->round_f32 = f32;
  r->step = s;
  r->offset = o;
  return true;
}

void refine_fit(const std::vector<double>& v, double* s, double* o) {
  const size_t n = v.size();
  // The k in a per-thread buffer, not zeroed (every entry is written before it is read): a
  // vector of n doubles allocated and zeroed per refit was a tenth of the refit's time.
  double* k = scratch<double, Scratch::kRefitSteps>(n);
  double kbar = 0, vbar = 0;
  const QuotientRounder round_quotient(*s);
  for (size_t i = 0; i < n; ++i) {
    k[i] = round_quotient(v[i] - *o);
    kbar += k[i];
    vbar += v[i];
  }
  kbar /= static_cast<double>(n);
  vbar /= static_cast<double>(n);
  double skv = 0, skk = 0;
  for (size_t i = 0; i < n; ++i) {
    skv += (k[i] - kbar) * (v[i] - vbar);
    skk += (k[i] - kbar) * (k[i] - kbar);
  }
  if (!(skk > 0)) return;
  *s = skv / skk;
  *o = vbar - *s * kbar;
}

namespace {

// The largest power of two that divides (as a multiple) at least 7/8 of the samples: a step
// when a few off-grid samples hide the grid from the smallest gap.
double common_power_of_two(const std::vector<double>& v) {
  int hist[2100] = {0};
  size_t nonzero = 0;
  for (double x : v) {
    if (x == 0) continue;
    // The exponent of x's lowest set bit, from its fields: x = mant 2^(e - 1075) (e the biased
    // exponent, 1 for subnormals, whose mantissa has no implicit bit). x is finite.
    const uint64_t b = bits_of(x);
    const int e = static_cast<int>((b >> 52) & 0x7FF);
    const uint64_t mant = (b & ((uint64_t{1} << 52) - 1)) | (e ? uint64_t{1} << 52 : 0);
    const int lsb = (e ? e : 1) - 1075 + __builtin_ctzll(mant);
    ++hist[std::min(2099, std::max(0, lsb + 1100))];
    ++nonzero;
  }
  size_t above = 0;
  for (int b = 2099; b >= 0; --b) {
    above += hist[b];
    if (above * 8 >= nonzero * 7 && nonzero > 0) return std::ldexp(1.0, b - 1100);
  }
  return 0;
}

// The (step, offset) pairs find_scaled tries, listed from the data and the hint (it tries the
// last listed first).
class FitList {
 public:
  FitList(const std::vector<double>& v, const std::vector<double>& sorted)
      : v_(v), sorted_(sorted) {
    small_ = sorted.front();
    for (double x : sorted)
      if (std::fabs(x) < std::fabs(small_)) small_ = x;
  }
  const std::vector<std::pair<double, double>>& fits() const { return fits_; }
  void push(double s, double o) { fits_.push_back({s, o}); }

  // Step s with offset 0; with `refine`, also s with the offset of the least sample, two rounds
  // of refine_fit from there (each with the offset pinned at the sample nearest 0 too), and the
  // reciprocals of integers near s and near the refined step.
  void add(double s, bool refine) {
    if (!(s > 0) || !std::isfinite(s)) return;
    double o = refine ? sorted_.front() - round_half_away(sorted_.front() / s) * s : 0.0;
    push(s, o);
    if (!refine) return;
    snap(s, 0.0);
    for (int it = 0; it < 2; ++it) {
      refine_once(&s, &o);
      if (!(s > 0) || !std::isfinite(s) || !std::isfinite(o)) return;
      push(s, o);
      // The sample nearest 0 has the finest rounding: pin the offset there.
      push(s, small_ - round_half_away((small_ - o) / s) * s);
    }
    snap(s, o);
  }

 private:
  // refine_fit's result depends on v and (s, o) alone: a pair refined before in this list is
  // looked up, not refit (bit for bit the same result). That happens in about one refit of
  // seven on the bench's takes: a fixed point of the first round is the second round's input,
  // and different steps' fits can meet.
  void refine_once(double* s, double* o) {
    for (const std::array<double, 4>& f : refits_)
      if (bits_of(f[0]) == bits_of(*s) && bits_of(f[1]) == bits_of(*o)) {
        *s = f[2];
        *o = f[3];
        return;
      }
    const double s0 = *s, o0 = *o;
    refine_fit(v_, s, o);
    refits_.push_back({s0, o0, *s, *o});
  }
  // A step that is the reciprocal of an integer (counts averaged over q samples, k / q) is only
  // approximated by a gap or a fit, which leaves exceptions wherever k * s lands near a float
  // rounding boundary, or (over a wide range of k) no fit at all: try the exact 1 / q, with the
  // offset 0 and snapped to a multiple of it.
  void snap(double s_est, double o_est) {
    const double q0 = std::round(1.0 / s_est);
    if (!(q0 >= 2 && q0 <= 1e6 && std::fabs(1.0 / s_est - q0) <= std::min(1e-3 * q0, 0.05))) return;
    // q0 - 1 too: the gap between two float32 values k / q, rounded, can be a hair below 1 / q
    // (Dance.c3d's channels are k / 32767, whose smallest gap rounds to 1 / 32768).
    for (double q = q0; q >= q0 - 1 && q >= 2; --q) {
      const double sq = 1.0 / q;
      push(sq, 0.0);
      const double oq = round_half_away(o_est / sq) * sq;
      if (oq != 0) push(sq, oq);
    }
  }

  const std::vector<double>& v_;
  const std::vector<double>& sorted_;
  double small_;                                 // the sample nearest 0
  std::vector<std::pair<double, double>> fits_;  // (step, offset)
  std::vector<std::array<double, 4>> refits_;    // (s, o) in, (s, o) out
};

// The fits find_scaled tries: the smallest gap between distinct values and, when it is wrong
// because one sample is off the grid by a hair (a sum that should have been 0 coming out as
// 1e-12), the lower quartile of the gaps, both refined; the largest power of two dividing every
// sample; the hint's scale and offset, and its scale refined.
std::vector<std::pair<double, double>> scaled_fits(const std::vector<double>& v,
                                                   const std::vector<double>& sorted,
                                                   const ChannelHint& hint) {
  double gap = 0;
  for (size_t i = 1; i < sorted.size(); ++i) {
    const double d = sorted[i] - sorted[i - 1];
    if (d > 0 && (gap == 0 || d < gap)) gap = d;
  }
  FitList list(v, sorted);
  list.add(gap, true);
  std::vector<double> gaps;
  gaps.reserve(sorted.size());
  for (size_t i = 1; i < sorted.size(); ++i)
    if (sorted[i] > sorted[i - 1]) gaps.push_back(sorted[i] - sorted[i - 1]);
  if (gaps.size() >= 8) {
    auto q = gaps.begin() + static_cast<std::ptrdiff_t>(gaps.size() / 4);
    std::nth_element(gaps.begin(), q, gaps.end());
    if (*q > gap * (1 + 1e-9)) list.add(*q, true);
  }
  list.add(common_power_of_two(v), false);
  if (hint.scale != 0) {
    list.push(std::fabs(hint.scale), hint.offset * std::fabs(hint.scale));
    list.add(std::fabs(hint.scale), true);
  }
  return list.fits();
}

// The cheapest of the fits, tried from the last listed: cost in bits, up to a constant, is the
// exceptions (about 3 bytes each) and log2 of the k's spread, which grows as the step shrinks.
// False when none fits.
bool cheapest_fit(const std::vector<double>& v, const std::vector<std::pair<double, double>>& fits,
                  bool f32, ChannelRepr* best) {
  const size_t n = v.size();
  auto cost = [&](const ChannelRepr& t) {
    return 24.0 * static_cast<double>(t.exc_index.size()) -
           static_cast<double>(n) * std::log2(t.step);
  };
  ChannelRepr t;  // its buffers are reused from fit to fit
  bool found = false;
  for (auto it = fits.rbegin(); it != fits.rend(); ++it) {
    // A fit equal to one already tried has the same cost, which never replaces the best.
    bool seen = false;
    for (auto jt = fits.rbegin(); jt != it && !seen; ++jt)
      seen = bits_of(jt->first) == bits_of(it->first) && bits_of(jt->second) == bits_of(it->second);
    if (seen) continue;
    // Once a fit is found, one with e exceptions replaces it only when 24 e - n log2(step) is
    // below its cost (the same expression, increasing in e): more exceptions than that fail
    // the fit early, as too many do anyway.
    size_t max_exc = n_max_exc(n);
    if (found) {
      const double best_cost = cost(*best), spread = static_cast<double>(n) * std::log2(it->first);
      size_t e = 0;
      while (e <= max_exc && 24.0 * static_cast<double>(e) - spread < best_cost) ++e;
      if (e == 0) continue;  // not even an exact fit would be cheaper
      max_exc = e - 1;
    }
    if (!fit_scaled(v, it->first, it->second, f32, max_exc, &t)) continue;
    if (!found || cost(t) < cost(*best)) {
      std::swap(*best, t);
      found = true;
    }
  }
  return found;
}

}  // namespace

// Tries the steps suggested by the data (the smallest gap between distinct values, refined by a
// least-squares fit) and by the hint; keeps the fit with the fewest exceptions.
bool find_scaled(const std::vector<double>& v, const std::vector<double>& sorted, bool f32,
                 const ChannelHint& hint, ChannelRepr* r) {
  ChannelRepr best;
  if (!cheapest_fit(v, scaled_fits(v, sorted, hint), f32, &best)) return false;
  // FORMAT.md 11.7: the window's previous scaled channel's step and offset, when they are this
  // fit's up to its last bits and leave no more exceptions, so that the header can name them.
  const ScaledShare& sh = hint.share;
  ChannelRepr t;
  if (sh.have && sh.round_f32 == best.round_f32 &&
      (bits_of(sh.step) != bits_of(best.step) || bits_of(sh.offset) != bits_of(best.offset)) &&
      std::fabs(sh.step / best.step - 1) < 1e-6 &&
      fit_scaled(v, sh.step, sh.offset, f32, best.exc_index.size(), &t))
    std::swap(best, t);
  r->round_f32 = best.round_f32;
  r->step = best.step;
  r->offset = best.offset;
  r->exc_index = std::move(best.exc_index);
  r->exc_delta = std::move(best.exc_delta);
  r->ints = std::move(best.ints);
  return true;
}

}  // namespace analog
}  // namespace capz

// Rounding of quotients for the scaled representation's fits (analog_repr.cpp).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace capz {
namespace analog {

// std::round (halves away from zero, sign of zero kept) without the library call or a branch
// on the fraction; exact. For 0 <= x < 2^52, x + h (h = 1/2 - 2^-54, the double below 1/2)
// rounds to a double in [floor(x), floor(x) + 1) when frac(x) < 1/2 (the sum stays at least
// ulp(x) + 2^-54 below floor(x) + 1, and doubles there are ulp(x) apart), and to one in
// [floor(x) + 1, floor(x) + 1.5] otherwise (frac = 1/2 gives floor(x) + 1 - 2^-54, nearer
// floor(x) + 1, or a tie at x = 1/2 that goes to the even 1): truncation gives floor(x + 1/2).
// Negative x by symmetry.
inline double round_half_away(double x) {
  if (!(std::fabs(x) < 4503599627370496.0)) return std::round(x);  // 2^52: integral, NaN, Inf
  const double s = x + std::copysign(0.49999999999999994, x);
  return std::copysign(static_cast<double>(static_cast<int64_t>(s)), x);
}

// round_half_away(d / s) for many d, mostly without dividing. With r = 1 / s rounded (s and r
// normal), y = d r is within |q| 2^-52 of the quotient q = d / s, and the rounded quotient
// within |q| 2^-53: below 2^23 they are less than 2^-28 apart, so y rounds as the rounded
// quotient does unless it is within 2^-26 of a half-integer. Then y's nearest integer (by
// adding and subtracting 1.5 2^52, exact) is the answer; near a half-integer, and in every
// other case, it divides. The sign of a zero result is the quotient's, whose sign y shares.
class QuotientRounder {
 public:
  explicit QuotientRounder(double s)
      : s_(s), r_(1 / s), fast_(std::isnormal(s) && std::isnormal(r_)) {}
  double operator()(double d) const {
    constexpr double kRound = 6755399441055744.0;  // 1.5 2^52
    const double y = d * r_;
    const double k = (y + kRound) - kRound;  // nearest integer, when |y| < 2^51
    if (fast_ && std::fabs(y) < 8388608.0 && 0.5 - std::fabs(y - k) > 1.0 / 67108864)
      return std::copysign(k, y);
    return round_half_away(d / s_);
  }
  // The same for two values at once (d[0], d[1]), when both take the path without a division:
  // true and the two results in *k; false (and *k unset) when either needs the division.
  typedef double Lanes __attribute__((vector_size(16)));
  bool pair(Lanes d, Lanes* k) const {
    typedef long long Mask __attribute__((vector_size(16)));
    return lanes<Lanes, Mask>(d, k);
  }
  // pair's test and results for any number of lanes: V a vector of doubles, M one of long long
  // as wide. Always inlined, so that it is compiled for its caller's target (AVX2 for four).
  template <typename V, typename M>
  __attribute__((always_inline)) bool lanes(const V& d, V* k) const {
    constexpr double kRound = 6755399441055744.0;  // 1.5 2^52
    constexpr long long kSign = static_cast<long long>(0x8000000000000000ull);
    auto magnitude = [](V * x) __attribute__((always_inline)) {
      M b;
      std::memcpy(&b, x, sizeof b);
      b &= ~kSign;
      std::memcpy(x, &b, sizeof b);
    };
    const V y = d * r_;
    const V near = (y + kRound) - kRound;
    V ay = y, off = y - near;
    magnitude(&ay);
    magnitude(&off);
    const M ok = (ay < 8388608.0) & (0.5 - off > 1.0 / 67108864);
    if (!fast_) return false;
    for (size_t l = 0; l < sizeof(M) / sizeof(long long); ++l)
      if (!ok[l]) return false;
    M kb, yb;
    std::memcpy(&kb, &near, sizeof kb);
    std::memcpy(&yb, &y, sizeof yb);
    kb = (kb & ~kSign) | (yb & kSign);  // copysign(near, y)
    std::memcpy(k, &kb, sizeof kb);
    return true;
  }

 private:
  double s_, r_;
  bool fast_;
};

}  // namespace analog
}  // namespace capz

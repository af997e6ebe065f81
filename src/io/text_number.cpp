// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "io/text_number.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace capz {

bool parse_double(const std::string& s, double* out) {
  const char* b = s.data();
  const char* e = b + s.size();
  if (b < e && *b == '+') ++b;
  if (b == e) return false;
  auto r = std::from_chars(b, e, *out, std::chars_format::general);
  return r.ec == std::errc() && r.ptr == e;
}

std::string format_decimal(double v, int min_decimals) {
  if (std::isnan(v)) return "NaN";
  char buf[400];
  char* end = buf + sizeof buf;
  std::to_chars_result r;
  double a = std::fabs(v);
  if (a != 0 && (a >= 1e21 || a < 1e-12)) {
    r = std::to_chars(buf, end, v, std::chars_format::scientific);
    return std::string(buf, r.ptr);
  }
  r = std::to_chars(buf, end, v, std::chars_format::fixed);
  std::string s(buf, r.ptr);
  if (min_decimals > 0) {
    size_t dot = s.find('.');
    int have = dot == std::string::npos ? 0 : static_cast<int>(s.size() - dot - 1);
    if (dot == std::string::npos) s += '.';
    if (have < min_decimals) s.append(static_cast<size_t>(min_decimals - have), '0');
  }
  return s;
}

std::string format_decimal_rounded(double v, int decimals) {
  std::string s = format_decimal(v, decimals);
  if (decimals < 0) return s;
  const size_t dot = s.find('.');
  if (dot == std::string::npos || s.find('e') != std::string::npos ||
      static_cast<int>(s.size() - dot - 1) <= decimals)
    return s;
  char buf[64];
  const int n = std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return n > 0 && static_cast<size_t>(n) < sizeof buf ? std::string(buf, static_cast<size_t>(n))
                                                      : s;
}

}  // namespace capz

// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "io/text_number.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

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

namespace capz {

namespace {

// Python's repr layout of a number whose shortest digits and exponent are in `sci`
// (std::to_chars scientific: "-d.ddde+XX"): positional when -4 <= exponent < 16 (".0" added to
// an integral value), else "d.ddde-XX" with at least two exponent digits.
void append_python(const char* b, const char* e, std::string* out) {
  if (b < e && *b == '-') out->push_back(*b++);
  const char* ep = std::find(b, e, 'e');
  std::string digits;
  for (const char* p = b; p < ep; ++p)
    if (*p != '.') digits.push_back(*p);
  int exp10 = 0;
  std::from_chars(ep + 1 + (ep + 1 < e && ep[1] == '+'), e, exp10);
  const int nd = static_cast<int>(digits.size());
  if (exp10 >= -4 && exp10 < 16) {
    if (exp10 < 0) {
      out->append("0.");
      out->append(static_cast<size_t>(-exp10 - 1), '0');
      out->append(digits);
    } else if (nd <= exp10 + 1) {
      out->append(digits);
      out->append(static_cast<size_t>(exp10 + 1 - nd), '0');
      out->append(".0");
    } else {
      out->append(digits, 0, static_cast<size_t>(exp10 + 1));
      out->push_back('.');
      out->append(digits, static_cast<size_t>(exp10 + 1), std::string::npos);
    }
    return;
  }
  out->push_back(digits[0]);
  if (nd > 1) {
    out->push_back('.');
    out->append(digits, 1, std::string::npos);
  }
  char buf[16];
  std::snprintf(buf, sizeof buf, "e%c%02d", exp10 < 0 ? '-' : '+', exp10 < 0 ? -exp10 : exp10);
  out->append(buf);
}

}  // namespace

void append_styled(double v, bool single, uint8_t style, uint8_t precision, std::string* out) {
  char buf[400];
  std::to_chars_result r{};
  switch (style) {
    case kStyleShortest:
      r = single ? std::to_chars(buf, buf + sizeof buf, static_cast<float>(v))
                 : std::to_chars(buf, buf + sizeof buf, v);
      out->append(buf, r.ptr);
      return;
    case kStylePythonDouble:
    case kStylePythonShortest:
      r = single && style == kStylePythonShortest
              ? std::to_chars(buf, buf + sizeof buf, static_cast<float>(v),
                              std::chars_format::scientific)
              : std::to_chars(buf, buf + sizeof buf, v, std::chars_format::scientific);
      append_python(buf, r.ptr, out);
      return;
    default: {
      const char* f = style == kStyleG ? "%.*g" : style == kStyleE ? "%.*e" : "%.*f";
      const int n = std::snprintf(buf, sizeof buf, f, static_cast<int>(precision), v);
      if (n > 0 && static_cast<size_t>(n) < sizeof buf) {
        out->append(buf, static_cast<size_t>(n));
      } else {  // %f of a huge value: longer than buf
        std::vector<char> big(static_cast<size_t>(n) + 1);
        std::snprintf(big.data(), big.size(), f, static_cast<int>(precision), v);
        out->append(big.data(), static_cast<size_t>(n));
      }
    }
  }
}

}  // namespace capz

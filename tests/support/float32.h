// v rounded to float32, as a double: a generator's float32 coordinates. Through a volatile float
// because GCC 12 (Debian 12's) at -O2 and above drops the float conversions of cos(a) and sin(a)
// of one argument in one loop once it has folded them into one sincos: such "float32" values
// stayed float64 in Release builds and were float32 in the sanitizer builds (-O1), so a test's
// data differed between them.
#pragma once

namespace capz_test {

inline double float32_value(double v) {
  volatile float f = static_cast<float>(v);
  return f;
}

}  // namespace capz_test

// Natural order of file names: runs of digits compare by numeric value, so "frame_2" sorts
// before "frame_10". A run right after a digit and a '.' is a decimal fraction and compares digit
// by digit when that number has 9 digits or more, a timestamp ("1691031766.781" < ".8" < ".881" <
// ".98": timestamps printed with their trailing zeros dropped). Other characters compare by byte
// value. Equal numeric values with different leading (or, in a fraction, trailing) zeros ("01" vs
// "1") and otherwise equal names fall back to plain byte order, so the order is total and
// deterministic.
#pragma once

#include <algorithm>
#include <string>

namespace capz {

// Whether the digit run at i follows a timestamp's point: '.' after a run of 9 or more digits
// (seconds since 1970 have 10, milliseconds 13). "take1.10" keeps 10 a number after 9.
inline bool timestamp_fraction(const std::string& a, size_t i) {
  if (i < 2 || a[i - 1] != '.') return false;
  size_t k = i - 1, run = 0;
  while (k > 0 && a[k - 1] >= '0' && a[k - 1] <= '9') --k, ++run;
  return run >= 9;
}

inline bool natural_less(const std::string& a, const std::string& b) {
  size_t i = 0, j = 0;
  auto digit = [](char c) { return c >= '0' && c <= '9'; };
  while (i < a.size() && j < b.size()) {
    if (digit(a[i]) && digit(b[j])) {
      size_t ie = i, je = j;
      while (ie < a.size() && digit(a[ie])) ++ie;
      while (je < b.size() && digit(b[je])) ++je;
      // The names agree up to here, so a's characters before the run are b's too.
      if (timestamp_fraction(a, i)) {
        for (size_t k = 0; k < std::max(ie - i, je - j); ++k) {
          const char da = i + k < ie ? a[i + k] : '0', db = j + k < je ? b[j + k] : '0';
          if (da != db) return da < db;
        }
        i = ie;
        j = je;
        continue;
      }
      size_t is = i, js = j;  // skip leading zeros
      while (is + 1 < ie && a[is] == '0') ++is;
      while (js + 1 < je && b[js] == '0') ++js;
      if (ie - is != je - js) return ie - is < je - js;
      int c = a.compare(is, ie - is, b, js, je - js);
      if (c != 0) return c < 0;
      i = ie;
      j = je;
    } else {
      if (a[i] != b[j]) return static_cast<unsigned char>(a[i]) < static_cast<unsigned char>(b[j]);
      ++i;
      ++j;
    }
  }
  if ((a.size() - i) != (b.size() - j)) return a.size() - i < b.size() - j;
  return a < b;
}

}  // namespace capz

// Frame files written by hand for the scan readers' tests (tests/unit/test_scan_io.cpp, the CLI's
// tests/cli/test_cli_user_inputs.cpp): a file's bytes, and small PCD frames in the layouts other
// writers use.
#pragma once

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace capz_test {

inline void put(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream o(file, std::ios::binary);
  o << bytes;
}

// The bytes of float32 values (little-endian hosts).
inline std::string floats(const std::vector<float>& v) {
  std::string s(v.size() * 4, '\0');
  if (!v.empty()) std::memcpy(&s[0], v.data(), s.size());
  return s;
}

// A value's bytes appended to *s (little-endian hosts): a record of a .bin frame built field by
// field.
template <class T>
void append_bytes(std::string* s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  s->append(b, sizeof(T));
}

// An ASCII PCD frame: x y z, intensity (U1) and a 2-element field n (F4, COUNT 2).
inline std::string ascii_pcd(const std::vector<std::vector<std::string>>& rows) {
  std::string s =
      "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z intensity n\nSIZE 4 4 4 1 4\nTYPE F F F U F\n"
      "COUNT 1 1 1 1 2\nWIDTH " +
      std::to_string(rows.size()) + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " +
      std::to_string(rows.size()) + "\nDATA ascii\n";
  for (const auto& r : rows) {
    for (size_t i = 0; i < r.size(); ++i) s += (i ? " " : "") + r[i];
    s += "\n";
  }
  return s;
}

// A binary PCD frame of x y z float32 and a 4-byte padding field "_" (n points), its header
// without a VIEWPOINT line (as some writers leave it out); `lie_points` > 0: the count the
// header announces instead of n.
inline std::string binary_pcd(size_t n, float base, size_t lie_points = 0) {
  const size_t announced = lie_points ? lie_points : n;
  std::string s =
      "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z _\nSIZE 4 4 4 4\nTYPE F F F U\n"
      "COUNT 1 1 1 1\nWIDTH " +
      std::to_string(announced) + "\nHEIGHT 1\nPOINTS " + std::to_string(announced) +
      "\nDATA binary\n";
  std::vector<float> v;
  for (size_t p = 0; p < n; ++p) {
    v.insert(v.end(), {base + static_cast<float>(p), 2.0f * static_cast<float>(p), -1.5f});
    v.push_back(0.0f);
  }
  return s + floats(v);
}

}  // namespace capz_test

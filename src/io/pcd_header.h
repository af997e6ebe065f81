// PCD frame headers, parsed by capz independently of PCL, and the checks of what a header
// announces against the file's size, made before PCL is given the bytes (PCL trusts the counts
// and allocates what they say). Part of the decoder library.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace capz {

// What capz needs from a PCD header, parsed independently of PCL so the counts can be checked
// against the file size before PCL allocates anything.
struct PcdHeader {
  std::vector<std::string> fields;
  std::vector<int> sizes;
  std::vector<char> types;
  std::vector<uint64_t> counts;
  uint64_t width = 0, height = 1, points = 0;
  std::string data;         // "ascii", "binary", "binary_compressed"
  size_t data_idx = 0;      // offset of the body
  uint64_t point_step = 0;  // bytes per point (sum size * count)
  uint64_t values_per_point = 0;
  std::string version;            // VERSION's value ("0.7"); empty when the file has none
  std::vector<double> viewpoint;  // VIEWPOINT's 7 values; empty when absent
};

// Parses the header of the PCD file `bytes` (`name` for messages) and checks that the body can
// hold the points it announces. Throws Error(kCorrupt), or kNotOurFormat for an unknown line.
PcdHeader parse_header(const std::vector<uint8_t>& bytes, const std::string& name);
// The same without the body check: `bytes` may be the file's first bytes only (at least through
// the DATA line). What a folder's frame counts are read from when it is opened.
PcdHeader parse_header_text(const std::vector<uint8_t>& bytes, const std::string& name);

// The body-size check parse_header makes, for a file of `file_size` bytes of which `bytes` are
// the first (through the DATA line and, for binary_compressed, the 8 bytes of sizes after it):
// what a folder's frames are checked with when it is opened, before anything is allocated for
// the points their headers announce. Throws Error(kCorrupt).
void check_body_fits(const std::vector<uint8_t>& bytes, uint64_t file_size, const PcdHeader& h,
                     const std::string& name);

// PCL's ASCII body reader turns a bad token or a short line into zeros without a word: checks
// that every non-blank line after the header holds exactly values_per_point numbers and that
// there are exactly `points` such lines. Throws Error(kCorrupt).
void check_ascii_body(const std::vector<uint8_t>& bytes, const PcdHeader& h,
                      const std::string& name);

}  // namespace capz

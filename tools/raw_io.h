// Benchmark helpers' shared file formats (tools/ only; not part of the library).
//
// Raw positions (".f32"): frames x points x 3 IEEE float32, little-endian, frame-major
//   (value i at byte 4*i, i = (f * points + p) * 3 + axis), no header: the shape travels in a
//   JSON sidecar or on the command line. Gap samples hold filled values (see fill_gaps()).
// Mask (".mask"): frames x points bytes, 1 = measured, 0 = gap.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/take.h"
#include "core/atomic_file.h"

namespace capz_tools {

// Writes `n` doubles as float32 LE (rounded to nearest) through an atomic output file.
inline void write_f32(const std::string& path, const double* v, size_t n) {
  capz::AtomicFile out(path, true);
  std::vector<uint8_t> buf;
  const size_t kChunk = size_t{1} << 16;
  for (size_t i = 0; i < n; i += kChunk) {
    size_t m = std::min(kChunk, n - i);
    buf.resize(m * 4);
    for (size_t k = 0; k < m; ++k) {
      float f = static_cast<float>(v[i + k]);
      uint32_t u;
      std::memcpy(&u, &f, 4);
      for (int b = 0; b < 4; ++b) buf[k * 4 + b] = static_cast<uint8_t>(u >> (8 * b));
    }
    out.write(buf.data(), buf.size());
  }
  out.commit();
}

// Reads a whole .f32 file; throws capz::Error(kCorrupt) unless it holds exactly `expect` values
// (expect == 0: any multiple of 4 bytes).
inline std::vector<double> read_f32(const std::string& path, size_t expect) {
  std::vector<uint8_t> bytes = capz::read_file(path);
  if (bytes.size() % 4 != 0 || (expect != 0 && bytes.size() != expect * 4))
    capz::fail(capz::ErrorCode::kCorrupt, path,
               "raw float32 file holds " + std::to_string(bytes.size()) + " bytes, expected " +
                   std::to_string(expect * 4));
  std::vector<double> v(bytes.size() / 4);
  for (size_t i = 0; i < v.size(); ++i) {
    uint32_t u = 0;
    for (int b = 0; b < 4; ++b) u |= static_cast<uint32_t>(bytes[i * 4 + b]) << (8 * b);
    float f;
    std::memcpy(&f, &u, 4);
    v[i] = f;
  }
  return v;
}

inline void write_bytes(const std::string& path, const std::vector<uint8_t>& v) {
  capz::AtomicFile out(path, true);
  out.write(v);
  out.commit();
}

// Fills gap samples in place for coding: a gap takes the point's previous valid position; a
// leading gap takes the first valid one; a point never valid stays at 0. Only xyz changes.
inline void fill_gaps(capz::Take* t) {
  for (size_t p = 0; p < t->points; ++p) {
    long first = -1;
    for (size_t f = 0; f < t->frames; ++f)
      if (t->is_valid(f, p)) {
        first = static_cast<long>(f);
        break;
      }
    double last[3] = {0, 0, 0};
    if (first >= 0) std::memcpy(last, t->at(static_cast<size_t>(first), p), sizeof last);
    for (size_t f = 0; f < t->frames; ++f) {
      double* x = t->at(f, p);
      if (t->is_valid(f, p) && std::isfinite(x[0]) && std::isfinite(x[1]) && std::isfinite(x[2]))
        std::memcpy(last, x, sizeof last);
      else
        std::memcpy(x, last, sizeof last);
    }
  }
}

inline bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// An original for the tools: any input capz reads, or a raw .f32 of frames x points (then
// `frames` and `points` must be given; `mask_path` empty = every sample valid).
inline capz::Take load_input(const std::string& path, size_t frames, size_t points,
                             const std::string& mask_path) {
  if (!ends_with(path, ".f32")) return capz::read_take(path);
  if (frames == 0 || points == 0)
    capz::fail(capz::ErrorCode::kUsage, path, "a raw .f32 input needs its shape (--shape F N)");
  capz::Take a;
  a.resize(frames, points);
  a.source = path;
  a.xyz = read_f32(path, frames * points * 3);
  if (mask_path.empty()) {
    std::fill(a.valid.begin(), a.valid.end(), 1);
  } else {
    a.valid = capz::read_file(mask_path);
    if (a.valid.size() != frames * points)
      capz::fail(capz::ErrorCode::kCorrupt, mask_path, "mask size does not match the shape");
  }
  return a;
}

// Minimal JSON string escaping for labels and paths.
inline std::string json_str(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    unsigned char u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      o += '\\';
      o += c;
    } else if (u < 0x20) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", u);
      o += b;
    } else {
      o += c;
    }
  }
  return o + "\"";
}

inline std::string json_num(double v) {
  if (!std::isfinite(v)) return v > 0 ? "1e999" : (v < 0 ? "-1e999" : "null");
  char b[40];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}

}  // namespace capz_tools

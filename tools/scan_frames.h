// PCD sweeps for the scan tools (scan_geometry_bits, scan_octree_bits): a frame's x y z as
// doubles (NaN kept), its ring / channel and distance fields when present; capz reads the files.
#pragma once

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/take.h"
#include "io/pcd_folder.h"

namespace scan_tools {

struct Frame {
  std::vector<double> xyz;      // points x 3, NaN kept
  std::vector<uint32_t> ring;   // the ring / channel field, or empty
  std::vector<float> distance;  // the distance / range field, or empty
};

// A field's value as a double (type F, U or I of 1, 2, 4 or 8 bytes), from its element's bytes.
inline double field_value(const capz::PointAttribute& a, const uint8_t* p) {
  const auto get = [p](auto v) {
    std::memcpy(&v, p, sizeof v);
    return static_cast<double>(v);
  };
  if (a.type == 'F') return a.size == 8 ? get(double{}) : get(float{});
  if (a.type == 'U')
    return a.size == 1   ? get(uint8_t{})
           : a.size == 2 ? get(uint16_t{})
           : a.size == 4 ? get(uint32_t{})
                         : get(uint64_t{});
  return a.size == 1   ? get(int8_t{})
         : a.size == 2 ? get(int16_t{})
         : a.size == 4 ? get(int32_t{})
                       : get(int64_t{});
}

// One PCD file, read by capz (capz::read_take: a one-frame take); a gap's x y z are NaN.
inline Frame read_frame(const std::string& path, bool use_ring) {
  const capz::Take t = capz::read_take(path);
  const size_t n = t.total_points();
  Frame fr;
  fr.xyz = t.xyz;
  for (size_t i = 0; i < n; ++i)
    if (!t.valid[i]) fr.xyz[3 * i] = fr.xyz[3 * i + 1] = fr.xyz[3 * i + 2] = NAN;
  for (const capz::PointAttribute& a : t.attributes) {
    const bool ring = use_ring && (a.name == "ring" || a.name == "channel" || a.name == "laser_id");
    const bool distance = a.name == "distance" || a.name == "range";
    if (!ring && !distance) continue;
    const size_t step = a.bytes_per_point();  // the first element of each point
    if (ring) fr.ring.resize(n);
    if (distance) fr.distance.resize(n);
    for (size_t i = 0; i < n; ++i) {
      const double v = field_value(a, a.data.data() + i * step);
      if (ring) fr.ring[i] = static_cast<uint32_t>(v);
      if (distance) fr.distance[i] = static_cast<float>(v);
    }
  }
  return fr;
}

// The frame files of a folder in name order (capz's own listing), or a single file itself.
inline std::vector<std::string> list_frames(const std::string& path) {
  struct stat st;
  if (stat(path.c_str(), &st) != 0) return {};
  if (!S_ISDIR(st.st_mode)) return {path};
  std::vector<std::string> out;
  for (const std::string& name : capz::list_pcd_frames(path)) out.push_back(path + "/" + name);
  return out;
}

}  // namespace scan_tools

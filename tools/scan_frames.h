// PCD sweeps for the scan tools (scan_geometry_bits, scan_octree_bits): a frame's x y z as
// doubles (NaN kept), its ring / channel and distance fields when present; PCL reads the files.
#pragma once

#include <dirent.h>
#include <pcl/PCLPointCloud2.h>
#include <pcl/io/pcd_io.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "capz/error.h"

namespace scan_tools {

struct Frame {
  std::vector<double> xyz;      // points x 3, NaN kept
  std::vector<uint32_t> ring;   // the ring / channel field, or empty
  std::vector<float> distance;  // the distance / range field, or empty
};

// A field's value as a double (any PCD type), from a point's bytes.
inline double field_value(const pcl::PCLPointField& f, const uint8_t* p) {
  p += f.offset;
  switch (f.datatype) {
    case pcl::PCLPointField::INT8:
      return *reinterpret_cast<const int8_t*>(p);
    case pcl::PCLPointField::UINT8:
      return *p;
    case pcl::PCLPointField::INT16: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case pcl::PCLPointField::UINT16: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case pcl::PCLPointField::INT32: {
      int32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case pcl::PCLPointField::UINT32: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case pcl::PCLPointField::FLOAT32: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case pcl::PCLPointField::FLOAT64: {
      double v;
      std::memcpy(&v, p, 8);
      return v;
    }
    default:
      return NAN;
  }
}

inline Frame read_frame(const std::string& path, bool use_ring) {
  pcl::PCLPointCloud2 c;
  if (pcl::io::loadPCDFile(path, c) != 0)
    throw capz::Error(capz::ErrorCode::kIo, path + ": unreadable");
  const pcl::PCLPointField* f[5] = {nullptr, nullptr, nullptr, nullptr, nullptr};
  for (const auto& fd : c.fields) {
    if (fd.name == "x") f[0] = &fd;
    if (fd.name == "y") f[1] = &fd;
    if (fd.name == "z") f[2] = &fd;
    if (use_ring && (fd.name == "ring" || fd.name == "channel" || fd.name == "laser_id"))
      f[3] = &fd;
    if (fd.name == "distance" || fd.name == "range") f[4] = &fd;
  }
  if (!f[0] || !f[1] || !f[2]) throw capz::Error(capz::ErrorCode::kIo, path + ": no x y z");
  Frame fr;
  const size_t n = size_t{c.width} * c.height;
  fr.xyz.resize(3 * n);
  if (f[3]) fr.ring.resize(n);
  if (f[4]) fr.distance.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* p = c.data.data() + i * c.point_step;
    for (int a = 0; a < 3; ++a) fr.xyz[3 * i + a] = field_value(*f[a], p);
    if (f[3]) fr.ring[i] = static_cast<uint32_t>(field_value(*f[3], p));
    if (f[4]) fr.distance[i] = static_cast<float>(field_value(*f[4], p));
  }
  return fr;
}

inline std::vector<std::string> list_frames(const std::string& path) {
  struct stat st;
  if (stat(path.c_str(), &st) != 0) return {};
  if (!S_ISDIR(st.st_mode)) return {path};
  std::vector<std::string> out;
  if (DIR* d = opendir(path.c_str())) {
    while (dirent* e = readdir(d)) {
      const std::string n = e->d_name;
      if (n.size() > 4 && n.substr(n.size() - 4) == ".pcd") out.push_back(path + "/" + n);
    }
    closedir(d);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace scan_tools

// PCL's OctreePointCloudCompression as a peer, one point cloud per frame (I-frames every
// --iframe frames, P-frames between, as PCL streams them). The only file here that includes
// PCL headers.
//
//   capz_octree encode IN.f32 FRAMES POINTS OUT.oct --point-res R [--octree-res O] [--iframe K]
//   capz_octree decode IN.oct FRAMES OUT.pts
//   capz_octree match  ORIG.f32 FRAMES POINTS IN.pts OUT.f32
//
// IN.f32/ORIG.f32: raw positions (raw_io.h). PCL reorders points (octree order) and may change
// their number, so decode writes OUT.pts: per frame a u32 LE count then count x 3 float32 LE.
// match pairs every original point with its nearest decoded point of the same frame (kd-tree)
// and writes those as a raw .f32 in the original order, so capz_metrics can compare it: the
// error it reports is the nearest-neighbour error, a lower bound of any true correspondence
// error. match prints JSON: decoded point count and the largest decoded-to-original distance.
#include <pcl/compression/octree_pointcloud_compression.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "capz/error.h"
#include "coding/bytes.h"
#include "raw_io.h"

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using Compression = pcl::io::OctreePointCloudCompression<pcl::PointXYZ>;

Cloud::Ptr frame_cloud(const std::vector<double>& xyz, size_t f, size_t points) {
  Cloud::Ptr c(new Cloud);
  c->resize(points);
  for (size_t p = 0; p < points; ++p) {
    const double* x = &xyz[(f * points + p) * 3];
    (*c)[p] =
        pcl::PointXYZ(static_cast<float>(x[0]), static_cast<float>(x[1]), static_cast<float>(x[2]));
  }
  return c;
}

void encode(const std::string& in, size_t frames, size_t points, const std::string& out,
            double point_res, double octree_res, unsigned iframe) {
  std::vector<double> xyz = capz_tools::read_f32(in, frames * points * 3);
  Compression enc(pcl::io::MANUAL_CONFIGURATION, false, point_res, octree_res, false, iframe,
                  false);
  std::ostringstream s;
  for (size_t f = 0; f < frames; ++f) enc.encodePointCloud(frame_cloud(xyz, f, points), s);
  std::string bytes = s.str();
  capz_tools::write_bytes(out, std::vector<uint8_t>(bytes.begin(), bytes.end()));
}

void decode(const std::string& in, size_t frames, const std::string& out) {
  std::vector<uint8_t> data = capz::read_file(in);
  std::istringstream s(std::string(data.begin(), data.end()));
  Compression dec(pcl::io::MANUAL_CONFIGURATION, false);
  capz::ByteWriter w;
  for (size_t f = 0; f < frames; ++f) {
    if (s.peek() == std::char_traits<char>::eof())  // PCL would block or misread past the end
      capz::fail(capz::ErrorCode::kCorrupt, in, "stream ends before frame " + std::to_string(f));
    Cloud::Ptr c(new Cloud);
    dec.decodePointCloud(s, c);
    w.u32(static_cast<uint32_t>(c->size()));
    for (const auto& pt : *c) {
      w.f32(pt.x);
      w.f32(pt.y);
      w.f32(pt.z);
    }
  }
  capz_tools::write_bytes(out, w.buffer());
}

void match(const std::string& orig, size_t frames, size_t points, const std::string& in,
           const std::string& out) {
  std::vector<double> xyz = capz_tools::read_f32(orig, frames * points * 3);
  std::vector<uint8_t> data = capz::read_file(in);
  capz::ByteReader r(data.data(), data.size(), in);
  std::vector<double> recon(xyz.size());
  size_t decoded = 0;
  double back_max = 0;  // largest distance from a decoded point to its nearest original
  for (size_t f = 0; f < frames; ++f) {
    size_t n = r.u32();
    if (n > r.remaining() / 12) capz::fail(capz::ErrorCode::kCorrupt, in, "bad point count");
    Cloud::Ptr c(new Cloud);
    c->resize(n);
    for (size_t i = 0; i < n; ++i) {
      float x = r.f32(), y = r.f32(), z = r.f32();
      (*c)[i] = pcl::PointXYZ(x, y, z);
    }
    decoded += n;
    if (n == 0) capz::fail(capz::ErrorCode::kCorrupt, in, "a frame decoded to no points");
    pcl::KdTreeFLANN<pcl::PointXYZ> tree;
    tree.setInputCloud(c);
    Cloud::Ptr o = frame_cloud(xyz, f, points);
    pcl::KdTreeFLANN<pcl::PointXYZ> otree;
    otree.setInputCloud(o);
    std::vector<int> idx(1);
    std::vector<float> d2(1);
    for (size_t p = 0; p < points; ++p) {
      tree.nearestKSearch((*o)[p], 1, idx, d2);
      const auto& q = (*c)[static_cast<size_t>(idx[0])];
      double* y = &recon[(f * points + p) * 3];
      y[0] = q.x;
      y[1] = q.y;
      y[2] = q.z;
    }
    for (size_t i = 0; i < n; ++i) {
      otree.nearestKSearch((*c)[i], 1, idx, d2);
      back_max = std::max(back_max, std::sqrt(static_cast<double>(d2[0])));
    }
  }
  capz_tools::write_f32(out, recon.data(), recon.size());
  std::printf("{\"decoded_points\": %zu, \"original_points\": %zu, \"back_max\": %s}\n", decoded,
              frames * points, capz_tools::json_num(back_max).c_str());
}

int usage() {
  std::fprintf(stderr,
               "usage: capz_octree encode IN.f32 FRAMES POINTS OUT.oct --point-res R "
               "[--octree-res O] [--iframe K]\n"
               "       capz_octree decode IN.oct FRAMES OUT.pts\n"
               "       capz_octree match ORIG.f32 FRAMES POINTS IN.pts OUT.f32\n");
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage();
  std::string mode = argv[1];
  try {
    if (mode == "encode" && argc >= 6) {
      double point_res = 0, octree_res = 0;
      unsigned iframe = 30;
      for (int i = 6; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--point-res" && i + 1 < argc) {
          point_res = std::stod(argv[++i]);
        } else if (a == "--octree-res" && i + 1 < argc) {
          octree_res = std::stod(argv[++i]);
        } else if (a == "--iframe" && i + 1 < argc) {
          iframe = static_cast<unsigned>(std::stoul(argv[++i]));
        } else {
          return usage();
        }
      }
      if (!(point_res > 0)) return usage();
      if (!(octree_res > 0)) octree_res = 8 * point_res;
      encode(argv[2], std::stoul(argv[3]), std::stoul(argv[4]), argv[5], point_res, octree_res,
             iframe);
    } else if (mode == "decode" && argc == 5) {
      decode(argv[2], std::stoul(argv[3]), argv[4]);
    } else if (mode == "match" && argc == 7) {
      match(argv[2], std::stoul(argv[3]), std::stoul(argv[4]), argv[5], argv[6]);
    } else {
      return usage();
    }
  } catch (const capz::Error& e) {
    std::fprintf(stderr, "capz_octree: %s\n", e.what());
    return static_cast<int>(e.code());
  }
  return 0;
}

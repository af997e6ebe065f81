// PCL's OctreePointCloudCompression as a peer, one point cloud per frame (I-frames every
// --iframe frames, P-frames between, as PCL streams them).
//
//   capz_octree encode IN.f32 FRAMES POINTS OUT.oct --point-res R [--octree-res O] [--iframe K]
//   capz_octree decode IN.oct FRAMES OUT.pts
//   capz_octree match  ORIG.f32 FRAMES POINTS IN.pts OUT.f32
//   capz_octree pcd    DIR --max-error B [--color] [--iframe K]
//
// IN.f32/ORIG.f32: raw positions (raw_io.h). PCL reorders points (octree order) and may change
// their number, so decode writes OUT.pts: per frame a u32 LE count then count x 3 float32 LE.
// match pairs every original point with its nearest decoded point of the same frame (kd-tree)
// and writes those as a raw .f32 in the original order, so capz_metrics can compare it: the
// error it reports is the nearest-neighbour error, a lower bound of any true correspondence
// error. match prints JSON: decoded point count and the largest decoded-to-original distance.
//
// pcd (issue 15) runs the whole round trip on a PCD folder in one process and prints JSON: the
// points with finite x y z of each frame (PCL's coder drops NaN points and the organized layout;
// their count is reported), with --color as pcl::PointXYZRGBA from the `rgb` / `rgba` field
// (colour coded at 8 bits a channel, PCL's finest; PCL codes r g b, not alpha), streamed through
// one encoder; point resolution R = B, then 0.999 B, 0.99 B, ... 0.5 B until every original point
// has a decoded point within B per coordinate (PCL truncates each coordinate to its R grid in the
// leaf, so its error reaches R), octree resolution 16 R. Errors by nearest decoded point of the
// same frame (per-coordinate distance, tools/cloud_match.h), colour compared on that pairing.
#include <pcl/compression/octree_pointcloud_compression.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <sstream>
#include <string>
#include <type_traits>

#include "capz/error.h"
#include "capz/io.h"
#include "cloud_match.h"
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

// One round trip of a PCD take through PCL's coder at point resolution `res`.
struct PcdRun {
  size_t bytes = 0, kept = 0, decoded = 0, colour_exact = 0, alpha_differs = 0;
  double pos_max = 0, pos_max_euclid = 0, colour_max = 0, enc_s = 0, dec_s = 0;
  bool colour_multiset_exact = true;  // every frame's r g b values came back, in some order
};

// Frame f's valid points with finite x y z as a PCL cloud, with their rgb / rgba for a colour
// point type.
template <typename PointT>
typename pcl::PointCloud<PointT>::Ptr frame_points(const capz::Take& t,
                                                   const capz::PointAttribute* rgb, size_t f) {
  using C = pcl::PointCloud<PointT>;
  constexpr bool kColour = std::is_same<PointT, pcl::PointXYZRGBA>::value;
  typename C::Ptr c(new C);
  for (size_t p = 0; p < t.points; ++p) {
    const double* x = t.at(f, p);
    if (!t.is_valid(f, p) || !std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
      continue;
    PointT q;
    q.x = static_cast<float>(x[0]);
    q.y = static_cast<float>(x[1]);
    q.z = static_cast<float>(x[2]);
    if constexpr (kColour) std::memcpy(&q.rgba, &rgb->data[(f * t.points + p) * 4], 4);
    c->push_back(q);
  }
  return c;
}

// Adds to run the colour error of original point q: the closest colour among the decoded points
// d[ties] (coincident points at its nearest distance), and whether all of them differ in alpha.
template <typename PointT>
void add_colour_error(const PointT& q, const pcl::PointCloud<PointT>& d,
                      const std::vector<uint32_t>& ties, PcdRun* run) {
  int best = 256;
  bool alpha = true;
  for (uint32_t k : ties) {
    const PointT& c = d[k];
    int dr = std::abs(int{q.r} - int{c.r}), dg = std::abs(int{q.g} - int{c.g}),
        db = std::abs(int{q.b} - int{c.b});
    best = std::min(best, std::max({dr, dg, db}));
    alpha = alpha && q.a != c.a;
  }
  run->colour_max = std::max(run->colour_max, static_cast<double>(best));
  run->colour_exact += best == 0;
  run->alpha_differs += alpha;
}

// Adds to run one frame's errors: each original point's distance to its nearest decoded point
// (per coordinate and euclidean) and, for a colour point type, the colours' multiset and error.
template <typename PointT>
void compare_frame(const pcl::PointCloud<PointT>& orig, const pcl::PointCloud<PointT>& d,
                   double bound, const std::string& source, PcdRun* run) {
  using C = pcl::PointCloud<PointT>;
  constexpr bool kColour = std::is_same<PointT, pcl::PointXYZRGBA>::value;
  std::vector<float> back(d.size() * 3);
  for (size_t i = 0; i < d.size(); ++i) {
    back[i * 3] = d[i].x;
    back[i * 3 + 1] = d[i].y;
    back[i * 3 + 2] = d[i].z;
  }
  capz_tools::CloudGrid grid(back, bound);
  if constexpr (kColour) {  // the colours of the frame as a multiset (r g b, not alpha)
    auto sorted = [](const C& c) {
      std::vector<uint32_t> v;
      for (const PointT& q : c) v.push_back(q.rgba & 0xffffffu);
      std::sort(v.begin(), v.end());
      return v;
    };
    if (sorted(d) != sorted(orig)) run->colour_multiset_exact = false;
  }
  std::vector<uint32_t> ties;
  for (const PointT& q : orig) {
    float xyz[3] = {q.x, q.y, q.z};
    double e = 0;
    long j = grid.nearest(xyz, &e, &ties);
    if (j < 0) capz::fail(capz::ErrorCode::kInternal, source, "PCL decoded no points");
    double s2 = 0;
    for (int a = 0; a < 3; ++a) s2 += (back[j * 3 + a] - xyz[a]) * (back[j * 3 + a] - xyz[a]);
    run->pos_max = std::max(run->pos_max, e);
    run->pos_max_euclid = std::max(run->pos_max_euclid, std::sqrt(s2));
    if constexpr (kColour) add_colour_error(q, d, ties, run);
  }
}

// Codes and decodes every frame of t through PCL's coder at point resolution res, the errors
// measured against bound.
template <typename PointT>
PcdRun pcd_round_trip(const capz::Take& t, const capz::PointAttribute* rgb, double bound,
                      double res, unsigned iframe) {
  using C = pcl::PointCloud<PointT>;
  constexpr bool kColour = std::is_same<PointT, pcl::PointXYZRGBA>::value;
  pcl::io::OctreePointCloudCompression<PointT> enc(pcl::io::MANUAL_CONFIGURATION, false, res,
                                                   16 * res, false, iframe, kColour, 8);
  pcl::io::OctreePointCloudCompression<PointT> dec(pcl::io::MANUAL_CONFIGURATION, false);
  PcdRun run;
  std::vector<typename C::Ptr> originals;
  std::stringstream s;
  std::clock_t c0 = std::clock();
  for (size_t f = 0; f < t.frames; ++f) {
    typename C::Ptr c = frame_points<PointT>(t, rgb, f);
    run.kept += c->size();
    if (c->empty()) capz::fail(capz::ErrorCode::kUsage, t.source, "a frame has no finite point");
    enc.encodePointCloud(c, s);
    originals.push_back(c);
  }
  std::clock_t c1 = std::clock();
  run.bytes = s.str().size();
  s.seekg(0);
  for (size_t f = 0; f < t.frames; ++f) {
    if (s.peek() == std::char_traits<char>::eof())
      capz::fail(capz::ErrorCode::kInternal, t.source,
                 "PCL stream ends before frame " + std::to_string(f));
    typename C::Ptr d(new C);
    std::clock_t d0 = std::clock();
    dec.decodePointCloud(s, d);
    run.dec_s += static_cast<double>(std::clock() - d0) / CLOCKS_PER_SEC;
    run.decoded += d->size();
    compare_frame(*originals[f], *d, bound, t.source, &run);
  }
  run.enc_s = static_cast<double>(c1 - c0) / CLOCKS_PER_SEC;
  return run;
}

void pcd(const std::string& dir, double bound, bool colour, unsigned iframe) {
  capz::Take t = capz::read_take(dir);
  const capz::PointAttribute* rgb = nullptr;
  for (const auto& a : t.attributes)
    if ((a.name == "rgb" || a.name == "rgba") && a.size == 4 && a.count == 1) rgb = &a;
  if (colour && rgb == nullptr)
    capz::fail(capz::ErrorCode::kUsage, dir, "--color needs an rgb or rgba field of 4 bytes");
  double res = bound;
  PcdRun run;
  for (double shrink : {1.0, 0.999, 0.99, 0.95, 0.9, 0.8, 0.7, 0.5}) {
    res = bound * shrink;
    run = colour ? pcd_round_trip<pcl::PointXYZRGBA>(t, rgb, bound, res, iframe)
                 : pcd_round_trip<pcl::PointXYZ>(t, nullptr, bound, res, iframe);
    if (run.pos_max <= bound) break;
  }
  std::printf(
      "{\"frames\": %zu, \"points\": %zu, \"kept_points\": %zu, \"decoded_points\": %zu,"
      " \"organized_dropped\": %s, \"bytes\": %zu, \"point_res\": %s, \"bound\": %s,"
      " \"pos_max_abs\": %s, \"pos_max_euclid\": %s, \"colour\": %s,"
      " \"colour_max_abs\": %s, \"colour_exact_points\": %zu,"
      " \"colour_multiset_exact\": %s, \"alpha_differs_points\": %zu, \"encode_s\": %.3f,"
      " \"decode_s\": %.3f}\n",
      t.frames, t.frames * t.points, run.kept, run.decoded,
      t.pcd && t.pcd->height > 1 ? "true" : "false", run.bytes, capz_tools::json_num(res).c_str(),
      capz_tools::json_num(bound).c_str(), capz_tools::json_num(run.pos_max).c_str(),
      capz_tools::json_num(run.pos_max_euclid).c_str(), colour ? "true" : "false",
      capz_tools::json_num(run.colour_max).c_str(), run.colour_exact,
      run.colour_multiset_exact ? "true" : "false", run.alpha_differs, run.enc_s, run.dec_s);
}

int usage() {
  std::fprintf(stderr,
               "usage: capz_octree encode IN.f32 FRAMES POINTS OUT.oct --point-res R "
               "[--octree-res O] [--iframe K]\n"
               "       capz_octree decode IN.oct FRAMES OUT.pts\n"
               "       capz_octree match ORIG.f32 FRAMES POINTS IN.pts OUT.f32\n"
               "       capz_octree pcd DIR --max-error B [--color] [--iframe K]\n");
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
    } else if (mode == "pcd" && argc >= 3) {
      double bound = 0;
      bool colour = false;
      unsigned iframe = 30;
      for (int i = 3; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--max-error" && i + 1 < argc) {
          bound = std::stod(argv[++i]);
        } else if (a == "--color") {
          colour = true;
        } else if (a == "--iframe" && i + 1 < argc) {
          iframe = static_cast<unsigned>(std::stoul(argv[++i]));
        } else {
          return usage();
        }
      }
      if (!(bound > 0)) return usage();
      pcd(argv[2], bound, colour, iframe);
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

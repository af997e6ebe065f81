// PCL's OctreePointCloudCompression as a scan benchmark peer (tools/scan_bench; issue #37).
// Links PCL's compression module only; no capz code.
//
//   scan_pcl_octree IN.frames POINT_RES IFRAME OUT.frames
//
// Codes the frames of IN.frames (frames_io.h) as one PCL stream (x y z, no colour, an I-frame
// every IFRAME frames and P-frames between, as PCL streams them), point resolution POINT_RES and
// octree resolution 16 x POINT_RES; then decodes the stream and writes the decoded frames to
// OUT.frames. PCL reorders the points (octree order), so the harness measures the error by the
// nearest decoded point. Prints JSON: stream bytes and the CPU seconds of the encode and decode
// loops (file reading excluded).
#include <pcl/compression/octree_pointcloud_compression.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <sstream>
#include <string>

#include "frames_io.h"

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using Compression = pcl::io::OctreePointCloudCompression<pcl::PointXYZ>;

Cloud::Ptr to_cloud(const scan_bench::Frame& fr) {
  Cloud::Ptr c(new Cloud);
  c->resize(fr.size() / 3);
  for (size_t p = 0; p < c->size(); ++p)
    (*c)[p] = pcl::PointXYZ(fr[p * 3], fr[p * 3 + 1], fr[p * 3 + 2]);
  return c;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: scan_pcl_octree IN.frames POINT_RES IFRAME OUT.frames\n");
    return 2;
  }
  try {
    const auto frames = scan_bench::read_frames(argv[1]);
    const double res = std::atof(argv[2]);
    const unsigned iframe = static_cast<unsigned>(std::atoi(argv[3]));
    std::vector<Cloud::Ptr> clouds;
    for (const auto& fr : frames) clouds.push_back(to_cloud(fr));

    const double t0 = scan_bench::cpu_seconds();
    Compression enc(pcl::io::MANUAL_CONFIGURATION, false, res, 16 * res, false, iframe, false);
    std::stringstream s;
    for (const auto& c : clouds) enc.encodePointCloud(c, s);
    const double t1 = scan_bench::cpu_seconds();
    const size_t bytes = s.str().size();

    Compression dec(pcl::io::MANUAL_CONFIGURATION, false);
    std::vector<scan_bench::Frame> out(frames.size());
    for (auto& fr : out) {
      if (s.peek() == std::char_traits<char>::eof())
        throw std::runtime_error("stream ends before the last frame");
      Cloud::Ptr c(new Cloud);
      dec.decodePointCloud(s, c);
      fr.reserve(c->size() * 3);
      for (const auto& p : *c) fr.insert(fr.end(), {p.x, p.y, p.z});
    }
    const double t2 = scan_bench::cpu_seconds();
    scan_bench::finish(argv[4], out, bytes, t1 - t0, t2 - t1);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "scan_pcl_octree: %s\n", e.what());
    return 1;
  }
  return 0;
}

// The scan encoder's frames too large to record (ScanWorkspace::record_limit): their spherical
// trials are only counted and the one kept is coded again, which gives the payload that
// recording and replaying gives (scan_encode.cpp's code_chosen).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "capz/io.h"
#include "coding/scan_geometry.h"
#include "scan_geometry_expect.h"

namespace capz {
namespace {

// g's payload with every frame recorded and with none, each decoded back to g.
void expect_same_payload(const ScanGeometry& g, const ScanHints& h, const std::string& what) {
  ScanWorkspace recorded, counted;
  counted.record_limit = 0;
  const std::vector<uint8_t> a = encode_scan_geometry(g, h, &recorded);
  const std::vector<uint8_t> b = encode_scan_geometry(g, h, &counted);
  EXPECT_EQ(a, b) << what;
  expect_same(g, decode_scan_geometry(b.data(), b.size(), what));
}

// The frames of t as a window of integers at per_metre a metre (sweep_geometry's, frame by frame).
ScanGeometry frames_of(const Take& t, double per_metre, ScanHints* h) {
  ScanGeometry g = sweep_geometry(t, per_metre, h);
  g.counts.clear();
  for (size_t f = 0; f < t.frames; ++f)
    g.counts.push_back(static_cast<uint32_t>(t.frame_points(f)));
  return g;
}

TEST(ScanRecords, GivenFramesNotRecordedThenTheSamePayloadAsRecorded) {
  // A spinning sensor's sweep whose lasers fire rings upward (the ring walk's trial), and one
  // whose firing order is a permutation of the rings (ring pairs'), from quantum_sweep.
  for (int order : {0, 1}) {
    ScanHints h;
    const ScanGeometry g = quantum_sweep(
        &h, 7u + static_cast<unsigned>(order), 16, 0.05,
        [](int, int, const auto& draw) { return static_cast<int>(draw() * 1000); },
        [&](int s, int64_t a, int, int v) {
          const int k = order == 0 ? s : (5 * s) % 16;
          return SweepLaser{static_cast<uint32_t>(k), a,
                            (-15.0 + 2.0 * k) * 3.141592653589793 / 180,
                            5 + 0.01 * ((v + 37 * k) % 400)};
        });
    expect_same_payload(g, h, "quantum sweep " + std::to_string(order));
  }
  // Real sweeps, at 1 mm and 1 cm: the Helios 16P cut (its dual returns, four frames of their own
  // counts), lidar_small (NaN gaps, six frames) and turn_small (turns).
  for (const char* name : {"scan_small", "lidar_small", "turn_small"})
    for (double per_metre : {500.0, 50.0}) {
      ScanHints h;
      const ScanGeometry g =
          frames_of(read_take(std::string(CAPZ_REPO_DATA) + "/" + name), per_metre, &h);
      expect_same_payload(g, h, std::string(name) + " at " + std::to_string(per_metre));
    }
}

}  // namespace
}  // namespace capz

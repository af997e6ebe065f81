// The second of x y of a spherical frame (docs/FORMAT.md "Scan geometry payload", step 4 and
// flags_f bit 6): from the azimuth where the columns' azimuths are exact, from the range's
// hypotenuse where they are not; the encoder chooses per frame, exactly; bit 6 without bit 2 is
// corrupt.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "capz/error.h"
#include "coding/scan_geometry.h"
#include "coding/scan_shared.h"

namespace capz {
namespace {

// Two sweeps of a spinning sensor on a 1 mm grid (step 0.002 m), ranges in whole 4 mm steps
// (the encoder finds them: range units). `jitter`: each firing's azimuth off its column by up to
// that many column steps either way (0: every azimuth on its column).
ScanGeometry sweeps(double jitter, ScanHints* h) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  ScanGeometry g;
  const int rings = 16, firings = 1000;
  const double column = 6.283185307179586 / firings;
  for (int f = 0; f < 2; ++f) {
    uint32_t n = 0;
    for (int c = 0; c < firings; ++c) {
      const double az = column * (c + jitter * (2 * u(rng) - 1));
      for (int k = 0; k < rings; ++k) {
        if (u(rng) < 0.05) continue;
        const double el = -0.26 + 0.4 * k / rings;
        double range = 30 + 4 * std::sin(3 * az) + std::cos(5 * az + k) + 0.05 * u(rng);
        range = 0.004 * std::floor(range / 0.004 + 0.5);
        const double rho = range * std::cos(el);
        const double p[3] = {rho * std::cos(az), rho * std::sin(az), range * std::sin(el)};
        g.valid.push_back(1);
        for (int a = 0; a < 3; ++a) {
          g.q.push_back(static_cast<int32_t>(std::floor(p[a] / 0.002 + 0.5)));
          h->xyz.push_back(static_cast<float>(p[a]));
        }
        h->ring.push_back(static_cast<uint32_t>(k));
        ++n;
      }
    }
    g.counts.push_back(n);
  }
  h->grid_per_unit = 500;
  return g;
}

// The payload, checked exact; its header.
scan::Header coded(const ScanGeometry& g, const ScanHints& h, std::vector<uint8_t>* p) {
  *p = encode_scan_geometry(g, h);
  const ScanGeometry back = decode_scan_geometry(p->data(), p->size(), "axis");
  EXPECT_EQ(back.counts, g.counts);
  EXPECT_EQ(back.valid, g.valid);
  EXPECT_EQ(back.q, g.q);
  return scan::read_header(p->data(), p->size(), "axis", 1u << 20);
}

TEST(ScanAxis, GivenAzimuthsOnTheirColumnsThenTheSecondAxisFromTheAzimuth) {
  ScanHints h;
  const ScanGeometry g = sweeps(0, &h);
  std::vector<uint8_t> p;
  const scan::Header hd = coded(g, h, &p);
  ASSERT_FALSE(hd.table.unit.empty());  // an exact range: the azimuth can win
  for (uint8_t fl : hd.flags) {
    EXPECT_NE(fl & scan::kSpherical, 0);
    EXPECT_EQ(fl & scan::kHypot, 0);
  }
}

TEST(ScanAxis, GivenAzimuthsOffTheirColumnsThenTheSecondAxisFromTheHypotenuse) {
  ScanHints h;
  const ScanGeometry g = sweeps(0.45, &h);
  std::vector<uint8_t> p;
  const scan::Header hd = coded(g, h, &p);
  ASSERT_FALSE(hd.table.unit.empty());
  for (uint8_t fl : hd.flags) {
    EXPECT_NE(fl & scan::kSpherical, 0);
    EXPECT_NE(fl & scan::kHypot, 0);
  }
}

// The offset of flags_f in a payload: after F and the counts (varints).
size_t flags_at(const scan::Header& hd) {
  size_t at = 1;  // F < 128 here
  for (uint32_t n : hd.counts)
    for (uint32_t v = n;; v >>= 7) {
      ++at;
      if (v < 128) break;
    }
  return at;
}

TEST(ScanAxis, GivenTheHypotenuseBitOnACartesianFrameWhenDecodedThenCorrupt) {
  ScanHints h;
  const ScanGeometry g = sweeps(0.45, &h);
  std::vector<uint8_t> p;
  const scan::Header hd = coded(g, h, &p);
  const size_t at = flags_at(hd);
  ASSERT_EQ(p[at], hd.flags[0]);
  ASSERT_NE(p[at] & scan::kHypot, 0);
  for (uint8_t bad : {static_cast<uint8_t>(p[at] & ~scan::kSpherical),     // bit 6 alone
                      static_cast<uint8_t>(scan::kHypot | scan::kRaster),  // on a raster frame
                      static_cast<uint8_t>(p[at] | 0x80)}) {               // bit 7
    std::vector<uint8_t> d = p;
    d[at] = bad;
    try {
      decode_scan_geometry(d.data(), d.size(), "damaged");
      ADD_FAILURE() << "decoded flags " << int(bad);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
      EXPECT_NE(std::string(e.what()).find("damaged"), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace capz

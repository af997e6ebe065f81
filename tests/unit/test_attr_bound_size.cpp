// --attr-error never makes a field's coding larger (FORMAT.md 16.4, encode_attributes_within):
// a bounded float field is kept exact in a window where its quantised values code no smaller,
// through the scan coder (frames of their own counts) and through POSW (frames of one count).
// The fields that grew before: float64 nanosecond timestamps at a bound of 1000, a distance in
// 2.5 mm steps (data/scan_small's, predicted from the range) at 0.01, a float field holding
// integers at 0.5 (already on the grid: its values and bytes as they were).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>

#include "capz/codec.h"
#include "capz/io.h"
#include "synthetic.h"

namespace capz {
namespace {

void put_bytes(PointAttribute* a, const void* v, size_t size) {
  const uint8_t* b = static_cast<const uint8_t*>(v);
  a->data.insert(a->data.end(), b, b + size);
}

// Appends a float field (size 4 or 8) named `name` to t, point i's value value(i, xyz of i).
template <class Value>
void add_float_field(Take* t, const std::string& name, int size, Value value) {
  t->pcd->fields.push_back({name, 'F', size, 1});
  t->attributes.push_back(attribute_of(t->pcd->fields.back()));
  PointAttribute& a = t->attributes.back();
  for (size_t i = 0; i < t->valid.size(); ++i) {
    const double v = value(i, &t->xyz[3 * i]);
    if (size == 8) {
      put_bytes(&a, &v, 8);
    } else {
      const float f = static_cast<float>(v);
      put_bytes(&a, &f, 4);
    }
  }
}

// The fields a driver writes that quantising used to make larger: nanosecond timestamps as
// float64 (a firing every 2304 ns), the range in 2.5 mm steps as float32, an integer-valued
// float32 intensity.
void add_driver_fields(Take* t) {
  if (t->pcd->fields.empty())
    t->pcd->fields = {{"x", 'F', 4, 1}, {"y", 'F', 4, 1}, {"z", 'F', 4, 1}};
  add_float_field(t, "t_ns", 8, [](size_t i, const double*) {
    return 1.6910317667815e18 + 2304.0 * static_cast<double>(i);
  });
  add_float_field(t, "distance", 4, [](size_t, const double* p) {
    const double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    return std::isfinite(r) ? 0.0025 * std::round(r / 0.0025) : 0.0;
  });
  add_float_field(t, "level", 4,
                  [](size_t i, const double*) { return static_cast<double>((i * 7919) % 97); });
}

// The take coded with `bounds` and without: the bounded stream's fields no larger, and each
// bounded value back within its bound (the others exact).
void expect_not_larger(const Take& t, const CompressOptions& base,
                       const std::map<std::string, double>& bounds) {
  CompressStats exact, within;
  compress(t, base, &exact);
  CompressOptions o = base;
  o.attr_error = bounds;
  const std::vector<uint8_t> z = compress(t, o, &within);
  EXPECT_LE(within.attribute_bytes, exact.attribute_bytes) << bounds.begin()->first;
  const Take d = decompress(z.data(), z.size());
  ASSERT_EQ(d.attributes.size(), t.attributes.size());
  for (size_t a = 0; a < t.attributes.size(); ++a) {
    const PointAttribute &s = t.attributes[a], &g = d.attributes[a];
    ASSERT_EQ(s.data.size(), g.data.size()) << s.name;
    const auto bound = bounds.find(s.name);
    if (bound == bounds.end()) {
      EXPECT_EQ(s.data, g.data) << s.name;
      continue;
    }
    for (size_t k = 0; k < s.data.size(); k += static_cast<size_t>(s.size)) {
      double x, y;
      if (s.size == 8) {
        std::memcpy(&x, &s.data[k], 8);
        std::memcpy(&y, &g.data[k], 8);
      } else {
        float fx, fy;
        std::memcpy(&fx, &s.data[k], 4);
        std::memcpy(&fy, &g.data[k], 4);
        x = fx, y = fy;
      }
      ASSERT_LE(std::fabs(x - y), bound->second) << s.name << " at " << k;
    }
  }
}

TEST(AttrBoundSize, ScanCoderNeverCodesABoundedFieldLarger) {
  Take t = capz_test::synthetic_sweeps(3, 120, 29, 4, 30, 2, 0.2, 11, 19, 4);
  add_driver_fields(&t);
  for (const bool lossless : {false, true}) {
    CompressOptions o;
    if (lossless)
      o.lossless = true;
    else
      o.max_error = 0.001;
    expect_not_larger(t, o, {{"t_ns", 1000}});
    expect_not_larger(t, o, {{"distance", 0.01}});
    expect_not_larger(t, o, {{"level", 0.5}});
  }
}

TEST(AttrBoundSize, PoswNeverCodesABoundedFieldLarger) {
  // A deforming blob's frames of one count, which POSW codes (not the scan coder).
  const capz_test::Synth s = capz_test::make_synth(12, 300, 6, true, 5);
  Take t;
  t.source = "synthetic";
  t.format = Format::kPCDFolder;
  t.units = "m";
  t.frames = s.frames;
  t.points = s.points;
  t.xyz = s.xyz;
  for (double& v : t.xyz) v = static_cast<double>(static_cast<float>(v));
  t.valid = s.valid;
  t.pcd = std::make_shared<PCDExtra>();
  t.pcd->width = s.points;
  t.pcd->height = 1;
  for (size_t f = 0; f < t.frames; ++f) t.pcd->frame_names.push_back(std::to_string(f) + ".pcd");
  add_driver_fields(&t);
  CompressOptions o;
  o.max_error = 0.001;
  CompressStats st;
  compress(t, o, &st);
  EXPECT_EQ(st.mode.find("scan"), std::string::npos) << st.mode;
  expect_not_larger(t, o, {{"t_ns", 1000}});
  expect_not_larger(t, o, {{"distance", 0.01}});
  expect_not_larger(t, o, {{"level", 0.5}});
}

// data/scan_small (four Helios 16P sweeps): its distance at 0.01, lossless positions, was 40,029
// B against 38,852 exact.
TEST(AttrBoundSize, ScanSmallDistanceAtACentimetre) {
  const Take t = read_take(std::string(CAPZ_REPO_DATA) + "/scan_small");
  CompressOptions o;
  o.lossless = true;
  expect_not_larger(t, o, {{"distance", 0.01}});
}

}  // namespace
}  // namespace capz

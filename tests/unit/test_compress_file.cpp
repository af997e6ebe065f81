// capz/compress_file.h: the target `capz compress` chooses (default bounds, one target only) and
// compress_file() writing what compress() gives for a take without an original file.
#include <gtest/gtest.h>

#include <cmath>

#include "capz/io.h"
#include "capz/tool/compress_file.h"
#include "capz/tool/file.h"
#include "test_util.h"

using namespace capz;

namespace {

// 20 frames x 3 points inside the box [0, 30] x [0, 40] x [0, 0] (diagonal 50), one gap.
Take box_take(const std::string& units) {
  Take t;
  t.resize(20, 3);
  t.units = units;
  t.rate = 100;
  t.labels = {"a", "b", "c"};
  for (size_t f = 0; f < 20; ++f)
    for (size_t p = 0; p < 3; ++p) {
      double* x = t.at(f, p);
      x[0] = 30.0 * static_cast<double>(f) / 19.0;
      x[1] = p == 1 ? 40.0 : static_cast<double>(p);
      x[2] = 0;
      t.valid[f * 3 + p] = 1;
    }
  t.valid[5 * 3 + 1] = 0;
  t.at(5, 1)[1] = 1e9;  // a gap's value counts for nothing
  return t;
}

double target_bound(const Take& t, const CompressTarget& target, CompressOptions* opts) {
  auto src = take_frames(t);
  set_compress_target(*src, target, opts);
  return opts->max_error;
}

}  // namespace

TEST(CompressTarget, DefaultIsOneTenthMillimetreInTheTakesUnits) {
  CompressOptions o;
  EXPECT_DOUBLE_EQ(target_bound(box_take("mm"), {}, &o), 0.1);
  EXPECT_DOUBLE_EQ(target_bound(box_take("cm"), {}, &o), 0.01);
  EXPECT_DOUBLE_EQ(target_bound(box_take("m"), {}, &o), 0.0001);
  EXPECT_FALSE(o.lossless);
  EXPECT_EQ(o.kg_error, 0);
}

TEST(CompressTarget, WithoutUnitsTheDefaultIsAFractionOfTheDiagonal) {
  CompressOptions o;
  EXPECT_DOUBLE_EQ(target_bound(box_take(""), {}, &o), 1e-4 * 50.0);
  Take none = box_take("");
  std::fill(none.valid.begin(), none.valid.end(), 0);
  EXPECT_DOUBLE_EQ(target_bound(none, {}, &o), 1.0);  // nothing to bound
  CompressTarget with_unit;
  with_unit.max_error = "0.1mm";
  EXPECT_EQ(capz_test::error_of([&] { target_bound(box_take(""), with_unit, &o); }),
            ErrorCode::kInvalidParameter);
}

// n points on a 10 x 10 x 1 grid (diagonal about 14.2) and one stray at (x, 0, 0).
Take stray_take(size_t n, double x) {
  Take t;
  t.resize(1, n + 1);
  for (size_t p = 0; p < n; ++p) {
    double* v = t.at(0, p);
    v[0] = static_cast<double>(p % 10);
    v[1] = static_cast<double>(p / 10 % 10);
    v[2] = static_cast<double>(p / 100 % 2);
  }
  t.at(0, n)[0] = x;
  std::fill(t.valid.begin(), t.valid.end(), 1);
  return t;
}

// The default bound of t and its note.
double default_of(const Take& t, CompressOptions* o, std::string* note) {
  auto src = take_frames(t);  // holds t by reference
  *note = set_compress_target(*src, {}, o);
  return o->max_error;
}

TEST(CompressTarget, AFewFarPointsDoNotSetTheDefaultBound) {
  CompressOptions o;
  std::string note;
  const double others = 1e-4 * std::sqrt(9.0 * 9 + 9 * 9 + 1);
  EXPECT_DOUBLE_EQ(default_of(stray_take(5000, 1e6), &o, &note), others);
  EXPECT_NE(note, "");  // it says why
  EXPECT_FALSE(o.lossless);
  // Under 1000 points, or far points as spread as the others: the whole box, no note.
  EXPECT_DOUBLE_EQ(default_of(stray_take(998, 1e6), &o, &note),
                   1e-4 * std::sqrt(1e6 * 1e6 + 9 * 9 + 1));
  EXPECT_EQ(note, "");
  EXPECT_DOUBLE_EQ(default_of(stray_take(5000, 1000), &o, &note),
                   1e-4 * std::sqrt(1000.0 * 1000 + 9 * 9 + 1));
  EXPECT_EQ(note, "");
  EXPECT_DOUBLE_EQ(default_of(stray_take(5000, 1500), &o, &note), others);
  EXPECT_NE(note, "");
  // A stray the grid's integers cannot reach at the others' bound: lossless, with the note.
  default_of(stray_take(5000, 1e30), &o, &note);
  EXPECT_TRUE(o.lossless);
  EXPECT_NE(note, "");
  // With units: as before.
  Take mm = stray_take(5000, 1e6);
  mm.units = "mm";
  EXPECT_DOUBLE_EQ(default_of(mm, &o, &note), 0.1);
  EXPECT_EQ(note, "");
}

TEST(CompressTarget, OneTargetOnly) {
  CompressOptions o;
  CompressTarget t;
  t.lossless = true;
  target_bound(box_take("mm"), t, &o);
  EXPECT_TRUE(o.lossless);
  t.kg_error = 0.5;
  EXPECT_EQ(capz_test::error_of([&] { target_bound(box_take("mm"), t, &o); }), ErrorCode::kUsage);
  CompressTarget kg;
  kg.kg_error = 0;
  EXPECT_EQ(capz_test::error_of([&] { target_bound(box_take("mm"), kg, &o); }),
            ErrorCode::kInvalidParameter);
  kg.kg_error = 0.5;
  target_bound(box_take("mm"), kg, &o);
  EXPECT_EQ(o.kg_error, 0.5);
  EXPECT_FALSE(o.lossless);
  EXPECT_EQ(o.max_error, 0);
  CompressTarget zero;
  zero.max_error = "0mm";
  EXPECT_EQ(capz_test::error_of([&] { target_bound(box_take("mm"), zero, &o); }),
            ErrorCode::kInvalidParameter);
  zero.max_error = "2cm";
  EXPECT_DOUBLE_EQ(target_bound(box_take("mm"), zero, &o), 20.0);
}

TEST(CompressFile, WritesTheBytesOfCompressWithTheChosenTarget) {
  capz_test::TempDir dir;
  const Take t = box_take("");
  const std::string in = dir.file("box/");
  write_take(t, in);  // a PCD folder: no original file, so no checksum or residue chunks
  const Take read = read_take(in);
  CompressOptions opts;
  CompressTarget target;
  target.max_error = "0.5mm";
  compress_file(in, dir.file("a.capz"), target, opts, "m", false);
  CompressOptions expect_opts;
  Take with_units = read;
  with_units.units = "m";
  expect_opts.max_error = 0.0005;
  EXPECT_EQ(read_file(dir.file("a.capz")), compress(with_units, expect_opts));
  EXPECT_EQ(
      capz_test::error_of([&] { compress_file(in, dir.file("a.capz"), target, opts, "m", false); }),
      ErrorCode::kUsage);  // exists
  EXPECT_EQ(capz_test::error_of(
                [&] { compress_file(in, dir.file("b.capz"), target, opts, "furlong", false); }),
            ErrorCode::kInvalidParameter);
  EXPECT_FALSE(std::filesystem::exists(dir.file("b.capz")));
}

// The rule for "a stream keeps its promise" (capz/verify.h): for each kind of promise a decoded
// take that keeps it and ones that break it, whole and a block of frames at a time.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>

#include "capz/codec.h"
#include "capz/metrics.h"
#include "capz/stream.h"
#include "capz/tool/verify.h"

using namespace capz;

namespace {

// 6 frames x 4 points in mm with one gap, C3D 4th words and two analog channels.
Take original() {
  Take t;
  t.format = Format::kC3D;
  t.resize(6, 4);
  t.rate = 100;
  t.units = "mm";
  t.labels = {"A", "B", "C", "D"};
  for (size_t f = 0; f < t.frames; ++f)
    for (size_t p = 0; p < t.points; ++p) {
      double* x = t.at(f, p);
      x[0] = 100.0 * static_cast<double>(p) + static_cast<double>(f);
      x[1] = 50.0 + 0.25 * static_cast<double>(f * p);
      x[2] = -20.0 + 3.0 * static_cast<double>(p);
      t.valid[f * t.points + p] = 1;
    }
  t.valid[2 * t.points + 1] = 0;  // frame 2, point 1: a gap
  t.xyz[(2 * t.points + 1) * 3] = 0;
  t.c3d = std::make_shared<C3DExtra>();
  t.c3d->residual.assign(t.frames * t.points, 0.5f);
  t.c3d->camera_mask.assign(t.frames * t.points, 3);
  t.analog.channels = 2;
  t.analog.samples_per_frame = 1;
  t.analog.rate = 100;
  t.analog.labels = {"F1", "F2"};
  for (size_t i = 0; i < t.frames * 2; ++i) t.analog.values.push_back(static_cast<double>(i));
  return t;
}

Take deep_copy(const Take& t) {
  Take c = t;
  if (t.c3d) c.c3d = std::make_shared<C3DExtra>(*t.c3d);
  return c;
}

Promise lossless() {
  Promise p;
  p.kind = Promise::Kind::kLossless;
  return p;
}
Promise bound(double e) {
  Promise p;
  p.kind = Promise::Kind::kBound;
  p.max_error = e;
  return p;
}
Promise kg(double target) {
  Promise p;
  p.kind = Promise::Kind::kKgTarget;
  p.kg_target = target;
  return p;
}

// Decoded = original with every valid coordinate moved by `d`.
Take shifted(const Take& a, double d) {
  Take b = deep_copy(a);
  for (size_t i = 0; i < a.frames * a.points; ++i)
    if (a.valid[i])
      for (int k = 0; k < 3; ++k) b.xyz[i * 3 + k] += d;
  return b;
}

bool has(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

}  // namespace

TEST(Promise, GivenStreamInfoThenThePromiseIsWhatTheHeaderSays) {
  StreamInfo si;
  si.lossless = true;
  EXPECT_EQ(promise_of(si).kind, Promise::Kind::kLossless);
  si.lossless = false;
  si.max_error = 0.25;
  EXPECT_EQ(promise_of(si).kind, Promise::Kind::kBound);
  EXPECT_EQ(promise_of(si).max_error, 0.25);
  si.transform_output = true;
  si.max_error = 0;
  si.kg_target = 0.5;
  EXPECT_EQ(promise_of(si).kind, Promise::Kind::kKgTarget);
  EXPECT_EQ(promise_of(si).kg_target, 0.5);
}

TEST(Promise, GivenLosslessThenOnlyBitIdenticalValidCoordinatesKeepIt) {
  const Take a = original();
  Take b = deep_copy(a);
  b.xyz[(2 * a.points + 1) * 3] = 12345;  // a gap's coordinate is not promised
  PromiseResult r = check_promise(a, b, lossless());
  EXPECT_TRUE(r.holds) << r.why;
  EXPECT_EQ(r.why, "");
  EXPECT_EQ(r.error.max_abs, 0);

  Take c = deep_copy(a);
  double& x = c.xyz[(3 * a.points + 2) * 3 + 1];
  x = std::nextafter(x, 1e9);  // one ulp
  r = check_promise(a, c, lossless());
  EXPECT_FALSE(r.holds);
  EXPECT_TRUE(has(r.why, "frame 3, point 2") && has(r.why, "lossless")) << r.why;

  // Equal as numbers but not as stored bits: a lossless stream must give the bits back.
  Take z = original();
  z.xyz[0] = 0.0;
  Take nz = deep_copy(z);
  nz.xyz[0] = -0.0;
  r = check_promise(z, nz, lossless());
  EXPECT_FALSE(r.holds);
  EXPECT_EQ(r.error.max_abs, 0);  // what `verify` used to accept
}

TEST(Promise, GivenABoundThenEveryValidCoordinateMustBeWithinIt) {
  const Take a = original();
  PromiseResult r = check_promise(a, shifted(a, 0.09), bound(0.1));
  EXPECT_TRUE(r.holds) << r.why;
  EXPECT_NEAR(r.error.max_abs, 0.09, 1e-9);

  Take b = shifted(a, 0.09);
  b.xyz[(5 * a.points + 3) * 3 + 2] += 0.02;
  r = check_promise(a, b, bound(0.1));
  EXPECT_FALSE(r.holds);
  EXPECT_TRUE(has(r.why, "frame 5, point 3") && has(r.why, "bound 0.1")) << r.why;

  Take n = deep_copy(a);
  n.xyz[4] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(check_promise(a, n, bound(0.1)).holds);
}

TEST(Promise, GivenAKgTargetThenTheWholeTakesKgErrorMustMeetItWithFiniteCoordinates) {
  const Take a = original();
  const Take b = shifted(a, 0.5);
  const double achieved = compare(a, b).kg_error;
  ASSERT_GT(achieved, 0);
  PromiseResult r = check_promise(a, b, kg(achieved * 1.01));
  EXPECT_TRUE(r.holds) << r.why;
  EXPECT_DOUBLE_EQ(r.error.kg_error, achieved);

  r = check_promise(a, b, kg(achieved * 0.99));
  EXPECT_FALSE(r.holds);
  EXPECT_TRUE(has(r.why, "KG error")) << r.why;

  Take inf = deep_copy(a);
  inf.xyz[7] = std::numeric_limits<double>::infinity();
  r = check_promise(a, inf, kg(1e300));
  EXPECT_FALSE(r.holds);
  EXPECT_TRUE(has(r.why, "not finite")) << r.why;
}

TEST(Promise, GivenTheMaskOrMetadataDifferThenNoPromiseHolds) {
  const Take a = original();
  for (const Promise& p : {lossless(), bound(1.0), kg(1e9)}) {
    Take m = deep_copy(a);
    m.valid[0] = 0;
    PromiseResult r = check_promise(a, m, p);
    EXPECT_FALSE(r.holds);
    EXPECT_TRUE(has(r.why, "gap mask")) << r.why;
    EXPECT_EQ(r.error.mask_mismatches, 1u);

    Take l = deep_copy(a);
    l.labels[2] = "X";
    EXPECT_FALSE(check_promise(a, l, p).holds);
    Take u = deep_copy(a);
    u.units = "m";
    EXPECT_FALSE(check_promise(a, u, p).holds);
    Take w = deep_copy(a);
    w.c3d->residual[5] = 1.0f;
    EXPECT_TRUE(has(check_promise(a, w, p).why, "residual")) << check_promise(a, w, p).why;
    Take v = deep_copy(a);
    v.analog.values[3] += 1;
    EXPECT_TRUE(has(check_promise(a, v, p).why, "analog values"));
    Take s = deep_copy(a);
    s.resize(5, 4);
    EXPECT_TRUE(has(check_promise(a, s, p).why, "decodes to 5 frames"));
  }
}

// Block by block (as compress --rm checks) gives the same verdict and measures as whole takes.
TEST(Promise, GivenBlocksOfFramesThenTheCheckAgreesWithTheWholeTake) {
  const Take a = original();
  Take b = shifted(a, 0.05);
  b.xyz[(4 * a.points + 0) * 3] += 1;  // frame 4 breaks a 0.1 bound
  for (double e : {0.1, 2.0}) {
    SCOPED_TRACE(e);
    std::unique_ptr<FrameSource> sa = take_frames(a), sb = take_frames(b);
    PromiseCheck check(bound(e));
    EXPECT_TRUE(check.header(sa->header(), sb->header()));
    FrameBlock x, y;
    for (size_t f = 0; f < a.frames; f += 4) {
      sa->read(f, 4, &x);
      sb->read(f, 4, &y);
      check.frames(x, y);
    }
    check.finish();
    const PromiseResult whole = check_promise(a, b, bound(e));
    EXPECT_EQ(check.holds(), whole.holds);
    EXPECT_EQ(check.why(), whole.why);
    EXPECT_EQ(check.holds(), e > 1);
    EXPECT_DOUBLE_EQ(check.error().max_abs, compare(a, b).max_abs);
    EXPECT_DOUBLE_EQ(check.error().kg_error, compare(a, b).kg_error);
  }
}

// Without measures (the encoder's self-check) the verdict and the first breach are the same,
// whichever coordinate of a sample breaks the promise, and nothing is measured.
TEST(Promise, GivenNoMeasuresThenTheSameVerdictAndNoMeasures) {
  const Take a = original();
  for (int axis = 0; axis < 3; ++axis)
    for (const Promise& p : {bound(0.1), lossless()}) {
      SCOPED_TRACE(axis);
      Take b = shifted(a, p.kind == Promise::Kind::kBound ? 0.05 : 0.0);
      b.xyz[(4 * a.points + 3) * 3 + static_cast<size_t>(axis)] += 1;  // frame 4, point 3
      std::unique_ptr<FrameSource> sa = take_frames(a), sb = take_frames(b);
      FrameBlock x, y;
      sa->read(0, a.frames, &x);
      sb->read(0, a.frames, &y);
      PromiseCheck measured(p), bare(p, false);
      EXPECT_FALSE(measured.frames(x, y));
      EXPECT_FALSE(bare.frames(x, y));
      EXPECT_EQ(bare.why(), measured.why());
      EXPECT_TRUE(has(bare.why(), "at frame 4, point 3 comes back as")) << bare.why();
      const double moved = b.xyz[(4 * a.points + 3) * 3 + static_cast<size_t>(axis)];
      char text[64];
      std::snprintf(text, sizeof text, "comes back as %.17g", moved);
      EXPECT_TRUE(has(bare.why(), text)) << bare.why();
      EXPECT_EQ(bare.error().samples, 0u);
      EXPECT_EQ(measured.error().samples, a.frames * a.points - 1);  // one gap
    }
}

// The rule against the real coder: what compress promises, decompress keeps.
TEST(Promise, GivenARealStreamThenItKeepsThePromiseItsHeaderMakes) {
  Take a = original();
  a.c3d.reset();  // a synthetic take's 4th words need a C3D parameter section to be stored
  for (bool exact : {true, false}) {
    CompressOptions o;
    o.lossless = exact;
    o.max_error = exact ? 0 : 0.2;
    const std::vector<uint8_t> bytes = compress(a, o);
    const Take b = decompress(bytes.data(), bytes.size(), "p.capz");
    const Promise p = promise_of(describe(bytes.data(), bytes.size(), "p.capz"));
    EXPECT_EQ(p.kind, exact ? Promise::Kind::kLossless : Promise::Kind::kBound);
    const PromiseResult r = check_promise(a, b, p);
    EXPECT_TRUE(r.holds) << r.why;
  }
}

// C3D reader on hand-built byte arrays (the builder: c3d_builder.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>

#include "c3d_builder.h"
#include "capz/error.h"
#include "capz/io.h"
#include "coding/c3d_params.h"
#include "core/atomic_file.h"
#include "io/c3d_internal.h"
#include "support/c3d_compare.h"
#include "test_util.h"

using namespace capz;
using capz::testing_support::expect_same_groups;
using capz::testing_support::expect_same_take;
namespace fs = std::filesystem;
using namespace c3d_builder;

// ---- numbers --------------------------------------------------------------------------------

TEST(C3DNumbers, DecFloatKnownBitPatterns) {
  // VAX F 1.0 = 0x40800000 stored as words (0x4080, 0x0000), each little-endian.
  const uint8_t one[4] = {0x80, 0x40, 0x00, 0x00};
  EXPECT_EQ(c3d::dec_to_float(one), 1.0f);
  // -2.5 = sign 1, exponent 130, fraction .01 -> 0xC1200000.
  const uint8_t m25[4] = {0x20, 0xC1, 0x00, 0x00};
  EXPECT_EQ(c3d::dec_to_float(m25), -2.5f);
  // 0.1 = IEEE 0x3DCCCCCD; VAX has the exponent 2 higher: 0x3ECCCCCD -> words 0x3ECC, 0xCCCD.
  const uint8_t tenth[4] = {0xCC, 0x3E, 0xCD, 0xCC};
  EXPECT_EQ(c3d::dec_to_float(tenth), 0.1f);
  const uint8_t zero[4] = {0, 0, 0, 0};
  EXPECT_EQ(c3d::dec_to_float(zero), 0.0f);
}

TEST(C3DNumbers, DecFloatRoundTripsEveryNormalFloat) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<uint32_t> bits;
  for (int i = 0; i < 100000; ++i) {
    uint32_t u = bits(rng);
    uint32_t e = (u >> 23) & 0xff;
    if (e == 0 || e >= 253) continue;  // VAX lacks IEEE's top exponents; denormals not needed
    float f;
    std::memcpy(&f, &u, 4);
    uint8_t b[4];
    c3d::float_to_dec(f, b);
    float back = c3d::dec_to_float(b);
    ASSERT_EQ(0, std::memcmp(&f, &back, 4)) << f;
  }
}

// ---- reading --------------------------------------------------------------------------------

TEST(C3DRead, IntelInt16GivesScaledIntegersResidualsMasksAndLabels) {
  Built b = small_trial(c3d::kIntel, false);
  Take t = read(b);
  EXPECT_EQ(t.format, Format::kC3D);
  ASSERT_EQ(t.frames, 4u);
  ASSERT_EQ(t.points, 3u);
  EXPECT_EQ(t.labels, (std::vector<std::string>{"LASI", "RASI", "LHEE"}));
  EXPECT_EQ(t.units, "mm");
  EXPECT_DOUBLE_EQ(t.rate, 100);
  EXPECT_FALSE(t.c3d->float_storage);
  EXPECT_DOUBLE_EQ(t.c3d->point_scale, 0.25);
  EXPECT_EQ(t.at(1, 2)[0], (100 + 20 + 1) * 0.25);
  EXPECT_EQ(t.at(3, 2)[1], (-50.0 - 6) * 0.25);
  EXPECT_FALSE(t.is_valid(2, 1));
  EXPECT_EQ(t.at(2, 1)[0], 0.0);
  EXPECT_EQ(t.gap_samples(), 1u);
  EXPECT_EQ(t.c3d->camera_mask[1 * 3 + 2], 3);
  EXPECT_FLOAT_EQ(t.c3d->residual[1 * 3 + 2], 3 * 0.25f);
  EXPECT_EQ(t.c3d->residual[2 * 3 + 1], -1.0f);
  EXPECT_EQ(t.analog.channels, 2);
  EXPECT_EQ(t.analog.samples_per_frame, 2);
  EXPECT_DOUBLE_EQ(t.analog.rate, 200);
  EXPECT_EQ(t.analog.labels, (std::vector<std::string>{"FZ1", "EMG1"}));
  ASSERT_EQ(t.analog.values.size(), 16u);
  EXPECT_EQ(t.analog.values[5], 5 * 37 - 200);
  EXPECT_TRUE(t.warnings.empty()) << t.warnings[0];
  const C3DParameter* used = t.c3d->param("point", "used");
  ASSERT_NE(used, nullptr);
  EXPECT_TRUE(used->locked);
  EXPECT_EQ(used->description, "Number of points");
}

TEST(C3DRead, AllSixEncodingsGiveTheSameTake) {
  Take ref = read(small_trial(c3d::kIntel, false));
  for (int proc : {c3d::kIntel, c3d::kDec, c3d::kMips})
    for (bool fl : {false, true}) {
      SCOPED_TRACE("processor " + std::to_string(proc) + (fl ? " float" : " int16"));
      Take t = read(small_trial(proc, fl));
      EXPECT_EQ(t.c3d->processor, proc);
      EXPECT_EQ(t.c3d->float_storage, fl);
      EXPECT_EQ(t.valid, ref.valid);
      // Multiples of 0.25 are exact in float and int16 alike.
      EXPECT_EQ(t.xyz, ref.xyz);
      EXPECT_EQ(t.c3d->camera_mask, ref.c3d->camera_mask);
      EXPECT_EQ(t.c3d->residual, ref.c3d->residual);
      EXPECT_EQ(t.analog.values, ref.analog.values);
      EXPECT_EQ(t.labels, ref.labels);
      EXPECT_DOUBLE_EQ(t.rate, 100);
    }
}

TEST(C3DRead, GapConventions) {
  Built b = small_trial(c3d::kIntel, true);
  b.samples[0] = {1, 2, 3, -1};            // negative residual
  b.samples[1] = {std::nan(""), 2, 3, 0};  // NaN coordinate
  b.samples[2] = {0, 0, 0, 5};             // all-zero coordinates
  b.samples[3] = {1, 2, 3, 65535};         // int16 -1 written as unsigned float
  b.samples[4] = {1, 2, 3, std::nan("")};  // NaN 4th word
  b.samples[5] = {4, 5, 6, 0x7f07};        // valid: mask 0x7f, residual 7 steps
  b.samples[6] = {4, 5, 6, 3.0e38};        // no int16 at all: valid, residual 0
  Take t = read(b);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(t.valid[static_cast<size_t>(i)], 0) << i;
  for (int i = 0; i < 5; ++i) EXPECT_EQ(t.xyz[static_cast<size_t>(3 * i)], 0.0) << i;
  EXPECT_EQ(t.valid[5], 1);
  EXPECT_EQ(t.c3d->camera_mask[5], 0x7f);
  EXPECT_FLOAT_EQ(t.c3d->residual[5], 7 * 0.25f);
  EXPECT_EQ(t.valid[6], 1);
  EXPECT_EQ(t.c3d->residual[6], 0.0f);
  EXPECT_TRUE(has_warning(t, "beyond 16 bits"));

  Built i = small_trial(c3d::kIntel, false);
  i.samples[0] = {10, 20, 30, -32768};  // any negative int16 is a gap
  i.samples[1] = {0, 0, 0, 0};
  Take ti = read(i);
  EXPECT_EQ(ti.valid[0], 0);
  EXPECT_EQ(ti.valid[1], 0);
  EXPECT_EQ(ti.valid[2], 1);
}

TEST(C3DRead, MoreThan255LabelsUseLabels2) {
  Built b;
  b.points = 300;
  b.frames = 2;
  std::vector<std::string> labels;
  for (size_t p = 0; p < b.points; ++p) labels.push_back("M" + std::to_string(p));
  for (size_t f = 0; f < b.frames; ++f)
    for (size_t p = 0; p < b.points; ++p)
      b.samples.push_back({static_cast<double>(p + 1), 1, 2, 0});
  standard_groups(b, labels);
  ASSERT_NE(b.groups[0].params.back().name, "LABELS");  // the builder wrote LABELS2
  Take t = read(b);
  EXPECT_EQ(t.labels, labels);
  EXPECT_TRUE(t.warnings.empty());

  // Written back with a different point count, LABELS / LABELS2 are rebuilt.
  Take cut = t;
  cut.points = 256;
  cut.labels.resize(256);
  cut.resize(2, 256);
  cut.c3d->residual.assign(512, -1);
  cut.c3d->camera_mask.assign(512, 0);
  auto bytes = c3d::encode_c3d_file(cut, {}, "cut.c3d");
  Take back = read_c3d_bytes(bytes.data(), bytes.size(), "cut.c3d");
  EXPECT_EQ(back.labels, cut.labels);
  EXPECT_EQ(back.c3d->param("POINT", "LABELS2")->as_strings().size(), 1u);
  EXPECT_EQ(back.c3d->param("POINT", "USED")->as_ints()[0], 256);
}

TEST(C3DRead, TruncatedDataReadsCompleteFramesAndSaysSo) {
  Built b = small_trial(c3d::kIntel, false);
  b.frames_written = 2;
  auto v = b.bytes();
  v.resize(v.size() + 5);  // half a frame more
  Take t = read_c3d_bytes(v.data(), v.size(), "cut.c3d");
  EXPECT_EQ(t.frames, 2u);
  EXPECT_TRUE(has_warning(t, "header says 4 frames, file holds 2"));
  EXPECT_EQ(t.at(1, 0)[0], 101 * 0.25);
}

TEST(C3DRead, MoreThan65535FramesFromTrialFieldsOrFloatFrames) {
  for (bool use_trial : {true, false}) {
    Built b;
    b.points = 1;
    b.frames = 70000;
    b.first = 1;
    b.header_last = 65535;
    for (size_t f = 0; f < b.frames; ++f)
      b.samples.push_back({static_cast<double>(f % 30000) + 1, 2, 3, 0});
    standard_groups(b, {"A"});
    if (use_trial) {
      b.groups.push_back({3,
                          "TRIAL",
                          "",
                          {ints("ACTUAL_START_FIELD", {1, 0}, {2}),
                           ints("ACTUAL_END_FIELD", {70000 - 65536, 1}, {2})}});
    } else {
      b.groups[0].params[1] = {"FRAMES", 4, {}, {70000}, "", "", false};
    }
    Take t = read(b);
    ASSERT_EQ(t.frames, 70000u) << use_trial;
    EXPECT_EQ(t.at(69999, 0)[0],
              static_cast<double>(69999 % 30000 + 1) * static_cast<double>(0.1f));

    // Written back: header saturated, POINT:FRAMES float, TRIAL fields; reads the same.
    auto bytes = c3d::encode_c3d_file(t, {}, "long.c3d");
    Take back = read_c3d_bytes(bytes.data(), bytes.size(), "long.c3d");
    expect_same_take(t, back);
    EXPECT_EQ(back.c3d->param("POINT", "FRAMES")->type, 4);
    EXPECT_EQ(back.c3d->param("TRIAL", "ACTUAL_END_FIELD")->as_ints(),
              (std::vector<int>{70000 - 65536, 1}));
  }
}

TEST(C3DRead, EmptyAndForeignInputsFailClearly) {
  try {
    read_c3d_bytes(nullptr, 0, "empty.c3d");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNotOurFormat);
    EXPECT_NE(std::string(e.what()).find("empty.c3d"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("0 bytes"), std::string::npos);
  }
  std::string text = "PathFileType\t4\t(X/Y/Z)\twalk.trc\n";
  try {
    read_c3d_bytes(reinterpret_cast<const uint8_t*>(text.data()), text.size(), "walk.trc");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kNotOurFormat);
  }
  std::vector<uint8_t> short_header(300, 0);
  short_header[0] = 2;
  short_header[1] = 0x50;
  try {
    read_c3d_bytes(short_header.data(), short_header.size(), "short.c3d");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
  }
  Built b = small_trial(c3d::kIntel, false);
  auto v = b.bytes();
  v[512 + 3] = 99;  // processor type
  try {
    read_c3d_bytes(v.data(), v.size(), "proc.c3d");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kUnsupportedVersion);
    EXPECT_NE(std::string(e.what()).find("processor type 99"), std::string::npos);
  }
  v = b.bytes();
  v.resize(600);  // header, then the parameter section cut short
  v[0] = 3;       // parameter section beyond the end
  try {
    read_c3d_bytes(v.data(), v.size(), "params.c3d");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
  }
}

TEST(C3DRead, GarbageParameterSectionIsToleratedWithWarnings) {
  Built b = small_trial(c3d::kIntel, false);
  auto v = b.bytes();
  std::mt19937 rng(3);
  for (size_t i = 512 + 4; i < 1024; ++i) v[i] = static_cast<uint8_t>(rng());
  v[512 + 4] = 5;  // a parameter entry with a 5-byte name, an offset, then type 7
  v[512 + 5] = 1;
  v[512 + 4 + 9] = 7;
  Take t = read_c3d_bytes(v.data(), v.size(), "garbage.c3d");
  EXPECT_TRUE(has_warning(t, "type 7"));
  EXPECT_EQ(t.points, 3u);  // the layout comes from the header
  EXPECT_EQ(t.frames, 4u);

  // Random bytes everywhere after a valid header: never a crash, an Error at worst.
  for (int trial = 0; trial < 200; ++trial) {
    auto w = b.bytes();
    for (size_t i = 512 + 4; i < w.size(); ++i)
      if (rng() % 8 == 0) w[i] = static_cast<uint8_t>(rng());
    try {
      Take g = read_c3d_bytes(w.data(), w.size(), "fuzz.c3d");
      EXPECT_EQ(g.xyz.size(), g.frames * g.points * 3);
    } catch (const Error&) {
    }
  }
}

TEST(C3DRead, LyingCountsAreClampedWithoutBigAllocations) {
  // Header: 65535 points, 65535 analog values, frames 1..65535; TRIAL says 2^31 frames; the
  // file is 2 KB. Honouring the counts would need terabytes.
  Built b;
  b.points = 65535;
  b.frames = 65535;
  b.channels = 65535;
  b.spf = 1;
  standard_groups(b, {"A"});
  b.groups.push_back(
      {3,
       "TRIAL",
       "",
       {ints("ACTUAL_START_FIELD", {1, 0}, {2}), ints("ACTUAL_END_FIELD", {0, 32767}, {2})}});
  b.frames_written = 0;
  auto v = b.bytes();
  v.resize(v.size() + 1000, 7);
  Take t = read_c3d_bytes(v.data(), v.size(), "liar.c3d");
  EXPECT_EQ(t.frames, 0u);
  EXPECT_TRUE(t.xyz.empty());
  EXPECT_TRUE(t.analog.values.empty());
  EXPECT_TRUE(has_warning(t, "file holds 0"));

  // Frames of nothing (no points, no analog): a count nothing can check is not trusted.
  Built e;
  e.frames = 60000;
  standard_groups(e, {});
  Take te = read(e);
  EXPECT_EQ(te.frames, 0u);
  EXPECT_TRUE(has_warning(te, "read as 0 frames"));

  // A parameter whose dimensions claim 4 * 255^7 bytes.
  Built p = small_trial(c3d::kIntel, false);
  p.groups[1].params.push_back({"HUGE", 4, {255, 255, 255, 255, 255, 255, 255}, {}, "", "", false});
  auto w = p.bytes();
  Take tp = read_c3d_bytes(w.data(), w.size(), "huge.c3d");
  EXPECT_TRUE(has_warning(tp, "HUGE"));
}

TEST(C3DRead, ParameterOffsetQuirksOfRealWriters) {
  // A MIPS file with one little-endian offset (c3d.org sample_02/sgi_*.c3d).
  Built m = small_trial(c3d::kMips, false);
  m.swapped_offset = "UNITS";
  Take tm = read(m);
  EXPECT_TRUE(has_warning(tm, "byte-swapped offset"));
  EXPECT_EQ(tm.units, "mm");
  EXPECT_EQ(tm.labels, (std::vector<std::string>{"LASI", "RASI", "LHEE"}));
  // A char parameter without its description byte, the offset skipping it (BTK's
  // badParameterOffset.c3d): the offset is followed and nothing after it is lost.
  Built d = small_trial(c3d::kIntel, false);
  d.no_desc_byte = "UNITS";
  Take td = read(d);
  EXPECT_TRUE(td.warnings.empty());
  EXPECT_EQ(td.units, "mm");
  EXPECT_EQ(td.labels, (std::vector<std::string>{"LASI", "RASI", "LHEE"}));
  EXPECT_EQ(td.analog.labels, (std::vector<std::string>{"FZ1", "EMG1"}));
}

TEST(C3DRead, UnsignedAnalogFormat) {
  Built b = small_trial(c3d::kIntel, false);
  b.analog[0] = -1;  // stored 0xFFFF
  b.groups[1].params.push_back(str("FORMAT", "UNSIGNED"));
  Take t = read(b);
  EXPECT_EQ(t.analog.values[0], 65535);
  auto bytes = c3d::encode_c3d_file(t, {}, "u.c3d");
  Take back = read_c3d_bytes(bytes.data(), bytes.size(), "u.c3d");
  EXPECT_EQ(back.analog.values, t.analog.values);
}

// C3D reader / writer / parameter codec on hand-built byte arrays.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>

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

namespace {

// ---- a small C3D builder, independent of the library's encoder -----------------------------

struct Param {
  std::string name;
  int8_t type;
  std::vector<int> dims;
  std::vector<double> nums;  // numeric values (type 1, 2, 4)
  std::string chars;         // char data (type -1)
  std::string desc;
  bool locked = false;
};
struct Group {
  int id;
  std::string name;
  std::string desc;
  std::vector<Param> params;
};

Param ints(const std::string& n, std::vector<double> v, std::vector<int> dims = {}) {
  return {n, 2, dims, v, "", "", false};
}
Param flt(const std::string& n, double v) {
  return {n, 4, {}, {v}, "", "", false};
}
Param str(const std::string& n, const std::string& s) {
  return {n, -1, {static_cast<int>(s.size())}, {}, s, "", false};
}
Param strs(const std::string& n, const std::vector<std::string>& v, int len) {
  std::string d;
  for (const auto& s : v) d += s + std::string(static_cast<size_t>(len) - s.size(), ' ');
  return {n, -1, {len, static_cast<int>(v.size())}, {}, d, "", false};
}

struct Sample {
  double x, y, z, w;  // w = the 4th word as a number (int16 value, or the float)
};

struct Built {
  int processor = c3d::kIntel;
  bool is_float = false;
  double scale = 0.1;  // magnitude; sign from is_float
  double rate = 100;
  size_t points = 0, frames = 0, channels = 0, spf = 0;
  long first = 1;
  long header_last = -1;  // -1: first + frames - 1
  std::vector<Group> groups;
  std::vector<Sample> samples;                      // frames x points
  std::vector<double> analog;                       // frames x spf x channels
  size_t frames_written = static_cast<size_t>(-1);  // truncate the data section
  std::string swapped_offset;  // this parameter's offset is written in the other byte order
  std::string no_desc_byte;    // this parameter lacks its description byte (offset skips it)

  void i16(std::vector<uint8_t>& o, double v) const {
    uint16_t u = static_cast<uint16_t>(static_cast<int16_t>(static_cast<long>(v)));
    if (processor == c3d::kMips) {
      o.push_back(static_cast<uint8_t>(u >> 8));
      o.push_back(static_cast<uint8_t>(u & 0xff));
    } else {
      o.push_back(static_cast<uint8_t>(u & 0xff));
      o.push_back(static_cast<uint8_t>(u >> 8));
    }
  }
  void u16at(std::vector<uint8_t>& o, size_t at, uint16_t u) const {
    std::vector<uint8_t> t;
    i16(t, static_cast<int16_t>(u));
    o[at] = t[0];
    o[at + 1] = t[1];
  }
  void f32(std::vector<uint8_t>& o, double v) const {
    uint8_t b[4];
    float f = static_cast<float>(v);
    if (processor == c3d::kDec) {
      c3d::float_to_dec(f, b);
    } else {
      uint32_t u;
      std::memcpy(&u, &f, 4);
      for (int i = 0; i < 4; ++i)
        b[i] = static_cast<uint8_t>(u >> (processor == c3d::kMips ? 24 - 8 * i : 8 * i));
    }
    o.insert(o.end(), b, b + 4);
  }

  std::vector<uint8_t> params() const {
    std::vector<uint8_t> o = {1, 0x50, 0, static_cast<uint8_t>(processor)};
    auto entry = [&](const std::string& name, bool locked, int id,
                     const std::vector<uint8_t>& body) {
      int n = static_cast<int>(name.size());
      o.push_back(static_cast<uint8_t>(static_cast<int8_t>(locked ? -n : n)));
      o.push_back(static_cast<uint8_t>(static_cast<int8_t>(id)));
      o.insert(o.end(), name.begin(), name.end());
      i16(o, static_cast<double>(body.size() + 2));
      if (name == swapped_offset) std::swap(o[o.size() - 2], o[o.size() - 1]);
      o.insert(o.end(), body.begin(), body.end());
    };
    for (const auto& g : groups) {
      std::vector<uint8_t> body = {static_cast<uint8_t>(g.desc.size())};
      body.insert(body.end(), g.desc.begin(), g.desc.end());
      entry(g.name, false, -g.id, body);
      for (const auto& p : g.params) {
        std::vector<uint8_t> b = {static_cast<uint8_t>(p.type),
                                  static_cast<uint8_t>(p.dims.size())};
        for (int d : p.dims) b.push_back(static_cast<uint8_t>(d));
        if (p.type == -1) b.insert(b.end(), p.chars.begin(), p.chars.end());
        for (double v : p.nums) {
          if (p.type == 1) b.push_back(static_cast<uint8_t>(v));
          if (p.type == 2) i16(b, v);
          if (p.type == 4) f32(b, v);
        }
        if (p.name != no_desc_byte) {
          b.push_back(static_cast<uint8_t>(p.desc.size()));
          b.insert(b.end(), p.desc.begin(), p.desc.end());
        }
        entry(p.name, p.locked, g.id, b);
      }
    }
    o.push_back(0);
    o.push_back(0);
    o.resize((o.size() + 511) / 512 * 512, 0);
    o[2] = static_cast<uint8_t>(o.size() / 512);
    return o;
  }

  std::vector<uint8_t> bytes() const {
    std::vector<uint8_t> p = params();
    const size_t data_start = 2 + p.size() / 512;
    std::vector<uint8_t> h(512, 0);
    h[0] = 2;
    h[1] = 0x50;
    long last = header_last >= 0 ? header_last : first + static_cast<long>(frames) - 1;
    u16at(h, 2, static_cast<uint16_t>(points));
    u16at(h, 4, static_cast<uint16_t>(channels * spf));
    u16at(h, 6, static_cast<uint16_t>(first));
    u16at(h, 8, static_cast<uint16_t>(last));
    std::vector<uint8_t> t;
    f32(t, is_float ? -scale : scale);
    f32(t, rate);
    std::copy(t.begin(), t.begin() + 4, h.begin() + 12);
    u16at(h, 16, static_cast<uint16_t>(data_start));
    u16at(h, 18, static_cast<uint16_t>(spf));
    std::copy(t.begin() + 4, t.end(), h.begin() + 20);
    std::vector<uint8_t> o(h.size() + p.size());
    std::copy(h.begin(), h.end(), o.begin());
    std::copy(p.begin(), p.end(), o.begin() + static_cast<long>(h.size()));
    size_t nf = std::min(frames, frames_written);
    for (size_t f = 0; f < nf; ++f) {
      for (size_t q = 0; q < points; ++q) {
        const Sample& s = samples[f * points + q];
        for (double v : {s.x, s.y, s.z, s.w}) is_float ? f32(o, v) : i16(o, v);
      }
      for (size_t k = 0; k < spf * channels; ++k) {
        double v = analog[f * spf * channels + k];
        is_float ? f32(o, v) : i16(o, v);
      }
    }
    return o;
  }
};

// Standard groups for a builder: POINT (1), ANALOG (2).
void standard_groups(Built& b, const std::vector<std::string>& labels,
                     const std::vector<std::string>& analog_labels = {}) {
  Group pg{1, "POINT", "3-D point parameters", {}};
  pg.params.push_back(ints("USED", {static_cast<double>(b.points)}));
  pg.params.push_back(ints("FRAMES", {static_cast<double>(b.frames)}));
  pg.params.push_back(ints("DATA_START", {0}));  // patched below
  pg.params.push_back(flt("SCALE", b.is_float ? -b.scale : b.scale));
  pg.params.push_back(flt("RATE", b.rate));
  pg.params.push_back(str("UNITS", "mm"));
  for (size_t k = 0; k * 255 < labels.size() || k == 0; ++k) {
    size_t e = std::min(labels.size(), (k + 1) * 255);
    pg.params.push_back(strs(k == 0 ? "LABELS" : "LABELS" + std::to_string(k + 1),
                             std::vector<std::string>(labels.begin() + static_cast<long>(k * 255),
                                                      labels.begin() + static_cast<long>(e)),
                             8));
  }
  pg.params[0].desc = "Number of points";
  pg.params[0].locked = true;
  b.groups.push_back(pg);
  Group ag{2, "ANALOG", "Analog parameters", {}};
  ag.params.push_back(ints("USED", {static_cast<double>(b.channels)}));
  ag.params.push_back(flt("RATE", b.rate * static_cast<double>(b.spf)));
  if (!analog_labels.empty()) ag.params.push_back(strs("LABELS", analog_labels, 6));
  b.groups.push_back(ag);
  // DATA_START: the parameter section size does not depend on its value.
  size_t ds = 2 + b.params().size() / 512;
  b.groups[0].params[2].nums = {static_cast<double>(ds)};
}

// A little gait-like trial: 3 points x 4 frames, one gap, 2 analog channels x 2 samples.
Built small_trial(int processor, bool is_float) {
  Built b;
  b.processor = processor;
  b.is_float = is_float;
  b.scale = 0.25;
  b.points = 3;
  b.frames = 4;
  b.channels = 2;
  b.spf = 2;
  for (size_t f = 0; f < b.frames; ++f)
    for (size_t p = 0; p < b.points; ++p) {
      double ix = 100 + 10.0 * static_cast<double>(p) + static_cast<double>(f);
      double iy = -50 - static_cast<double>(f * p);
      double iz = 1000 + static_cast<double>(p);
      double w = static_cast<double>(((p + 1) << 8) | (f + 2));  // mask p+1, residual f+2 steps
      Sample s =
          is_float ? Sample{ix * b.scale, iy * b.scale, iz * b.scale, w} : Sample{ix, iy, iz, w};
      if (f == 2 && p == 1) s = {0, 0, 0, -1};  // a gap
      b.samples.push_back(s);
    }
  for (size_t k = 0; k < b.frames * b.spf * b.channels; ++k)
    b.analog.push_back(static_cast<double>(static_cast<long>(k) * 37 - 200));
  standard_groups(b, {"LASI", "RASI", "LHEE"}, {"FZ1", "EMG1"});
  return b;
}

Take read(const Built& b) {
  auto v = b.bytes();
  return read_c3d_bytes(v.data(), v.size(), "test.c3d");
}

bool has_warning(const Take& t, const std::string& part) {
  for (const auto& w : t.warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

}  // namespace

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

// ---- writing --------------------------------------------------------------------------------

TEST(C3DWrite, ReadWriteReadIsExactForEveryEncoding) {
  for (int proc : {c3d::kIntel, c3d::kDec, c3d::kMips})
    for (bool fl : {false, true}) {
      SCOPED_TRACE("processor " + std::to_string(proc) + (fl ? " float" : " int16"));
      Take t = read(small_trial(proc, fl));
      auto bytes = c3d::encode_c3d_file(t, {}, "rt.c3d");
      EXPECT_EQ(bytes[512 + 3], c3d::kIntel);
      Take back = read_c3d_bytes(bytes.data(), bytes.size(), "rt.c3d");
      expect_same_take(t, back);
      EXPECT_EQ(back.c3d->float_storage, fl);
      EXPECT_TRUE(back.warnings.empty());
      // Every parameter kept, in order, with its description and lock; only DATA_START moves.
      expect_same_groups(t.c3d->groups, back.c3d->groups, {"POINT:DATA_START"});
      // A second generation is byte-identical.
      EXPECT_EQ(c3d::encode_c3d_file(back, {}, "rt2.c3d"), bytes);
    }
}

// Some writers store counts as one byte (sample_35's Mega Electronics file: POINT:DATA_START).
// The writer updates such a parameter in place: still one byte while the value fits one.
TEST(C3DWrite, ByteTypedCountsStayOneByte) {
  Built b = small_trial(c3d::kIntel, false);
  for (Param& p : b.groups[0].params)
    if (p.name == "DATA_START" || p.name == "USED") p.type = 1;
  Take t = read(b);
  ASSERT_EQ(t.c3d->param("POINT", "DATA_START")->type, 1);
  auto bytes = c3d::encode_c3d_file(t, {}, "byte.c3d");
  Take back = read_c3d_bytes(bytes.data(), bytes.size(), "byte.c3d");
  for (const char* name : {"DATA_START", "USED"}) {
    SCOPED_TRACE(name);
    const C3DParameter* p = back.c3d->param("POINT", name);
    ASSERT_NE(p, nullptr);
    EXPECT_EQ(p->type, 1);
    EXPECT_EQ(p->data.size(), 1u);
  }
  EXPECT_EQ(back.c3d->param("POINT", "USED")->as_ints()[0], 3);
  const int header_data_start = bytes[16] | bytes[17] << 8;  // header word 9
  EXPECT_EQ(back.c3d->param("POINT", "DATA_START")->as_ints()[0], header_data_start);
  expect_same_take(t, back);
}

TEST(C3DWrite, Int16StorageKeepsTheStoredIntegers) {
  Built b = small_trial(c3d::kIntel, false);
  b.scale = 0.0833333;  // not exact in binary
  b.groups.clear();
  standard_groups(b, {"A", "B", "C"});
  Take t = read(b);
  auto bytes = c3d::encode_c3d_file(t, {}, "q.c3d");
  Take back = read_c3d_bytes(bytes.data(), bytes.size(), "q.c3d");
  EXPECT_FALSE(back.c3d->float_storage);
  EXPECT_EQ(0, std::memcmp(t.xyz.data(), back.xyz.data(), t.xyz.size() * 8));
  // The data section of the written file holds the same integers as the source.
  auto src = b.bytes();
  size_t src_data = (static_cast<size_t>(src[16] | (src[17] << 8)) - 1) * 512;
  size_t out_data = (static_cast<size_t>(bytes[16] | (bytes[17] << 8)) - 1) * 512;
  ASSERT_EQ(src.size() - src_data, bytes.size() - out_data);
  EXPECT_TRUE(std::equal(src.begin() + static_cast<long>(src_data), src.end(),
                         bytes.begin() + static_cast<long>(out_data)));

  // c3d_float writes float; values stay within float precision of the int16 grid.
  WriteOptions o;
  o.c3d_float = true;
  auto fb = c3d::encode_c3d_file(t, o, "f.c3d");
  Take ft = read_c3d_bytes(fb.data(), fb.size(), "f.c3d");
  EXPECT_TRUE(ft.c3d->float_storage);
  for (size_t i = 0; i < t.xyz.size(); ++i) EXPECT_NEAR(ft.xyz[i], t.xyz[i], 1e-3);
}

TEST(C3DWrite, TakeFromElsewhereGetsAFreshParameterSection) {
  Take t;
  t.format = Format::kTRC;
  t.resize(5, 2);
  t.rate = 60;
  t.units = "m";
  t.first_frame = 10;
  t.labels = {"head", "toe"};
  for (size_t f = 0; f < 5; ++f)
    for (size_t p = 0; p < 2; ++p) {
      if (f == 3 && p == 0) continue;
      double* x = t.at(f, p);
      x[0] = 0.5 + 0.001 * static_cast<double>(f);
      x[1] = static_cast<float>(1.25 * static_cast<double>(p));
      x[2] = -0.75;
      t.valid[f * 2 + p] = 1;
    }
  for (auto& v : t.xyz) v = static_cast<float>(v);  // exact in float storage
  auto bytes = c3d::encode_c3d_file(t, {}, "fresh.c3d");
  Take back = read_c3d_bytes(bytes.data(), bytes.size(), "fresh.c3d");
  EXPECT_TRUE(back.warnings.empty()) << back.warnings[0];
  EXPECT_TRUE(back.c3d->float_storage);
  EXPECT_EQ(back.valid, t.valid);
  EXPECT_EQ(back.xyz, t.xyz);
  EXPECT_EQ(back.labels, t.labels);
  EXPECT_EQ(back.units, "m");
  EXPECT_DOUBLE_EQ(back.rate, 60);
  EXPECT_EQ(back.first_frame, 10);
  for (const char* g : {"POINT", "ANALOG", "TRIAL"}) EXPECT_NE(back.c3d->group(g), nullptr) << g;
  EXPECT_NE(back.c3d->param("POINT", "SCALE"), nullptr);
  EXPECT_LT(back.c3d->param("POINT", "SCALE")->as_floats()[0], 0);
}

// new_c3d_parameters gives the section write_c3d writes for a take alone: setting it as the
// take's section changes no byte, and a group added to it is written beside it.
TEST(C3DWrite, NewParameterSectionIsWhatTheWriterGivesATakeAlone) {
  for (int with_analog = 0; with_analog < 2; ++with_analog) {
    Take t;
    t.resize(7, 3);
    t.rate = 120;
    t.units = "mm";
    t.first_frame = 4;
    t.labels = {"A", "B", "C"};
    for (size_t i = 0; i < t.valid.size(); ++i) {
      t.valid[i] = i % 5 != 2;
      for (int a = 0; a < 3; ++a)
        t.xyz[3 * i + a] = t.valid[i] ? 1000.5 - 37.25 * static_cast<double>(i + a) : 0;
    }
    if (with_analog) {
      t.analog.channels = 2;
      t.analog.samples_per_frame = 4;
      t.analog.rate = 480;
      t.analog.labels = {"Fz", "EMG"};
      t.analog.values.resize(7 * 4 * 2);
      for (size_t i = 0; i < t.analog.values.size(); ++i)
        t.analog.values[i] = 0.5 * static_cast<double>(i) - 3;
    }
    const auto alone = c3d::encode_c3d_file(t, {}, "alone.c3d");
    Take s = t;
    s.c3d = new_c3d_parameters(t, "s.c3d");
    EXPECT_TRUE(s.c3d->float_storage);
    EXPECT_EQ(s.c3d->point_scale, 0);
    EXPECT_EQ(c3d::encode_c3d_file(s, {}, "s.c3d"), alone) << with_analog;

    C3DGroup g;
    g.id = 9;
    g.name = "SUBJECTS";
    C3DParameter w;
    w.name = "WEIGHT";
    w.description = "kg";
    w.type = 4;
    w.data = {0, 0, 0x8c, 0x42};  // 70.0f
    g.params.push_back(w);
    s.c3d->groups.push_back(g);
    const auto with = c3d::encode_c3d_file(s, {}, "s.c3d");
    Take back = read_c3d_bytes(with.data(), with.size(), "s.c3d");
    ASSERT_NE(back.c3d->param("SUBJECTS", "WEIGHT"), nullptr);
    EXPECT_EQ(back.c3d->param("SUBJECTS", "WEIGHT")->as_floats(), std::vector<float>{70.0f});
    EXPECT_EQ(back.xyz, read_c3d_bytes(alone.data(), alone.size(), "a").xyz);
    EXPECT_EQ(back.analog.values, t.analog.values);
    EXPECT_EQ(back.first_frame, 4);
  }
  Take big;
  big.resize(1, 70000);
  EXPECT_THROW(new_c3d_parameters(big, "big"), Error);
}

TEST(C3DWrite, WritesAtomicallyAndRefusesToOverwrite) {
  capz_test::TempDir tmp("capz_c3d_unit");
  const std::string dir = tmp.path().string();
  std::string out = tmp.file("walk.c3d");
  Take t = read(small_trial(c3d::kDec, true));
  write_c3d(t, out);
  Take back = read_c3d(out);
  expect_same_take(t, back);
  try {
    write_c3d(t, out);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kUsage);
  }
  WriteOptions o;
  o.overwrite = true;
  write_c3d(t, out, o);
  size_t entries = 0;
  for (const auto& e : fs::directory_iterator(dir)) (void)e, ++entries;
  EXPECT_EQ(entries, 1u);  // no temporary left behind
}

// ---- parameter codec ------------------------------------------------------------------------

TEST(C3DParams, EncodeDecodeIsExact) {
  Built b = small_trial(c3d::kMips, true);
  b.groups[0].params.push_back({"BYTES", 1, {3}, {1, 200, 255}, "", "raw bytes", true});
  b.groups[0].params.push_back({"MATRIX", 4, {2, 3}, {1, 2, 3, 4.5, -5, 1e-8}, "", "", false});
  b.groups[0].params.push_back({"EMPTY", -1, {0, 0}, {}, "", "", false});
  b.groups.push_back({9, "CUSTOM", "locked group", {}});
  Take t = read(b);
  C3DExtra x = *t.c3d;
  C3DGroup implicit;
  implicit.id = 12;
  implicit.implicit = true;
  implicit.params.push_back(x.groups[0].params[0]);
  x.groups.push_back(implicit);
  x.groups[2].locked = true;

  std::vector<uint8_t> enc = encode_c3d_parameters(x);
  ASSERT_EQ(enc.size() % 512, 0u);
  EXPECT_EQ(enc[3], 84);
  EXPECT_EQ(enc[2], enc.size() / 512);
  C3DExtra y;
  decode_c3d_parameters(enc.data(), enc.size(), "params", &y);
  expect_same_groups(x.groups, y.groups);
  EXPECT_EQ(encode_c3d_parameters(y), enc);
  EXPECT_EQ(y.param("POINT", "MATRIX")->as_floats()[3], 4.5f);
  EXPECT_EQ(y.param("POINT", "BYTES")->as_ints()[1], 200);

  // A cut section is an error for the container, never a silent loss.
  for (size_t cut : {size_t{3}, size_t{40}, size_t{300}}) {
    try {
      decode_c3d_parameters(enc.data(), cut, "params", &y);
      ADD_FAILURE() << cut;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
      EXPECT_NE(std::string(e.what()).find("params"), std::string::npos);
    }
  }
}

TEST(C3DParams, EncoderRejectsWhatC3DCannotHold) {
  C3DExtra x;
  C3DGroup g;
  g.id = 1;
  g.name = "POINT";
  C3DParameter p;
  p.name = "BAD";
  p.type = 2;
  p.dims = {3};
  p.data = {1, 2};  // 2 bytes for 3 int16
  g.params.push_back(p);
  x.groups.push_back(g);
  EXPECT_THROW(encode_c3d_parameters(x), Error);
  x.groups[0].params[0].dims = {1};
  x.groups[0].name = std::string(200, 'A');
  EXPECT_THROW(encode_c3d_parameters(x), Error);
}

// ---- EVENT group ------------------------------------------------------------------------------

namespace {
C3DParameter float_array(const std::string& name, std::vector<int> dims, std::vector<float> v) {
  C3DParameter p;
  p.name = name;
  p.type = 4;
  p.dims = std::move(dims);
  p.data.resize(4 * v.size());
  for (size_t i = 0; i < v.size(); ++i) std::memcpy(&p.data[4 * i], &v[i], 4);
  return p;
}
}  // namespace

TEST(C3DEvents, FieldsFromTheEventGroupWhereGiven) {
  C3DExtra x;
  EXPECT_TRUE(c3d_events(x).empty());
  C3DGroup& g = c3d::ensure_group(x.groups, "EVENT", "");
  EXPECT_TRUE(c3d_events(x).empty());  // no TIMES: no event
  c3d::set_int16(c3d::ensure_param(g, "USED", ""), 3);
  g.params.push_back(float_array("TIMES", {2, 3}, {0, 1.5f, 2, 0.25f, 0, 7}));
  c3d::set_strings(c3d::ensure_param(g, "LABELS", ""), {"Foot Strike", "Foot Off", "Event"});
  c3d::set_strings(c3d::ensure_param(g, "CONTEXTS", ""), {"Left", "Right"});  // one short
  c3d::set_int16_array(c3d::ensure_param(g, "ICON_IDS", ""), {1, 2, 0});
  std::vector<C3DEvent> e = c3d_events(x);
  ASSERT_EQ(e.size(), 3u);
  EXPECT_EQ(e[0].label, "Foot Strike");
  EXPECT_EQ(e[0].context, "Left");
  EXPECT_DOUBLE_EQ(e[0].time, 1.5);
  EXPECT_DOUBLE_EQ(e[1].time, 120.25);  // 2 minutes and 0.25 s
  EXPECT_EQ(e[1].icon_id, 2);
  EXPECT_EQ(e[2].context, "");
  EXPECT_EQ(e[2].generic_flag, 0);  // GENERIC_FLAGS absent
  EXPECT_EQ(e[2].description, "");
  EXPECT_DOUBLE_EQ(e[2].time, 7);

  c3d::set_int16(*c3d::find_param(g, "USED"), 2);  // USED counts
  EXPECT_EQ(c3d_events(x).size(), 2u);
  c3d::set_int16(*c3d::find_param(g, "USED"), 9);  // never more than TIMES holds
  EXPECT_EQ(c3d_events(x).size(), 3u);
  C3DParameter& used = *c3d::find_param(g, "USED");  // a byte USED counts too
  used.type = 1;
  used.dims.clear();
  used.data = {1};
  EXPECT_EQ(c3d_events(x).size(), 1u);
  g.params.erase(g.params.begin());  // without USED, as many as TIMES holds
  EXPECT_EQ(c3d_events(x).size(), 3u);
  *c3d::find_param(g, "TIMES") = float_array("TIMES", {5}, {0, 1, 0, 2, 9});  // 1-D, odd
  e = c3d_events(x);
  ASSERT_EQ(e.size(), 2u);
  EXPECT_DOUBLE_EQ(e[1].time, 2);
}

TEST(C3DEvents, SetThenReadGivesThemBackAndSurvivesTheWriter) {
  std::vector<C3DEvent> ev(3);
  ev[0].label = "Foot Strike";
  ev[0].context = "Left";
  ev[0].time = 1.25;
  ev[0].icon_id = 1;
  ev[1].label = "Foot Off";
  ev[1].context = "Right";
  ev[1].description = "toe off";
  ev[1].subject = "S1";
  ev[1].time = 125.5;  // written as 2 minutes and 5.5 s
  ev[1].generic_flag = -3;
  ev[2].time = 0;

  Take t;
  t.resize(4, 1);
  t.rate = 100;
  t.units = "mm";
  for (size_t i = 0; i < 3; ++i) t.xyz[i] = 10.0 + static_cast<double>(i);
  t.valid[0] = 1;
  t.c3d = new_c3d_parameters(t, "ev.c3d");
  set_c3d_events(t.c3d.get(), ev);
  const C3DParameter* times = t.c3d->param("EVENT", "TIMES");
  ASSERT_NE(times, nullptr);
  EXPECT_EQ(times->dims, (std::vector<int>{2, 3}));
  EXPECT_EQ(times->as_floats()[2], 2.0f);
  EXPECT_EQ(times->as_floats()[3], 5.5f);
  auto same = [&](const std::vector<C3DEvent>& got) {
    ASSERT_EQ(got.size(), ev.size());
    for (size_t i = 0; i < ev.size(); ++i) {
      EXPECT_EQ(got[i].label, ev[i].label) << i;
      EXPECT_EQ(got[i].context, ev[i].context) << i;
      EXPECT_EQ(got[i].description, ev[i].description) << i;
      EXPECT_EQ(got[i].subject, ev[i].subject) << i;
      EXPECT_DOUBLE_EQ(got[i].time, ev[i].time) << i;
      EXPECT_EQ(got[i].icon_id, ev[i].icon_id) << i;
      EXPECT_EQ(got[i].generic_flag, ev[i].generic_flag) << i;
    }
  };
  same(c3d_events(*t.c3d));
  const auto bytes = c3d::encode_c3d_file(t, {}, "ev.c3d");
  same(c3d_events(*read_c3d_bytes(bytes.data(), bytes.size(), "ev.c3d").c3d));

  // Replacing: one event left in every list; refusals change nothing.
  ev.resize(1);
  set_c3d_events(t.c3d.get(), ev);
  same(c3d_events(*t.c3d));
  EXPECT_EQ(t.c3d->param("EVENT", "LABELS")->as_strings().size(), 1u);
  const std::vector<C3DGroup> before = t.c3d->groups;
  std::vector<C3DEvent> bad = ev;
  bad[0].time = -1;
  EXPECT_THROW(set_c3d_events(t.c3d.get(), bad), Error);
  bad[0].time = 1;
  bad[0].icon_id = 40000;
  EXPECT_THROW(set_c3d_events(t.c3d.get(), bad), Error);
  EXPECT_THROW(set_c3d_events(t.c3d.get(), std::vector<C3DEvent>(256)), Error);
  expect_same_groups(t.c3d->groups, before);
}

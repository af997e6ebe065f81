// Lossy analog channels (docs/FORMAT.md 16.3): the quantiser keeps every sample within its bound
// and on the channel's own lattice, the window codec codes the result exactly and smaller, META
// carries the bounds (and rejects bad ones), and compress / decompress / verify keep the promise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/take.h"
#include "capz/verify.h"
#include "coding/analog/analog_codec.h"
#include "coding/analog/analog_quant.h"
#include "coding/bytes.h"
#include "coding/container.h"
#include "coding/entropy.h"
#include "coding/lzma_block.h"
#include "coding/meta.h"
#include "test_util.h"

using namespace capz;
using analog::ChannelBound;
using analog::ChannelHint;
using capz_test::error_of;

namespace {

uint64_t bits(double v) {
  uint64_t b;
  std::memcpy(&b, &v, 8);
  return b;
}

// An EMG-like noisy signal in int16 counts.
std::vector<double> noisy_counts(size_t n, unsigned seed, double amplitude) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g(0, amplitude);
  std::vector<double> v(n);
  double slow = 0;
  for (size_t i = 0; i < n; ++i) {
    slow = 0.99 * slow + g(rng) * 0.1;
    v[i] = std::max(-32768.0, std::min(32767.0, std::round(slow * 20 + g(rng))));
  }
  return v;
}

ChannelBound int16_bound(double bound, double factor) {
  ChannelBound b;
  b.bound = bound;
  b.factor = factor;
  b.integers = true;
  b.lo = -32768;
  b.hi = 32767;
  return b;
}

size_t coded_size(const std::vector<double>& v, const ChannelHint& h = {}) {
  AnalogHints hints;
  hints.channel.push_back(h);
  return encode_analog_window(v.data(), v.size(), 1, hints).size();
}

std::vector<double> round_trip(const std::vector<double>& v, const ChannelHint& h) {
  AnalogHints hints;
  hints.channel.push_back(h);
  const std::vector<uint8_t> b = encode_analog_window(v.data(), v.size(), 1, hints);
  std::vector<double> back(v.size());
  decode_analog_window(b.data(), b.size(), v.size(), 1, back.data(), "t");
  return back;
}

}  // namespace

TEST(AnalogQuantiser, GivenInt16CountsThenWithinBoundOnTheOddLatticeAndSmaller) {
  const std::vector<double> orig = noisy_counts(8000, 1, 300);
  // 0.01 N per count and a bound of 0.052 N: 5 counts, so every 11th count.
  const ChannelBound b = int16_bound(0.052, 0.01);
  std::vector<double> q = orig;
  const ChannelHint h = analog::quantise_channel(q.data(), 1, q.size(), b, {});
  EXPECT_EQ(h.lattice_step, 11);
  size_t moved = 0;
  for (size_t i = 0; i < q.size(); ++i) {
    EXPECT_LE(std::fabs(q[i] - orig[i]), 5) << i;
    EXPECT_TRUE(analog::within_bound(q[i], orig[i], b));
    EXPECT_EQ(q[i], std::floor(q[i]));
    EXPECT_EQ(std::fmod(std::fabs(q[i]), 11.0), 0.0) << q[i];
    moved += q[i] != orig[i];
  }
  EXPECT_GT(moved, q.size() / 2);
  EXPECT_EQ(round_trip(q, h), q);  // the codec codes the quantised samples exactly
  // log2(11) = 3.46 bits a sample fewer; at least 80% of that saved.
  EXPECT_LT(static_cast<double>(coded_size(q, h)),
            static_cast<double>(coded_size(orig)) - 0.8 * 3.46 * 8000 / 8)
      << coded_size(q, h) << " vs " << coded_size(orig);
}

TEST(AnalogQuantiser, GivenABoundFinerThanTheStepThenTheChannelIsLeftAlone) {
  const std::vector<double> orig = noisy_counts(1000, 2, 100);
  std::vector<double> q = orig;
  const ChannelHint h =
      analog::quantise_channel(q.data(), 1, q.size(), int16_bound(0.009, 0.01), {});
  EXPECT_EQ(h.lattice_step, 0);
  EXPECT_EQ(q, orig);
}

TEST(AnalogQuantiser, GivenScaledFloatsThenTheyStayOnTheirAdcLattice) {
  // float32 samples that are counts x 2^-12 V + 0.25 (a float file of ADC counts in volts).
  const std::vector<double> counts = noisy_counts(4000, 3, 500);
  const double s0 = 1.0 / 4096, o0 = 0.25;
  std::vector<double> orig(counts.size());
  for (size_t i = 0; i < counts.size(); ++i)
    orig[i] = static_cast<double>(static_cast<float>(counts[i] * s0 + o0));
  ChannelBound b;
  b.bound = 3.5 * s0;  // volts; factor 1: m = 3, every 7th step
  b.factor = 1;
  b.lo = -1e30;
  b.hi = 1e30;
  std::vector<double> q = orig;
  const ChannelHint h = analog::quantise_channel(q.data(), 1, q.size(), b, {});
  EXPECT_NEAR(h.lattice_step, 7 * s0, 1e-12);
  for (size_t i = 0; i < q.size(); ++i) {
    ASSERT_LE(std::fabs(q[i] - orig[i]), b.bound) << i;
    const double k = (q[i] - o0) / s0;  // still a whole number of ADC steps
    EXPECT_NEAR(k, std::round(k), 1e-6) << i;
    EXPECT_EQ(static_cast<double>(static_cast<float>(q[i])), q[i]);
  }
  EXPECT_EQ(round_trip(q, h), q);
  EXPECT_LT(coded_size(q, h), coded_size(orig));
}

TEST(AnalogQuantiser, GivenFloatsOnNoLatticeThenWithinBoundAndFloat32) {
  std::mt19937 rng(4);
  std::normal_distribution<double> g(0, 1);
  std::vector<double> orig(5000);
  double x = 0;
  for (double& v : orig) v = static_cast<double>(static_cast<float>(x = 0.9 * x + g(rng)));
  ChannelBound b;
  b.bound = 0.01;
  b.factor = 2;  // physical = 2 x stored: 0.005 stored units
  b.lo = -1e30;
  b.hi = 1e30;
  std::vector<double> q = orig;
  const ChannelHint h = analog::quantise_channel(q.data(), 1, q.size(), b, {});
  EXPECT_NEAR(h.lattice_step, 0.01, 1e-6);
  for (size_t i = 0; i < q.size(); ++i) {
    ASSERT_LE(std::fabs(q[i] - orig[i]) * 2, 0.01) << i;
    EXPECT_EQ(static_cast<double>(static_cast<float>(q[i])), q[i]);
  }
  EXPECT_EQ(round_trip(q, h), q);
  EXPECT_LT(coded_size(q, h) * 2, coded_size(orig));
}

TEST(AnalogQuantiser, GivenGapsAndStorageEdgesThenThoseSamplesAreKept) {
  std::vector<double> orig = noisy_counts(2000, 5, 200);
  double nan_payload;
  const uint64_t payload = 0x7ff8000000001234ull;
  std::memcpy(&nan_payload, &payload, 8);
  orig[10] = nan_payload;
  orig[11] = std::numeric_limits<double>::infinity();
  orig[12] = 65535;  // uint16 storage: the top count
  orig[13] = 0;
  ChannelBound b = int16_bound(7, 1);  // 7 counts: every 15th
  b.lo = 0;
  b.hi = 65535;
  b.offset = 3;  // physical zero at count 3: the lattice goes through it
  for (double& v : orig)
    if (std::isfinite(v)) v = std::fabs(v);
  std::vector<double> q = orig;
  const ChannelHint h = analog::quantise_channel(q.data(), 1, q.size(), b, {});
  EXPECT_EQ(h.lattice_step, 15);
  EXPECT_EQ(h.lattice_offset, 3);
  EXPECT_EQ(bits(q[10]), payload);
  EXPECT_TRUE(std::isinf(q[11]));
  EXPECT_LE(q[12], 65535);  // 65538 would be the nearest lattice point: out of range, kept
  EXPECT_EQ(q[12], 65535);
  for (size_t i = 0; i < q.size(); ++i)
    if (std::isfinite(orig[i])) {
      EXPECT_LE(std::fabs(q[i] - orig[i]), 7) << i;
      EXPECT_GE(q[i], 0);
    }
  const std::vector<double> back = round_trip(q, h);
  for (size_t i = 0; i < q.size(); ++i) EXPECT_EQ(bits(back[i]), bits(q[i])) << i;
}

// ---- META ------------------------------------------------------------------------------------

namespace {

Take take_with_analog(int channels) {
  Take t;
  t.format = Format::kC3D;
  t.frames = 4;
  t.points = 0;
  t.analog.channels = channels;
  t.analog.samples_per_frame = 1;
  t.analog.rate = 100;
  t.analog.labels.assign(static_cast<size_t>(channels), "ch");
  return t;
}

Take meta_round_trip(const std::vector<uint8_t>& payload, int channels) {
  std::vector<uint8_t> buf;
  append_chunk(&buf, "META", payload);
  const Chunk c = read_chunk(buf.data(), buf.size(), 0, "t");
  Take t;
  t.frames = 4;
  t.analog.channels = channels;
  bool words = false;
  decode_meta(c, "t", &t, &words, 8);
  return t;
}

// META's fields (codings 0 and 2) as coding 0, with `extra` appended.
std::vector<uint8_t> as_coding0(const std::vector<uint8_t>& meta,
                                const std::vector<uint8_t>& extra = {}) {
  ByteReader r(meta.data(), meta.size(), "t");
  const uint8_t coding = r.u8();
  std::vector<uint8_t> fields;
  if (coding == 0) {
    fields.assign(meta.begin() + 1, meta.end());
  } else if (coding == 1) {
    const size_t n = static_cast<size_t>(r.varint());
    fields = decode_bytes(meta.data() + r.offset(), r.remaining(), n, "t");
  } else {
    EXPECT_EQ(coding, 2);
    const size_t n = static_cast<size_t>(r.varint());
    fields = lzma2_decode(meta.data() + r.offset(), r.remaining(), n, "t");
  }
  std::vector<uint8_t> out(1 + fields.size(), 0);
  std::copy(fields.begin(), fields.end(), out.begin() + 1);
  out.insert(out.end(), extra.begin(), extra.end());
  return out;
}

}  // namespace

TEST(AnalogLossyMeta, GivenBoundsThenTheyComeBackAndLosslessTakesWriteNothing) {
  Take t = take_with_analog(5);
  const std::vector<uint8_t> plain = as_coding0(encode_meta(t, false));
  t.analog.bounds = {0, 0.05, 0, 0, 2.5};
  t.analog.factors = {1, 0.01, 1, 1, 0.125};
  const std::vector<uint8_t> meta = encode_meta(t, false);
  const Take back = meta_round_trip(meta, 5);
  EXPECT_EQ(back.analog.bounds, t.analog.bounds);
  EXPECT_EQ(back.analog.factors, t.analog.factors);
  // The block is appended: the lossless take's fields are a prefix of the lossy one's.
  const std::vector<uint8_t> lossy = as_coding0(meta);
  ASSERT_GT(lossy.size(), plain.size());
  EXPECT_TRUE(std::equal(plain.begin(), plain.end(), lossy.begin()));
  EXPECT_TRUE(meta_round_trip(plain, 5).analog.bounds.empty());
}

TEST(AnalogLossyMeta, GivenBadBoundBlocksThenCorrupt) {
  const Take t = take_with_analog(3);
  const std::vector<uint8_t> meta = encode_meta(t, false);
  auto block = [](uint64_t nb, std::vector<std::pair<uint64_t, std::pair<double, double>>> e) {
    ByteWriter w;
    w.varint(nb);
    for (const auto& x : e) {
      w.varint(x.first);
      w.f64(x.second.first);
      w.f64(x.second.second);
    }
    return w.buffer();
  };
  const ErrorCode corrupt = ErrorCode::kCorrupt;
  auto dec = [&](const std::vector<uint8_t>& extra) {
    return error_of([&] { meta_round_trip(as_coding0(meta, extra), 3); });
  };
  EXPECT_NO_THROW(meta_round_trip(as_coding0(meta, block(1, {{2, {0.5, 1}}})), 3));
  EXPECT_EQ(dec(block(0, {})), corrupt);
  EXPECT_EQ(dec(block(4, {{0, {1, 1}}, {0, {1, 1}}, {0, {1, 1}}, {0, {1, 1}}})), corrupt);
  EXPECT_EQ(dec(block(1, {{3, {1, 1}}})), corrupt);               // channel 3 of 3
  EXPECT_EQ(dec(block(2, {{1, {1, 1}}, {1, {1, 1}}})), corrupt);  // 1, then 3
  EXPECT_EQ(dec(block(1, {{0, {-1, 1}}})), corrupt);
  EXPECT_EQ(dec(block(1, {{0, {0, 1}}})), corrupt);
  EXPECT_EQ(dec(block(1, {{0, {1, 0}}})), corrupt);
  EXPECT_EQ(dec(block(1, {{0, {std::numeric_limits<double>::infinity(), 1}}})), corrupt);
  EXPECT_EQ(dec(block(1, {{0, {std::nan(""), 1}}})), corrupt);
  EXPECT_EQ(dec({0x01, 0x00, 0x01}), corrupt);  // truncated
}

// ---- the whole codec on real takes -----------------------------------------------------------

namespace {

struct Lossy {
  Take original, decoded;
  StreamInfo info;
  size_t bytes = 0, lossless_bytes = 0;
};

Lossy compress_lossy(const std::string& path, const std::map<std::string, double>& bounds) {
  Lossy r;
  r.original = read_take(path);
  CompressOptions o;
  o.max_error = 0.1;
  const std::vector<uint8_t> plain = compress(r.original, o);
  o.analog_max_error = bounds;
  const std::vector<uint8_t> b = compress(r.original, o);
  r.bytes = b.size();
  r.lossless_bytes = plain.size();
  r.info = describe(b.data(), b.size(), path);
  r.decoded = decompress(b.data(), b.size(), path);
  return r;
}

}  // namespace

TEST(AnalogLossyCodec, GivenAForcePlateTakeThenBoundsHoldInPhysicalUnitsAndItShrinks) {
  const std::string path = std::string(CAPZ_REPO_DATA) + "/EB015PI.c3d";
  const Lossy r = compress_lossy(path, {{"nt", 0.5}, {"ntmm", 50}});
  const std::vector<AnalogPhysics> phys = analog_physics(r.original);
  ASSERT_EQ(r.info.analog_bounds.size(), phys.size());
  EXPECT_FALSE(r.info.lossless);
  size_t lossy = 0, moved = 0;
  for (size_t c = 0; c < phys.size(); ++c) {
    const double want = phys[c].unit == "nt" ? 0.5 : phys[c].unit == "ntmm" ? 50 : 0;
    EXPECT_EQ(r.info.analog_bounds[c], want) << c;
    if (want > 0) {
      ++lossy;
      EXPECT_EQ(r.info.analog_factors[c], phys[c].factor);
    }
  }
  EXPECT_EQ(lossy, 12u);
  const size_t C = phys.size();
  const std::vector<double>&a = r.original.analog.values, &d = r.decoded.analog.values;
  ASSERT_EQ(a.size(), d.size());
  for (size_t i = 0; i < a.size(); ++i) {
    const size_t c = i % C;
    if (r.info.analog_bounds[c] > 0) {
      ASSERT_LE(std::fabs(a[i] - d[i]) * phys[c].factor, r.info.analog_bounds[c]) << i;
      moved += a[i] != d[i];
    } else {
      ASSERT_EQ(bits(a[i]), bits(d[i])) << "lossless channel " << c << " sample " << i;
    }
  }
  EXPECT_GT(moved, 0u);
  EXPECT_LT(r.bytes, r.lossless_bytes);
  EXPECT_TRUE(check_promise(r.original, r.decoded, promise_of(r.info)).holds);
  // The same decoded take against an exact promise fails: the check is not vacuous.
  Promise exact = promise_of(r.info);
  exact.analog_bounds.clear();
  EXPECT_FALSE(check_promise(r.original, r.decoded, exact).holds);
}

TEST(AnalogLossyCodec, GivenALabelAndItsUnitThenTheLabelWinsAndUnknownKeysAreReported) {
  const std::string path = std::string(CAPZ_REPO_DATA) + "/EB015PI.c3d";
  const Take t = read_take(path);
  const std::vector<AnalogPhysics> phys = analog_physics(t);
  size_t first_nt = 0;
  while (first_nt < phys.size() && phys[first_nt].unit != "nt") ++first_nt;
  ASSERT_LT(first_nt, phys.size());
  const std::string label = t.analog.labels[first_nt];
  ASSERT_FALSE(label.empty());
  CompressOptions o;
  o.max_error = 0.1;
  o.analog_max_error = {{"nt", 0.5}, {label, 2}, {"Parsec", 1}};
  CompressStats st;
  const std::vector<uint8_t> b = compress(t, o, &st);
  const StreamInfo si = describe(b.data(), b.size());
  EXPECT_EQ(si.analog_bounds[first_nt], 2);
  for (size_t c = first_nt + 1; c < phys.size(); ++c)
    if (phys[c].unit == "nt" && t.analog.labels[c] != label) {
      EXPECT_EQ(si.analog_bounds[c], 0.5);
    }
  EXPECT_EQ(st.analog_unmatched, std::vector<std::string>{"Parsec"});
}

// More than 255 analog channels continue ANALOG:SCALE, OFFSET and UNITS in SCALE2, OFFSET2,
// UNITS2 (a parameter holds at most 255 entries): the channels past 255 take their physics from
// the continuations, not a factor of 1 and no unit.
TEST(AnalogLossyCodec, GivenMoreThan255ChannelsThenPhysicsFromTheNumberedContinuations) {
  auto floats = [](const std::string& name, size_t n, float v) {
    C3DParameter p;
    p.name = name;
    p.type = 4;
    p.dims = {static_cast<int>(n)};
    p.data.resize(4 * n);
    for (size_t i = 0; i < n; ++i) std::memcpy(p.data.data() + 4 * i, &v, 4);
    return p;
  };
  auto units = [](const std::string& name, size_t n, const std::string& u) {
    C3DParameter p;
    p.name = name;
    p.type = -1;
    p.dims = {4, static_cast<int>(n)};
    for (size_t i = 0; i < n; ++i) {
      std::string e = u;
      e.resize(4, ' ');
      p.data.insert(p.data.end(), e.begin(), e.end());
    }
    return p;
  };
  Take t;
  t.analog.channels = 300;
  t.analog.samples_per_frame = 1;
  t.c3d = std::make_shared<C3DExtra>();
  C3DGroup g;
  g.id = 2;
  g.name = "ANALOG";
  g.params = {floats("SCALE", 255, -0.5f),  floats("SCALE2", 45, 0.25f),
              floats("GEN_SCALE", 1, 2.0f), floats("OFFSET", 255, 10.0f),
              floats("OFFSET2", 45, 20.0f), units("UNITS", 255, "V"),
              units("UNITS2", 45, "N")};
  g.params[2].dims.clear();  // GEN_SCALE: one value
  t.c3d->groups.push_back(g);
  const std::vector<AnalogPhysics> phys = analog_physics(t);
  ASSERT_EQ(phys.size(), 300u);
  EXPECT_EQ(phys[0].scale, -1.0);
  EXPECT_EQ(phys[0].factor, 1.0);
  EXPECT_EQ(phys[0].offset, 10.0);
  EXPECT_EQ(phys[0].unit, "V");
  EXPECT_EQ(phys[254].unit, "V");
  EXPECT_EQ(phys[255].scale, 0.5);
  EXPECT_EQ(phys[299].factor, 0.5);
  EXPECT_EQ(phys[299].offset, 20.0);
  EXPECT_EQ(phys[299].unit, "N");
  const AnalogHints h = analog_hints(t);
  ASSERT_EQ(h.channel.size(), 300u);
  EXPECT_EQ(h.channel[299].scale, 0.5);
}

TEST(AnalogLossyCodec, GivenUnitsSpelledSeveralWaysThenOneSpelling) {
  for (const char* v : {"V", "Volt", " volts ", "VOLT"}) EXPECT_EQ(canonical_analog_unit(v), "V");
  for (const char* n : {"N", "nt", "Newtons", "newton"}) EXPECT_EQ(canonical_analog_unit(n), "N");
  for (const char* nm : {"Nm", "N-M", "N.m", "ntm"}) EXPECT_EQ(canonical_analog_unit(nm), "Nm");
  for (const char* nmm : {"Nmm", "ntmm", "N.mm", "N-mm"})
    EXPECT_EQ(canonical_analog_unit(nmm), "Nmm");
  EXPECT_EQ(canonical_analog_unit("mV"), "mV");
  EXPECT_EQ(canonical_analog_unit("uV"), "uV");
  EXPECT_EQ(canonical_analog_unit(" d.u. "), "d.u.");  // unknown: as written, trimmed
  EXPECT_EQ(canonical_analog_unit("Rad/s"), "Rad/s");
  // A take whose force channels say "nt" is bounded by a key "N".
  const Take t = read_take(std::string(CAPZ_REPO_DATA) + "/EB015PI.c3d");
  CompressOptions o;
  o.max_error = 0.1;
  o.analog_max_error = {{"N", 0.5}};
  CompressStats st;
  const std::vector<uint8_t> b = compress(t, o, &st);
  const StreamInfo si = describe(b.data(), b.size());
  const std::vector<AnalogPhysics> phys = analog_physics(t);
  ASSERT_EQ(si.analog_bounds.size(), phys.size());
  for (size_t c = 0; c < phys.size(); ++c)
    EXPECT_EQ(si.analog_bounds[c], phys[c].unit == "nt" ? 0.5 : 0.0) << c;
  EXPECT_TRUE(st.analog_unmatched.empty());
}

TEST(AnalogLossyCodec, GivenLosslessOrABadBoundThenInvalidParameter) {
  const Take t = read_take(std::string(CAPZ_REPO_DATA) + "/EB015PI.c3d");
  const ErrorCode invalid = ErrorCode::kInvalidParameter;
  CompressOptions o;
  o.lossless = true;
  o.analog_max_error = {{"nt", 0.5}};
  EXPECT_EQ(error_of([&] { compress(t, o); }), invalid);
  o.lossless = false;
  o.max_error = 0.1;
  for (double bad : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    o.analog_max_error = {{"nt", bad}};
    EXPECT_EQ(error_of([&] { compress(t, o); }), invalid) << bad;
  }
}

TEST(AnalogLossyCodec, GivenSharedEmgTakesThenTheBoundHoldsAndTheWrittenC3DReadsTheSame) {
  const std::string dir = CAPZ_SHARED_DATA;
  const std::vector<std::pair<std::string, std::map<std::string, double>>> takes = {
      {"/c3d/btkdata/others/1123x01EMG.c3d", {{"mV", 0.01}}},
      {"/c3d/c3dorg/sample_30/emgwl.c3d", {{"V", 0.01}}},  // 2.4 steps of 4.15 mV
      {"/c3d/c3dorg/sample_00/Cometa Systems/EMG Data Cometa.c3d", {{"uV", 10}, {"g", 0.01}}}};
  size_t ran = 0;
  for (const auto& tk : takes) {
    const std::string path = dir + tk.first;
    if (!std::ifstream(path)) continue;
    ++ran;
    const Lossy r = compress_lossy(path, tk.second);
    ASSERT_FALSE(r.info.analog_bounds.empty()) << path;
    EXPECT_TRUE(check_promise(r.original, r.decoded, promise_of(r.info)).holds) << path;
    EXPECT_LT(r.bytes, r.lossless_bytes) << path;
    // The C3D written from the archive holds the decoded samples exactly.
    const std::string out = ::testing::TempDir() + "/lossy_analog.c3d";
    std::remove(out.c_str());
    write_take(r.decoded, out);
    const Take back = read_take(out);
    ASSERT_EQ(back.analog.values.size(), r.decoded.analog.values.size());
    for (size_t i = 0; i < back.analog.values.size(); ++i)
      ASSERT_EQ(bits(back.analog.values[i]), bits(r.decoded.analog.values[i])) << path << " " << i;
  }
  if (ran == 0) GTEST_SKIP() << "shared data not found at " << dir;
}

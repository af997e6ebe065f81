#include <gtest/gtest.h>

#include <cstring>

#include "capz/error.h"
#include "capz/metrics.h"
#include "codec/ts/ts_codec.h"
#include "synthetic.h"

using namespace capz;

namespace {
void roundtrip(const capz_test::Synth& s, const TransformParams& tp, TsEncodeReport* rep,
               std::vector<uint8_t>* bytes_out = nullptr) {
  TsCodec codec;
  std::vector<uint8_t> bytes;
  std::vector<double> recon, dec;
  codec.encode_report(s.view(), tp, &bytes, &recon, rep);
  ASSERT_EQ(recon.size(), s.xyz.size());
  codec.decode(bytes.data(), bytes.size(), s.frames, s.points, &dec);
  ASSERT_EQ(dec.size(), recon.size());
  EXPECT_EQ(0, std::memcmp(dec.data(), recon.data(), sizeof(double) * dec.size()))
      << "decoder output differs from the encoder's reconstruction";
  if (bytes_out) *bytes_out = bytes;
}
}  // namespace

TEST(TsCodec, GivenRepeatedPosesWhenEncodedAtKgTargetThenDecodeIsBitExactAndTargetHolds) {
  auto s = capz_test::make_synth(60, 150, 20, true, 11);
  for (int k : {1, 3}) {
    TransformParams tp;
    tp.kg_error = 0.5;
    tp.clusters = k;
    TsEncodeReport rep;
    roundtrip(s, tp, &rep);
    EXPECT_EQ(rep.clusters, k);
    EXPECT_LE(rep.kg_error, 0.5);
    EXPECT_GT(rep.kg_error, 0.05);  // the search used its budget, not a needlessly fine one
    // Much smaller than the raw floats.
    EXPECT_LT(rep.bytes, s.frames * s.points * 12 / 8);
  }
}

TEST(TsCodec, GivenGapsWhenEncodedThenKgMeasuredOnValidSamplesHolds) {
  auto s = capz_test::make_synth(40, 80, 10, true, 5, 0.1);
  TransformParams tp;
  tp.kg_error = 0.2;
  tp.clusters = -1;  // auto
  TsEncodeReport rep;
  TsCodec codec;
  std::vector<uint8_t> bytes;
  std::vector<double> recon;
  codec.encode_report(s.view(), tp, &bytes, &recon, &rep);
  ErrorStats e = compare(s.frames, s.points, s.xyz.data(), recon.data(), s.valid.data());
  EXPECT_LE(e.kg_error, 0.2);
  EXPECT_NEAR(e.kg_error, rep.kg_error, 1e-9);
  std::vector<double> dec;
  codec.decode(bytes.data(), bytes.size(), s.frames, s.points, &dec);
  EXPECT_EQ(0, std::memcmp(dec.data(), recon.data(), sizeof(double) * dec.size()));
}

TEST(TsCodec, GivenSameInputTwiceThenSameBytes) {
  auto s = capz_test::make_synth(30, 50, 10, true, 9);
  TransformParams tp;
  tp.kg_error = 1.0;
  tp.clusters = 2;
  TsEncodeReport rep;
  std::vector<uint8_t> a, b;
  roundtrip(s, tp, &rep, &a);
  roundtrip(s, tp, &rep, &b);
  EXPECT_EQ(a, b);
}

TEST(TsCodec, GivenMoreClustersOnPeriodicMotionThenFewerPcsPerCluster) {
  auto s = capz_test::make_synth(80, 120, 20, false, 21);
  TransformParams tp;
  tp.kg_error = 0.1;
  TsEncodeReport one, four;
  tp.clusters = 1;
  roundtrip(s, tp, &one);
  tp.clusters = 4;
  roundtrip(s, tp, &four);
  ASSERT_EQ(four.pcs.size(), 4u);
  for (int p : four.pcs) EXPECT_LE(p, one.pcs[0]);
}

TEST(TsCodec, GivenUnknownOptionThenInvalidParameter) {
  auto s = capz_test::make_synth(5, 10, 5, false, 1);
  TransformParams tp;
  tp.options["no_such_knob"] = "1";
  TsCodec codec;
  std::vector<uint8_t> bytes;
  std::vector<double> recon;
  try {
    codec.encode(s.view(), tp, &bytes, &recon);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInvalidParameter);
  }
}

TEST(TsCodec, GivenTruncatedOrAlteredPayloadThenCorruptNotCrash) {
  auto s = capz_test::make_synth(20, 30, 10, true, 4);
  TransformParams tp;
  tp.kg_error = 1.0;
  tp.clusters = 2;
  TsCodec codec;
  std::vector<uint8_t> bytes;
  std::vector<double> recon;
  codec.encode(s.view(), tp, &bytes, &recon);
  for (size_t cut = 0; cut < bytes.size(); cut += std::max<size_t>(1, bytes.size() / 97)) {
    std::vector<double> dec;
    try {
      codec.decode(bytes.data(), cut, s.frames, s.points, &dec);
      ADD_FAILURE() << "truncation at " << cut << " accepted";
    } catch (const Error& e) {
      EXPECT_TRUE(e.code() == ErrorCode::kCorrupt || e.code() == ErrorCode::kUnsupportedVersion);
    }
  }
  std::vector<double> dec;
  EXPECT_THROW(codec.decode(bytes.data(), bytes.size(), s.frames + 1, s.points, &dec), Error);
  // Flipped bytes: either rejected as corrupt or decoded to something; never a crash.
  for (size_t i = 0; i < bytes.size(); i += 7) {
    std::vector<uint8_t> bad = bytes;
    bad[i] ^= 0x5a;
    try {
      codec.decode(bad.data(), bad.size(), s.frames, s.points, &dec);
    } catch (const Error& e) {
      EXPECT_TRUE(e.code() == ErrorCode::kCorrupt || e.code() == ErrorCode::kUnsupportedVersion)
          << e.what();
    }
  }
}

// META codings 2 and 3 (docs/FORMAT.md 5.1): raw LZMA2 blocks, with or without a preset
// dictionary, round-trip exactly, anything else is rejected as corrupt, and the encoder keeps
// the smallest coding.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/take.h"
#include "coding/bytes.h"
#include "coding/c3d_params.h"
#include "coding/container.h"
#include "coding/lzma_block.h"
#include "coding/meta.h"
#include "core/hash.h"

using namespace capz;

namespace {

std::vector<uint8_t> text_like(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  const std::string words[] = {"POINT", "ANALOG", "LABELS",        "SCALE",
                               "RATE",  "  ",     "FORCE_PLATFORM"};
  std::vector<uint8_t> v;
  while (v.size() < n) {
    const std::string& w = words[rng() % 7];
    v.insert(v.end(), w.begin(), w.end());
    v.push_back(static_cast<uint8_t>(rng() % 4 == 0 ? rng() : ' '));
  }
  v.resize(n);
  return v;
}

// The error code f throws, 0 when it throws none.
int code_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return static_cast<int>(e.code());
  }
  return 0;
}
constexpr int kCorrupt = static_cast<int>(ErrorCode::kCorrupt);

// A META payload decoded as a decoder does, for a take of `points` and `channels`.
Take decode_meta_payload(const std::vector<uint8_t>& payload, size_t points = 2, int channels = 3) {
  std::vector<uint8_t> buf;
  append_chunk(&buf, "META", payload);
  const Chunk c = read_chunk(buf.data(), buf.size(), 0, "t");
  Take t;
  t.points = points;
  t.analog.channels = channels;
  bool words = false;
  decode_meta(c, "t", &t, &words, 8);
  return t;
}

// The fields a META payload holds, for codings 0 and 2.
std::vector<uint8_t> fields_of(const std::vector<uint8_t>& meta) {
  ByteReader r(meta.data(), meta.size(), "t");
  const uint8_t coding = r.u8();
  if (coding == 0) return std::vector<uint8_t>(meta.begin() + 1, meta.end());
  EXPECT_EQ(coding, 2);
  const size_t n = static_cast<size_t>(r.varint());
  return lzma2_decode(meta.data() + r.offset(), r.remaining(), n, "t");
}

}  // namespace

TEST(Lzma2Block, GivenTextAndRandomInputsThenExactRoundTrip) {
  std::mt19937 rng(7);
  for (size_t n : {size_t{1}, size_t{100}, size_t{70000}, size_t{300000}}) {
    std::vector<uint8_t> text = text_like(n, static_cast<unsigned>(n));
    std::vector<uint8_t> noise(n);
    for (auto& b : noise) b = static_cast<uint8_t>(rng());
    for (const auto* in : {&text, &noise}) {
      const std::vector<uint8_t> z = lzma2_encode(in->data(), in->size());
      EXPECT_EQ(lzma2_decode(z.data(), z.size(), in->size(), "t"), *in) << n;
    }
    const std::vector<uint8_t> z = lzma2_encode(text.data(), text.size());
    if (n >= 70000) {
      EXPECT_LT(z.size(), n / 4) << "text-like bytes should compress";
    }
  }
}

TEST(Lzma2Block, GivenWrongSizeTruncatedOrGarbageThenCorrupt) {
  const std::vector<uint8_t> in = text_like(5000, 1);
  const std::vector<uint8_t> z = lzma2_encode(in.data(), in.size());
  auto dec = [&](const std::vector<uint8_t>& b, size_t n) {
    return code_of([&] { lzma2_decode(b.data(), b.size(), n, "t"); });
  };
  EXPECT_EQ(dec(z, in.size() + 1), kCorrupt);  // says fewer bytes than asked
  EXPECT_EQ(dec(z, in.size() - 1), kCorrupt);  // holds more than asked
  EXPECT_EQ(dec(std::vector<uint8_t>(z.begin(), z.end() - 1), in.size()), kCorrupt);
  std::vector<uint8_t> trailing = z;
  trailing.push_back(0);
  EXPECT_EQ(dec(trailing, in.size()), kCorrupt);
  std::mt19937 rng(3);
  for (int k = 0; k < 200; ++k) {
    std::vector<uint8_t> g(1 + rng() % 300);
    for (auto& b : g) b = static_cast<uint8_t>(rng());
    const int c = dec(g, 1 + rng() % 10000);
    EXPECT_EQ(c, kCorrupt);
  }
  std::vector<uint8_t> flipped = z;
  flipped[flipped.size() / 2] ^= 0x55;
  const int c = dec(flipped, in.size());
  // A flip may still decode to n bytes (LZMA2 has no check of its own: the chunk CRC has it);
  // it must never crash or decode to another size.
  EXPECT_TRUE(c == kCorrupt || c == 0);
}

TEST(MetaCoding, GivenALargeParameterSectionThenCoding2IsChosenAndFieldsComeBack) {
  Take t;
  t.format = Format::kC3D;
  t.units = "mm";
  t.rate = 100;
  t.points = 3;
  t.labels = {"LASI", "RASI", "LPSI"};
  t.c3d = std::make_shared<C3DExtra>();
  C3DGroup g;
  g.id = 1;
  g.name = "POINT";
  for (int k = 0; k < 60; ++k) {
    C3DParameter p;
    p.name = "DESCRIPTION" + std::to_string(k);
    p.description = "a description that repeats in many parameters of the section";
    p.type = -1;
    const std::vector<uint8_t> text = text_like(64, static_cast<unsigned>(k % 5));
    p.dims = {64};
    p.data = text;
    g.params.push_back(p);
  }
  t.c3d->groups.push_back(g);
  const std::vector<uint8_t> meta = encode_meta(t, false);
  ASSERT_FALSE(meta.empty());
  EXPECT_EQ(meta[0], 2) << "LZMA2 should be the smallest coding of a repetitive section";
  // Coding 1 of the same fields, for comparison.
  Take back;
  back.points = 3;
  std::vector<uint8_t> buf;
  append_chunk(&buf, "META", meta);
  const Chunk c = read_chunk(buf.data(), buf.size(), 0, "t");
  bool words = true;
  decode_meta(c, "t", &back, &words, 8);
  EXPECT_EQ(back.labels, t.labels);
  EXPECT_EQ(back.units, "mm");
  ASSERT_TRUE(back.c3d);
  ASSERT_EQ(back.c3d->groups.size(), 1u);
  ASSERT_EQ(back.c3d->groups[0].params.size(), 60u);
  EXPECT_EQ(back.c3d->groups[0].params[59].data, t.c3d->groups[0].params[59].data);
}

TEST(MetaCoding, GivenCoding2WithImplausibleSizeOrBadStreamThenCorrupt) {
  auto payload = [](uint64_t n, const std::vector<uint8_t>& data) {
    ByteWriter w;
    w.u8(2);
    w.varint(n);
    w.bytes(data);
    return w.buffer();
  };
  const std::vector<uint8_t> fields = text_like(100, 2);
  const std::vector<uint8_t> z = lzma2_encode(fields.data(), fields.size());
  EXPECT_EQ(code_of([&] { decode_meta_payload(payload(0, z)); }), kCorrupt);
  EXPECT_EQ(code_of([&] { decode_meta_payload(payload(uint64_t{1} << 27, z)); }), kCorrupt);
  EXPECT_EQ(code_of([&] { decode_meta_payload(payload(fields.size() + 5, z)); }), kCorrupt);
  EXPECT_EQ(code_of([&] { decode_meta_payload(payload(10, {1, 2, 3})); }), kCorrupt);
  ByteWriter w;
  w.u8(3);
  EXPECT_EQ(code_of([&] { decode_meta_payload(w.buffer()); }), kCorrupt);
}

TEST(MetaCoding, GivenLabelsTheParametersHoldThenNotWrittenTwiceAndDerivedBack) {
  Take t;
  t.format = Format::kC3D;
  t.points = 2;
  t.analog.channels = 3;
  t.labels = {"LASI", "RASI"};
  t.analog.labels = {"Fx", "Fy", ""};  // the reader pads to the channel count
  t.c3d = std::make_shared<C3DExtra>();
  C3DGroup point, analog;
  point.id = 1;
  point.name = "POINT";
  analog.id = 2;
  analog.name = "ANALOG";
  auto chars = [](const std::string& name, const std::vector<std::string>& v, int w) {
    C3DParameter p;
    p.name = name;
    p.type = -1;
    p.dims = {w, static_cast<int>(v.size())};
    for (const std::string& s : v) {
      std::string f = s;
      f.resize(static_cast<size_t>(w), ' ');
      p.data.insert(p.data.end(), f.begin(), f.end());
    }
    return p;
  };
  point.params.push_back(chars("LABELS", {"LASI", "RASI"}, 4));
  analog.params.push_back(chars("LABELS", {"Fx", "Fy"}, 2));
  t.c3d->groups = {point, analog};
  const std::vector<uint8_t> with = encode_meta(t, false);
  auto occurrences = [](const std::vector<uint8_t>& b, const std::string& w) {
    size_t n = 0;
    for (auto it = b.begin(); (it = std::search(it, b.end(), w.begin(), w.end())) != b.end(); ++it)
      ++n;
    return n;
  };
  EXPECT_EQ(occurrences(fields_of(with), "RASI"), 1u)
      << "the label is written once, in the parameters";
  Take back = decode_meta_payload(with);
  EXPECT_EQ(back.labels, t.labels);
  EXPECT_EQ(back.analog.labels, t.analog.labels);
  EXPECT_TRUE(back.descriptions.empty());
  // A take whose labels differ from its parameters' keeps its own, listed.
  Take other = t;
  other.labels = {"LASI", "renamed"};
  const std::vector<uint8_t> listed = encode_meta(other, false);
  EXPECT_EQ(occurrences(fields_of(listed), "LASI"), 2u) << "listed and in the parameters";
  Take back2 = decode_meta_payload(listed);
  EXPECT_EQ(back2.labels, other.labels);
}

TEST(MetaCoding, GivenLabelsFromParametersWithoutAC3DBlockThenCorrupt) {
  ByteWriter f;  // the fields of 3.2 with extras = 8 (bit 3 without bit 0)
  f.str("x");
  f.str("mm");
  f.f64(100);
  f.svarint(1);
  f.varint(0);
  f.varint(0);
  f.f64(0);
  f.varint(0);
  f.u8(8);
  ByteWriter w;
  w.u8(0);
  w.bytes(f.buffer());
  EXPECT_EQ(code_of([&] { decode_meta_payload(w.buffer()); }), kCorrupt);
}

// META coding 3 (docs/FORMAT.md 5.1): LZMA2 after dictionary 1.

TEST(MetaDictionary, GivenDictionary1ThenItIsTheBytesFormatMdNames) {
  // FORMAT.md 5.8 names the dictionary by size and XXH3-128: a changed
  // docs/format/meta-dict-1.bin would silently make every 8.0 stream undecodable.
  const LzmaPreset d = meta_dictionary(1);
  ASSERT_EQ(d.size, 94519u);
  EXPECT_EQ(digest_hex(hash128(d.data, d.size)), "aa2a583249dd1c1bd2cdc8880a51c0dc");
  EXPECT_EQ(meta_dictionary(0).size, 0u);
  EXPECT_EQ(meta_dictionary(2).size, 0u);
}

TEST(Lzma2Block, GivenAPresetDictionaryThenRoundTripAndItMustMatch) {
  const std::vector<uint8_t> in = text_like(5000, 4);
  const LzmaPreset d = meta_dictionary(1);
  const std::vector<uint8_t> z = lzma2_encode(in.data(), in.size(), d);
  EXPECT_EQ(lzma2_decode(z.data(), z.size(), in.size(), "t", d), in);
  // Without the dictionary the stream does not decode (it starts without a dictionary reset).
  EXPECT_EQ(code_of([&] { lzma2_decode(z.data(), z.size(), in.size(), "t"); }), kCorrupt);
}

TEST(MetaCoding, GivenARealC3DThenCoding3IsSmallestAndReadOnlyFromMajor8) {
  const Take t = read_c3d(std::string(CAPZ_REPO_DATA) + "/EB015PI.c3d");
  ASSERT_TRUE(t.c3d);
  const std::vector<uint8_t> plain = encode_meta(t, false);
  const std::vector<uint8_t> dict = encode_meta(t, false, true);
  EXPECT_EQ(meta_coding(plain), 2);
  ASSERT_EQ(meta_coding(dict), 3);
  ASSERT_GE(dict.size(), 2u);
  EXPECT_EQ(dict[1], 1) << "dictionary 1";
  EXPECT_LT(dict.size(), plain.size() * 3 / 4) << "the dictionary should pay on a Vicon take";
  std::vector<uint8_t> a, b;
  append_chunk(&a, "META", plain);
  append_chunk(&b, "META", dict);
  const Chunk ca = read_chunk(a.data(), a.size(), 0, "t");
  const Chunk cb = read_chunk(b.data(), b.size(), 0, "t");
  EXPECT_EQ(decode_meta_fields(cb, "t", 8), decode_meta_fields(ca, "t", 8));
  Take back;
  back.points = t.points;
  back.analog.channels = t.analog.channels;
  bool words = true;
  decode_meta(cb, "t", &back, &words, 8);
  EXPECT_FALSE(words);
  EXPECT_EQ(back.labels, t.labels);
  EXPECT_EQ(back.analog.labels, t.analog.labels);
  ASSERT_TRUE(back.c3d);
  EXPECT_EQ(encode_c3d_parameters(*back.c3d), encode_c3d_parameters(*t.c3d));
  // A stream of major 7 or lower has no coding 3.
  for (int major : {5, 7})
    EXPECT_EQ(code_of([&] { decode_meta_fields(cb, "t", major); }), kCorrupt) << major;
}

TEST(MetaCoding, GivenCoding3WithUnknownDictionaryOrBadStreamThenCorrupt) {
  const std::vector<uint8_t> fields = text_like(300, 5);
  const std::vector<uint8_t> z = lzma2_encode(fields.data(), fields.size(), meta_dictionary(1));
  auto payload = [&](int number, uint64_t n, const std::vector<uint8_t>& data) {
    ByteWriter w;
    w.u8(3);
    w.u8(static_cast<uint8_t>(number));
    w.varint(n);
    w.bytes(data);
    return w.buffer();
  };
  auto fields_back = [&](const std::vector<uint8_t>& p) {
    std::vector<uint8_t> buf;
    append_chunk(&buf, "META", p);
    const Chunk c = read_chunk(buf.data(), buf.size(), 0, "t");
    return decode_meta_fields(c, "t", 8);
  };
  EXPECT_EQ(fields_back(payload(1, fields.size(), z)), fields);
  for (int number : {0, 2, 255})
    EXPECT_EQ(code_of([&] { fields_back(payload(number, fields.size(), z)); }), kCorrupt);
  EXPECT_EQ(code_of([&] { fields_back(payload(1, 0, z)); }), kCorrupt);
  EXPECT_EQ(code_of([&] { fields_back(payload(1, fields.size() + 1, z)); }), kCorrupt);
  EXPECT_EQ(code_of([&] {
              fields_back(payload(1, fields.size(), {z.begin(), z.end() - 1}));
            }),
            kCorrupt);
  const std::vector<uint8_t> only_coding = {3};
  EXPECT_EQ(code_of([&] { fields_back(only_coding); }), kCorrupt);
}

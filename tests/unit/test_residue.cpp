// The lossless residue's pieces (src/core/hash, src/io/residue/): the checksum, packing, byte
// patches and the C3D residue on synthetic files with the oddities real files have (garbage in
// gap samples, trailing bytes, a truncated last frame, a header claiming more frames, 4th words
// beyond 16 bits, DEC and MIPS number forms); a damaged residue throws kCorrupt.
#include <gtest/gtest.h>
#include <xxhash.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "capz/io.h"
#include "capz/stream.h"
#include "core/atomic_file.h"
#include "core/hash.h"
#include "io/c3d_internal.h"
#include "io/residue/c3d_residue.h"
#include "io/residue/pack.h"
#include "io/residue/patch.h"
#include "io/residue/trc_residue.h"
#include "test_util.h"

using namespace capz;
using capz_test::error_of;

namespace {

// Writes `n` bytes to `name` in `dir`; returns the path.
std::string put_file(const capz_test::TempDir& dir, const std::string& name, const void* p,
                     size_t n) {
  const std::string path = dir.file(name);
  AtomicFile f(path, true);
  f.write(p, n);
  f.commit();
  return path;
}

std::vector<uint8_t> random_bytes(size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> v(n);
  for (auto& b : v) b = static_cast<uint8_t>(rng() & 0xff);
  return v;
}

}  // namespace

// ---- hash -------------------------------------------------------------------------------------

TEST(ResidueHash, EmptyInputGivesTheKnownXxh3_128) {
  EXPECT_EQ(digest_hex(hash128(nullptr, 0)), "99aa06d3014798d86001c324468d497f");
}

TEST(ResidueHash, PiecesGiveTheOneShotDigestInCanonicalOrder) {
  const std::vector<uint8_t> v = random_bytes(100000, 1);
  const XXH128_hash_t one = XXH3_128bits(v.data(), v.size());
  Digest128 want;
  for (int i = 0; i < 8; ++i) {
    want[i] = static_cast<uint8_t>(one.high64 >> (56 - 8 * i));
    want[8 + i] = static_cast<uint8_t>(one.low64 >> (56 - 8 * i));
  }
  for (size_t piece : {1u, 7u, 4096u, 100000u}) {
    Hasher h;
    for (size_t at = 0; at < v.size(); at += piece)
      h.update(v.data() + at, std::min(piece, v.size() - at));
    EXPECT_EQ(h.digest(), want) << piece;
  }
  std::vector<uint8_t> w = v;
  w[5000] ^= 1;
  EXPECT_NE(hash128(w.data(), w.size()), want);
}

TEST(ResidueHash, FileDigestEqualsBufferDigest) {
  capz_test::TempDir dir("capz_residue_unit");
  const std::vector<uint8_t> v = random_bytes(3u << 20, 2);  // spans several 1 MiB reads
  EXPECT_EQ(hash128_file(put_file(dir, "a.bin", v.data(), v.size())), hash128(v.data(), v.size()));
}

// ---- pack -------------------------------------------------------------------------------------

TEST(ResiduePack, RoundTripsStoredZstdAndDictionary) {
  const std::vector<uint8_t> noise = random_bytes(300, 3);
  std::vector<uint8_t> text(5000);
  for (size_t i = 0; i < text.size(); ++i) text[i] = static_cast<uint8_t>("LASI RASI "[i % 10]);
  std::vector<uint8_t> dict = random_bytes(4000, 4), like_dict = dict;
  like_dict[100] ^= 0xff;
  struct Case {
    std::vector<uint8_t> data, dict;
    int method;
  };
  for (const Case& c :
       {Case{{}, {}, 0}, Case{noise, {}, 0}, Case{text, {}, 1}, Case{like_dict, dict, 2}}) {
    ByteWriter w;
    residue::pack(c.data, c.dict, w);
    EXPECT_EQ(w.buffer()[0], c.method);
    ByteReader r(w.buffer().data(), w.size(), "test");
    EXPECT_EQ(residue::unpack(r, c.dict), c.data);
    EXPECT_TRUE(r.at_end());
  }
}

TEST(ResiduePack, DamagedPayloadThrowsCorrupt) {
  std::vector<uint8_t> text(5000);
  for (size_t i = 0; i < text.size(); ++i) text[i] = static_cast<uint8_t>(i % 13);
  ByteWriter w;
  residue::pack(text, {}, w);
  const std::vector<uint8_t> good = w.buffer();
  for (size_t cut = 0; cut < good.size(); ++cut) {
    ByteReader r(good.data(), cut, "test");
    EXPECT_EQ(error_of([&] { residue::unpack(r, {}); }), ErrorCode::kCorrupt) << cut;
  }
  for (size_t i = 0; i < good.size(); ++i)
    for (int bit = 0; bit < 8; ++bit) {
      std::vector<uint8_t> bad = good;
      bad[i] ^= static_cast<uint8_t>(1 << bit);
      ByteReader r(bad.data(), bad.size(), "test");
      try {
        residue::unpack(r, {});  // a flip zstd cannot see may decode to other bytes
      } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::kCorrupt) << i << " " << bit << " " << e.what();
      }
    }
  // A stored size far beyond the frame's real output is refused without allocating it.
  ByteWriter huge;
  huge.u8(1);
  huge.varint(uint64_t{1} << 60);
  huge.varint(good.size() - 3);
  huge.bytes(good.data() + 3, good.size() - 3);
  ByteReader r(huge.buffer().data(), huge.size(), "test");
  EXPECT_EQ(error_of([&] { residue::unpack(r, {}); }), ErrorCode::kCorrupt);
  // A size above the caller's limit is refused before any zstd work.
  ByteReader within(good.data(), good.size(), "test");
  EXPECT_EQ(residue::unpack(within, {}, text.size()), text);
  ByteReader over(good.data(), good.size(), "test");
  EXPECT_EQ(error_of([&] { residue::unpack(over, {}, text.size() - 1); }), ErrorCode::kCorrupt);
}

// ---- patch ------------------------------------------------------------------------------------

TEST(ResiduePatch, DiffThenApplyGivesTheOriginal) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    const size_t n = rng() % 2000;
    std::vector<uint8_t> orig = random_bytes(n, static_cast<uint32_t>(trial)), regen = orig;
    const size_t changes = n ? rng() % 20 : 0;
    for (size_t k = 0; k < changes; ++k) regen[rng() % n] ^= static_cast<uint8_t>(1 + rng() % 255);
    std::vector<uint8_t> p = residue::diff_bytes(regen.data(), orig.data(), n);
    EXPECT_EQ(p.empty(), regen == orig);
    residue::apply_patch(p, regen.data(), n, "test");
    ASSERT_EQ(regen, orig) << trial;
  }
}

namespace {

// The stored form of docs/FORMAT.md 14.1, byte by byte: a run starts at a differing byte and
// takes in every further difference fewer than 3 equal bytes past its end.
std::vector<uint8_t> patch_byte_by_byte(const std::vector<uint8_t>& regen,
                                        const std::vector<uint8_t>& orig) {
  std::vector<std::pair<size_t, size_t>> runs;
  const size_t n = orig.size();
  for (size_t i = 0; i < n; ++i) {
    if (regen[i] == orig[i]) continue;
    size_t end = i + 1;
    for (size_t k = end; k < n && k < end + 3; ++k)
      if (regen[k] != orig[k]) end = k + 1;
    runs.emplace_back(i, end);
    i = end;
  }
  if (runs.empty()) return {};
  ByteWriter w;
  w.varint(runs.size());
  size_t end = 0;
  for (auto& r : runs) {
    w.varint(r.first - end);
    w.varint(r.second - r.first - 1);
    end = r.second;
  }
  for (auto& r : runs) w.bytes(orig.data() + r.first, r.second - r.first);
  return w.buffer();
}

}  // namespace

TEST(ResiduePatch, RunsAreTheByteByByteOnesAtAnyDensityAndAlignment) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 400; ++trial) {
    const size_t n = rng() % 300;
    std::vector<uint8_t> orig = random_bytes(n, static_cast<uint32_t>(trial)), regen = orig;
    // From a few scattered differences to nearly every byte, and gaps of 0..4 equal bytes
    // around the 8-byte words the diff compares.
    const unsigned per_mille = trial % 4 == 0   ? 5
                               : trial % 4 == 1 ? 200
                               : trial % 4 == 2 ? 600
                                                : 950;
    for (size_t k = 0; k < n; ++k)
      if (rng() % 1000 < per_mille) regen[k] ^= static_cast<uint8_t>(1 + rng() % 255);
    if (n && trial % 7 == 0) regen[n - 1] ^= 1;  // a difference at the very end
    ASSERT_EQ(residue::diff_bytes(regen.data(), orig.data(), n), patch_byte_by_byte(regen, orig))
        << trial;
  }
}

TEST(ResiduePatch, MalformedPatchThrowsCorrupt) {
  std::vector<uint8_t> orig(100, 7), regen(100, 7);
  regen[10] = regen[90] = 0;
  const std::vector<uint8_t> p = residue::diff_bytes(regen.data(), orig.data(), orig.size());
  std::vector<uint8_t> buf(100);
  for (size_t cut = 1; cut < p.size(); ++cut) {
    std::vector<uint8_t> bad(p.begin(), p.begin() + static_cast<long>(cut));
    EXPECT_EQ(error_of([&] { residue::apply_patch(bad, buf.data(), buf.size(), "t"); }),
              ErrorCode::kCorrupt);
  }
  EXPECT_EQ(error_of([&] { residue::apply_patch(p, buf.data(), 50, "t"); }), ErrorCode::kCorrupt);
  std::vector<uint8_t> longer = p;
  longer.push_back(0);
  EXPECT_EQ(error_of([&] { residue::apply_patch(longer, buf.data(), 100, "t"); }),
            ErrorCode::kCorrupt);
}

// ---- C3D residue ------------------------------------------------------------------------------

namespace {

// 10 frames x 4 points, 2 channels x 2 samples, one gap per frame from frame 2 on; int16 or
// float storage at scale 0.25 (coordinates are multiples of it), Intel form as the writer writes.
std::vector<uint8_t> synthetic_c3d(bool is_float) {
  Take t;
  t.format = Format::kC3D;
  t.resize(10, 4);
  t.rate = 100;
  t.units = "mm";
  t.labels = {"A", "B", "C", "D"};
  t.c3d = std::make_shared<C3DExtra>();
  t.c3d->float_storage = is_float;
  t.c3d->point_scale = 0.25;
  t.c3d->residual.assign(40, -1.0f);
  t.c3d->camera_mask.assign(40, 0);
  for (size_t f = 0; f < 10; ++f)
    for (size_t p = 0; p < 4; ++p) {
      const size_t i = f * 4 + p;
      if (f >= 2 && p == (f % 4)) continue;  // a gap
      t.valid[i] = 1;
      for (int a = 0; a < 3; ++a) t.at(f, p)[a] = 0.25 * static_cast<double>(100 * a + 7 * f + p);
      t.c3d->residual[i] = 0.25f * static_cast<float>(f + 1);
      t.c3d->camera_mask[i] = static_cast<uint8_t>(p + 1);
    }
  t.analog.channels = 2;
  t.analog.samples_per_frame = 2;
  t.analog.rate = 200;
  t.analog.labels = {"FZ", "EMG"};
  for (size_t k = 0; k < 40; ++k) t.analog.values.push_back(static_cast<double>(k * 37) - 300);
  return c3d::encode_c3d_file(t, WriteOptions(), "synthetic.c3d");
}

size_t data_offset(const std::vector<uint8_t>& v) {
  return (static_cast<size_t>(v[16] | (v[17] << 8)) - 1) * c3d::kBlock;
}

struct Encoded {
  std::vector<uint8_t> part;
  std::vector<std::vector<uint8_t>> windows;
  std::vector<FrameBlock> blocks;
  std::vector<C3DGroup> groups;
};

Encoded encode(const std::string& path, size_t block) {
  Encoded e;
  auto src = open_c3d_frames(path);
  residue::C3DResidueEncoder enc(path);
  for (size_t f = 0; f < src->header().frames; f += block) {
    e.blocks.emplace_back();
    src->read(f, block, &e.blocks.back());
    e.windows.push_back(enc.window(e.blocks.back()));
  }
  e.groups = src->header().c3d->groups;
  e.part = enc.file_part(e.groups);
  return e;
}

std::vector<uint8_t> decode(const Encoded& e) {
  residue::C3DResidueDecoder dec(e.part.data(), e.part.size(), e.groups, "test");
  std::vector<uint8_t> out = dec.head();
  for (size_t w = 0; w < e.blocks.size(); ++w)
    dec.window(e.blocks[w], e.windows[w].data(), e.windows[w].size(), &out);
  out.insert(out.end(), dec.tail().begin(), dec.tail().end());
  return out;
}

// Writes `bytes`, encodes its residue in blocks of 3 frames, rebuilds and compares. Returns the
// total size of the window payloads.
size_t round_trip(const std::vector<uint8_t>& bytes, const std::string& what) {
  capz_test::TempDir dir("capz_residue_unit");
  const std::string path = put_file(dir, "t.c3d", bytes.data(), bytes.size());
  Encoded e = encode(path, 3);
  EXPECT_EQ(decode(e), bytes) << what;
  size_t n = 0;
  for (auto& w : e.windows) n += w.size();
  return n;
}

void put16(std::vector<uint8_t>& v, size_t at, int16_t x) {
  c3d::put_u16le(static_cast<uint16_t>(x), &v[at]);
}

}  // namespace

TEST(ResidueC3D, WriterOutputNeedsNoPatches) {
  for (bool fl : {false, true}) EXPECT_EQ(round_trip(synthetic_c3d(fl), "clean"), 0u) << fl;
}

TEST(ResidueC3D, Int16OdditiesRoundTrip) {
  const std::vector<uint8_t> clean = synthetic_c3d(false);
  const size_t d = data_offset(clean), per_frame = (4 * 4 + 4) * 2;
  std::vector<uint8_t> v = clean;  // gap at frame 2, point 2: garbage coordinates, word -5
  put16(v, d + 2 * per_frame + 2 * 8, 1234);
  put16(v, d + 2 * per_frame + 2 * 8 + 6, -5);
  EXPECT_GT(round_trip(v, "gap garbage"), 0u);
  v = clean;  // junk in the parameter section's unused bytes, trailing bytes after the data
  for (size_t k = d - 16; k < d; ++k) v[k] = static_cast<uint8_t>(k);
  const std::vector<uint8_t> trailing = random_bytes(700, 9);
  v.insert(v.end(), trailing.begin(), trailing.end());
  EXPECT_EQ(round_trip(v, "unused and trailing bytes"), 0u);
  v = clean;  // header says 11 frames, the file holds 10 and half of the 11th
  put16(v, 8, 11);
  v.insert(v.end(), clean.end() - static_cast<long>(per_frame / 2), clean.end());
  EXPECT_EQ(round_trip(v, "truncated frame"), 0u);
}

TEST(ResidueC3D, FloatOdditiesRoundTrip) {
  const std::vector<uint8_t> clean = synthetic_c3d(true);
  const size_t d = data_offset(clean), per_frame = (4 * 4 + 4) * 4;
  std::vector<uint8_t> v = clean;
  c3d::put_f32le(1.7e38f, &v[d + 12]);  // a 4th word beyond 16 bits (valid, residual 0)
  uint32_t nan = 0x7fc01234;            // a NaN with a payload in a gap's x
  std::memcpy(&v[d + 3 * per_frame + 3 * 16], &nan, 4);
  c3d::put_f32le(-2.0f, &v[d + 3 * per_frame + 3 * 16 + 12]);
  c3d::put_f32le(7.5f, &v[d + 5 * per_frame + 16 + 12]);  // a 4th word with a fraction
  EXPECT_GT(round_trip(v, "float oddities"), 0u);
}

TEST(ResidueC3D, RegeneratedDecAndMipsFramesDecodeToTheirValues) {
  for (int proc : {c3d::kIntel, c3d::kDec, c3d::kMips})
    for (bool fl : {false, true}) {
      SCOPED_TRACE(std::to_string(proc) + (fl ? " float" : " int16"));
      residue::C3DFrameLayout lay;
      lay.processor = proc;
      lay.float_storage = fl;
      lay.scale = 0.5;
      lay.frames = 3;
      lay.points = 2;
      lay.analog_values = 3;
      lay.per_frame = (2 * 4 + 3 + 1) * (fl ? 4 : 2);  // one analog value the reader skips
      FrameBlock b;
      b.reset(0, 3, 2, 3, true);
      for (size_t i = 0; i < 6; ++i) {
        b.valid[i] = i != 4;
        for (int a = 0; a < 3; ++a) b.xyz[3 * i + a] = b.valid[i] ? 0.5 * (i * 10 + a + 1) : 0;
        b.residual[i] = b.valid[i] ? 1.5f : -1.0f;
        b.camera_mask[i] = b.valid[i] ? 3 : 0;
      }
      for (size_t k = 0; k < 9; ++k) b.analog[k] = static_cast<double>(k) - 4;
      std::vector<uint8_t> bytes(3 * lay.per_frame);
      residue::regenerate_c3d_frames(lay, b, bytes.data());
      c3d::DataLayout dl;
      dl.nf.processor = proc;
      dl.per_frame = lay.per_frame;
      dl.frames = 3;
      dl.points = 2;
      dl.analog_values = 3;
      dl.float_storage = fl;
      dl.scale = 0.5;
      FrameBlock got;
      got.reset(0, 3, 2, 3, true);
      size_t wide = 0;
      c3d::decode_frames(dl, bytes.data(), 3, got.xyz.data(), got.valid.data(), got.residual.data(),
                         got.camera_mask.data(), got.analog.data(), &wide);
      EXPECT_EQ(got.xyz, b.xyz);
      EXPECT_EQ(got.valid, b.valid);
      EXPECT_EQ(got.residual, b.residual);
      EXPECT_EQ(got.camera_mask, b.camera_mask);
      EXPECT_EQ(got.analog, b.analog);
      const size_t elem = fl ? 4 : 2;  // the skipped analog value is zero
      for (size_t f = 0; f < 3; ++f)
        for (size_t k = 0; k < elem; ++k) EXPECT_EQ(bytes[(f + 1) * lay.per_frame - 1 - k], 0);
    }
}

// The rotation section regenerated in each processor's form (docs/FORMAT.md 14.1) reads back
// as the C3D reader reads it: the same float32s (a NaN's bits too, except through VAX F, which
// has no NaN).
TEST(ResidueC3D, RegeneratedRotationsDecodeToTheirValuesInEveryProcessorForm) {
  for (int proc : {c3d::kIntel, c3d::kDec, c3d::kMips}) {
    SCOPED_TRACE(proc);
    residue::C3DFrameLayout lay;
    lay.processor = proc;
    lay.float_storage = true;
    lay.frames = 3;
    lay.rotations = true;
    lay.rot_per_frame = 2 * c3d::kRotationBytes;  // 2 segments, 1 sample a frame
    FrameBlock b;
    b.reset(0, 3, 0, 0, false, 2);
    for (size_t i = 0; i < b.rotation_matrices.size(); ++i)
      b.rotation_matrices[i] = 0.25f * static_cast<float>(i % 17) - 1.5f;
    for (size_t i = 0; i < b.rotation_reliability.size(); ++i)
      b.rotation_reliability[i] = proc == c3d::kDec || i != 3 ? 1.0f : std::nanf("");
    std::vector<uint8_t> bytes(3 * lay.rot_per_frame);
    residue::regenerate_c3d_rotations(lay, b, bytes.data());
    c3d::DataLayout dl;
    dl.nf.processor = proc;
    std::vector<float> m(b.rotation_matrices.size()), r(b.rotation_reliability.size());
    c3d::decode_c3d_rotations(dl, bytes.data(), r.size(), m.data(), r.data());
    EXPECT_EQ(0, std::memcmp(m.data(), b.rotation_matrices.data(), 4 * m.size()));
    EXPECT_EQ(0, std::memcmp(r.data(), b.rotation_reliability.data(), 4 * r.size()));
  }
}

TEST(ResidueC3D, DamagedResidueThrowsCorruptNeverCrashes) {
  std::vector<uint8_t> v = synthetic_c3d(false);
  const size_t d = data_offset(v);
  put16(v, d + 2 * 40 + 2 * 8, 999);  // gap garbage, so window 0 has a patch
  capz_test::TempDir dir("capz_residue_unit");
  const std::string path = put_file(dir, "t.c3d", v.data(), v.size());
  const Encoded good = encode(path, 3);
  ASSERT_FALSE(good.windows[0].empty());
  for (size_t cut = 0; cut < good.part.size(); ++cut) {
    Encoded bad = good;
    bad.part.resize(cut);
    EXPECT_EQ(error_of([&] { decode(bad); }), ErrorCode::kCorrupt) << cut;
  }
  for (size_t cut = 0; cut < good.windows[0].size(); ++cut) {
    Encoded bad = good;
    bad.windows[0].resize(cut);
    if (cut == 0) {
      EXPECT_NE(decode(bad), v);  // no patch: the rebuild differs (the checksum's job)
      continue;
    }
    EXPECT_EQ(error_of([&] { decode(bad); }), ErrorCode::kCorrupt) << cut;
  }
  for (size_t i = 0; i < good.part.size() + good.windows[0].size(); ++i)
    for (int bit = 0; bit < 8; ++bit) {
      Encoded bad = good;
      uint8_t& b = i < good.part.size() ? bad.part[i] : bad.windows[0][i - good.part.size()];
      b ^= static_cast<uint8_t>(1 << bit);
      try {
        decode(bad);
      } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::kCorrupt) << i << " " << bit << " " << e.what();
      }
    }
  // The original's size, when known, must be the layout's.
  EXPECT_NO_THROW(residue::C3DResidueDecoder(good.part.data(), good.part.size(), good.groups,
                                             "test", v.size()));
  EXPECT_EQ(error_of([&] {
              residue::C3DResidueDecoder(good.part.data(), good.part.size(), good.groups, "test",
                                         v.size() + 1);
            }),
            ErrorCode::kCorrupt);
  // Blocks out of order, and a tail asked for before every frame was rebuilt.
  residue::C3DResidueDecoder dec(good.part.data(), good.part.size(), good.groups, "test");
  std::vector<uint8_t> out;
  EXPECT_EQ(error_of([&] { dec.window(good.blocks[1], nullptr, 0, &out); }), ErrorCode::kCorrupt);
  EXPECT_EQ(error_of([&] { dec.tail(); }), ErrorCode::kCorrupt);
}

// ---- TRC residue ------------------------------------------------------------------------------

namespace {

const char* kTrcHead =
    "PathFileType\t4\t(X/Y/Z)\tx.trc\n"
    "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\n"
    "100.00\t100.00\t  4\t2\tmm\n"
    "Frame#\tTime\tA\t\t\tB\t\t\n"
    "\t\tX1\tY1\tZ1\tX2\tY2\tZ2\n"
    "\n";

// Encodes `text` (written to a file) in blocks of 2 rows, rebuilds it from the frames as read,
// and returns the residue's size.
size_t trc_round_trip(const std::string& text, const std::string& what) {
  capz_test::TempDir dir("capz_residue_unit");
  const std::string path = put_file(dir, "t.trc", text.data(), text.size());
  auto src = open_trc_frames(path);
  const residue::FileResidue r = residue::encode_trc_residue(path, *src, 2);
  std::string back;
  residue::rebuild_trc(
      r, *src, 2, [&](const uint8_t* p, size_t n) { back.append(p, p + n); }, path);
  EXPECT_EQ(back, text) << what;
  return r.bytes();
}

}  // namespace

TEST(ResidueTRC, SpellingsLineEndsAndOddRowsRoundTrip) {
  const std::string rows =
      "1\t0.000\t1.500000\t-2.250000\t3.000000\tNaN\tNaN\tNaN\t\n"
      "2\t0.010\t1.600000\t-2.350000\t3.100000\t4.000000\t5.000000\t6.000000\t\n"
      "3\t0.020\t1.700000\t-0.000000\t3.200000\t4.100000\t5.100000\t6.100000\t\n"
      "4\t0.030\t1.800000\t-2.550000\t3.300000\t4.200000\t5.200000\t6.200000\t\n";
  const size_t clean = trc_round_trip(kTrcHead + rows, "padded decimals, NaN gaps");
  // Shortest spellings, CRLF, a BOM, blank lines between rows, a partial sample, a short row,
  // a field in exponent form and no line end after the last row.
  std::string odd = "\xEF\xBB\xBF" + std::string(kTrcHead) +
                    "1\t0\t1.5\t-2.25\t3\t\t\t\r\n"
                    "\r\n"
                    "2\t0.01\t1.6\t-2.35\t3.1\t4\t5\tNaN\r\n"
                    "3\t0.02\t1.7\t1e-3\t3.2\r\n"
                    "4\t0.03\t1.8\t-2.55\t3.3\t4.2\t5.2\t6.2";
  trc_round_trip(odd, "odd rows");
  // Space-separated columns with alignment: every row is an exception, still exact.
  std::string spaced = kTrcHead;
  spaced += "1  0.00   1.5  2.5  3.5   4.5  5.5  6.5\n2  0.01   1.5  2.5  3.5   4.5  5.5  6.5\n";
  trc_round_trip(spaced, "space separated");
  EXPECT_LT(clean, 200u);
}

TEST(ResidueTRC, CommaSeparatedFilesRoundTripAtTheCostOfTheirTabForm) {
  // The same rows with tabs and as a spreadsheet saves them: commas, every line padded to the
  // widest line's field count, blank lines of only commas, CRLF.
  std::string tab_rows, comma_rows;
  for (int r = 0; r < 40; ++r) {
    char row[200];
    std::snprintf(row, sizeof row, "%d\t%.2f\t%.4f\t%.4f\t%.4f\t%.4f\t%.4f\t%.4f\t\n", r + 1,
                  r * 0.01, 700 + r * 0.3127, 80 - r * 0.0421, 191.5 + r * 0.01, 651.25 + r,
                  313.5 - r * 0.7, 179.125);
    tab_rows += row;
    std::string c = row;
    std::replace(c.begin(), c.end(), '\t', ',');
    c.replace(c.size() - 1, 1, "\r\n");
    if (r == 7) c.insert(c.size() - 2, ",");  // one row a field wider: an exception
    comma_rows += c;
  }
  const size_t tabs = trc_round_trip(kTrcHead + tab_rows, "tabs");
  const std::string head =
      "PathFileType,4,(X/Y/Z),x.trc,,,,,\r\n"
      "DataRate,CameraRate,NumFrames,NumMarkers,Units,,,,\r\n"
      "100.00,100.00,  4,2,mm,,,,\r\n"
      "Frame#,Time,A,,,B,,,\r\n"
      ",,X1,Y1,Z1,X2,Y2,Z2,\r\n"
      ",,,,,,,,\r\n";
  const size_t commas = trc_round_trip(head + comma_rows, "commas");
  // The same rows cost the same: the padding is a width, CRLF a flag (FORMAT.md 14.5); what the
  // commas add is the wider row's exception and the layout byte.
  EXPECT_LT(commas, tabs + 12) << "tabs " << tabs << ", commas " << commas;
  // pyomeca's rows: no closing delimiter, a line of commas between two rows, no final line end.
  trc_round_trip(head +
                     "1,0,1.5,2.5,3.5,,,\n"
                     ",,,,,,,\n"
                     "2,0.01,1.6,2.6,3.6,4.6,5.6,6.6",
                 "pyomeca");
}

TEST(ResidueTRC, DamagedResidueThrowsCorruptNeverCrashes) {
  const std::string text = std::string(kTrcHead) +
                           "1\t0.000\t1.5\t2.5\t3.5\t\t\t\n2\t0.010\t1.5\t2.5\t3.5\t4\t5\t6\n"
                           "3\t0.020\t1.5\t2.5\t3.5\t4\t5\t6\n";
  capz_test::TempDir dir("capz_residue_unit");
  const std::string path = put_file(dir, "t.trc", text.data(), text.size());
  auto src = open_trc_frames(path);
  const residue::FileResidue good = residue::encode_trc_residue(path, *src, 2);
  auto rebuild = [&](const residue::FileResidue& r) {
    std::string back;
    residue::rebuild_trc(
        r, *src, 2, [&](const uint8_t* p, size_t n) { back.append(p, p + n); }, path);
    return back;
  };
  ASSERT_EQ(rebuild(good), text);
  for (size_t w = 0; w < good.windows.size(); ++w)
    for (size_t cut = 0; cut < good.windows[w].size(); ++cut) {
      residue::FileResidue bad = good;
      bad.windows[w].resize(cut);
      EXPECT_EQ(error_of([&] { rebuild(bad); }), ErrorCode::kCorrupt) << w << " " << cut;
    }
  for (size_t cut = 0; cut < good.file_part.size(); ++cut) {
    residue::FileResidue bad = good;
    bad.file_part.resize(cut);
    EXPECT_EQ(error_of([&] { rebuild(bad); }), ErrorCode::kCorrupt) << cut;
  }
  for (size_t w = 0; w < good.windows.size(); ++w)
    for (size_t i = 0; i < good.windows[w].size(); ++i)
      for (int bit = 0; bit < 8; ++bit) {
        residue::FileResidue bad = good;
        bad.windows[w][i] ^= static_cast<uint8_t>(1 << bit);
        try {
          rebuild(bad);
        } catch (const Error& e) {
          EXPECT_EQ(e.code(), ErrorCode::kCorrupt) << w << " " << i << " " << bit << e.what();
        }
      }
  residue::FileResidue fewer = good;
  fewer.windows.pop_back();
  EXPECT_EQ(error_of([&] { rebuild(fewer); }), ErrorCode::kCorrupt);
}

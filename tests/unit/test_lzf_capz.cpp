// capz's LZF compressor (coding/lzf.h) against a plain statement of its rule, and the PCD
// writer's buffers kept from frame to frame (io/pcd_frame_writer.h): the same bytes.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <memory>
#include <random>
#include <vector>

#include "coding/lzf.h"
#include "io/pcd_frame_writer.h"

namespace {

// capz's LZF as its rule reads, byte by byte: a 2^16-slot table of positions (none at the start)
// hashed from the 3 bytes at i (p[0] most significant, times 2654435761, the top 16 bits); a
// match when the slot's position is at most 8192 back and its 3 bytes are i's, as long as the
// bytes agree (at most 264 and the input's end); every position a match covers indexed.
std::vector<uint8_t> reference_lzf(const std::vector<uint8_t>& in) {
  const size_t n = in.size();
  std::vector<int64_t> table(size_t{1} << 16, -1);
  std::vector<uint8_t> out;
  auto key = [&](size_t p) {
    const uint32_t v = uint32_t{in[p]} << 16 | uint32_t{in[p + 1]} << 8 | in[p + 2];
    return (v * 2654435761u) >> 16;
  };
  auto literals = [&](size_t from, size_t to) {
    for (; from < to; from += 32) {
      const size_t k = std::min<size_t>(32, to - from);
      out.push_back(static_cast<uint8_t>(k - 1));
      out.insert(out.end(), in.begin() + static_cast<long>(from),
                 in.begin() + static_cast<long>(from + k));
    }
  };
  size_t i = 0, lit = 0;
  while (i + 3 <= n) {
    const uint32_t h = key(i);
    const int64_t cand = table[h];
    table[h] = static_cast<int64_t>(i);
    const size_t c = static_cast<size_t>(cand);
    if (cand < 0 || i - c > 8192 || std::memcmp(&in[c], &in[i], 3) != 0) {
      ++i;
      continue;
    }
    size_t len = 3;
    while (len < 264 && i + len < n && in[c + len] == in[i + len]) ++len;
    literals(lit, i);
    const size_t off = i - c - 1, l = len - 2;
    if (l < 7) {
      out.push_back(static_cast<uint8_t>(l << 5 | off >> 8));
    } else {
      out.push_back(static_cast<uint8_t>(7 << 5 | off >> 8));
      out.push_back(static_cast<uint8_t>(l - 7));
    }
    out.push_back(static_cast<uint8_t>(off & 255));
    for (size_t k = i + 1; k < i + len && k + 3 <= n; ++k) table[key(k)] = static_cast<int64_t>(k);
    i += len;
    lit = i;
  }
  literals(lit, n);
  return out;
}

void expect_reference(const std::vector<uint8_t>& in) {
  const std::vector<uint8_t> want = reference_lzf(in);
  EXPECT_EQ(capz::lzf_compress(in.data(), in.size()), want) << in.size() << " bytes";
  std::vector<uint8_t> buf(capz::lzf_bound(in.size()));
  ASSERT_LE(want.size(), buf.size());
  const size_t n = capz::lzf_compress_into(in.data(), in.size(), buf.data());
  EXPECT_EQ(std::vector<uint8_t>(buf.begin(), buf.begin() + static_cast<long>(n)), want);
  EXPECT_EQ(capz::lzf_decompress(want.data(), want.size(), in.size(), "test"), in);
}

TEST(LzfCapz, ShortInputsFollowTheRule) {
  for (size_t n = 0; n < 40; ++n) {
    std::vector<uint8_t> same(n, 7), ramp(n);
    for (size_t i = 0; i < n; ++i) ramp[i] = static_cast<uint8_t>(i % 5);
    expect_reference(same);
    expect_reference(ramp);
  }
}

TEST(LzfCapz, RandomInputsFollowTheRule) {
  std::mt19937 rng(37);
  for (int t = 0; t < 200; ++t) {  // small alphabets: matches of every length, ends mid-match
    std::vector<uint8_t> in(rng() % 6000);
    const uint32_t alphabet = 1 + rng() % 6;
    for (uint8_t& c : in) c = static_cast<uint8_t>(rng() % alphabet);
    expect_reference(in);
  }
}

TEST(LzfCapz, LongRunsAndFarRepeatsFollowTheRule) {
  std::mt19937 rng(11);
  std::vector<uint8_t> block(8190);
  for (uint8_t& c : block) c = static_cast<uint8_t>(rng());
  for (size_t gap : {8189, 8190, 8191, 8192, 8193}) {  // a repeat at the window's edge
    std::vector<uint8_t> in(block.begin(),
                            block.begin() + static_cast<long>(std::min(gap, block.size())));
    in.resize(gap, 0x55);
    in.insert(in.end(), block.begin(), block.begin() + 600);
    expect_reference(in);
  }
  std::vector<uint8_t> run(100000, 0);  // matches of the most length, one after another
  for (size_t i = 50000; i < run.size(); ++i) run[i] = static_cast<uint8_t>(i % 3 == 0);
  expect_reference(run);
}

TEST(LzfCapz, FloatPlanesFollowTheRule) {
  std::mt19937 rng(5);  // field-major float32 x y z of a sweep-like cloud, as the PCD writer's
  const size_t n = 20000;
  std::vector<uint8_t> in(n * 12);
  for (size_t a = 0; a < 3; ++a)
    for (size_t i = 0; i < n; ++i) {
      const float v = static_cast<float>(static_cast<int>(rng() % 40000) - 20000) * 0.001f;
      std::memcpy(&in[(a * n + i) * 4], &v, 4);
    }
  expect_reference(in);
}

// The writer's field-major buffer kept from frame to frame (larger, then smaller frames) gives
// the bytes of a fresh one.
TEST(LzfCapz, PcdWriterScratchGivesTheSameFile) {
  capz::PcdFrameLayout l;
  l.encoding = "binary_compressed";
  for (const char* name : {"x", "y", "z"}) l.fields.push_back(capz::PCDField{name, 'F', 4, 1});
  l.fields.push_back(capz::PCDField{"intensity", 'U', 1, 1});
  std::mt19937 rng(3);
  std::vector<uint8_t> scratch;
  for (size_t n : {5000, 20000, 7, 0, 12000}) {
    std::vector<uint8_t> points(n * 13);
    for (uint8_t& c : points) c = static_cast<uint8_t>(rng() % 4);
    l.width = n;
    const std::vector<uint8_t> fresh = capz::pcd_frame_bytes(l, points.data());
    EXPECT_EQ(capz::pcd_frame_bytes(l, points.data(), capz::LzfVariant::kCapz, &scratch), fresh);
    EXPECT_EQ(capz::pcd_frame_bytes(l, points.data(), capz::LzfVariant::kLiblzf13, &scratch),
              capz::pcd_frame_bytes(l, points.data(), capz::LzfVariant::kLiblzf13));
  }
}

// A frame file built from the arrays (pcd_frame_file: a binary_compressed body field-major from
// them, without the point-major buffer) holds the bytes of pcd_frame_points then
// pcd_frame_bytes: float32 and float64 coordinates with gaps, a padding field, fields of 1, 2
// and 12 bytes a point, in each encoding, frame after frame through the same buffers.
TEST(LzfCapz, PcdFrameFromArraysGivesTheSameFile) {
  std::mt19937 rng(5);
  for (int xyz_size : {4, 8}) {
    capz::Take t;
    t.pcd = std::make_shared<capz::PCDExtra>();
    for (const char* name : {"x", "y", "z"})
      t.pcd->fields.push_back(capz::PCDField{name, 'F', xyz_size, 1});
    for (const capz::PCDField& f :
         {capz::PCDField{"_", 'U', 1, 3}, capz::PCDField{"ring", 'U', 2, 1},
          capz::PCDField{"normal", 'F', 4, 3}, capz::PCDField{"i", 'U', 1, 1}}) {
      t.pcd->fields.push_back(f);
      t.attributes.push_back(capz::attribute_of(f));
    }
    for (const char* enc : {"binary_compressed", "binary", "ascii"}) {
      capz::PcdFramePlan plan = capz::pcd_frame_plan(t, enc);
      std::vector<uint8_t> points, body;
      for (size_t n : {3000, 7, 0, 1200}) {
        std::vector<double> xyz(n * 3);
        std::vector<uint8_t> valid(n);
        for (size_t i = 0; i < n; ++i) {
          valid[i] = rng() % 5 != 0;
          for (int a = 0; a < 3; ++a) xyz[i * 3 + a] = static_cast<double>(rng() % 100000) * 1e-3;
        }
        std::vector<std::vector<uint8_t>> data;
        std::vector<const uint8_t*> attrs;
        for (const capz::PointAttribute& a : t.attributes) {
          data.emplace_back(n * a.bytes_per_point());
          for (uint8_t& c : data.back()) c = static_cast<uint8_t>(rng() % 7);
        }
        for (const std::vector<uint8_t>& d : data) attrs.push_back(d.data());
        plan.layout.width = n;
        std::vector<uint8_t> fresh_points;
        capz::pcd_frame_points(plan, n, xyz.data(), valid.data(), attrs, &fresh_points);
        const std::vector<uint8_t> want = capz::pcd_frame_bytes(plan.layout, fresh_points.data());
        EXPECT_EQ(capz::pcd_frame_file(plan, n, xyz.data(), valid.data(), attrs, &points, &body),
                  want)
            << enc << ", float" << xyz_size * 8 << ", " << n << " points";
      }
    }
  }
}

}  // namespace

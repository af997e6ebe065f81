// The packed laser table (docs/FORMAT.md "Packed laser table", `units` bit 5): a sweep of many
// rings codes its table packed, smaller than plain and to the same points; fields re-packed
// wider decode the same; a damaged exponent, width, value or padding is corrupt.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "coding/bytes.h"
#include "coding/scan_geometry.h"
#include "coding/scan_shared.h"
#include "scan_geometry_expect.h"

namespace capz {
namespace {

constexpr int kRings = 64;

// One sweep of kRings lasers 0.2 degrees apart, 4 mm range steps (range units), on the 1 mm
// bound's 2 mm grid.
ScanGeometry sweep(ScanHints* h) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  ScanGeometry g;
  const int firings = 300;
  for (int c = 0; c < firings; ++c) {
    const double az = -1.0 + 2.0 * c / firings;
    for (int k = 0; k < kRings; ++k) {
      if (u(rng) < 0.2) continue;
      const double el = (-6.0 + 0.2 * k) * 3.141592653589793 / 180;
      push_polar(&g, h, az + 0.0001 * k, el, 3 + 2 * std::sin(3 * az + k) + 0.02 * u(rng),
                 static_cast<uint32_t>(k));
    }
  }
  g.counts.push_back(static_cast<uint32_t>(g.total()));
  h->grid_per_unit = 500;
  return g;
}

// A packed field as read: exponent, first integer, width and the differences' values.
struct Field {
  int e = 0;
  int64_t j0 = 0;
  unsigned b = 0;
  std::vector<int64_t> d;  // J_k - J_(k-1), k = 1..K-1
};

// The packed fields of payload p (K rings, `count` fields) and where they end.
std::vector<Field> read_fields(const std::vector<uint8_t>& p, size_t count, size_t* end) {
  ByteReader r(p.data(), p.size(), "fields");
  r.bytes(units_offset(p) + 1);
  std::vector<Field> out(count);
  for (Field& f : out) {
    f.e = r.u8();
    f.j0 = r.svarint();
    f.b = r.u8();
    const uint8_t* bits = r.bytes(((kRings - 1) * f.b + 7) / 8);
    size_t at = 0;
    for (int k = 1; k < kRings; ++k) {
      uint64_t v = 0;
      for (unsigned i = 0; i < f.b; ++i, ++at) v |= uint64_t{(bits[at >> 3] >> (at & 7)) & 1u} << i;
      f.d.push_back(static_cast<int64_t>(v >> 1) ^ -static_cast<int64_t>(v & 1));
    }
  }
  *end = r.offset();
  return out;
}

// p with its packed fields written as `fields` say (each at its own width b), and the
// padding's last bit set when `pad`.
std::vector<uint8_t> rewritten(const std::vector<uint8_t>& p, const std::vector<Field>& fields,
                               size_t end, bool pad = false) {
  ByteWriter w;
  w.bytes(p.data(), units_offset(p) + 1);
  for (const Field& f : fields) {
    w.u8(static_cast<uint8_t>(f.e));
    w.svarint(f.j0);
    w.u8(static_cast<uint8_t>(f.b));
    std::vector<uint8_t> bits(((kRings - 1) * f.b + 7) / 8, 0);
    size_t at = 0;
    for (int64_t d : f.d) {
      const uint64_t v = (static_cast<uint64_t>(d) << 1) ^ static_cast<uint64_t>(d >> 63);
      for (unsigned i = 0; i < f.b; ++i, ++at)
        bits[at >> 3] |= static_cast<uint8_t>(((v >> i) & 1u) << (at & 7));
    }
    if (pad && !bits.empty()) bits.back() |= 0x80;
    w.bytes(bits);
  }
  w.bytes(p.data() + end, p.size() - end);
  return w.buffer();
}

TEST(ScanPack, GivenManyRingsThenTheTablePackedSmallerAndExact) {
  ScanHints h;
  const ScanGeometry g = sweep(&h);
  const std::vector<uint8_t> p = encode_scan_geometry(g, h);
  expect_same(g, decode_scan_geometry(p.data(), p.size(), "packed"));
  const scan::Header hd = scan::read_header(p.data(), p.size(), "packed", 1u << 22);
  ASSERT_EQ(hd.table.rings(), size_t{kRings});
  ASSERT_EQ(p[units_offset(p)] & scan::kPackBit, scan::kPackBit);
  ASSERT_EQ(hd.table.pack.size(), hd.table.unit.empty() ? 3u : 4u);
  // The same values plain: the same points, at least 10 bytes a ring more.
  const std::vector<uint8_t> plain = unpacked(p);
  expect_same(g, decode_scan_geometry(plain.data(), plain.size(), "plain"));
  EXPECT_GT(plain.size(), p.size() + 10 * kRings);
}

// The sweep, its payload and the payload's packed fields (and where they end).
struct Packed {
  ScanHints h;
  ScanGeometry g = sweep(&h);
  std::vector<uint8_t> p = encode_scan_geometry(g, h);
  size_t end = 0;
  std::vector<Field> fields =
      read_fields(p, scan::read_header(p.data(), p.size(), "p", 1u << 22).table.pack.size(), &end);
};

TEST(ScanPack, GivenFieldsRepackedWiderThenTheSamePoints) {
  const Packed c;
  const std::vector<uint8_t>& p = c.p;
  std::vector<Field> f = c.fields;
  EXPECT_EQ(rewritten(p, f, c.end), p);  // the reading above is the format's
  for (Field& x : f) x.b = std::min(x.b + 3, scan::kMaxPackBits);
  const std::vector<uint8_t> wide = rewritten(p, f, c.end);
  EXPECT_GT(wide.size(), p.size());
  expect_same(c.g, decode_scan_geometry(wide.data(), wide.size(), "wide"));
}

TEST(ScanPack, GivenDamagedFieldsThenCorrupt) {
  const Packed c;
  const std::vector<uint8_t>& p = c.p;
  const std::vector<Field>& f = c.fields;
  const size_t end = c.end;
  const ScanGeometry& g = c.g;
  for (size_t i = 0; i < f.size(); ++i) {
    std::vector<Field> d = f;
    d[i].e = scan::kMaxPackExponent + 1;  // exponent out of range
    expect_scan_corrupt(rewritten(p, d, end));
    d = f;
    d[i].b = scan::kMaxPackBits + 1;  // differences too wide
    expect_scan_corrupt(rewritten(p, d, end));
    d = f;
    d[i].j0 = scan::kMaxPacked + 1;  // the first integer out of range
    expect_scan_corrupt(rewritten(p, d, end));
    d = f;
    d[i].j0 = scan::kMaxPacked;  // a later one out of range
    d[i].b = std::max(d[i].b, 2u);
    d[i].d.assign(kRings - 1, 1);
    expect_scan_corrupt(rewritten(p, d, end));
    d = f;
    d[i].b = (d[i].b | 1) == d[i].b ? d[i].b : d[i].b + 1;  // odd: 63 b bits leave padding
    ASSERT_NE(((kRings - 1) * d[i].b) % 8, 0u);
    expect_scan_corrupt(rewritten(p, d, end, true));  // a padding bit set
  }
  // Cut inside the first field's differences: corrupt, never read past the end.
  const size_t cut = units_offset(p) + 5;
  expect_scan_corrupt(
      std::vector<uint8_t>(p.begin(), p.begin() + static_cast<std::ptrdiff_t>(cut)));
  // The pack bit cleared: the packed bytes read as a plain table do not give the points.
  std::vector<uint8_t> d = p;
  d[units_offset(p)] &= static_cast<uint8_t>(~scan::kPackBit);
  try {
    EXPECT_NE(decode_scan_geometry(d.data(), d.size(), "damaged").q, g.q);
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kCorrupt);
  }
}

}  // namespace
}  // namespace capz

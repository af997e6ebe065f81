// The laser table and the payload's header, written (docs/FORMAT.md "Scan geometry payload"),
// and the packed laser table, encoder side ("Packed laser table"): the table's values rounded
// to multiples of 2^-E per field, and written as differences of a few bits.
#include <algorithm>
#include <cmath>

#include "coding/bytes.h"
#include "coding/scan_shared.h"
#include "coding/scan_table.h"

namespace capz {
namespace scan {

namespace {

// A packed field: its exponent and values (multiples of 2^-e, as the decoder gives them).
struct Field {
  int e = 0;
  std::vector<double> v;
};

uint64_t zigzag64(int64_t d) {
  return (static_cast<uint64_t>(d) << 1) ^ static_cast<uint64_t>(d >> 63);
}

// The field's integers J_k = v_k 2^e (exact: pack_table made the values so).
std::vector<int64_t> integers(const Field& f) {
  std::vector<int64_t> j;
  j.reserve(f.v.size());
  for (double v : f.v) j.push_back(static_cast<int64_t>(std::ldexp(v, f.e)));
  return j;
}

// Bits of the widest difference's zig-zag.
unsigned width(const std::vector<int64_t>& j) {
  unsigned b = 0;
  for (size_t k = 1; k < j.size(); ++k) {
    uint64_t u = zigzag64(j[k] - j[k - 1]);
    unsigned n = 0;
    while (u) ++n, u >>= 1;
    b = std::max(b, n);
  }
  return b;
}

size_t packed_size(const Field& f) {
  const std::vector<int64_t> j = integers(f);
  uint64_t u = zigzag64(j[0]);
  size_t n = 2;  // E and the varint's last byte
  while (u >= 0x80) ++n, u >>= 7;
  if (j.size() > 1) n += 1 + ((j.size() - 1) * width(j) + 7) / 8;
  return n;
}

void write_field(const Field& f, ByteWriter* w) {
  const std::vector<int64_t> j = integers(f);
  w->u8(static_cast<uint8_t>(f.e));
  w->svarint(j[0]);
  if (j.size() < 2) return;
  const unsigned b = width(j);
  w->u8(static_cast<uint8_t>(b));
  std::vector<uint8_t> bits(((j.size() - 1) * b + 7) / 8, 0);
  size_t at = 0;
  for (size_t k = 1; k < j.size(); ++k) {
    const uint64_t u = zigzag64(j[k] - j[k - 1]);
    for (unsigned i = 0; i < b; ++i, ++at)
      bits[at >> 3] |= static_cast<uint8_t>(((u >> i) & 1u) << (at & 7));
  }
  w->bytes(bits);
}

// The least e (0..52) with 2^e >= x, lowered while a value's |v| 2^e would exceed 2^53;
// -1 when even e = 0 would.
int exponent(const std::vector<double>& v, double x) {
  int e = 0;
  while (e < 52 && std::ldexp(1.0, e) < x) ++e;
  double most = 0;
  for (double a : v) most = std::max(most, std::fabs(a));
  while (e >= 0 && std::ldexp(most, e) > 0x1p53) --e;
  return e;
}

// v rounded to multiples of 2^-e, each then rounded to binary32 when `narrow`.
std::vector<double> rounded(const std::vector<double>& v, int e, bool narrow) {
  std::vector<double> out;
  out.reserve(v.size());
  for (double a : v) {
    const double r = std::ldexp(std::nearbyint(std::ldexp(a, e)), -e);
    out.push_back(narrow ? static_cast<double>(static_cast<float>(r)) : r);
  }
  return out;
}

// The table's packed fields in their order (FORMAT.md), from its values as they are.
std::vector<Field> fields(const Table& t) {
  std::vector<Field> f(3);
  for (size_t k = 0; k < t.rings(); ++k) {
    f[0].v.push_back(t.azimuth0[k]);
    f[1].v.push_back(t.slope[k]);
    f[2].v.push_back(t.z0[k]);
  }
  if (!t.unit.empty()) f.push_back(Field{0, t.unit});
  if (std::any_of(t.offset.begin(), t.offset.end(), [](double v) { return v != 0; }))
    f.push_back(Field{0, t.offset});
  for (size_t i = 0; i < f.size() && i < t.pack.size(); ++i) f[i].e = t.pack[i];
  return f;
}

}  // namespace

void pack_table(Table* t, double reach) {
  const size_t rings = t->rings();
  if (rings == 0) return;
  reach = std::max(reach, 1.0);
  double least_unit = kMaxUnit;
  for (double u : t->unit) least_unit = std::min(least_unit, u);
  std::vector<Field> f = fields(*t);
  // 2^E >= 64 R: an angle's or slope's rounding (at most 2^-(E+1)) moves a point at range R by
  // at most 1/128 of a grid step (256 R cost hesai-at128 0.6 % more, 1024 R 1.2 %; 16 R cost
  // hesai-xt32m and velodyne-vlp16 more: docs/lab/2026-11-29-at128.md).
  const double need[5] = {64 * reach, 64 * reach, 64, 64 * reach / least_unit, 64};
  for (size_t i = 0; i < f.size(); ++i) {
    f[i].e = exponent(f[i].v, need[i]);
    if (f[i].e < 0) return;
    f[i].v = rounded(f[i].v, f[i].e, i < 3);
  }
  Table p = *t;
  for (size_t k = 0; k < rings; ++k) {
    p.azimuth0[k] = static_cast<float>(f[0].v[k]);
    p.slope[k] = static_cast<float>(f[1].v[k]);
    p.z0[k] = static_cast<float>(f[2].v[k]);
  }
  if (f.size() > 3) p.unit = f[3].v;
  if (f.size() > 4) p.offset = f[4].v;
  p.pack.clear();
  for (const Field& x : f) p.pack.push_back(static_cast<uint8_t>(x.e));
  std::vector<Field> g = fields(p);  // the offsets may all have rounded to 0
  g.resize(std::min(g.size(), p.pack.size()));
  p.pack.resize(g.size());
  for (size_t k = 0; k < p.unit.size(); ++k)
    if (!(p.unit[k] >= kMinUnit && p.unit[k] <= kMaxUnit)) return;
  size_t packed = 0;
  for (const Field& x : g) packed += packed_size(x);
  const size_t plain =
      rings *
      (12 + (g.size() > 3 ? 8 : 0) +
       (std::any_of(t->offset.begin(), t->offset.end(), [](double v) { return v != 0; }) ? 8 : 0));
  if (packed < plain) *t = std::move(p);
}

void write_packed_table(const Table& t, ByteWriter* w) {
  for (const Field& f : fields(t)) write_field(f, w);
}

void write_header(const ScanGeometry& g, const std::vector<uint8_t>& flags, const Table& t,
                  std::vector<uint8_t>* out, const std::vector<int32_t>* turns) {
  ByteWriter w;
  w.varint(g.counts.size());
  for (uint32_t n : g.counts) w.varint(n);
  w.bytes(flags);
  write_table(t, &w, turns);
  out->insert(out->end(), w.buffer().begin(), w.buffer().end());
}

void write_table(const Table& t, ByteWriter* out, const std::vector<int32_t>* turns) {
  ByteWriter& w = *out;
  w.varint(t.rings());
  if (t.rings() > 0) {
    w.f32(t.step);
    w.varint(t.columns);
    const bool offsets =
        std::any_of(t.offset.begin(), t.offset.end(), [](double v) { return v != 0; });
    w.u8(static_cast<uint8_t>(
        (t.unit.empty() ? 0
         : offsets      ? 2
                        : 1) |
        (t.bow != 0 ? scan::kBowBit : 0) | (t.turn ? scan::kTurnBit : 0) |
        (t.share.empty() ? 0 : scan::kShareBit) | (t.pack.empty() ? 0 : scan::kPackBit) |
        (t.slots == 0 ? 0 : scan::kSlotBit) | (t.before ? scan::kBeforeBit : 0)));
    if (!t.pack.empty()) {
      write_packed_table(t, &w);
    } else {
      for (size_t k = 0; k < t.rings(); ++k) {
        w.f32(t.azimuth0[k]);
        w.f32(t.slope[k]);
        w.f32(t.z0[k]);
      }
      for (size_t k = 0; k < t.unit.size(); ++k) {
        w.f64(t.unit[k]);
        if (offsets) w.f64(t.offset[k]);
      }
    }
    if (t.bow != 0) w.f32(t.bow);
    if (!t.share.empty()) {
      w.f32(t.fire_turn);
      for (float v : t.share) w.f32(v);
    }
    if (t.slots != 0) {
      w.u8(static_cast<uint8_t>(t.slots));
      for (uint8_t m : t.slot) w.u8(m);
    }
    const bool turned =
        turns && std::any_of(turns->begin(), turns->end(), [](int32_t v) { return v != 0; });
    w.u8(static_cast<uint8_t>((turned ? scan::kMoreTurns : 0) |  // the more byte (FORMAT.md)
                              (t.successors ? scan::kMoreSuccessors : 0)));
    if (turned)
      for (int32_t v : *turns) w.svarint(v);
  }
}

}  // namespace scan
}  // namespace capz

// Fuzz target: the ATTR coder of PCD point fields (src/coding/attributes.h, FORMAT.md 5.3, 6,
// 7.3). Byte 0 picks the mode (bits 0-1), the field set (bits 2-4, and bit 6: sets 8-9 normal
// triples, 10-15 float fields of values k D beside key fields, for predictor 12) and whether the
// window has position integers (bit 7: predictors 10 and 11 allowed, the integers made from the
// shape; bit 5: a ragged window of format 1.1, one frame of every point, coded key-first with
// predictors 12 and 13, decoded positions and geometry rings made from the shape, and with bit 7
// three frames for predictor 12's sweep bit), bytes 1-2 the shape (frames 1..16,
// points 1..256, width a divisor-free 1..points):
//   mode even: the rest is an ATTR body; decoding must return or throw capz::Error, and what
//     decodes must re-encode to a body that decodes to the same bytes;
//   mode odd: the rest are field bytes (repeated to fill the window; for sets 10-15 the
//     parameters of quantum_fields), which must round-trip.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "capz/error.h"
#include "coding/attributes.h"
#include "fuzz_common.h"

namespace {

capz::AttrSpec spec(const char* name, char type, int size, int count) {
  capz::AttrSpec s;
  s.name = name;
  s.type = type;
  s.size = size;
  s.count = count;
  return s;
}

// Sets 10-15: float lanes of values k D (predictor 12, quantum) beside key fields, a float
// placed before its key in the layout (filled by quantum_fields below in the odd mode).
bool quantum_set(int k) {
  return (k & 8) != 0 && (k & 6) != 0;
}

// Field sets covering every lane kind: colour (F and U), integers of each size and signedness,
// floats, COUNT above 1, and (8 and 9) normal triples that predictor 9 completes.
std::vector<capz::AttrSpec> field_set(int k) {
  if (quantum_set(k))
    return (k & 1) ? std::vector<capz::AttrSpec>{spec("ring", 'U', 1, 1), spec("t", 'F', 8, 1),
                                                 spec("azimuth", 'F', 4, 1)}
                   : std::vector<capz::AttrSpec>{
                         spec("distance", 'F', 4, 1), spec("channel", 'U', 2, 1),
                         spec("elevation", 'F', 4, 1), spec("intensity", 'U', 1, 1)};
  if (k & 8)
    return (k & 1) ? std::vector<capz::AttrSpec>{spec("normal", 'F', 4, 3), spec("i", 'U', 1, 1)}
                   : std::vector<capz::AttrSpec>{
                         spec("normal_x", 'F', 4, 1), spec("normal_y", 'F', 4, 1),
                         spec("label", 'U', 2, 1), spec("normal_z", 'F', 4, 1)};
  switch (k & 7) {
    case 0:
      return {spec("rgb", 'F', 4, 1)};
    case 1:
      return {spec("rgba", 'U', 4, 1), spec("intensity", 'F', 4, 1)};
    case 2:
      return {spec("label", 'U', 2, 1), spec("ring", 'U', 1, 1)};
    case 3:
      return {spec("t", 'F', 8, 1), spec("id", 'I', 8, 1)};
    case 4:
      return {spec("desc", 'F', 4, 5)};
    case 5:
      return {spec("a", 'I', 1, 2), spec("b", 'I', 2, 1), spec("c", 'I', 4, 1)};
    case 6:
      return {spec("u", 'U', 8, 1), spec("normal_x", 'F', 4, 1)};
    default:
      return {spec("rgb", 'U', 4, 1), spec("_", 'U', 1, 3)};
  }
}

// The window's position integers (nullptr: none) and, for a ragged window, its decoded positions.
struct Stream {
  const int32_t* q = nullptr;
  const capz::RaggedFields* ragged = nullptr;
};

void round_trip(const std::vector<capz::AttrSpec>& specs,
                const std::vector<std::vector<uint8_t>>& data, const uint8_t* valid, size_t frames,
                size_t points, size_t width, const Stream& st) {
  const std::vector<uint8_t> enc = capz::encode_attributes(
      specs, data, valid, frames, points, width, st.q, st.ragged != nullptr, st.ragged);
  std::vector<std::vector<uint8_t>> back;
  capz::decode_attributes(enc.data(), enc.size(), specs, valid, frames, points, width, &back,
                          "re-encoded", st.q, st.ragged);
  CAPZ_FUZZ_CHECK(back == data);
}

// Odd mode of a quantum set: key fields of a few values, float lanes k D for a step D from the
// input, k from the point's range (distance), from a table by key (elevation, azimuth) or the
// previous k plus a small step (t); the float32 product as a driver computes it, or the binary64
// one rounded once (--attr-error's) by the input, and some values a step off the rule.
std::vector<std::vector<uint8_t>> quantum_fields(const std::vector<capz::AttrSpec>& specs, size_t n,
                                                 const double* xyz, const uint8_t* data,
                                                 size_t size) {
  size_t at = 0;
  auto next = [&]() -> uint8_t { return data[at++ % size]; };
  std::vector<std::vector<uint8_t>> fields;
  std::vector<uint16_t> keys(n, 0);
  for (const capz::AttrSpec& s : specs) {
    std::vector<uint8_t> b(n * static_cast<size_t>(s.size));
    if (s.type != 'F') {
      const uint8_t kinds = static_cast<uint8_t>(1 + next() % 16);
      for (size_t p = 0; p < n; ++p) {
        const uint16_t v = static_cast<uint16_t>(next() % kinds);
        if (s.name == "ring" || s.name == "channel") keys[p] = v;
        for (int i = 0; i < s.size; ++i)
          b[p * static_cast<size_t>(s.size) + static_cast<size_t>(i)] =
              static_cast<uint8_t>(v >> (8 * i));
      }
      fields.push_back(std::move(b));
      continue;
    }
    fields.push_back(std::move(b));
  }
  for (size_t a = 0; a < specs.size(); ++a) {
    const capz::AttrSpec& s = specs[a];
    if (s.type != 'F') continue;
    const double d = std::ldexp(1 + next() / 256.0, -static_cast<int>(next() % 16));
    const bool wide = next() & 1;
    int32_t table[16], k = static_cast<int32_t>(next()) - 128;
    for (int32_t& t : table) t = static_cast<int32_t>(next()) * 37 - 4000;
    for (size_t p = 0; p < n; ++p) {
      const uint8_t c = next();
      if (s.name == "distance" && xyz)
        k = static_cast<int32_t>(
                std::floor(std::sqrt(xyz[3 * p] * xyz[3 * p] + xyz[3 * p + 1] * xyz[3 * p + 1] +
                                     xyz[3 * p + 2] * xyz[3 * p + 2]) /
                               d +
                           0.5)) +
            c % 3 - 1;
      else if (s.name == "t")
        k += c % 4;
      else
        k = table[keys[p] % 16] += (c > 250 ? 1 : 0);
      const double v = static_cast<double>(k) * d;
      uint8_t* out = fields[a].data() + p * static_cast<size_t>(s.size);
      if (s.size == 8) {
        std::memcpy(out, &v, 8);
      } else {
        float f = wide ? static_cast<float>(v)
                       : static_cast<float>(static_cast<double>(static_cast<float>(k)) *
                                            static_cast<double>(static_cast<float>(d)));
        if (c == 255) f = std::nextafter(f, 1e30f);
        std::memcpy(out, &f, 4);
      }
    }
  }
  return fields;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 3) return 0;
  const uint8_t mode = data[0];
  const std::vector<capz::AttrSpec> specs = field_set(((mode >> 2) & 7) | ((mode >> 3) & 8));
  Stream st;
  const bool near = (mode & 128) != 0, ragged = (mode & 32) != 0;
  // A ragged window is one frame of all its points.
  const size_t frames = ragged ? 1 : 1 + (data[1] & 15);
  const size_t points = ragged ? (1 + (data[1] & 15)) * (1 + data[2]) : 1 + data[2];
  // Scattered integer positions drifting by frame (nearest points are not index order).
  std::vector<int32_t> q(near ? frames * points * 3 : 0);
  for (size_t i = 0; i < q.size(); ++i)
    q[i] = static_cast<int32_t>(
               static_cast<uint32_t>(((i / 3) % points) * 2654435761u + (i % 3) * 40503u) >> 24) +
           static_cast<int32_t>(i / (3 * points));
  st.q = near ? q.data() : nullptr;
  // Decoded positions of a ragged window: points on a slowly turning spiral, ranges 1..40 m.
  std::vector<double> xyz(ragged ? 3 * points : 0);
  for (size_t i = 0; i < points && ragged; ++i) {
    const double a = 0.01 * static_cast<double>(i), r = 1 + static_cast<double>(i % 97) * 0.4;
    xyz[3 * i] = r * (1 - a * a / 2);
    xyz[3 * i + 1] = r * a;
    xyz[3 * i + 2] = 0.001 * static_cast<double>(i % 13);
  }
  capz::RaggedFields rf;
  rf.xyz = xyz.data();
  // A ragged window's geometry rings (predictor 13: 7 rings, every fifth point without one) and,
  // with integers, three frames for predictor 12's sweep cells.
  std::vector<uint16_t> rings(ragged ? points : 0);
  for (size_t i = 0; i < rings.size(); ++i)
    rings[i] = i % 5 == 4 ? uint16_t{0xFFFF} : static_cast<uint16_t>((i * 3) % 7);
  const std::vector<size_t> offsets = {0, points / 3, 2 * points / 3, points};
  rf.ring = ragged ? rings.data() : nullptr;
  if (ragged && near) {
    rf.q = q.data();
    rf.frame_offsets = offsets.data();
    rf.frames = 3;
  }
  st.ragged = ragged ? &rf : nullptr;
  const size_t width = 1 + (static_cast<size_t>(data[1] >> 4) * 7) % points;
  // Modes 4k+2 and 4k+3 decode / code under a gap mask (every third point a gap, and a run).
  std::vector<uint8_t> mask(frames * points);
  for (size_t i = 0; i < mask.size(); ++i) mask[i] = i % 3 != 0 && (i / 7) % 5 != 2;
  const uint8_t* valid = (mode & 2) ? mask.data() : nullptr;
  data += 3;
  size -= 3;
  if (mode % 2 == 0) {
    std::vector<std::vector<uint8_t>> out;
    try {
      capz::decode_attributes(data, size, specs, valid, frames, points, width, &out, "fuzz ATTR",
                              st.q, st.ragged);
    } catch (const capz::Error&) {
      return 0;
    }
    round_trip(specs, out, valid, frames, points, width, st);
    return 0;
  }
  if (size == 0) return 0;
  if (quantum_set(((mode >> 2) & 7) | ((mode >> 3) & 8))) {
    const auto fields =
        quantum_fields(specs, frames * points, ragged ? xyz.data() : nullptr, data, size);
    round_trip(specs, fields, valid, frames, points, width, st);
    return 0;
  }
  std::vector<std::vector<uint8_t>> fields;
  size_t at = 0;
  for (const capz::AttrSpec& s : specs) {
    std::vector<uint8_t> b(frames * points * static_cast<size_t>(s.size * s.count));
    for (auto& x : b) x = data[at++ % size];
    fields.push_back(std::move(b));
  }
  round_trip(specs, fields, valid, frames, points, width, st);
  return 0;
}

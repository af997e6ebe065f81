// Hints from point fields (scan_field_hints.h).
#include "codec/scan_field_hints.h"

#include <algorithm>
#include <cstring>
#include <initializer_list>

namespace capz {
namespace {

// The index of block b's first point field (layouts: the take's attributes) named one of
// `names` whose layout `fits`, with a value for every point; -1 when none.
template <class Fits>
long field_index(const std::vector<PointAttribute>& layouts, const FrameBlock& b,
                 std::initializer_list<const char*> names, Fits fits) {
  for (size_t i = 0; i < layouts.size() && i < b.attributes.size(); ++i) {
    const PointAttribute& a = layouts[i];
    if (a.count != 1 || !fits(a) ||
        std::none_of(names.begin(), names.end(), [&](const char* n) { return a.name == n; }))
      continue;
    const size_t size = b.total_points() * static_cast<size_t>(a.size);
    return b.attributes[i].size() == size ? static_cast<long>(i) : -1;
  }
  return -1;
}

long ring_index(const std::vector<PointAttribute>& layouts, const FrameBlock& b) {
  return field_index(layouts, b, {"ring", "channel", "laser_id", "laser"},
                     [](const PointAttribute& a) { return a.type != 'F' && a.size <= 4; });
}

long distance_index(const std::vector<PointAttribute>& layouts, const FrameBlock& b) {
  return field_index(layouts, b, {"distance", "range"}, [](const PointAttribute& a) {
    return a.type == 'F' && (a.size == 4 || a.size == 8);
  });
}

}  // namespace

// The ring / laser / channel number of every point of block b from an unsigned or signed
// integer field of that name (layouts: the take's attributes), or empty.
std::vector<uint32_t> ring_field(const std::vector<PointAttribute>& layouts, const FrameBlock& b) {
  const long i = ring_index(layouts, b);
  if (i < 0) return {};
  const size_t n = b.total_points(), sz = static_cast<size_t>(layouts[size_t(i)].size);
  const std::vector<uint8_t>& data = b.attributes[size_t(i)];
  std::vector<uint32_t> r(n);
  for (size_t p = 0; p < n; ++p) {
    uint32_t v = 0;
    for (size_t k = 0; k < sz; ++k) v |= static_cast<uint32_t>(data[p * sz + k]) << (8 * k);
    r[p] = v;
  }
  return r;
}

// The source's distance field (a float `distance` or `range`, the sensor's measured range), or
// empty: a hint of the sensor's range step (ScanHints::distance).
std::vector<float> distance_field(const std::vector<PointAttribute>& layouts, const FrameBlock& b) {
  const long i = distance_index(layouts, b);
  if (i < 0) return {};
  const size_t n = b.total_points();
  const std::vector<uint8_t>& data = b.attributes[size_t(i)];
  std::vector<float> d(n);
  for (size_t p = 0; p < n; ++p) {
    if (layouts[size_t(i)].size == 4) {
      std::memcpy(&d[p], &data[4 * p], 4);
    } else {
      double v;
      std::memcpy(&v, &data[8 * p], 8);
      d[p] = static_cast<float>(v);
    }
  }
  return d;
}

void keep_hint_fields(const std::vector<PointAttribute>& layouts, FrameBlock* b) {
  const long ring = ring_index(layouts, *b), distance = distance_index(layouts, *b);
  for (size_t i = 0; i < b->attributes.size(); ++i)
    if (static_cast<long>(i) != ring && static_cast<long>(i) != distance)
      std::vector<uint8_t>().swap(b->attributes[i]);
}

}  // namespace capz

// Fuzz target: the .bin frame reader (io/bin_folder.h), in KITTI's record (x y z intensity),
// nuScenes' (x y z intensity ring) or a declared one (--bin-fields: fields of any PCD type),
// chosen by the input's first bytes. On arbitrary bytes it must return or throw capz::Error (a
// size that is not a whole number of points). A frame it accepts has size / point points, and the
// writer's bytes of it are the input but for the gaps' NaNs.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "capz/error.h"
#include "fuzz_common.h"
#include "io/bin_folder.h"

namespace {

// The record the input's first bytes choose (consumed from *data / *size).
std::vector<capz::PCDField> record_of(const uint8_t** data, size_t* size) {
  const uint8_t pick = (*data)[0];
  ++*data;
  --*size;
  if ((pick & 3) == 0) return capz::bin_record_fields({});
  if ((pick & 3) == 1) return capz::bin_record_fields({"a.pcd.bin"});
  static const capz::PCDField kTypes[] = {
      {"f", 'F', 4, 1}, {"d", 'F', 8, 1}, {"u", 'U', 1, 1}, {"w", 'U', 2, 1}, {"v", 'U', 4, 1},
      {"q", 'U', 8, 1}, {"b", 'I', 1, 1}, {"s", 'I', 2, 1}, {"i", 'I', 4, 1}, {"l", 'I', 8, 1}};
  std::vector<capz::PCDField> record;
  const size_t n = (pick >> 2) % 7;  // 0 .. 6 fields
  for (size_t k = 0; k<n&& * size> 0; ++k) {
    capz::PCDField f = kTypes[(*data)[0] % 10];
    f.name += std::to_string(k);
    record.push_back(f);
    ++*data;
    --*size;
  }
  return record;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::vector<capz::PCDField> record = record_of(&data, &size);
  const size_t point = capz::bin_point_bytes(record);
  capz::FrameData f;
  try {
    capz::read_bin_frame(data, size, "fuzz.bin", &f, record);
  } catch (const capz::Error&) {
    CAPZ_FUZZ_CHECK(size % point != 0);
    return 0;
  }
  CAPZ_FUZZ_CHECK(size % point == 0 && f.points == size / point &&
                  f.attrs.size() == record.size() && f.valid.size() == f.points);
  capz::Take layout;  // the fields as the reader's take holds them
  std::vector<const uint8_t*> attrs;
  for (size_t k = 0; k < record.size(); ++k) {
    CAPZ_FUZZ_CHECK(f.attrs[k].size() == static_cast<size_t>(record[k].size) * f.points);
    layout.attributes.push_back(capz::attribute_of(record[k]));
    attrs.push_back(f.attrs[k].data());
  }
  const std::vector<uint8_t> again = capz::bin_record_frame(
      capz::bin_record_sources(layout, record), f.points, f.xyz.data(), f.valid.data(), attrs);
  CAPZ_FUZZ_CHECK(again.size() == size);
  for (size_t p = 0; p < f.points; ++p)
    if (f.valid[p])
      CAPZ_FUZZ_CHECK(std::memcmp(again.data() + point * p, data + point * p, point) == 0);
  return 0;
}

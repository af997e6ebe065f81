// Fuzz target: the PLY frame reader (io/ply.h): header and body, ASCII and binary of either
// byte order. On arbitrary bytes it must return or throw capz::Error. A frame it accepts holds
// the vertices its header announces (every array sized for them, gaps where a coordinate is not
// finite), and the writer's bytes of that frame, read again, give the same frame.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "capz/error.h"
#include "fuzz_common.h"
#include "io/ply.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::vector<uint8_t> bytes(data, data + size);
  capz::PlyHeader h;
  capz::FrameData f;
  try {
    h = capz::parse_ply_header(bytes, "fuzz.ply");
    capz::read_ply_frame(bytes, h, "fuzz.ply", &f);
  } catch (const capz::Error&) {
    return 0;
  }
  CAPZ_FUZZ_CHECK(f.points == h.vertices && f.xyz.size() == 3 * f.points &&
                  f.valid.size() == f.points && f.attrs.size() + 3 == h.fields.size());
  for (size_t p = 0; p < f.points; ++p)
    if (f.valid[p])
      for (int a = 0; a < 3; ++a) CAPZ_FUZZ_CHECK(std::isfinite(f.xyz[3 * p + a]));
  // Written back in the same layout and read again: the same frame.
  capz::Take t;
  t.resize(1, f.points);
  t.xyz = f.xyz;
  t.valid = f.valid;
  auto extra = std::make_shared<capz::PLYExtra>();
  extra->encoding = h.encoding;
  extra->fields = h.fields;
  extra->type_names = h.type_names;
  t.ply = extra;
  size_t k = 0;
  for (const capz::PCDField& fd : h.fields) {
    if (fd.name == "x" || fd.name == "y" || fd.name == "z") continue;
    capz::PointAttribute a = capz::attribute_of(fd);
    a.data = f.attrs[k++];
    t.attributes.push_back(a);
  }
  const capz::PlyPlan plan = capz::ply_plan(t, "");
  std::vector<const uint8_t*> attrs;
  for (const capz::PointAttribute& a : t.attributes) attrs.push_back(a.data.data());
  const std::vector<uint8_t> again =
      capz::ply_frame_bytes(plan, f.points, t.xyz.data(), t.valid.data(), attrs);
  capz::FrameData g;
  const capz::PlyHeader h2 = capz::parse_ply_header(again, "again.ply");
  capz::read_ply_frame(again, h2, "again.ply", &g);
  CAPZ_FUZZ_CHECK(g.points == f.points && g.valid == f.valid && g.attrs.size() == f.attrs.size());
  for (size_t i = 0; i < f.xyz.size(); ++i)
    CAPZ_FUZZ_CHECK(!f.valid[i / 3] || g.xyz[i] == f.xyz[i]);
  for (size_t a = 0; a < f.attrs.size(); ++a) {
    const capz::PointAttribute& at = t.attributes[a];
    if (at.type != 'F' || h.encoding != "ascii") {
      CAPZ_FUZZ_CHECK(g.attrs[a] == f.attrs[a]);
      continue;
    }
    // Float text keeps every value but not a NaN's payload.
    for (size_t p = 0; p < f.points; ++p) {
      double x, y;
      if (at.size == 4) {
        float fx, fy;
        std::memcpy(&fx, &f.attrs[a][4 * p], 4);
        std::memcpy(&fy, &g.attrs[a][4 * p], 4);
        x = fx, y = fy;
      } else {
        std::memcpy(&x, &f.attrs[a][8 * p], 8);
        std::memcpy(&y, &g.attrs[a][8 * p], 8);
      }
      CAPZ_FUZZ_CHECK(x == y || (std::isnan(x) && std::isnan(y)));
    }
  }
  return 0;
}

// capz_rawdump IN OUT.f32 [--mask OUT.mask] [--meta OUT.json]
// Reads any input capz reads (.c3d, .trc, PCD folder) and writes its positions as raw float32
// (see raw_io.h) with gaps filled, so that peers (xz, zstd, fpzip, zfp, draco, PCL) all compress
// the same numbers. The JSON sidecar gives shape, units, rate, storage and the bounding box.
#include <algorithm>
#include <cstdio>
#include <limits>
#include <string>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/take.h"
#include "raw_io.h"

namespace {

int usage() {
  std::fprintf(stderr, "usage: capz_rawdump IN OUT.f32 [--mask OUT.mask] [--meta OUT.json]\n");
  return 1;
}

std::string meta_json(const capz::Take& t, const std::string& in) {
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    lo[k] = std::numeric_limits<double>::infinity();
    hi[k] = -lo[k];
  }
  double max_frame_range = 0;  // largest per-frame extent over the axes (what draco quantises)
  for (size_t f = 0; f < t.frames; ++f) {
    double flo[3], fhi[3];
    for (int k = 0; k < 3; ++k) {
      flo[k] = std::numeric_limits<double>::infinity();
      fhi[k] = -flo[k];
    }
    for (size_t p = 0; p < t.points; ++p) {
      const double* x = t.at(f, p);  // filled values included: peers code them
      for (int k = 0; k < 3; ++k) {
        flo[k] = std::min(flo[k], x[k]);
        fhi[k] = std::max(fhi[k], x[k]);
        if (t.is_valid(f, p)) {
          lo[k] = std::min(lo[k], x[k]);
          hi[k] = std::max(hi[k], x[k]);
        }
      }
    }
    for (int k = 0; k < 3; ++k)
      if (t.points) max_frame_range = std::max(max_frame_range, fhi[k] - flo[k]);
  }
  double diag2 = 0;
  for (int k = 0; k < 3; ++k)
    if (hi[k] >= lo[k]) diag2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
  std::string storage = "float";
  double scale = 0;
  if (t.c3d) {
    storage = t.c3d->float_storage ? "float" : "int16";
    scale = t.c3d->point_scale;
  } else if (t.format == capz::Format::kTRC) {
    storage = "text";
  }
  std::string s = "{\n";
  s += "  \"source\": " + capz_tools::json_str(in) + ",\n";
  s += "  \"format\": " + capz_tools::json_str(capz::format_name(t.format)) + ",\n";
  s += "  \"frames\": " + std::to_string(t.frames) + ",\n";
  s += "  \"points\": " + std::to_string(t.points) + ",\n";
  s += "  \"units\": " + capz_tools::json_str(t.units) + ",\n";
  s += "  \"rate\": " + capz_tools::json_num(t.rate) + ",\n";
  s += "  \"storage\": " + capz_tools::json_str(storage) + ",\n";
  s += "  \"point_scale\": " + capz_tools::json_num(scale) + ",\n";
  s += "  \"gap_samples\": " + std::to_string(t.gap_samples()) + ",\n";
  s += "  \"analog_channels\": " + std::to_string(t.analog.channels) + ",\n";
  s += "  \"bbox_diag\": " + capz_tools::json_num(std::sqrt(diag2)) + ",\n";
  s += "  \"max_frame_range\": " + capz_tools::json_num(max_frame_range) + "\n";
  s += "}\n";
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return usage();
  std::string in = argv[1], out = argv[2], mask_path, meta_path;
  for (int i = 3; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--mask" && i + 1 < argc) {
      mask_path = argv[++i];
    } else if (a == "--meta" && i + 1 < argc) {
      meta_path = argv[++i];
    } else {
      return usage();
    }
  }
  try {
    capz::Take t = capz::read_take(in);
    capz_tools::fill_gaps(&t);
    capz_tools::write_f32(out, t.xyz.data(), t.xyz.size());
    if (!mask_path.empty()) capz_tools::write_bytes(mask_path, t.valid);
    if (!meta_path.empty()) {
      std::string m = meta_json(t, in);
      capz_tools::write_bytes(meta_path, std::vector<uint8_t>(m.begin(), m.end()));
    }
  } catch (const capz::Error& e) {
    std::fprintf(stderr, "capz_rawdump: %s\n", e.what());
    return static_cast<int>(e.code());
  }
  return 0;
}

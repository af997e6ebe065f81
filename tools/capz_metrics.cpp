// capz_metrics ORIG RECON [--shape FRAMES POINTS] [--mask ORIG.mask]
// Error of a reconstruction against the original, over the original's valid samples only, with
// the one metrics module (capz/metrics.h compare()). Prints one JSON object on stdout.
//   ORIG  : any input capz reads (.c3d, .trc, PCD folder), or a raw .f32 (raw_io.h) with
//           --shape (and --mask; without it every sample counts as valid).
//   RECON : a raw .f32 of ORIG's shape, or any input capz reads (e.g. a decompressed .c3d).
// "exact_f32" is true when every valid sample of RECON equals ORIG rounded to float32 (what a
// lossless coder of the raw float32 dump must give); "exact" when it equals ORIG itself.
#include <cmath>
#include <cstdio>
#include <string>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/metrics.h"
#include "raw_io.h"

namespace {

int usage() {
  std::fprintf(stderr,
               "usage: capz_metrics ORIG RECON [--shape FRAMES POINTS] [--mask ORIG.mask]\n");
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return usage();
  std::string orig_path = argv[1], recon_path = argv[2], mask_path;
  size_t frames = 0, points = 0;
  for (int i = 3; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--shape" && i + 2 < argc) {
      frames = std::stoul(argv[++i]);
      points = std::stoul(argv[++i]);
    } else if (a == "--mask" && i + 1 < argc) {
      mask_path = argv[++i];
    } else {
      return usage();
    }
  }
  try {
    capz::Take a = capz_tools::load_input(orig_path, frames, points, mask_path);
    capz::Take b;
    if (capz_tools::ends_with(recon_path, ".f32")) {
      b.resize(a.frames, a.points);
      b.source = recon_path;
      b.xyz = capz_tools::read_f32(recon_path, a.frames * a.points * 3);
      b.valid.clear();  // a raw dump carries no mask: no mismatch count
    } else {
      b = capz::read_take(recon_path);
    }
    capz::ErrorStats s = capz::compare(a, b);
    bool exact = true, exact_f32 = true;
    for (size_t i = 0; i < a.frames * a.points; ++i) {
      if (!a.valid[i]) continue;
      for (int k = 0; k < 3; ++k) {
        double x = a.xyz[i * 3 + k], y = b.xyz[i * 3 + k];
        if (x != y) exact = false;
        if (static_cast<double>(static_cast<float>(x)) != y) exact_f32 = false;
      }
    }
    using capz_tools::json_num;
    std::printf(
        "{\"max_error\": %s, \"max_abs\": %s, \"rmse\": %s, \"kg_error\": %s, \"psnr\": %s, "
        "\"samples\": %zu, \"mask_mismatches\": %zu, \"exact\": %s, \"exact_f32\": %s, "
        "\"frames\": %zu, \"points\": %zu}\n",
        json_num(s.max_error).c_str(), json_num(s.max_abs).c_str(), json_num(s.rmse).c_str(),
        json_num(s.kg_error).c_str(), json_num(s.psnr).c_str(), s.samples, s.mask_mismatches,
        exact ? "true" : "false", exact_f32 ? "true" : "false", a.frames, a.points);
  } catch (const capz::Error& e) {
    std::fprintf(stderr, "capz_metrics: %s\n", e.what());
    return static_cast<int>(e.code());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "capz_metrics: %s\n", e.what());
    return 1;
  }
  return 0;
}

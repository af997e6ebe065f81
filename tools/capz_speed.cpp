// In-process speed of the container coder: reads a take once, then times compress() and
// decompress() of it over several repetitions by process CPU time (std::clock), excluding
// process start-up, reading the input and writing an output. Figures are MB/s of raw float32
// positions (frames x points x 3 x 4 bytes), the unit of issue 3's speed target.
//
//   capz_speed INPUT (--max-error X | --lossless) [--codec NAME] [--no-check] [--reps N]
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <string>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"

namespace {

double cpu_seconds() {
  return static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
}

int usage() {
  std::fprintf(stderr,
               "usage: capz_speed INPUT (--max-error X | --lossless) [--codec NAME] [--no-check] "
               "[--reps N]\n");
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return usage();
  capz::CompressOptions o;
  int reps = 5;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--max-error" && i + 1 < argc) {
      o.max_error = std::stod(argv[++i]);
    } else if (a == "--lossless") {
      o.lossless = true;
    } else if (a == "--codec" && i + 1 < argc) {
      o.codec = argv[++i];
    } else if (a == "--no-check") {
      o.check = false;
    } else if (a == "--reps" && i + 1 < argc) {
      reps = std::max(1, std::stoi(argv[++i]));
    } else {
      return usage();
    }
  }
  try {
    const capz::Take take = capz::read_take(argv[1]);
    const double raw_mb = static_cast<double>(take.frames * take.points * 12) / 1e6;
    std::vector<uint8_t> bytes;
    double enc = 1e30, dec = 1e30;  // the fastest repetition of each
    for (int r = 0; r < reps; ++r) {
      double t0 = cpu_seconds();
      bytes = capz::compress(take, o);
      double t1 = cpu_seconds();
      capz::Take back = capz::decompress(bytes.data(), bytes.size());
      double t2 = cpu_seconds();
      enc = std::min(enc, t1 - t0);
      dec = std::min(dec, t2 - t1);
    }
    std::printf(
        "%s: raw %.2f MB, %zu bytes; encode %.1f ms (%.1f MB/s), decode %.1f ms (%.1f MB/s)"
        ", best of %d\n",
        argv[1], raw_mb, bytes.size(), enc * 1e3, raw_mb / enc, dec * 1e3, raw_mb / dec, reps);
  } catch (const capz::Error& e) {
    std::fprintf(stderr, "capz_speed: %s\n", e.what());
    return 2;
  }
  return 0;
}

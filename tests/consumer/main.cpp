// A program outside capz using the installed library (tests/consumer/CMakeLists.txt).
// Built against capz::capz: `compress_take DIR` writes DIR/bound.capz (max error 0.5 mm) and
// DIR/lossless.capz of a synthetic take. Built against capz::decode (CONSUMER_DECODE_ONLY):
// `decode_take DIR` decodes both and checks them against the same take. Exit 0 when all holds.
#include <capz/codec.h>
#include <capz/error.h>
#include <capz/take.h>
#include <capz/version.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

// Ten markers on a body walking and swaying, 100 Hz, mm; marker 3 missing in frames 40-59.
capz::Take synthetic_take() {
  capz::Take t;
  t.frames = 200;
  t.points = 10;
  t.rate = 100;
  t.units = "mm";
  t.xyz.resize(t.frames * t.points * 3);
  t.valid.assign(t.frames * t.points, 1);
  for (size_t p = 0; p < t.points; ++p) t.labels.push_back("M" + std::to_string(p));
  for (size_t f = 0; f < t.frames; ++f)
    for (size_t p = 0; p < t.points; ++p) {
      const double s = static_cast<double>(f) / 100.0, q = static_cast<double>(p);
      double* x = &t.xyz[(f * t.points + p) * 3];
      x[0] = 1000.0 * s + 80.0 * std::cos(q) + 15.0 * std::sin(6.0 * s + q);
      x[1] = 80.0 * std::sin(q) + 10.0 * std::cos(4.0 * s + 0.5 * q);
      x[2] = 900.0 + 60.0 * q + 5.0 * std::sin(12.0 * s);
    }
  for (size_t f = 40; f < 60; ++f) t.valid[f * t.points + 3] = 0;
  return t;
}

int failures = 0;
void check(bool ok, const std::string& what) {
  if (!ok) {
    std::fprintf(stderr, "consumer: FAILED: %s\n", what.c_str());
    ++failures;
  }
}

std::vector<uint8_t> read_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(f), {});
}

#ifndef CONSUMER_DECODE_ONLY
void write_bytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream f(path, std::ios::binary);
  f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  check(static_cast<bool>(f), "writing " + path);
}

void run(const std::string& dir) {
  const capz::Take take = synthetic_take();
  capz::CompressOptions bound;
  bound.max_error = 0.5;
  capz::CompressStats stats;
  const std::vector<uint8_t> a = capz::compress(take, bound, &stats);
  check(stats.bytes == a.size() && a.size() < take.xyz.size() * 4, "compressed size");
  write_bytes(dir + "/bound.capz", a);
  capz::CompressOptions lossless;
  lossless.lossless = true;
  write_bytes(dir + "/lossless.capz", capz::compress(take, lossless));
  std::printf("consumer: capz %s wrote %zu bytes at 0.5 mm (%zu raw float32)\n",
              capz::version_string(), a.size(), stats.raw_bytes);
}
#else
void run(const std::string& dir) {
  const capz::Take take = synthetic_take();
  for (const char* name : {"bound", "lossless"}) {
    const std::string path = dir + "/" + name + ".capz";
    const std::vector<uint8_t> bytes = read_bytes(path);
    const capz::Take back = capz::decompress(bytes.data(), bytes.size(), path);
    check(back.frames == take.frames && back.points == take.points, path + ": shape");
    check(back.valid == take.valid && back.labels == take.labels, path + ": gaps and labels");
    const bool exact = std::string(name) == "lossless";
    double worst = 0;
    for (size_t i = 0; i < take.xyz.size() && back.xyz.size() == take.xyz.size(); ++i)
      if (take.valid[i / 3]) worst = std::max(worst, std::fabs(back.xyz[i] - take.xyz[i]));
    check(exact ? worst == 0 : worst <= 0.5, path + ": error " + std::to_string(worst));
    std::printf("consumer: decoded %s: %zu frames x %zu points, max error %g mm\n", path.c_str(),
                back.frames, back.points, worst);
  }
  // A damaged stream is refused with capz::Error, never a crash.
  std::vector<uint8_t> bytes = read_bytes(dir + "/bound.capz");
  bytes.resize(bytes.size() / 2);
  bool refused = false;
  try {
    capz::decompress(bytes.data(), bytes.size(), "half.capz");
  } catch (const capz::Error&) {
    refused = true;
  }
  check(refused, "a truncated stream is refused");
}
#endif

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR\n", argv[0]);
    return 2;
  }
  try {
    run(argv[1]);
  } catch (const capz::Error& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
  return failures == 0 ? 0 : 1;
}

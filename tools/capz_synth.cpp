// capz_synth SOURCE OUT --minutes M [--rate HZ] [--points N] [--noise MM] [--seed S]
// A long synthetic take for the scale benchmark, built from a real one: the source's frames are
// played forwards then backwards (so the motion stays continuous at the turns) until M minutes
// at HZ (default 200) are filled; points are the source's first N (default 100), and when the
// source has fewer, copies of its points shifted by 100 mm per copy along x; Gaussian noise of
// sigma MM millimetres (default 0.05, converted to the source's units) is added to every
// coordinate so no loop repeats exactly. The source's gap pattern is kept (looped the same way).
// OUT is written by capz's own writer (.c3d or .trc, float storage).
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "capz/error.h"
#include "capz/io.h"
#include "raw_io.h"

namespace {

int usage() {
  std::fprintf(stderr,
               "usage: capz_synth SOURCE OUT.c3d|OUT.trc --minutes M [--rate HZ] [--points N]"
               " [--noise MM] [--seed S]\n");
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) return usage();
  std::string src = argv[1], out = argv[2];
  double minutes = 0, rate = 200, noise_mm = 0.05;
  size_t want_points = 100;
  unsigned seed = 1;
  for (int i = 3; i < argc; ++i) {
    std::string a = argv[i];
    if (i + 1 >= argc) return usage();
    if (a == "--minutes") {
      minutes = std::stod(argv[++i]);
    } else if (a == "--rate") {
      rate = std::stod(argv[++i]);
    } else if (a == "--points") {
      want_points = std::stoul(argv[++i]);
    } else if (a == "--noise") {
      noise_mm = std::stod(argv[++i]);
    } else if (a == "--seed") {
      seed = static_cast<unsigned>(std::stoul(argv[++i]));
    } else {
      return usage();
    }
  }
  if (!(minutes > 0) || !(rate > 0) || want_points == 0) return usage();
  try {
    capz::Take s = capz::read_take(src);
    if (s.frames < 2 || s.points == 0)
      capz::fail(capz::ErrorCode::kInvalidParameter, src, "source needs >= 2 frames and points");
    capz_tools::fill_gaps(&s);
    double metres = capz::units_to_metres(s.units);
    if (metres == 0) metres = 0.001;   // unknown units: treat as mm
    const double mm = 0.001 / metres;  // one millimetre in the source's units
    const size_t frames = static_cast<size_t>(std::llround(minutes * 60 * rate));

    capz::Take t;
    t.source = out;
    t.format = capz_tools::ends_with(out, ".trc") ? capz::Format::kTRC : capz::Format::kC3D;
    t.resize(frames, want_points);
    t.rate = rate;
    t.units = s.units.empty() ? "mm" : s.units;
    for (size_t p = 0; p < want_points; ++p) t.labels.push_back("M" + std::to_string(p + 1));
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0.0, noise_mm * mm);
    const size_t period = 2 * (s.frames - 1);
    for (size_t f = 0; f < frames; ++f) {
      size_t k = f % period;
      size_t sf = k < s.frames ? k : period - k;  // forwards, then backwards
      for (size_t p = 0; p < want_points; ++p) {
        size_t sp = p % s.points;
        double shift = static_cast<double>(p / s.points) * 100 * mm;
        const double* x = s.at(sf, sp);
        double* y = t.at(f, p);
        y[0] = x[0] + shift + noise(rng);
        y[1] = x[1] + noise(rng);
        y[2] = x[2] + noise(rng);
        t.valid[f * want_points + p] = s.valid[sf * s.points + sp];
      }
    }
    capz::WriteOptions wo;
    wo.overwrite = true;
    wo.c3d_float = true;
    capz::write_take(t, out, wo);
    std::printf("{\"frames\": %zu, \"points\": %zu, \"rate\": %g, \"units\": %s}\n", frames,
                want_points, rate, capz_tools::json_str(t.units).c_str());
  } catch (const capz::Error& e) {
    std::fprintf(stderr, "capz_synth: %s\n", e.what());
    return static_cast<int>(e.code());
  }
  return 0;
}

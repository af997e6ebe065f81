// Seeded synthetic point sequences for the ts codec tests: a deforming blob whose pose repeats
// with a period, moved by a rigid motion (rotation about z and a translation).
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "capz/codec.h"

namespace capz_test {

struct Synth {
  size_t frames = 0, points = 0;
  std::vector<double> xyz;
  std::vector<uint8_t> valid;
  capz::PositionsView view() const {
    capz::PositionsView v;
    v.frames = frames;
    v.points = points;
    v.xyz = xyz.data();
    v.valid = valid.data();
    return v;
  }
};

inline Synth make_synth(size_t frames, size_t points, size_t period, bool rigid, uint32_t seed,
                        double gap_rate = 0) {
  Synth s;
  s.frames = frames;
  s.points = points;
  s.xyz.resize(frames * points * 3);
  s.valid.assign(frames * points, 1);
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01(0, 1);
  std::uniform_real_distribution<double> u01(0, 1);
  std::vector<double> base(points * 3), m1(points * 3), m2(points * 3), m3(points * 3);
  for (size_t i = 0; i < points * 3; ++i) {
    base[i] = n01(rng);
    m1[i] = 0.3 * n01(rng);
    m2[i] = 0.2 * n01(rng);
    m3[i] = 0.1 * n01(rng);
  }
  const double pi = 3.14159265358979323846;
  for (size_t f = 0; f < frames; ++f) {
    const double ph = 2 * pi * static_cast<double>(f % period) / static_cast<double>(period);
    const double a1 = std::sin(ph), a2 = std::cos(2 * ph), a3 = std::sin(3 * ph);
    const double ang = rigid ? 0.02 * static_cast<double>(f) : 0.0;
    const double tx = rigid ? 0.05 * static_cast<double>(f) : 0.0;
    const double c = std::cos(ang), sn = std::sin(ang);
    for (size_t p = 0; p < points; ++p) {
      double v[3];
      for (int a = 0; a < 3; ++a) {
        const size_t i = p * 3 + static_cast<size_t>(a);
        v[a] = base[i] + a1 * m1[i] + a2 * m2[i] + a3 * m3[i];
      }
      double* o = &s.xyz[(f * points + p) * 3];
      o[0] = c * v[0] - sn * v[1] + tx;
      o[1] = sn * v[0] + c * v[1] + 0.5;
      o[2] = v[2] - 0.25;
      if (gap_rate > 0 && u01(rng) < gap_rate) s.valid[f * points + p] = 0;
    }
  }
  return s;
}

}  // namespace capz_test

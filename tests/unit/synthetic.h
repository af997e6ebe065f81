// Seeded synthetic point sequences for the codec unit tests (frames x points x 3, row-major):
// - make_synth: a deforming blob whose pose repeats with a period, optionally moved by a rigid
//   motion (rotation about z and a translation) — what ts's clustering and PCA look for;
// - rigid_bodies: rigid bodies spinning and translating on seeded paths — what pdct's local
//   frames look for.
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
    return capz::PositionsView{frames, points, xyz.data(), valid.data()};
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

// A take of `bodies` rigid bodies of `per_body` points each (points body-major: body b owns
// points [b * per_body, (b + 1) * per_body)). Each body spins about its own axis at its own rate
// and translates; body b is centred near (300 b, 0, 0) in frame 0. Sizes ~ 100 units.
inline Synth rigid_bodies(size_t bodies, size_t per_body, size_t frames, uint32_t seed,
                          double noise = 0.0) {
  Synth t;
  t.frames = frames;
  t.points = bodies * per_body;
  t.xyz.resize(frames * t.points * 3);
  t.valid.assign(frames * t.points, 1);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-50, 50);
  std::normal_distribution<double> g(0, 1);
  for (size_t b = 0; b < bodies; ++b) {
    std::vector<double> local(per_body * 3);
    for (double& v : local) v = u(rng);
    const double rate = 0.02 + 0.03 * static_cast<double>(b);  // rad / frame
    const double tilt = 0.3 * static_cast<double>(b + 1);      // axis tilt
    const double ax[3] = {std::sin(tilt), 0.3, std::cos(tilt)};
    const double n = std::sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
    const double k[3] = {ax[0] / n, ax[1] / n, ax[2] / n};
    for (size_t f = 0; f < frames; ++f) {
      const double th = rate * static_cast<double>(f) * (b % 2 ? -1.0 : 1.0);
      const double c = std::cos(th), s = std::sin(th);
      const double shift[3] = {300.0 * b + 2.0 * f, 40.0 * std::sin(0.05 * f + b), 1.5 * f};
      for (size_t i = 0; i < per_body; ++i) {
        const double* v = &local[3 * i];
        // Rodrigues rotation of v about k by th.
        const double kv = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
        const double kxv[3] = {k[1] * v[2] - k[2] * v[1], k[2] * v[0] - k[0] * v[2],
                               k[0] * v[1] - k[1] * v[0]};
        double* out = &t.xyz[3 * (f * t.points + b * per_body + i)];
        for (int a = 0; a < 3; ++a)
          out[a] = v[a] * c + kxv[a] * s + k[a] * kv * (1 - c) + shift[a] + noise * g(rng);
      }
    }
  }
  return t;
}

}  // namespace capz_test

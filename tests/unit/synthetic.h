// Seeded synthetic point sequences for the codec unit tests (frames x points x 3, row-major):
// - make_synth: a deforming blob whose pose repeats with a period, optionally moved by a rigid
//   motion (rotation about z and a translation) — what ts's clustering and PCA look for;
// - rigid_bodies: rigid bodies spinning and translating on seeded paths — what pdct's local
//   frames look for;
// - synthetic_sweeps: a ragged take of 16-beam spinning LiDAR sweeps, each its own point count.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "codec/transform.h"
#include "support/float32.h"

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

// A ragged take (a PCD folder's, metres, float32 coordinates) of `frames` sweeps of a 16-beam
// spinning LiDAR: frame f has columns0 + dcolumns f columns of 16 points (elevations -15 .. 15
// degrees), the range r0 + r1 |sin(k azimuth)| plus seeded noise within +-noise; point i (over
// all frames) is a NaN gap when i % gap_every == gap_at. Frames are named f0.pcd, f1.pcd, ...
inline capz::Take synthetic_sweeps(size_t frames, size_t columns0, size_t dcolumns, double r0,
                                   double r1, double k, double noise, uint32_t seed,
                                   size_t gap_every, size_t gap_at) {
  capz::Take t;
  t.source = "synthetic";
  t.format = capz::Format::kPCDFolder;
  t.units = "m";
  t.frames = frames;
  t.frame_offsets.assign(1, 0);
  t.pcd = std::make_shared<capz::PCDExtra>();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-noise, noise);
  const double pi = 3.14159265358979323846, nan = std::numeric_limits<double>::quiet_NaN();
  for (size_t f = 0; f < frames; ++f) {
    const size_t columns = columns0 + dcolumns * f;
    for (size_t c = 0; c < columns; ++c)
      for (int ring = 0; ring < 16; ++ring) {
        const double az = 2 * pi * static_cast<double>(c) / static_cast<double>(columns);
        const double el = (-15.0 + 2.0 * ring) * pi / 180;
        const double r = r0 + r1 * std::fabs(std::sin(k * az)) + jitter(rng);
        const bool gap = t.valid.size() % gap_every == gap_at;
        t.xyz.push_back(gap ? nan : capz_test::float32_value(r * std::cos(el) * std::cos(az)));
        t.xyz.push_back(gap ? nan : capz_test::float32_value(r * std::cos(el) * std::sin(az)));
        t.xyz.push_back(gap ? nan : capz_test::float32_value(r * std::sin(el)));
        t.valid.push_back(gap ? 0 : 1);
      }
    t.frame_offsets.push_back(t.valid.size());
    t.pcd->frame_names.push_back("f" + std::to_string(f) + ".pcd");
  }
  return t;
}

// t (a PCD take of x y z) with a U2 point field `name` whose byte i is byte(i), and the PCD
// layout x y z F4 plus the field.
template <class Byte>
capz::Take with_u2_field(capz::Take t, const std::string& name, Byte byte) {
  capz::PointAttribute a{name, 'U', 2, 1, {}};
  a.data.resize(t.total_points() * 2);
  for (size_t i = 0; i < a.data.size(); ++i) a.data[i] = static_cast<uint8_t>(byte(i));
  t.attributes.push_back(a);
  t.pcd->fields = {capz::PCDField{"x", 'F', 4, 1}, capz::PCDField{"y", 'F', 4, 1},
                   capz::PCDField{"z", 'F', 4, 1}, capz::PCDField{name, 'U', 2, 1}};
  return t;
}

}  // namespace capz_test

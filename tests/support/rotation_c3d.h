// Rotation takes for tests and benchmarks (issue #38, item 2): C3D files with a ROTATION section
// of the kind Theia and Visual3D write, built deterministically by a C3D writer of their own
// (header block, parameter section and data laid out here, not by capz's writer), so the
// residue sees a file layout capz did not make.
//
// The motion: a walking body of `segments` rigid segments (segment 0 the world body, the
// identity), each turning smoothly (yaw, pitch and roll of a gait cycle near 1 Hz with
// harmonics) and moving with the pelvis (about 1.3 m/s forward, sway and bounce) plus an offset
// that turns with it; matrices computed in double and rounded to float32 (orthonormal within
// float32 rounding), last row 0 0 0 1, reliability 1. `noise_deg` / `noise_mm`: Gaussian jitter
// of the angles and positions (a tracker's noise; 0: perfectly smooth). Invalid samples (a
// segment lost for a run of samples) are written as ezc3d writes them: 16 NaN and reliability
// -1. Points (markers riding on the segments) and analog channels (force-like sinusoids with
// noise) are optional. Intel processor, float storage. A splitmix64 generator seeded by `seed`
// makes every random choice, so a spec gives the same bytes on every run.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace capz_test {

struct RotationTakeSpec {
  size_t segments = 21;
  size_t frames = 340;          // point frames
  size_t ratio = 1;             // rotation samples per point frame
  double rate = 85;             // point frames per second
  size_t points = 0;            // markers
  size_t channels = 0;          // analog channels
  size_t analog_per_frame = 0;  // analog samples per point frame (with channels)
  double noise_deg = 0.05, noise_mm = 0.2;
  size_t lost_runs = 3;  // runs of invalid samples (a segment lost for 8-40 samples)
  uint64_t seed = 1;
};

namespace rotation_c3d_detail {

struct Rng {
  uint64_t s;
  uint64_t next() {
    uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double gauss() {  // Box-Muller
    const double u = uniform() + 0x1.0p-54, v = uniform();
    return std::sqrt(-2 * std::log(u)) * std::cos(6.283185307179586 * v);
  }
};

inline void put16(std::vector<uint8_t>& b, int v) {
  b.push_back(static_cast<uint8_t>(v & 0xff));
  b.push_back(static_cast<uint8_t>((v >> 8) & 0xff));
}
inline void putf(std::vector<uint8_t>& b, float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<uint8_t>(u >> (8 * i)));
}

// A parameter section written entry by entry: groups first, then parameters.
struct Params {
  std::vector<uint8_t> b;
  size_t last_offset = 0;  // where the last entry's next-entry offset sits
  void entry(int id, const std::string& name, const std::vector<uint8_t>& body,
             const std::string& desc) {
    b.push_back(static_cast<uint8_t>(name.size()));
    b.push_back(static_cast<uint8_t>(static_cast<int8_t>(id)));
    b.insert(b.end(), name.begin(), name.end());
    last_offset = b.size();
    put16(b, static_cast<int>(2 + body.size() + 1 + desc.size()));
    b.insert(b.end(), body.begin(), body.end());
    b.push_back(static_cast<uint8_t>(desc.size()));
    b.insert(b.end(), desc.begin(), desc.end());
  }
  void group(int id, const std::string& name, const std::string& desc) {
    entry(-id, name, {}, desc);
  }
  // type 2 int16, 4 float, -1 char; dims; data bytes.
  size_t param(int id, const std::string& name, int type, const std::vector<int>& dims,
               const std::vector<uint8_t>& data, const std::string& desc = "") {
    std::vector<uint8_t> body;
    body.push_back(static_cast<uint8_t>(static_cast<int8_t>(type)));
    body.push_back(static_cast<uint8_t>(dims.size()));
    for (int d : dims) body.push_back(static_cast<uint8_t>(d));
    const size_t at = b.size() + 2 + name.size() + 2 + body.size();
    body.insert(body.end(), data.begin(), data.end());
    entry(id, name, body, desc);
    return at;
  }
  void i16(int id, const std::string& name, int v, const std::string& desc = "") {
    std::vector<uint8_t> d;
    put16(d, v);
    param(id, name, 2, {}, d, desc);
  }
  size_t i16_later(int id, const std::string& name, const std::string& desc = "") {
    return param(id, name, 2, {}, {0, 0}, desc);
  }
  void f32(int id, const std::string& name, float v, const std::string& desc = "") {
    std::vector<uint8_t> d;
    putf(d, v);
    param(id, name, 4, {}, d, desc);
  }
  void strings(int id, const std::string& name, const std::vector<std::string>& s, int width,
               const std::string& desc = "") {
    std::vector<uint8_t> d;
    for (const std::string& x : s)
      for (int i = 0; i < width; ++i)
        d.push_back(static_cast<uint8_t>(i < static_cast<int>(x.size()) ? x[i] : ' '));
    param(id, name, -1, {width, static_cast<int>(s.size())}, d, desc);
  }
};

inline const char* segment_name(size_t g) {
  static const char* kNames[] = {"worldbody", "pelvis",  "l_thigh", "l_shank", "l_foot", "l_toes",
                                 "r_thigh",   "r_shank", "r_foot",  "r_toes",  "torso",  "head",
                                 "l_uarm",    "l_larm",  "l_hand",  "r_uarm",  "r_larm", "r_hand",
                                 "l_clav",    "r_clav",  "neck"};
  return kNames[g % 21];
}

// Rz(a) Ry(b) Rx(c), row-major 3x3.
inline void rotation(double a, double b, double c, double m[9]) {
  const double ca = std::cos(a), sa = std::sin(a), cb = std::cos(b), sb = std::sin(b),
               cc = std::cos(c), sc = std::sin(c);
  const double r[9] = {ca * cb,
                       ca * sb * sc - sa * cc,
                       ca * sb * cc + sa * sc,
                       sa * cb,
                       sa * sb * sc + ca * cc,
                       sa * sb * cc - ca * sc,
                       -sb,
                       cb * sc,
                       cb * cc};
  for (int i = 0; i < 9; ++i) m[i] = r[i];
}

// The samples: (frames * ratio) x segments x 17 floats (16 column-major, reliability).
inline std::vector<float> rotation_samples(const RotationTakeSpec& s, Rng& rng) {
  const size_t S = s.frames * s.ratio, G = s.segments;
  const double dt = 1.0 / (s.rate * static_cast<double>(s.ratio)), kDeg = M_PI / 180;
  struct Seg {
    double base[3], amp[3][2], phase[3][2], off[3];
  };
  std::vector<Seg> seg(G);
  for (Seg& g : seg) {
    for (int a = 0; a < 3; ++a) {
      g.base[a] = (rng.uniform() - 0.5) * (a == 0 ? 40 : 20) * kDeg;
      for (int h = 0; h < 2; ++h) {
        g.amp[a][h] = rng.uniform() * (a == 1 ? 35 : 12) * kDeg / (h + 1);
        g.phase[a][h] = rng.uniform() * 6.283185307179586;
      }
      g.off[a] = (rng.uniform() - 0.5) * (a == 2 ? 1400 : 400);
    }
  }
  std::vector<uint8_t> lost(S * G, 0);
  for (size_t r = 0; r < s.lost_runs && G > 1 && S > 0; ++r) {
    const size_t g = 1 + rng.next() % (G - 1), len = 8 + rng.next() % 33;
    const size_t from = rng.next() % S;
    for (size_t i = from; i < from + len && i < S; ++i) lost[i * G + g] = 1;
  }
  const double f0 = 0.95;  // gait cycles per second
  std::vector<float> out(S * G * 17);
  for (size_t i = 0; i < S; ++i) {
    const double t = static_cast<double>(i) * dt, w = 6.283185307179586 * f0 * t;
    const double pelvis[3] = {-2000 + 1300 * t, 25 * std::sin(w), 950 + 18 * std::sin(2 * w)};
    const double heading = 0.1 * std::sin(0.3 * w);
    for (size_t g = 0; g < G; ++g) {
      float* o = &out[(i * G + g) * 17];
      if (lost[i * G + g]) {
        for (int k = 0; k < 16; ++k) o[k] = std::nanf("");
        o[16] = -1;
        continue;
      }
      double m[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, p[3] = {0, 0, 0};
      if (g > 0) {
        const Seg& q = seg[g];
        double ang[3];
        for (int a = 0; a < 3; ++a) {
          ang[a] = q.base[a] + s.noise_deg * kDeg * rng.gauss();
          for (int h = 0; h < 2; ++h) ang[a] += q.amp[a][h] * std::sin((h + 1) * w + q.phase[a][h]);
        }
        rotation(ang[0] + heading, ang[1], ang[2], m);
        double hr[9];
        rotation(heading, 0, 0, hr);
        for (int a = 0; a < 3; ++a) {
          p[a] = pelvis[a] + s.noise_mm * rng.gauss();
          for (int b = 0; b < 3; ++b) p[a] += hr[3 * a + b] * q.off[b];
        }
      }
      for (int col = 0; col < 3; ++col) {
        for (int row = 0; row < 3; ++row) o[col * 4 + row] = static_cast<float>(m[3 * row + col]);
        o[col * 4 + 3] = 0;
      }
      for (int row = 0; row < 3; ++row) o[12 + row] = static_cast<float>(p[row]);
      o[15] = 1;
      o[16] = 1;
    }
  }
  return out;
}

}  // namespace rotation_c3d_detail

// The whole file.
inline std::vector<uint8_t> make_rotation_c3d(const RotationTakeSpec& s) {
  using namespace rotation_c3d_detail;
  Rng rng{s.seed};
  const std::vector<float> rot = rotation_samples(s, rng);
  const size_t F = s.frames, N = s.points, A = s.channels * s.analog_per_frame;
  const int kPoint = 1, kAnalog = 2, kTrial = 3, kRot = 4;
  Params p;
  p.b = {1, 80, 0, 84};  // section header: block count filled in below, Intel
  p.group(kPoint, "POINT", "3-D point parameters");
  p.i16(kPoint, "USED", static_cast<int>(N), "Number of 3-D points");
  p.i16(kPoint, "FRAMES", static_cast<int>(F), "Number of frames");
  const size_t point_start = p.i16_later(kPoint, "DATA_START", "Number of first block");
  p.f32(kPoint, "SCALE", -1.0f, "3-D scale factor");
  p.f32(kPoint, "RATE", static_cast<float>(s.rate), "3-D data rate");
  p.strings(kPoint, "UNITS", {"mm"}, 2, "3-D units");
  if (N > 0) {
    std::vector<std::string> labels;
    for (size_t i = 0; i < N; ++i) labels.push_back("M" + std::to_string(i));
    p.strings(kPoint, "LABELS", labels, 4, "Point labels");
  }
  p.group(kAnalog, "ANALOG", "Analog data parameters");
  p.i16(kAnalog, "USED", static_cast<int>(s.channels), "Number of analog channels");
  p.f32(kAnalog, "RATE", static_cast<float>(s.rate * static_cast<double>(s.analog_per_frame)),
        "Analog data rate");
  p.f32(kAnalog, "GEN_SCALE", 1.0f, "General scale factor");
  if (s.channels > 0) {
    std::vector<std::string> labels;
    std::vector<uint8_t> scales, offsets;
    for (size_t i = 0; i < s.channels; ++i) {
      labels.push_back("FZ" + std::to_string(i));
      putf(scales, 1.0f);
      put16(offsets, 0);
    }
    const int n = static_cast<int>(s.channels);
    p.strings(kAnalog, "LABELS", labels, 4, "Channel labels");
    p.param(kAnalog, "SCALE", 4, {n}, scales, "Channel scale factors");
    p.param(kAnalog, "OFFSET", 2, {n}, offsets, "Channel zero offsets");
    p.strings(kAnalog, "UNITS", std::vector<std::string>(s.channels, "N"), 1, "Channel units");
  }
  p.group(kTrial, "TRIAL", "Trial parameters");
  p.i16(kTrial, "ACTUAL_START_FIELD", 1);
  p.i16(kTrial, "ACTUAL_END_FIELD", static_cast<int>(F));
  p.group(kRot, "ROTATION", "Rotation (4x4) data");
  p.i16(kRot, "USED", static_cast<int>(s.segments), "Number of rotation signals");
  const size_t rot_start = p.i16_later(kRot, "DATA_START", "Number of first block");
  p.i16(kRot, "RATIO", static_cast<int>(s.ratio), "Rotation samples per point frame");
  p.f32(kRot, "RATE", static_cast<float>(s.rate * static_cast<double>(s.ratio)), "Rotation rate");
  std::vector<std::string> labels;
  for (size_t g = 0; g < s.segments; ++g)
    labels.push_back(std::string(segment_name(g)) + "_4X4" +
                     (g >= 21 ? std::to_string(g / 21) : ""));
  p.strings(kRot, "LABELS", labels, 16, "Rotation labels");
  std::vector<uint8_t>& b = p.b;
  b[p.last_offset] = b[p.last_offset + 1] = 0;  // the last entry's next-entry offset is 0
  const size_t blocks = (b.size() + 511) / 512;
  b.resize(blocks * 512, 0);
  b[2] = static_cast<uint8_t>(blocks);
  const size_t data_block = 2 + blocks;
  const size_t per_frame = (4 * N + A) * 4;
  const size_t rot_block = data_block + (F * per_frame + 511) / 512;
  b[point_start] = static_cast<uint8_t>(data_block & 0xff);
  b[point_start + 1] = static_cast<uint8_t>(data_block >> 8);
  b[rot_start] = static_cast<uint8_t>(rot_block & 0xff);
  b[rot_start + 1] = static_cast<uint8_t>(rot_block >> 8);

  std::vector<uint8_t> file(512, 0);
  file[0] = 2;
  file[1] = 80;
  std::vector<uint8_t> h;
  put16(h, static_cast<int>(N));
  put16(h, static_cast<int>(A));
  put16(h, 1);
  put16(h, static_cast<int>(F));
  put16(h, 10);
  putf(h, -1.0f);
  put16(h, static_cast<int>(data_block));
  put16(h, static_cast<int>(s.analog_per_frame));
  putf(h, static_cast<float>(s.rate));
  std::copy(h.begin(), h.end(), file.begin() + 2);
  file.insert(file.end(), b.begin(), b.end());
  // Points ride on segment 1 + (i mod (G-1)) with a fixed offset; analog channels: sinusoids
  // with noise.
  const size_t G = s.segments;
  for (size_t f = 0; f < F; ++f) {
    for (size_t i = 0; i < N; ++i) {
      const float* m = &rot[(f * s.ratio * G + (G > 1 ? 1 + i % (G - 1) : 0)) * 17];
      const double off[3] = {40.0 + 10 * static_cast<double>(i % 3), 30.0, -20.0};
      bool ok = !std::isnan(m[0]);
      for (int a = 0; a < 3; ++a) {
        double v = m[12 + a];
        for (int c = 0; c < 3; ++c) v += static_cast<double>(m[c * 4 + a]) * off[c];
        putf(file, ok ? static_cast<float>(v + 0.3 * rng.gauss()) : 0.0f);
      }
      putf(file, ok ? 0.0f : -1.0f);
    }
    for (size_t k = 0; k < A; ++k) {
      const double t = (static_cast<double>(f) + static_cast<double>(k / s.channels) /
                                                     static_cast<double>(s.analog_per_frame)) /
                       s.rate;
      putf(file, static_cast<float>(400 * std::sin(6.0 * t + static_cast<double>(k % s.channels)) +
                                    2 * rng.gauss()));
    }
  }
  file.resize((rot_block - 1) * 512, 0);
  for (float v : rot) putf(file, v);
  file.resize((file.size() + 511) / 512 * 512, 0);
  return file;
}

// The takes of the tests and the benchmark (docs/BENCHMARKS.md), by name.
struct NamedRotationTake {
  std::string name;
  RotationTakeSpec spec;
};
inline std::vector<NamedRotationTake> rotation_takes() {
  std::vector<NamedRotationTake> out;
  RotationTakeSpec s;  // 21 segments x 340 samples at 85 Hz, no points, no analog
  out.push_back({"rot21", s});
  RotationTakeSpec smooth = s;  // a filtered output: no jitter, no lost samples
  smooth.noise_deg = smooth.noise_mm = 0;
  smooth.lost_runs = 0;
  smooth.seed = 2;
  out.push_back({"rot21_smooth", smooth});
  RotationTakeSpec pa = s;  // with 40 markers and 8 analog channels at 10 samples a frame
  pa.points = 40;
  pa.channels = 8;
  pa.analog_per_frame = 10;
  pa.seed = 3;
  out.push_back({"rot21_points_analog", pa});
  RotationTakeSpec r2 = s;  // rotations at twice the point rate, 20 markers
  r2.ratio = 2;
  r2.points = 20;
  r2.seed = 4;
  out.push_back({"rot21_ratio2_points", r2});
  RotationTakeSpec big = s;  // more segments, a longer take, more lost runs
  big.segments = 42;
  big.frames = 1020;
  big.lost_runs = 12;
  big.seed = 5;
  out.push_back({"rot42_long", big});
  return out;
}

}  // namespace capz_test

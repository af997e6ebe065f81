// For the round-trip fuzz targets: a take and compression options built from fuzz bytes, and the
// checks every decode of its stream must pass.
//
// Bytes: [0] frames-1 (1..32), [1] bits 0-2 points-1 (1..8), bit 7 rotations (bits 3-4
// segments-1, bit 5 samples per frame-1, values as raw float32 bits after the coordinates),
// bit 6 analog channels (after the coordinates and rotations: one byte, bits 0-1 channels-1,
// bits 2-3 samples per frame-1, bits 4-5 the values' kind: int16 counts, float32 bits (NaN
// payloads, Inf, -0.0), float32(k x step) for a step from the next byte, or small integers held
// for runs; bit 6 a bound on channel A0 when not lossless, 2^-(next byte % 20); then the values),
// [2] options: bit 0 lossless, bits 1-2 value
// kind (int16 x 0.01, int16 x 1, float32 bits, small ints), bits 3-5 window frames (1..8),
// bit 6 codec ts, bit 7 a KG target (0.05 .. 3.2 %) instead of a bound, with ts (bit 6) or pdct;
// [3] bound exponent (or KG target); then one byte of gap bits per 8 samples, then values
// (read cyclically, so short inputs still fill the take).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/metrics.h"
#include "fuzz_common.h"

namespace capz_fuzz {

struct RoundTripCase {
  capz::Take take;
  capz::CompressOptions opts;
  bool kg = false;          // a KG target (opts.kg_error) instead of a bound
  double kg_target = 0;     // percent
  double bound = 0;         // the bound asked for (when neither lossless nor kg)
  double analog_bound = 0;  // channel A0's bound (0: every analog channel lossless)
};

// A float32 from the next four bytes (little-endian bits: NaN payloads, Inf, -0.0 included).
template <typename Next>
float next_float32(Next& next) {
  uint32_t u = 0;
  for (int b = 0; b < 4; ++b) u |= static_cast<uint32_t>(next()) << (8 * b);
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

// Analog channels from the bytes `next` gives (the layout above); a bound on A0 (when
// `may_bound`) goes into opts.analog_max_error and *bound.
template <typename Next>
void fuzz_analog(Next& next, size_t frames, bool may_bound, capz::Take* t,
                 capz::CompressOptions* opts, double* bound) {
  const uint8_t a = next();
  capz::Analog& an = t->analog;
  an.channels = 1 + (a & 3);
  an.samples_per_frame = 1 + ((a >> 2) & 3);
  an.rate = t->rate * an.samples_per_frame;
  for (int ch = 0; ch < an.channels; ++ch) an.labels.push_back("A" + std::to_string(ch));
  const int kind = (a >> 4) & 3;
  const uint8_t sb = kind == 2 ? next() : 0;
  // 2^-(0..15), or 1/q for q = 3..130 (a step no float is a multiple of)
  const double step = sb & 0x80 ? 1.0 / (3 + (sb & 0x7F)) : std::ldexp(1.0, -(sb & 15));
  const size_t n =
      frames * static_cast<size_t>(an.samples_per_frame) * static_cast<size_t>(an.channels);
  an.values.resize(n);
  std::vector<int32_t> held(static_cast<size_t>(an.channels), 0);
  for (size_t i = 0; i < n; ++i) {
    double v = 0;
    if (kind == 0) {
      v = static_cast<int16_t>(next() | next() << 8);
    } else if (kind == 1) {
      v = next_float32(next);
    } else if (kind == 2) {
      v = static_cast<float>(static_cast<int16_t>(next() | next() << 8) * step);
    } else {
      int32_t& h = held[i % held.size()];
      const uint8_t b = next();
      if (b < 64) h += static_cast<int8_t>(b << 2) >> 2;  // changes a quarter of the time
      v = h;
    }
    an.values[i] = v;
  }
  if ((a & 0x40) && may_bound) {
    *bound = std::ldexp(1.0, -(next() % 20));
    opts->analog_max_error["A0"] = *bound;
  }
}

// Builds the case from `data` (layout above); false when there are fewer than 5 bytes.
inline bool round_trip_case(const uint8_t* data, size_t size, RoundTripCase* c) {
  if (size < 5) return false;
  const size_t frames = 1 + data[0] % 32;
  const size_t points = 1 + data[1] % 8;
  const uint8_t opt = data[2];
  const bool lossless = opt & 1;
  const int kind = (opt >> 1) & 3;
  const size_t window = 1 + ((opt >> 3) & 7);
  const bool ts = (opt >> 6) & 1;
  c->kg = !lossless && ((opt >> 7) & 1);
  c->kg_target = 0.05 * (1 + data[3] % 64);                         // percent
  c->bound = std::ldexp(1.0, -static_cast<int>(data[3] % 24) + 4);  // 16 .. 2^-19
  const uint8_t* rest = data + 4;
  const size_t n_rest = size - 4;
  size_t pos = 0;
  auto next = [&]() { return rest[pos++ % n_rest]; };

  capz::Take& t = c->take;
  t = capz::Take();
  t.source = "fuzz";
  t.format = capz::Format::kTRC;
  t.resize(frames, points);
  t.rate = 100;
  t.units = "mm";
  for (size_t p = 0; p < points; ++p) t.labels.push_back("M" + std::to_string(p));
  const size_t samples = frames * points;
  for (size_t i = 0; i < samples; i += 8) {
    const uint8_t bits = next();
    for (size_t k = i; k < std::min(samples, i + 8); ++k) t.valid[k] = (bits >> (k - i)) & 1;
  }
  for (size_t i = 0; i < samples; ++i) {
    for (int a = 0; a < 3; ++a) {
      double v = 0;
      if (kind == 0 || kind == 1) {
        const int16_t q = static_cast<int16_t>(next() | next() << 8);
        v = kind == 0 ? q * 0.01 : q;
      } else if (kind == 2) {
        v = next_float32(next);
      } else {
        v = static_cast<int8_t>(next());
      }
      if (!std::isfinite(v) || std::fabs(v) > 1e12) t.valid[i] = 0;
      t.xyz[i * 3 + a] = v;
    }
  }
  for (size_t i = 0; i < samples; ++i)
    if (!t.valid[i]) t.xyz[i * 3] = t.xyz[i * 3 + 1] = t.xyz[i * 3 + 2] = 0;
  if (data[1] & 0x80) {  // rotations: any float32 bits, kept exactly whatever the bound
    capz::Rotations& r = t.rotations;
    r.segments = 1 + ((data[1] >> 3) & 3);
    r.samples_per_frame = 1 + ((data[1] >> 5) & 1);
    r.rate = 100.0 * r.samples_per_frame;
    const size_t n = frames * r.per_frame();
    r.matrices.resize(n * 16);
    r.reliability.resize(n);
    for (float& v : r.matrices) v = next_float32(next);
    for (float& v : r.reliability) v = next_float32(next);
  }

  capz::CompressOptions& o = c->opts;
  o = capz::CompressOptions();
  c->analog_bound = 0;
  if (data[1] & 0x40) fuzz_analog(next, frames, !lossless, &t, &o, &c->analog_bound);
  o.lossless = lossless;
  o.max_error = lossless || c->kg ? 0 : c->bound;
  o.kg_error = c->kg ? c->kg_target : 0;
  o.window_frames = window;
  o.codec = ts ? "ts" : c->kg ? "pdct" : "none";
  return true;
}

// The analog channels come back with their layout and labels, every sample bit for bit, but
// channel A0's finite samples within its bound when it has one (a take without C3D parameters:
// the stored values are the physical ones).
inline void check_analog(const RoundTripCase& c, const capz::Take& b) {
  const capz::Analog &x = c.take.analog, &y = b.analog;
  CAPZ_FUZZ_CHECK(y.channels == x.channels && y.samples_per_frame == x.samples_per_frame &&
                  y.rate == x.rate && y.labels == x.labels && y.values.size() == x.values.size());
  for (size_t i = 0; i < x.values.size(); ++i) {
    const double u = x.values[i], v = y.values[i];
    if (c.analog_bound > 0 && i % static_cast<size_t>(x.channels) == 0 && std::isfinite(u)) {
      if (!(std::isfinite(v) && std::fabs(v - u) <= c.analog_bound)) {
        std::fprintf(stderr, "analog sample %zu: %.17g -> %.17g, bound %.17g\n", i, u, v,
                     c.analog_bound);
        std::abort();
      }
    } else if (std::memcmp(&u, &v, sizeof u) != 0) {
      std::fprintf(stderr, "analog sample %zu: %.17g -> %.17g\n", i, u, v);
      std::abort();
    }
  }
}

// Decodes a stream just made from the case and aborts unless it comes back with the same shape
// and gap mask, every valid coordinate within the bound (bit-exact when lossless; for a KG target
// with a transform, whose reconstruction is the output and has no bound, finite with a KG error
// at most the target), and the same rate, units and labels.
inline void check_round_trip(const RoundTripCase& c, const std::vector<uint8_t>& bytes) {
  const capz::Take& t = c.take;
  capz::Take b;
  try {
    b = capz::decompress(bytes.data(), bytes.size(), "round trip");
  } catch (const capz::Error& e) {
    std::fprintf(stderr, "decompress of a fresh stream failed: %s\n", e.what());
    std::abort();
  }
  const capz::StreamInfo si = capz::describe(bytes.data(), bytes.size(), "round trip");
  check_take_shape(b);
  CAPZ_FUZZ_CHECK(b.frames == t.frames && b.points == t.points);
  CAPZ_FUZZ_CHECK(b.valid == t.valid);
  CAPZ_FUZZ_CHECK(b.rate == t.rate && b.units == t.units && b.labels == t.labels);
  CAPZ_FUZZ_CHECK(b.rotations.segments == t.rotations.segments &&
                  b.rotations.per_frame() == t.rotations.per_frame() &&
                  b.rotations.matrices.size() == t.rotations.matrices.size() &&
                  b.rotations.reliability.size() == t.rotations.reliability.size());
  if (!t.rotations.matrices.empty())  // bit for bit, in every mode
    CAPZ_FUZZ_CHECK(std::memcmp(b.rotations.matrices.data(), t.rotations.matrices.data(),
                                t.rotations.matrices.size() * 4) == 0 &&
                    std::memcmp(b.rotations.reliability.data(), t.rotations.reliability.data(),
                                t.rotations.reliability.size() * 4) == 0);
  check_analog(c, b);
  const size_t samples = t.frames * t.points;
  if (si.transform_output) {
    CAPZ_FUZZ_CHECK(c.kg);
    for (size_t i = 0; i < samples; ++i)
      if (t.valid[i])
        for (int a = 0; a < 3; ++a) CAPZ_FUZZ_CHECK(std::isfinite(b.xyz[i * 3 + a]));
    const double achieved = capz::compare(t, b).kg_error;
    if (!(achieved <= c.kg_target * (1 + 1e-9))) {
      std::fprintf(stderr, "KG error %.17g over the target %.17g\n", achieved, c.kg_target);
      std::abort();
    }
    return;
  }
  // Otherwise a bound holds: the one asked for, or with a KG target (codec none) the stored one.
  const double held = c.kg ? si.max_error : c.bound;
  for (size_t i = 0; i < samples; ++i) {
    if (!t.valid[i]) continue;
    for (int a = 0; a < 3; ++a) {
      const double x = t.xyz[i * 3 + a], y = b.xyz[i * 3 + a];
      if (c.opts.lossless) {
        CAPZ_FUZZ_CHECK(std::memcmp(&x, &y, sizeof x) == 0);
      } else if (!(std::fabs(x - y) <= held)) {
        std::fprintf(stderr, "sample %zu axis %d: %.17g -> %.17g, bound %.17g\n", i, a, x, y, held);
        std::abort();
      }
    }
  }
}

}  // namespace capz_fuzz

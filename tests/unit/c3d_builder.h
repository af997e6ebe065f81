// A small C3D builder for the reader/writer tests, independent of the library's encoder.
#pragma once

#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>

#include "capz/error.h"
#include "capz/io.h"
#include "coding/c3d_params.h"
#include "core/atomic_file.h"
#include "io/c3d_internal.h"
#include "support/c3d_compare.h"
#include "test_util.h"

namespace c3d_builder {
using namespace capz;

// ---- a small C3D builder, independent of the library's encoder -----------------------------

struct Param {
  std::string name;
  int8_t type;
  std::vector<int> dims;
  std::vector<double> nums;  // numeric values (type 1, 2, 4)
  std::string chars;         // char data (type -1)
  std::string desc;
  bool locked = false;
};
struct Group {
  int id;
  std::string name;
  std::string desc;
  std::vector<Param> params;
};

inline Param ints(const std::string& n, std::vector<double> v, std::vector<int> dims = {}) {
  return {n, 2, dims, v, "", "", false};
}
inline Param flt(const std::string& n, double v) {
  return {n, 4, {}, {v}, "", "", false};
}
inline Param str(const std::string& n, const std::string& s) {
  return {n, -1, {static_cast<int>(s.size())}, {}, s, "", false};
}
inline Param strs(const std::string& n, const std::vector<std::string>& v, int len) {
  std::string d;
  for (const auto& s : v) d += s + std::string(static_cast<size_t>(len) - s.size(), ' ');
  return {n, -1, {len, static_cast<int>(v.size())}, {}, d, "", false};
}

struct Sample {
  double x, y, z, w;  // w = the 4th word as a number (int16 value, or the float)
};

struct Built {
  int processor = c3d::kIntel;
  bool is_float = false;
  double scale = 0.1;  // magnitude; sign from is_float
  double rate = 100;
  size_t points = 0, frames = 0, channels = 0, spf = 0;
  long first = 1;
  long header_last = -1;  // -1: first + frames - 1
  std::vector<Group> groups;
  std::vector<Sample> samples;                      // frames x points
  std::vector<double> analog;                       // frames x spf x channels
  size_t frames_written = static_cast<size_t>(-1);  // truncate the data section
  std::string swapped_offset;  // this parameter's offset is written in the other byte order
  std::string no_desc_byte;    // this parameter lacks its description byte (offset skips it)

  void i16(std::vector<uint8_t>& o, double v) const {
    uint16_t u = static_cast<uint16_t>(static_cast<int16_t>(static_cast<long>(v)));
    if (processor == c3d::kMips) {
      o.push_back(static_cast<uint8_t>(u >> 8));
      o.push_back(static_cast<uint8_t>(u & 0xff));
    } else {
      o.push_back(static_cast<uint8_t>(u & 0xff));
      o.push_back(static_cast<uint8_t>(u >> 8));
    }
  }
  void u16at(std::vector<uint8_t>& o, size_t at, uint16_t u) const {
    std::vector<uint8_t> t;
    i16(t, static_cast<int16_t>(u));
    o[at] = t[0];
    o[at + 1] = t[1];
  }
  void f32(std::vector<uint8_t>& o, double v) const {
    uint8_t b[4];
    float f = static_cast<float>(v);
    if (processor == c3d::kDec) {
      c3d::float_to_dec(f, b);
    } else {
      uint32_t u;
      std::memcpy(&u, &f, 4);
      for (int i = 0; i < 4; ++i)
        b[i] = static_cast<uint8_t>(u >> (processor == c3d::kMips ? 24 - 8 * i : 8 * i));
    }
    o.insert(o.end(), b, b + 4);
  }

  std::vector<uint8_t> params() const {
    std::vector<uint8_t> o = {1, 0x50, 0, static_cast<uint8_t>(processor)};
    auto entry = [&](const std::string& name, bool locked, int id,
                     const std::vector<uint8_t>& body) {
      int n = static_cast<int>(name.size());
      o.push_back(static_cast<uint8_t>(static_cast<int8_t>(locked ? -n : n)));
      o.push_back(static_cast<uint8_t>(static_cast<int8_t>(id)));
      o.insert(o.end(), name.begin(), name.end());
      i16(o, static_cast<double>(body.size() + 2));
      if (name == swapped_offset) std::swap(o[o.size() - 2], o[o.size() - 1]);
      o.insert(o.end(), body.begin(), body.end());
    };
    for (const auto& g : groups) {
      std::vector<uint8_t> body = {static_cast<uint8_t>(g.desc.size())};
      body.insert(body.end(), g.desc.begin(), g.desc.end());
      entry(g.name, false, -g.id, body);
      for (const auto& p : g.params) {
        std::vector<uint8_t> b = {static_cast<uint8_t>(p.type),
                                  static_cast<uint8_t>(p.dims.size())};
        for (int d : p.dims) b.push_back(static_cast<uint8_t>(d));
        if (p.type == -1) b.insert(b.end(), p.chars.begin(), p.chars.end());
        for (double v : p.nums) {
          if (p.type == 1) b.push_back(static_cast<uint8_t>(v));
          if (p.type == 2) i16(b, v);
          if (p.type == 4) f32(b, v);
        }
        if (p.name != no_desc_byte) {
          b.push_back(static_cast<uint8_t>(p.desc.size()));
          b.insert(b.end(), p.desc.begin(), p.desc.end());
        }
        entry(p.name, p.locked, g.id, b);
      }
    }
    o.push_back(0);
    o.push_back(0);
    o.resize((o.size() + 511) / 512 * 512, 0);
    o[2] = static_cast<uint8_t>(o.size() / 512);
    return o;
  }

  std::vector<uint8_t> bytes() const {
    std::vector<uint8_t> p = params();
    const size_t data_start = 2 + p.size() / 512;
    std::vector<uint8_t> h(512, 0);
    h[0] = 2;
    h[1] = 0x50;
    long last = header_last >= 0 ? header_last : first + static_cast<long>(frames) - 1;
    u16at(h, 2, static_cast<uint16_t>(points));
    u16at(h, 4, static_cast<uint16_t>(channels * spf));
    u16at(h, 6, static_cast<uint16_t>(first));
    u16at(h, 8, static_cast<uint16_t>(last));
    std::vector<uint8_t> t;
    f32(t, is_float ? -scale : scale);
    f32(t, rate);
    std::copy(t.begin(), t.begin() + 4, h.begin() + 12);
    u16at(h, 16, static_cast<uint16_t>(data_start));
    u16at(h, 18, static_cast<uint16_t>(spf));
    std::copy(t.begin() + 4, t.end(), h.begin() + 20);
    std::vector<uint8_t> o(h.size() + p.size());
    std::copy(h.begin(), h.end(), o.begin());
    std::copy(p.begin(), p.end(), o.begin() + static_cast<long>(h.size()));
    size_t nf = std::min(frames, frames_written);
    for (size_t f = 0; f < nf; ++f) {
      for (size_t q = 0; q < points; ++q) {
        const Sample& s = samples[f * points + q];
        for (double v : {s.x, s.y, s.z, s.w}) is_float ? f32(o, v) : i16(o, v);
      }
      for (size_t k = 0; k < spf * channels; ++k) {
        double v = analog[f * spf * channels + k];
        is_float ? f32(o, v) : i16(o, v);
      }
    }
    return o;
  }
};

// Standard groups for a builder: POINT (1), ANALOG (2).
inline void standard_groups(Built& b, const std::vector<std::string>& labels,
                            const std::vector<std::string>& analog_labels = {}) {
  Group pg{1, "POINT", "3-D point parameters", {}};
  pg.params.push_back(ints("USED", {static_cast<double>(b.points)}));
  pg.params.push_back(ints("FRAMES", {static_cast<double>(b.frames)}));
  pg.params.push_back(ints("DATA_START", {0}));  // patched below
  pg.params.push_back(flt("SCALE", b.is_float ? -b.scale : b.scale));
  pg.params.push_back(flt("RATE", b.rate));
  pg.params.push_back(str("UNITS", "mm"));
  for (size_t k = 0; k * 255 < labels.size() || k == 0; ++k) {
    size_t e = std::min(labels.size(), (k + 1) * 255);
    pg.params.push_back(strs(k == 0 ? "LABELS" : "LABELS" + std::to_string(k + 1),
                             std::vector<std::string>(labels.begin() + static_cast<long>(k * 255),
                                                      labels.begin() + static_cast<long>(e)),
                             8));
  }
  pg.params[0].desc = "Number of points";
  pg.params[0].locked = true;
  b.groups.push_back(pg);
  Group ag{2, "ANALOG", "Analog parameters", {}};
  ag.params.push_back(ints("USED", {static_cast<double>(b.channels)}));
  ag.params.push_back(flt("RATE", b.rate * static_cast<double>(b.spf)));
  if (!analog_labels.empty()) ag.params.push_back(strs("LABELS", analog_labels, 6));
  b.groups.push_back(ag);
  // DATA_START: the parameter section size does not depend on its value.
  size_t ds = 2 + b.params().size() / 512;
  b.groups[0].params[2].nums = {static_cast<double>(ds)};
}

// A little gait-like trial: 3 points x 4 frames, one gap, 2 analog channels x 2 samples.
inline Built small_trial(int processor, bool is_float) {
  Built b;
  b.processor = processor;
  b.is_float = is_float;
  b.scale = 0.25;
  b.points = 3;
  b.frames = 4;
  b.channels = 2;
  b.spf = 2;
  for (size_t f = 0; f < b.frames; ++f)
    for (size_t p = 0; p < b.points; ++p) {
      double ix = 100 + 10.0 * static_cast<double>(p) + static_cast<double>(f);
      double iy = -50 - static_cast<double>(f * p);
      double iz = 1000 + static_cast<double>(p);
      double w = static_cast<double>(((p + 1) << 8) | (f + 2));  // mask p+1, residual f+2 steps
      Sample s =
          is_float ? Sample{ix * b.scale, iy * b.scale, iz * b.scale, w} : Sample{ix, iy, iz, w};
      if (f == 2 && p == 1) s = {0, 0, 0, -1};  // a gap
      b.samples.push_back(s);
    }
  for (size_t k = 0; k < b.frames * b.spf * b.channels; ++k)
    b.analog.push_back(static_cast<double>(static_cast<long>(k) * 37 - 200));
  standard_groups(b, {"LASI", "RASI", "LHEE"}, {"FZ1", "EMG1"});
  return b;
}

inline Take read(const Built& b) {
  auto v = b.bytes();
  return read_c3d_bytes(v.data(), v.size(), "test.c3d");
}

inline bool has_warning(const Take& t, const std::string& part) {
  for (const auto& w : t.warnings)
    if (w.find(part) != std::string::npos) return true;
  return false;
}

}  // namespace c3d_builder

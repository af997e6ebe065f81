// compress / decompress / describe (include/capz/codec.h): the Take <-> .capz pipeline.
// Per window: quantise (bound layer) -> optional transform prediction -> predictors + entropy
// coding (coding/positions.h); gaps, C3D sample words and analog beside it.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <string>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/stream.h"
#include "codec/decoder_registry.h"
#include "codec/registry.h"
#include "coding/analog_v3.h"
#include "coding/bytes.h"
#include "coding/c3d_words.h"
#include "coding/container.h"
#include "coding/entropy.h"
#include "coding/mask.h"
#include "coding/positions.h"
#include "core/atomic_file.h"
#include "core/input_file.h"

namespace capz {
namespace {

const char* mode_name(PosMode m) {
  switch (m) {
    case PosMode::kGrid:
      return "grid";
    case PosMode::kDecimal:
      return "decimal-grid";
    case PosMode::kFloat32:
      return "float32-bits";
    case PosMode::kFloat64:
      return "float64-bits";
    case PosMode::kFloat32Grid:
      return "float32-grid";
  }
  return "?";
}

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, 8) == 0;
}

// How coordinates become integers (docs/FORMAT.md 3.1).
struct Grid {
  PosMode mode = PosMode::kGrid;
  double step = 0;   // kGrid: multiplier; kDecimal: divisor
  double bound = 0;  // per-coordinate bound that holds (0 = exact)
  bool lossless = false;
};

template <PosMode M>
inline double dequantise_as(const Grid& g, int32_t q, uint32_t lo) {
  if constexpr (M == PosMode::kGrid) return static_cast<double>(q) * g.step;
  if constexpr (M == PosMode::kDecimal) return static_cast<double>(q) / g.step;
  if constexpr (M == PosMode::kFloat32) return static_cast<double>(ordered_to_float(q));
  if constexpr (M == PosMode::kFloat32Grid)
    return static_cast<double>(static_cast<float>(static_cast<double>(q) * g.step));
  if constexpr (M == PosMode::kFloat64)
    return ordered_to_double(
        static_cast<int64_t>((static_cast<uint64_t>(static_cast<uint32_t>(q)) << 32) | lo));
}

// Calls fn(std::integral_constant<PosMode, g.mode>()): one dispatch, then code for that mode.
template <typename Fn>
void with_mode(PosMode m, Fn&& fn) {
  switch (m) {
    case PosMode::kGrid:
      return fn(std::integral_constant<PosMode, PosMode::kGrid>());
    case PosMode::kDecimal:
      return fn(std::integral_constant<PosMode, PosMode::kDecimal>());
    case PosMode::kFloat32:
      return fn(std::integral_constant<PosMode, PosMode::kFloat32>());
    case PosMode::kFloat32Grid:
      return fn(std::integral_constant<PosMode, PosMode::kFloat32Grid>());
    case PosMode::kFloat64:
      return fn(std::integral_constant<PosMode, PosMode::kFloat64>());
  }
}

// dequantise_as() of every valid coordinate of a window into rec (frames x points x 3), one loop
// per mode.
void dequantise_window(const Grid& g, const WindowInts& wi, std::vector<double>* rec) {
  const size_t n = wi.frames * wi.points;
  double* out = rec->data();
  const int32_t* q = wi.q.data();
  const uint32_t* lo = g.mode == PosMode::kFloat64 ? wi.lo.data() : nullptr;
  with_mode(g.mode, [&](auto m) {
    for (size_t i = 0; i < n; ++i)
      if (wi.valid[i])
        for (size_t k = i * 3; k < i * 3 + 3; ++k)
          out[k] = dequantise_as<decltype(m)::value>(g, q[k], lo ? lo[k] : 0);
  });
}

// C3D reads an all-zero coordinate triple as a gap, so a valid sample that quantises to
// exactly (0, 0, 0) comes back as (0, 0, FLT_MIN) from a lossy C3D stream (FORMAT.md 3.3): a
// normal float32 that survives float storage, far inside the bound's margin.
inline void keep_valid_off_origin(Format source, bool lossless, double* x) {
  if (source == Format::kC3D && !lossless && x[0] == 0 && x[1] == 0 && x[2] == 0)
    x[2] = static_cast<double>(std::numeric_limits<float>::min());
}

bool c3d_int16(const Take& t) {
  return t.c3d && !t.c3d->float_storage && t.c3d->point_scale > 0;
}

// The step of the integers `capz decompress` writes for this take (c3d_write.cpp: stored =
// lround(x / scale) with the scale as float32), or 0 when the written values are the decoded
// doubles to within float32 (float C3D, TRC, PCD).
double written_int16_scale(const Take& t) {
  return c3d_int16(t) ? static_cast<double>(static_cast<float>(t.c3d->point_scale)) : 0.0;
}

// x as the C3D writer stores it at int16 scale `scale`.
inline double as_written(double x, double scale) {
  const double q = x / scale;
  return std::fabs(q) < 4.5e15 ? std::round(q) * scale : x;  // beyond: not int16, written as is
}

// True when grid g reproduces coordinate x exactly (bit for bit).
template <PosMode M>
inline bool grid_exact_as(const Grid& g, double x) {
  const double v = M == PosMode::kDecimal ? x * g.step : x / g.step;
  if (!(std::fabs(v) <= kMaxGridIndex)) return false;
  return same_bits(dequantise_as<M>(g, round_to_int(v), 0), x);
}

// What choosing the grid needs to know of every valid sample, gathered in one pass over the
// take (a block of frames at a time, blocks in order). Each field equals what a pass over the
// whole take computes: maxima, minima, all-of flags and in-order sums.
struct TakeScan {
  double max_abs = 0;                                         // largest |coordinate|
  double min_cheb = std::numeric_limits<double>::infinity();  // smallest max(|x|, |y|, |z|)
  std::vector<Grid> candidates;  // lossless grids in order of preference (lossless_candidates)
  std::vector<uint8_t> exact;    // per candidate: every valid coordinate reproduced exactly
  bool lossless = false;         // a lossless target: all_float32 is tracked
  bool all_float32 = true;       // every valid coordinate is a float32 value
  bool words_on_grid = false;    // C3D residual words are point_scale multiples
  std::vector<uint8_t> kinds;    // analog channel kinds (analog_v3.h)
  bool kg = false;               // accumulate centred_sq
  double centred_sq = 0;         // sum of squared distances to each frame's centroid
  // With kg: the valid coordinates in take order, for the grid search, while they number at
  // most kg_cap (kg_cached turns false, and the vector is freed, past it).
  size_t kg_cap = 0;
  bool kg_cached = false;
  std::vector<double> kg_coords;
};

// Exact lossless grids in the order the encoder prefers them (docs/FORMAT.md 3.1): the int16
// C3D grid, a float C3D's scale grid, then decimal grids (the TRC's own decimals first).
// all = false: only the int16 grid (what a bound needs to detect a lossless int16 take).
std::vector<Grid> lossless_candidates(const Take& t, bool all) {
  std::vector<Grid> c;
  Grid g;
  g.lossless = true;
  if (c3d_int16(t)) {
    g.mode = PosMode::kGrid;
    g.step = t.c3d->point_scale;
    c.push_back(g);
  }
  if (!all) return c;
  if (t.c3d && t.c3d->float_storage && t.c3d->point_scale > 0) {
    g.mode = PosMode::kFloat32Grid;
    g.step = t.c3d->point_scale;
    c.push_back(g);
  }
  std::vector<int> ks;
  if (t.trc && t.trc->decimals >= 0 && t.trc->decimals <= 9) ks.push_back(t.trc->decimals);
  for (int k = 0; k <= 9; ++k)
    if (ks.empty() || k != ks[0]) ks.push_back(k);
  for (int k : ks) {
    g.mode = PosMode::kDecimal;
    g.step = std::pow(10.0, k);
    c.push_back(g);
  }
  return c;
}

TakeScan start_scan(const Take& hdr, const CompressOptions& opts) {
  TakeScan s;
  s.candidates = lossless_candidates(hdr, opts.lossless);
  s.exact.assign(s.candidates.size(), 1);
  s.words_on_grid = hdr.c3d && hdr.c3d->point_scale > 0;
  s.kinds.assign(static_cast<size_t>(std::max(0, hdr.analog.channels)), 0);
  s.kg = !opts.lossless && opts.kg_error > 0;
  s.lossless = opts.lossless;
  return s;
}

// Keeps the KG search's coordinates during the scan (TakeScan::kg_coords), up to cap_bytes.
void cache_kg_coordinates(const Take& hdr, size_t cap_bytes, TakeScan* s) {
  s->kg_cap = cap_bytes / sizeof(double);
  s->kg_cached = s->kg && s->kg_cap >= 3;
  if (s->kg_cached) s->kg_coords.reserve(std::min(s->kg_cap, hdr.frames * hdr.points * 3));
}

// Adds frames b (blocks in order) to the scan; throws kInvalidParameter on a valid sample that is
// not finite. words: the blocks carry C3D residual words (point_scale: the take's).
void scan_block(const FrameBlock& b, const std::string& src, bool words, double point_scale,
                TakeScan* s) {
  const size_t n = b.frames * b.points;
  for (size_t i = 0; i < n; ++i) {
    if (!b.valid[i]) continue;
    const double* x = &b.xyz[i * 3];
    double cheb = 0;
    for (int a = 0; a < 3; ++a) {
      if (!std::isfinite(x[a]))
        fail(ErrorCode::kInvalidParameter, src, "a valid sample holds NaN or infinity");
      const double ax = std::fabs(x[a]);
      s->max_abs = std::max(s->max_abs, ax);
      cheb = std::max(cheb, ax);
      if (s->lossless && s->all_float32 && !is_float32(x[a])) s->all_float32 = false;
    }
    s->min_cheb = std::min(s->min_cheb, cheb);
  }
  // Each candidate grid still exact, one loop per grid (its mode fixed), until a miss.
  for (size_t c = 0; c < s->candidates.size(); ++c) {
    if (!s->exact[c]) continue;
    const Grid& g = s->candidates[c];
    with_mode(g.mode, [&](auto m) {
      for (size_t i = 0; i < n; ++i)
        if (b.valid[i])
          for (size_t k = i * 3; k < i * 3 + 3; ++k)
            if (!grid_exact_as<decltype(m)::value>(g, b.xyz[k])) {
              s->exact[c] = 0;
              return;
            }
    });
  }
  if (words && s->words_on_grid && !residuals_on_grid(b.residual, b.valid, point_scale))
    s->words_on_grid = false;
  if (s->kg_cached) {
    for (size_t i = 0; i < b.frames * b.points && s->kg_cached; ++i) {
      if (!b.valid[i]) continue;
      if (s->kg_coords.size() + 3 > s->kg_cap) {
        s->kg_cached = false;
        std::vector<double>().swap(s->kg_coords);
        break;
      }
      s->kg_coords.insert(s->kg_coords.end(), &b.xyz[i * 3], &b.xyz[i * 3 + 3]);
    }
  }
  if (s->kg) {
    for (size_t f = 0; f < b.frames; ++f) {
      const double* fx = &b.xyz[f * b.points * 3];
      const uint8_t* fv = &b.valid[f * b.points];
      double c[3] = {0, 0, 0};
      size_t k = 0;
      for (size_t p = 0; p < b.points; ++p)
        if (fv[p]) {
          for (int a = 0; a < 3; ++a) c[a] += fx[p * 3 + a];
          ++k;
        }
      if (!k) continue;
      for (double& v : c) v /= static_cast<double>(k);
      for (size_t p = 0; p < b.points; ++p)
        if (fv[p])
          for (int a = 0; a < 3; ++a)
            s->centred_sq += (fx[p * 3 + a] - c[a]) * (fx[p * 3 + a] - c[a]);
    }
  }
  if (!s->kinds.empty())
    update_analog_kinds(b.analog.data(), b.analog.size(), static_cast<int>(s->kinds.size()),
                        &s->kinds);
}

Grid lossless_grid(const TakeScan& s) {
  for (size_t c = 0; c < s.candidates.size(); ++c)
    if (s.exact[c]) return s.candidates[c];
  Grid g;
  g.lossless = true;
  g.step = 0;
  g.mode = s.all_float32 ? PosMode::kFloat32 : PosMode::kFloat64;
  return g;
}

// A C3D stores every coordinate off its int16 grid as float32, so writing the decoded take
// rounds it once more, by up to half a float32 ulp at the largest coordinate. The grid keeps
// that much of the bound in reserve, so the bound holds in the written file, not only in the
// decoded doubles (bigparlove.c3d, with coordinates near 2^18 mm, missed 0.03 mm by 0.00125
// mm without it). Returns 0 for outputs that store the decoded doubles exactly.
double output_rounding_reserve(const Take& t, const TakeScan& s, double bound) {
  if (t.format != Format::kC3D) return 0;  // TRC and PCD writers keep every decoded double
  int e = 0;
  std::frexp(s.max_abs + bound, &e);  // magnitude in [2^(e-1), 2^e): float32 ulp 2^(e-24)
  return std::ldexp(1.0, e - 25);
}

// A grid step for `bound` with the output's rounding reserve taken off.
double reserved_step(const Take& t, const TakeScan& s, double bound) {
  const double r = output_rounding_reserve(t, s, bound);
  if (!(bound > r))
    fail(ErrorCode::kInvalidParameter, t.source,
         "max error " + std::to_string(bound) + " is below the float32 resolution of a C3D at " +
             "coordinates up to " + std::to_string(s.max_abs) + " (use --lossless)");
  return grid_step_for_bound(bound - r);
}

// A grid whose step bounds every coordinate's error by `bound`, in the decoded take and in the
// file the decoder writes in the source's format.
Grid bounded_grid(const Take& t, const TakeScan& s, double bound) {
  Grid g;
  g.mode = PosMode::kGrid;
  g.bound = bound;
  if (c3d_int16(t)) {
    const double sc = t.c3d->point_scale;
    double m = std::max(1.0, std::floor(2.0 * bound / sc));
    if (m == 1.0) {
      g.step = sc;
      g.bound = sc / 2;
      if (!s.exact.empty() && s.exact[0]) {  // candidate 0 is the int16 grid
        g.lossless = true;
        g.bound = 0;
        return g;
      }
    }
    // A coarser int16 multiple must not move a valid sample onto (0, 0, 0), which C3D reads as
    // a gap (the FLT_MIN rule cannot help int16 storage): step down m until none does. A sample
    // lands there when max(|x|, |y|, |z|) < m s / 2.
    for (; m > 1; m -= 1)
      if (!(s.min_cheb < m * sc / 2)) break;
    g.step = m * sc;
    if (m * sc / 2 > bound) g.step = reserved_step(t, s, bound);  // off the grid: float32 C3D
    if (m == 1) g.bound = sc / 2;
  } else {
    g.step = reserved_step(t, s, bound);
  }
  if (s.max_abs / g.step >= kMaxGridIndex)
    fail(ErrorCode::kInvalidParameter, t.source,
         "max error " + std::to_string(bound) + " is too fine for coordinates up to " +
             std::to_string(s.max_abs) + " (the grid index would overflow 32 bits)");
  return g;
}

// sq plus the squared quantisation errors of coordinates x[0..n) on a grid of step `step`,
// added in order.
double quantised_sq_error(const double* x, size_t n, double step, double sq = 0) {
  for (size_t k = 0; k < n; ++k) {
    const double d = x[k] - static_cast<double>(round_to_int(x[k] / step)) * step;
    sq += d * d;
  }
  return sq;
}

// Sum of squared errors of quantising every valid coordinate of the source on a grid of
// `step`, in take order (one pass over the source; the same sum as over TakeScan::kg_coords).
double quantised_sq_error(FrameSource& src, double step, size_t block, FrameBlock* b) {
  double sq = 0;
  const size_t F = src.header().frames;
  std::vector<double> x;
  for (size_t f0 = 0; f0 < F; f0 += block) {
    src.read(f0, std::min(block, F - f0), b);
    x.clear();
    for (size_t i = 0; i < b->frames * b->points; ++i)
      if (b->valid[i]) x.insert(x.end(), &b->xyz[i * 3], &b->xyz[i * 3 + 3]);
    sq = quantised_sq_error(x.data(), x.size(), step, sq);
  }
  return sq;
}

// Squared error and centred energy (per-frame centroid, metrics.h) of a window's valid samples.
// written_scale > 0: the error of b as the C3D writer stores it at that int16 scale (as_written).
double window_sq_error(size_t fn, size_t n, const double* a, const double* b, const uint8_t* valid,
                       double written_scale = 0) {
  double s = 0;
  for (size_t i = 0; i < fn * n; ++i)
    if (valid[i])
      for (size_t k = i * 3; k < i * 3 + 3; ++k) {
        const double d = a[k] - (written_scale > 0 ? as_written(b[k], written_scale) : b[k]);
        s += d * d;
      }
  return s;
}
double centred_sq_window(size_t fn, size_t n, const double* x, const uint8_t* valid) {
  double cs = 0;
  for (size_t f = 0; f < fn; ++f) {
    double c[3] = {0, 0, 0};
    size_t m = 0;
    for (size_t p = 0; p < n; ++p)
      if (valid[f * n + p]) {
        for (int a = 0; a < 3; ++a) c[a] += x[(f * n + p) * 3 + a];
        ++m;
      }
    if (!m) continue;
    for (double& v : c) v /= static_cast<double>(m);
    for (size_t p = 0; p < n; ++p)
      if (valid[f * n + p])
        for (int a = 0; a < 3; ++a) {
          const double d = x[(f * n + p) * 3 + a] - c[a];
          cs += d * d;
        }
  }
  return cs;
}

// The largest grid whose KG error is at or under `kg` percent (bisection on the step; each step
// is one pass over the valid coordinates).
Grid kg_grid(FrameSource& src, const TakeScan& s, double kg, size_t block, FrameBlock* b) {
  const Take& t = src.header();
  const double cs = s.centred_sq;
  const double top = std::max(s.max_abs, 1e-300);
  // The search evaluates about 26 steps. Each used to read the whole source again (for a C3D,
  // parsing it: 14 MB/s against 32 MB/s with --max-error on AlbertoREAL.c3d); the scan kept the
  // valid coordinates for it when they fit CompressOptions::kg_cache_bytes, else it streams.
  auto kg_of = [&](double step) {
    if (!(cs > 0)) return 0.0;
    const double sq = s.kg_cached ? quantised_sq_error(s.kg_coords.data(), s.kg_coords.size(), step)
                                  : quantised_sq_error(src, step, block, b);
    return 100.0 * std::sqrt(sq / cs);
  };
  double lo = top / 1e9, hi = 2 * top;
  if (kg_of(hi) <= kg) {
    lo = hi;
  } else {
    for (int it = 0; it < 50 && hi / lo > 1.0 + 1e-6; ++it) {
      double mid = std::sqrt(lo * hi);
      (kg_of(mid) <= kg ? lo : hi) = mid;
    }
  }
  double step = lo;
  if (c3d_int16(t)) {  // stay on the file's int16 grid
    const double sc = t.c3d->point_scale;
    step = std::max(1.0, std::floor(step / sc)) * sc;
  }
  return bounded_grid(t, s, step / 2 / (1.0 - 0x1p-30));
}

// Integers of a block of frames.
WindowInts window_ints(const FrameBlock& b, const Grid& g) {
  WindowInts w;
  w.frames = b.frames;
  w.points = b.points;
  const size_t n = b.frames * b.points;
  w.valid = b.valid;
  w.q.assign(n * 3, 0);
  if (g.mode == PosMode::kFloat64) w.lo.assign(n * 3, 0);
  // Transform output (grid mode, step 0, FORMAT.md 3.1) quantises nothing: q stays 0. Dividing
  // by the step would give infinities, and converting them to int is undefined behaviour (found
  // by fuzz_simple_round_trip under clang's UBSan, whose -fsanitize=undefined includes
  // float-cast-overflow; GCC's does not).
  if (g.mode == PosMode::kGrid && g.step == 0) return w;
  const double* x = b.xyz.data();
  // One loop per mode (the mode is the same for every coordinate).
  auto each_valid = [&](auto quantise) {
    for (size_t i = 0; i < n; ++i)
      if (w.valid[i])
        for (size_t k = i * 3; k < i * 3 + 3; ++k) quantise(k);
  };
  const double step = g.step;
  switch (g.mode) {
    case PosMode::kGrid:
    case PosMode::kFloat32Grid:
      each_valid([&](size_t k) { w.q[k] = round_to_int(x[k] / step); });
      break;
    case PosMode::kDecimal:
      each_valid([&](size_t k) { w.q[k] = round_to_int(x[k] * step); });
      break;
    case PosMode::kFloat32:
      each_valid([&](size_t k) { w.q[k] = float_to_ordered(static_cast<float>(x[k])); });
      break;
    case PosMode::kFloat64:
      each_valid([&](size_t k) {
        uint64_t o = static_cast<uint64_t>(double_to_ordered(x[k]));
        w.q[k] = static_cast<int32_t>(static_cast<uint32_t>(o >> 32));
        w.lo[k] = static_cast<uint32_t>(o);
      });
      break;
  }
  return w;
}
// Transform prediction on the grid (docs/FORMAT.md 3.3 predictor 3): round(recon / step).
std::vector<int32_t> grid_prediction(const std::vector<double>& recon, double step) {
  std::vector<int32_t> t(recon.size());
  for (size_t i = 0; i < recon.size(); ++i) {
    double v = recon[i] / step;
    if (!(v >= -kMaxGridIndex)) v = -kMaxGridIndex;  // also NaN
    if (v > kMaxGridIndex) v = kMaxGridIndex;
    t[i] = round_to_int(v);
  }
  return t;
}

// What a transform codec is given: the block's positions with gaps filled (transform.h).
std::vector<double> filled_window(const FrameBlock& b) {
  return fill_gaps(b.frames, b.points, b.xyz.data(), b.valid.data());
}

// POSW body with transform output (FORMAT.md 3.3): the codec block alone.
std::vector<uint8_t> transform_only_positions(const std::vector<uint8_t>& codec_bytes) {
  ByteWriter b;
  b.varint(codec_bytes.size());
  b.bytes(codec_bytes);
  return std::move(b.buffer());
}

struct CodecOnly {
  const uint8_t* data = nullptr;
  size_t size = 0;
};
CodecOnly split_transform_only(const uint8_t* data, size_t size, const std::string& what) {
  ByteReader r(data, size, what);
  CodecOnly c;
  const uint64_t n = r.varint();
  if (n == 0 || n > r.remaining())
    fail(ErrorCode::kCorrupt, what,
         "transform output: codec block length " + std::to_string(n) + " with " +
             std::to_string(r.remaining()) + " bytes left");
  c.size = static_cast<size_t>(n);
  c.data = r.bytes(c.size);
  if (r.remaining() != 0)
    fail(ErrorCode::kCorrupt, what, "transform output: bytes after the codec block");
  return c;
}

// Window positions with transform output: the codec's reconstruction of the valid samples.
void decode_transform_output(const uint8_t* data, size_t size, const StreamHeader& h, size_t fn,
                             const std::string& what, WindowInts* wi, std::vector<double>* xyz) {
  const TransformDecoder* codec = find_decoder(h.codec);
  if (!codec)
    fail(ErrorCode::kUnsupportedVersion, what,
         "stream uses transform codec id " + std::to_string(h.codec) + ", unknown to this capz");
  const CodecOnly co = split_transform_only(data, size, what);
  codec->decode(co.data, co.size, fn, h.points, xyz);
  if (xyz->size() != fn * h.points * 3)
    fail(ErrorCode::kCorrupt, what, "codec payload has the wrong size");
  for (size_t i = 0; i < fn * h.points; ++i)
    if (wi->valid[i])
      for (int a = 0; a < 3; ++a)
        if (!std::isfinite((*xyz)[i * 3 + a]))
          fail(ErrorCode::kCorrupt, what, "the transform reconstructs a non-finite value");
}

[[noreturn]] void check_failed(const Take& t, size_t w, const std::string& what) {
  fail(ErrorCode::kInternal, t.source,
       "self-check failed in window " + std::to_string(w) + ": " + what +
           " (please report this; --no-check skips the check)");
}

std::vector<uint8_t> with_window_index(size_t w, uint8_t flag, const std::vector<uint8_t>& body) {
  ByteWriter b;
  b.varint(w);
  if (flag != 0xFF) b.u8(flag);
  b.bytes(body);
  return std::move(b.buffer());
}

// Where the encoder puts the stream: appended to memory, or written to a file as it goes.
class StreamOut {
 public:
  explicit StreamOut(std::vector<uint8_t>* mem) : mem_(mem) {}
  explicit StreamOut(AtomicFile* file) : file_(file) {}
  // Appends buf and clears it.
  void flush(std::vector<uint8_t>* buf) {
    if (mem_) {
      mem_->insert(mem_->end(), buf->begin(), buf->end());
    } else {
      file_->write(*buf);
    }
    size_ += buf->size();
    buf->clear();
  }
  size_t size() const { return size_; }

 private:
  std::vector<uint8_t>* mem_ = nullptr;
  AtomicFile* file_ = nullptr;
  size_t size_ = 0;
};

}  // namespace

// ---------------------------------------------------------------------------------------------
size_t auto_window_frames(size_t points) {
  size_t w = 1024;
  while (w < 8192 && w * points < (size_t{1} << 16)) w *= 2;
  return w;
}

namespace {
// allow_tout = false: a KG target with a transform goes through the grid (the fallback when the
// transform's own reconstruction misses the target in some window).
void compress_source(FrameSource& source, const CompressOptions& opts, StreamOut* out,
                     CompressStats* stats, bool allow_tout = true);
// Thrown by compress_source when a transform-output window misses the KG target.
struct TransformMissedTarget {};

std::vector<uint8_t> compress_with_codec(const Take& take, const CompressOptions& opts,
                                         CompressStats* stats, bool allow_tout = true) {
  if (take.xyz.size() != take.frames * take.points * 3 ||
      take.valid.size() != take.frames * take.points)
    fail(ErrorCode::kInvalidParameter, take.source,
         "take arrays do not match its frame and point counts");
  const bool analog = take.analog.channels > 0 && take.analog.samples_per_frame > 0;
  if (analog && take.analog.values.size() !=
                    take.frames * static_cast<size_t>(take.analog.samples_per_frame) *
                        static_cast<size_t>(take.analog.channels))
    fail(ErrorCode::kInvalidParameter, take.source,
         "analog values do not match frames x samples x channels");
  std::unique_ptr<FrameSource> src = take_frames(take);
  std::vector<uint8_t> bytes;
  StreamOut out(&bytes);
  compress_source(*src, opts, &out, stats, allow_tout);
  return bytes;
}

std::vector<uint8_t> compress_one(const Take& take, const CompressOptions& opts,
                                  CompressStats* stats) {
  try {
    return compress_with_codec(take, opts, stats);
  } catch (const TransformMissedTarget&) {
    return compress_with_codec(take, opts, stats, false);
  }
}
}  // namespace

namespace {
// The --codec-opt keys meant for `codec`: a key "name.key" goes to the codec called name only
// (a name that is no codec is an error); a bare key goes to whichever codec was chosen.
std::map<std::string, std::string> options_for(const TransformCodec& codec,
                                               const std::map<std::string, std::string>& all) {
  std::map<std::string, std::string> mine;
  for (const auto& kv : all) {
    const size_t dot = kv.first.find('.');
    if (dot == std::string::npos) {
      mine[kv.first] = kv.second;
      continue;
    }
    const std::string prefix = kv.first.substr(0, dot);
    if (!find_codec(prefix))
      fail(ErrorCode::kInvalidParameter, "",
           "--codec-opt " + kv.first + ": '" + prefix + "' is not a codec (ts, pdct)");
    if (prefix == codec.name()) mine[kv.first.substr(dot + 1)] = kv.second;
  }
  return mine;
}
}  // namespace

// "auto" tries every candidate stage on the whole take and keeps the smallest stream: the plain
// coder ("none") first, then each registered transform. A transform that cannot run on this
// take (e.g. pdct on fewer than 3 points) is skipped, never fatal, so auto is never worse than
// "none". Encode time is the sum of all candidates' (about 3x), decode time is the winner's.
std::vector<uint8_t> compress(const Take& take, const CompressOptions& opts, CompressStats* stats) {
  if (opts.codec != "auto") return compress_one(take, opts, stats);
  // Options are checked before any trial: a mistyped key is the user's error, not a reason to
  // skip a codec. Under auto a key must name its codec ("ts.lpc_order=2").
  for (const auto& kv : opts.codec_options)
    if (kv.first.find('.') == std::string::npos)
      fail(ErrorCode::kInvalidParameter, take.source,
           "--codec auto: name the codec of option '" + kv.first + "' (e.g. ts." + kv.first + ")");
  for (const TransformCodec* c : all_codecs()) {
    TransformParams p;
    p.clusters = opts.clusters;
    p.options = options_for(*c, opts.codec_options);
    c->check_params(p);
  }
  CompressOptions o = opts;
  o.codec = "none";
  o.codec_options.clear();
  CompressStats best_stats;
  std::vector<uint8_t> best = compress_with_codec(take, o, &best_stats);
  if (!opts.lossless) {
    for (const TransformCodec* c : all_codecs()) {
      o.codec = c->name();
      o.codec_options = opts.codec_options;
      CompressStats st;
      std::vector<uint8_t> out;
      try {
        out = compress_one(take, o, &st);
      } catch (const Error& e) {
        if (e.code() != ErrorCode::kInvalidParameter) throw;
        continue;  // this stage does not apply to the take
      }
      if (out.size() < best.size()) {
        best.swap(out);
        best_stats = st;
      }
    }
  }
  if (stats) *stats = best_stats;
  return best;
}

namespace {
void compress_source(FrameSource& source, const CompressOptions& opts, StreamOut* out,
                     CompressStats* stats, bool allow_tout) {
  const Take& take = source.header();
  const std::string& src = take.source;
  // Up to 8192 frames a window keeps even an all-gap window above the decoder's plausibility
  // floor of one byte per 2900 samples (docs/FORMAT.md 2).
  if (opts.window_frames > 8192)
    fail(ErrorCode::kInvalidParameter, src, "window size must be 1 .. 8192 frames");
  const size_t F = take.frames, N = take.points;
  // Transform codecs keep 1024-frame windows by default (their cost grows with the window).
  const bool plain = opts.codec.empty() || opts.codec == "none";
  const size_t W = opts.window_frames ? opts.window_frames : plain ? auto_window_frames(N) : 1024;
  const bool words = source.has_sample_words();
  const double point_scale = take.c3d ? take.c3d->point_scale : 0;
  FrameBlock block;

  const TransformCodec* codec = nullptr;
  if (!opts.codec.empty() && opts.codec != "none") {
    codec = find_codec(opts.codec);
    if (!codec) fail(ErrorCode::kInvalidParameter, src, "unknown codec '" + opts.codec + "'");
  } else if (!opts.codec_options.empty()) {
    fail(ErrorCode::kInvalidParameter, src,
         "--codec-opt " + opts.codec_options.begin()->first + ": codec none takes no options");
  }
  // Only a KG target and a transform: the transform's reconstruction is the output, no grid and
  // no bound layer (FORMAT.md 3.1 "transform output"); the transform meets the KG target itself.
  const bool tout = allow_tout && !opts.lossless && opts.kg_error > 0 && codec && N > 0 && F > 0;
  const double written_scale = tout ? written_int16_scale(take) : 0.0;
  // Pass 1: what the grid and the per-take coding choices depend on.
  TakeScan scan = start_scan(take, opts);
  if (!tout) cache_kg_coordinates(take, opts.kg_cache_bytes, &scan);
  for (size_t f0 = 0; f0 < F; f0 += W) {
    source.read(f0, std::min(W, F - f0), &block);
    scan_block(block, src, words, point_scale, &scan);
  }
  Grid g;
  if (tout) {
    g.mode = PosMode::kGrid;  // step 0, bound 0: nothing is quantised
  } else if (opts.lossless) {
    g = lossless_grid(scan);
  } else if (opts.kg_error > 0) {
    g = kg_grid(source, scan, opts.kg_error, W, &block);
    std::vector<double>().swap(scan.kg_coords);  // not needed by the coding pass
  } else if (opts.max_error > 0 && std::isfinite(opts.max_error)) {
    g = bounded_grid(take, scan, opts.max_error);
  } else {
    fail(ErrorCode::kInvalidParameter, src,
         "no error target: give a positive max error, a KG error target, or lossless");
  }

  TransformParams tparams;
  tparams.max_error = tout ? 0.0 : g.bound > 0 ? g.bound : g.step / 2;
  tparams.grid_step = g.step;
  tparams.kg_error = opts.kg_error;
  tparams.clusters = opts.clusters;
  if (codec) {
    tparams.options = options_for(*codec, opts.codec_options);
    codec->check_params(tparams);
  }
  if (g.mode != PosMode::kGrid) codec = nullptr;  // float-bit lossless: prediction only

  const bool analog = take.analog.channels > 0 && take.analog.samples_per_frame > 0;
  const size_t S = analog ? static_cast<size_t>(take.analog.samples_per_frame) : 0;
  const size_t C = analog ? static_cast<size_t>(take.analog.channels) : 0;
  const bool words_on_grid = words && scan.words_on_grid;
  const std::vector<uint8_t> kinds = analog ? scan.kinds : std::vector<uint8_t>();

  StreamHeader h;
  h.frames = F;
  h.points = static_cast<uint32_t>(N);
  h.window_frames = static_cast<uint32_t>(W);
  h.source_format = take.format;
  h.mode = g.mode;
  h.codec = codec ? codec->id() : 0;
  h.lossless = g.lossless;
  h.transform_output = tout;
  h.kg_target = tout ? opts.kg_error : 0.0;
  h.step = g.step;
  h.max_error = g.bound;
  h.analog_channels = static_cast<uint32_t>(C);
  h.analog_samples_per_frame = static_cast<uint32_t>(S);

  // Pass 2: code each window, write its chunks, drop it.
  std::vector<uint8_t> buf;
  write_file_header(&buf);
  append_chunk(&buf, "HEAD", encode_header(h));
  append_chunk(&buf, "META", encode_meta(take, words));
  size_t other = buf.size(), pos_bytes = 0, analog_bytes = 0;
  out->flush(&buf);

  ErrorAccumulator acc;
  std::vector<IndexEntry> index;
  const bool f64 = g.mode == PosMode::kFloat64;
  for (size_t w = 0, f0 = 0; f0 < F; ++w, f0 += W) {
    const size_t fn = std::min(W, F - f0);
    source.read(f0, fn, &block);
    IndexEntry ie;
    ie.offset = out->size();
    WindowInts wi = window_ints(block, g);
    std::vector<uint8_t> codec_bytes;
    std::vector<int32_t> tpred;
    std::vector<double> recon;
    // With transform output: the window's centred energy and its squared-error budget.
    const double centred = tout ? centred_sq_window(fn, N, block.xyz.data(), wi.valid.data()) : 0;
    const double kg_budget = opts.kg_error / 100 * (opts.kg_error / 100) * centred;
    if (codec && N > 0) {
      std::vector<double> filled = filled_window(block);
      PositionsView view{fn, N, filled.data(), wi.valid.data()};
      TransformParams wp = tparams;
      for (int attempt = 0;; ++attempt) {
        codec_bytes.clear();  // encode appends
        recon.clear();
        codec->encode(view, wp, &codec_bytes, &recon);
        if (recon.size() != fn * N * 3)
          throw Error(ErrorCode::kInternal, std::string("codec ") + codec->name() +
                                                " returned a reconstruction of the wrong size");
        // Transform output decompressed to an int16 C3D is rounded once more to the file's
        // scale, which adds error the codec did not see. When the rounded window misses the KG
        // target, the codec is run again with the target lowered by what the rounding added
        // (squared errors add: e_t^2 + rounding = target^2), at most three times; the check
        // below then holds both the decoded and the written values to the target.
        if (!tout || written_scale == 0 || attempt == 3) break;
        const double e_t = window_sq_error(fn, N, block.xyz.data(), recon.data(), wi.valid.data());
        const double e_w =
            window_sq_error(fn, N, block.xyz.data(), recon.data(), wi.valid.data(), written_scale);
        if (e_w <= kg_budget || !(centred > 0)) break;
        const double room = kg_budget - std::max(0.0, e_w - e_t);
        if (!(room > 0)) break;  // the rounding alone exceeds the target: the grid fallback
        wp.kg_error = 100 * std::sqrt(0.98 * room / centred);
      }
      if (!tout) tpred = grid_prediction(recon, g.step);
    }
    const bool gaps = std::find(wi.valid.begin(), wi.valid.end(), 0) != wi.valid.end();
    std::vector<uint8_t> pos = tout ? transform_only_positions(codec_bytes)
                                    : encode_positions(wi, codec_bytes, tpred, f64);
    append_chunk(&buf, "POSW", with_window_index(w, gaps ? 1 : 0, pos));
    std::vector<uint8_t> mask;
    if (gaps) {
      mask = encode_mask(wi.valid.data(), fn, N);
      append_chunk(&buf, "MASK", with_window_index(w, 0xFF, mask));
    }
    pos_bytes += buf.size();
    size_t before = buf.size();
    std::vector<uint8_t> cw;
    if (words) {
      cw = encode_c3d_words(block.residual.data(), block.camera_mask.data(), wi.valid.data(),
                            fn * N, N, point_scale, words_on_grid);
      append_chunk(&buf, "C3DW", with_window_index(w, 0xFF, cw));
      other += buf.size() - before;
    }
    std::vector<uint8_t> an;
    if (analog) {
      before = buf.size();
      an = encode_analog(block.analog.data(), fn * S, take.analog.channels, kinds);
      append_chunk(&buf, "ANLG", with_window_index(w, 0xFF, an));
      analog_bytes += buf.size() - before;
    }
    ie.bytes = buf.size();
    index.push_back(ie);
    out->flush(&buf);

    // Reconstruction as the decoder will produce it, for the bound check and the stats.
    std::vector<double> rec(fn * N * 3, 0.0);
    if (tout) {
      for (size_t i = 0; i < fn * N; ++i)
        if (wi.valid[i]) std::copy(&recon[i * 3], &recon[i * 3 + 3], &rec[i * 3]);
    } else {
      dequantise_window(g, wi, &rec);
    }
    const double* orig = block.xyz.data();
    for (size_t i = 0; i < fn * N; ++i) {
      if (!wi.valid[i]) continue;
      for (size_t k = i * 3; k < i * 3 + 3; ++k)
        if (!std::isfinite(rec[k]))
          check_failed(take, w, "a valid coordinate reconstructs to a non-finite value");
      keep_valid_off_origin(take.format, g.lossless, &rec[i * 3]);
      if (tout) continue;  // transform output promises no bound
      for (size_t k = i * 3; k < i * 3 + 3; ++k) {
        bool ok = g.lossless ? same_bits(rec[k], orig[k]) : std::fabs(rec[k] - orig[k]) <= g.bound;
        if (!ok)
          check_failed(
              take, w,
              "coordinate " + std::to_string(orig[k]) + " comes back as " + std::to_string(rec[k]));
      }
    }
    if (tout) {  // each window within the KG target makes the take meet it (FORMAT.md 3.1)
      if (window_sq_error(fn, N, orig, rec.data(), wi.valid.data()) > kg_budget ||
          (written_scale > 0 &&
           window_sq_error(fn, N, orig, rec.data(), wi.valid.data(), written_scale) > kg_budget))
        throw TransformMissedTarget();
    }
    acc.add(fn, N, orig, rec.data(), wi.valid.data());

    if (opts.check) {  // decode what was written and compare
      const std::string what = "self-check";
      WindowInts back;
      back.frames = fn;
      back.points = N;
      back.valid.assign(fn * N, 1);
      if (gaps) decode_mask(mask.data(), mask.size(), fn, N, back.valid.data(), what);
      if (back.valid != wi.valid) check_failed(take, w, "gap mask differs");
      if (tout) {
        const CodecOnly co = split_transform_only(pos.data(), pos.size(), what);
        std::vector<double> rback;
        codec->decode(co.data, co.size, fn, N, &rback);
        if (rback.size() != recon.size() ||
            std::memcmp(rback.data(), recon.data(), recon.size() * sizeof(double)) != 0)
          check_failed(
              take, w,
              std::string("codec ") + codec->name() + " decodes differently than it encoded");
      } else {
        PositionsPayload pp = split_positions(pos.data(), pos.size(), what);
        std::vector<int32_t> tback;
        if (codec && N > 0) {
          std::vector<double> rback;
          codec->decode(pp.codec_bytes, pp.codec_size, fn, N, &rback);
          tback = grid_prediction(rback, g.step);
          if (tback != tpred)
            check_failed(
                take, w,
                std::string("codec ") + codec->name() + " decodes differently than it encoded");
        }
        decode_positions(pp, tback, f64, kPositionScheme, &back, what);
        for (size_t i = 0; i < fn * N; ++i)
          if (wi.valid[i])
            for (size_t k = i * 3; k < i * 3 + 3; ++k)
              if (back.q[k] != wi.q[k] || (f64 && back.lo[k] != wi.lo[k]))
                check_failed(take, w, "positions decode differently");
      }
      if (words) {
        std::vector<float> r(fn * N);
        std::vector<uint8_t> cam(fn * N);
        decode_c3d_words(cw.data(), cw.size(), wi.valid.data(), fn * N, N, point_scale, r.data(),
                         cam.data(), what);
        if (std::memcmp(r.data(), block.residual.data(), fn * N * 4) != 0 ||
            std::memcmp(cam.data(), block.camera_mask.data(), fn * N) != 0)
          check_failed(take, w, "C3D sample words differ");
      }
      if (analog) {
        std::vector<double> rows(fn * S * C);
        decode_analog(an.data(), an.size(), fn * S, take.analog.channels, rows.data(), what);
        if (std::memcmp(rows.data(), block.analog.data(), rows.size() * 8) != 0)
          check_failed(take, w, "analog values differ");
      }
    }
    if (opts.progress) opts.progress(f0 + fn, F);
  }
  append_chunk(&buf, "INDX", encode_index(index));
  other += buf.size();
  out->flush(&buf);

  if (stats) {
    stats->bytes = out->size();
    stats->raw_bytes = F * N * 12;
    stats->bpvf = bpvf(out->size(), F, N);
    stats->step = g.mode == PosMode::kDecimal                                     ? 1.0 / g.step
                  : (g.mode == PosMode::kGrid || g.mode == PosMode::kFloat32Grid) ? g.step
                                                                                  : 0;
    stats->mode = tout ? "transform-output" : mode_name(g.mode);
    stats->lossless = g.lossless;
    stats->codec = codec ? codec->name() : "none";
    stats->error = acc.finish();
    stats->position_bytes = pos_bytes;
    stats->analog_bytes = analog_bytes;
    stats->other_bytes = other;
  }
}
}  // namespace

void compress_stream(FrameSource& source, const CompressOptions& opts, const std::string& path,
                     bool overwrite, CompressStats* stats) {
  if (opts.codec == "auto")
    fail(ErrorCode::kInvalidParameter, source.header().source,
         "codec auto compares whole-take encodings and is not streamed");
  try {
    AtomicFile file(path, overwrite);
    StreamOut out(&file);
    compress_source(source, opts, &out, stats);
    file.commit();
  } catch (const TransformMissedTarget&) {  // a second pass through the grid (see compress_one)
    AtomicFile file(path, overwrite);
    StreamOut out(&file);
    compress_source(source, opts, &out, stats, false);
    file.commit();
  }
}

// ---------------------------------------------------------------------------------------------
namespace {

// The .capz bytes a decoder reads: all in memory, or read from a file on demand (then only
// HEAD, META, INDX and one window's chunks are held at a time).
class StreamBytes {
 public:
  virtual ~StreamBytes() = default;
  virtual size_t size() const = 0;
  // Bytes [off, off + n), off + n <= size(); the pointer is valid until the next call.
  virtual const uint8_t* get(size_t off, size_t n) = 0;
  virtual uint64_t bytes_read() const { return 0; }
};

class MemoryBytes : public StreamBytes {
 public:
  MemoryBytes(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  size_t size() const override { return size_; }
  const uint8_t* get(size_t off, size_t) override { return data_ + off; }

 private:
  const uint8_t* data_;
  size_t size_;
};

class FileBytes : public StreamBytes {
 public:
  explicit FileBytes(const std::string& path) : file_(path) {}
  size_t size() const override { return static_cast<size_t>(file_.size()); }
  const uint8_t* get(size_t off, size_t n) override {
    buf_.resize(n);
    file_.read_at(off, buf_.data(), n);
    return buf_.data();
  }
  uint64_t bytes_read() const override { return file_.bytes_read(); }

 private:
  InputFile file_;
  std::vector<uint8_t> buf_;
};

uint32_t le32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 |
         static_cast<uint32_t>(p[2]) << 16 | static_cast<uint32_t>(p[3]) << 24;
}

// The chunk at `off` (read_chunk's checks), its bytes fetched from `b`; its payload pointer is
// valid until the next b.get().
Chunk chunk_at(StreamBytes& b, size_t off, const std::string& name) {
  const size_t size = b.size();
  if (off > size || size - off < kChunkOverhead) return read_chunk(nullptr, size, off, name, off);
  const uint32_t len = le32(b.get(off, 8) + 4);
  const size_t n = len <= size - off - kChunkOverhead ? kChunkOverhead + len : 8;
  return read_chunk(b.get(off, n), size, off, name, off);
}

struct Parsed {
  StreamHeader h;
  Take take;  // metadata only
  bool words = false;
  std::vector<IndexEntry> index;
  size_t first_window_offset = 0;
  size_t index_offset = 0;
  std::map<std::string, size_t> chunk_bytes;
  int major = 1, minor = 0;
};

// Reads HEAD, META and INDX (found from the end of the stream).
Parsed parse_stream(StreamBytes& b, const std::string& name) {
  const size_t size = b.size();
  Parsed ps;
  const uint8_t* fh = b.get(0, std::min(size, kFileHeaderBytes));
  ps.minor = check_file_header(fh, std::min(size, kFileHeaderBytes), name);
  ps.major = fh[9];
  Chunk c = chunk_at(b, kFileHeaderBytes, name);
  if (c.type != "HEAD") fail(ErrorCode::kCorrupt, name, "first chunk is " + c.type + ", not HEAD");
  ps.h = decode_header(c, name);
  ps.chunk_bytes["HEAD"] += c.end - c.offset;
  Chunk m = chunk_at(b, c.end, name);
  if (m.type != "META") fail(ErrorCode::kCorrupt, name, "second chunk is " + m.type + ", not META");
  ps.chunk_bytes["META"] += m.end - m.offset;
  check_header_fits(ps.h, size, name);
  ps.take.frames = static_cast<size_t>(ps.h.frames);
  ps.take.points = ps.h.points;
  ps.take.format = ps.h.source_format;
  ps.take.analog.channels = static_cast<int>(std::min<uint32_t>(ps.h.analog_channels, 1u << 30));
  ps.take.analog.samples_per_frame =
      static_cast<int>(std::min<uint32_t>(ps.h.analog_samples_per_frame, 1u << 30));
  decode_meta(m, name, &ps.take, &ps.words);
  ps.first_window_offset = m.end;
  // INDX ends the file; its payload's last 4 bytes give its payload length.
  if (size < m.end + kChunkOverhead + 4)
    fail(ErrorCode::kCorrupt, name, "truncated: the stream ends before its INDX chunk");
  const uint64_t ilen = le32(b.get(size - 8, 4));
  if (ilen + kChunkOverhead > size - m.end)
    fail(ErrorCode::kCorrupt, name, "truncated or damaged: no INDX chunk at the end of the stream");
  const size_t ioff = size - kChunkOverhead - static_cast<size_t>(ilen);
  Chunk k = chunk_at(b, ioff, name);
  if (k.type != "INDX" || k.end != size)
    fail(ErrorCode::kCorrupt, name, "truncated or damaged: no INDX chunk at the end of the stream");
  ps.index = decode_index(k, name);
  ps.index_offset = ioff;
  ps.chunk_bytes["INDX"] += k.end - k.offset;
  if (ps.index.size() != ps.h.windows())
    fail(ErrorCode::kCorrupt, name,
         "INDX lists " + std::to_string(ps.index.size()) + " windows, HEAD implies " +
             std::to_string(ps.h.windows()));
  return ps;
}

// A whole-stream decode checks that the windows tile the stream exactly.
void check_tiling(const Parsed& ps, size_t size, const std::string& name) {
  size_t expect = ps.first_window_offset;
  for (size_t w = 0; w < ps.index.size(); ++w) {
    if (ps.index[w].offset != expect)
      fail(ErrorCode::kCorrupt, name,
           "INDX: window " + std::to_string(w) + " starts at byte " +
               std::to_string(ps.index[w].offset) + ", expected " + std::to_string(expect));
    expect += static_cast<size_t>(std::min<uint64_t>(ps.index[w].bytes, size));
  }
  if (expect != ps.index_offset)
    fail(ErrorCode::kCorrupt, name,
         "INDX: windows end at byte " + std::to_string(expect) + ", the index starts at " +
             std::to_string(ps.index_offset));
}

// Decodes window w whole into *out (frames [w W, ...), the take's points).
void decode_window(StreamBytes& bytes, const std::string& name, const Parsed& ps, size_t w,
                   FrameBlock* out) {
  const StreamHeader& h = ps.h;
  const size_t N = h.points;
  const size_t f0 = w * h.window_frames;
  const size_t fn = std::min<size_t>(h.window_frames, static_cast<size_t>(h.frames) - f0);
  const size_t S = h.analog_samples_per_frame, C = h.analog_channels;
  const IndexEntry& ie = ps.index[w];
  const size_t size = bytes.size();
  if (ie.offset < ps.first_window_offset || ie.offset >= size || ie.bytes > size - ie.offset)
    fail(ErrorCode::kCorrupt, name,
         "INDX entry of window " + std::to_string(w) + " points outside the file");
  const size_t base = static_cast<size_t>(ie.offset);
  const size_t end = base + static_cast<size_t>(ie.bytes);
  const uint8_t* region = bytes.get(base, end - base);  // the window's chunks
  size_t off = base;
  const std::string wname = " of window " + std::to_string(w);
  auto next = [&](const char* type, bool required) -> Chunk {
    while (off < end) {
      const uint8_t* p = region + (off - base);
      if (end - off < kChunkOverhead || le32(p + 4) > end - off - kChunkOverhead)
        fail(ErrorCode::kCorrupt, name,
             "chunk at byte " + std::to_string(off) + wname + " runs past its INDX extent");
      Chunk c = read_chunk(region, end, off, name, base);
      if (c.type == type) {
        off = c.end;
        return c;
      }
      if (c.type == "POSW" || c.type == "MASK" || c.type == "C3DW" || c.type == "ANLG") break;
      off = c.end;  // unknown chunk: skipped
    }
    if (required) fail(ErrorCode::kCorrupt, name, std::string("missing chunk ") + type + wname);
    return Chunk();
  };
  auto open = [&](const Chunk& c, ByteReader* r) {
    uint64_t idx = r->varint();
    if (idx != w)
      fail(ErrorCode::kCorrupt, name,
           "chunk " + c.type + " at byte " + std::to_string(c.offset) + " belongs to window " +
               std::to_string(idx) + ", expected " + std::to_string(w));
  };
  Chunk pc = next("POSW", true);
  const std::string pwhat = (name.empty() ? "" : name + ": ") + "chunk POSW" + wname;
  ByteReader pr(pc.payload, pc.size, pwhat);
  open(pc, &pr);
  const uint8_t has_mask = pr.u8();
  if (has_mask > 1) fail(ErrorCode::kCorrupt, pwhat, "bad has_mask byte");
  WindowInts wi;
  wi.frames = fn;
  wi.points = N;
  wi.valid.assign(fn * N, 1);
  if (has_mask) {
    Chunk mc = next("MASK", true);
    ByteReader mr(mc.payload, mc.size, "MASK");
    open(mc, &mr);
    decode_mask(mc.payload + mr.offset(), mc.size - mr.offset(), fn, N, wi.valid.data(),
                (name.empty() ? "" : name + ": ") + "chunk MASK" + wname);
  }
  std::vector<double> tout_xyz;  // transform output (FORMAT.md 3.1): the reconstruction itself
  if (h.transform_output)
    decode_transform_output(pc.payload + pr.offset(), pc.size - pr.offset(), h, fn, pwhat, &wi,
                            &tout_xyz);
  PositionsPayload pp;
  if (!h.transform_output)
    pp = split_positions(pc.payload + pr.offset(), pc.size - pr.offset(), pwhat);
  std::vector<int32_t> tpred;
  if (h.codec != 0 && N > 0 && !h.transform_output) {
    const TransformDecoder* codec = find_decoder(h.codec);
    if (!codec)
      fail(ErrorCode::kUnsupportedVersion, name,
           "stream uses transform codec id " + std::to_string(h.codec) + ", unknown to this capz");
    std::vector<double> recon;
    codec->decode(pp.codec_bytes, pp.codec_size, fn, N, &recon);
    if (recon.size() != fn * N * 3)
      fail(ErrorCode::kCorrupt, pwhat, "codec payload has the wrong size");
    tpred = grid_prediction(recon, h.step);
  }
  const bool f64 = h.mode == PosMode::kFloat64;
  if (!h.transform_output) decode_positions(pp, tpred, f64, position_scheme(ps.major), &wi, pwhat);
  if (C > 0 && S > 0 && fn * S * C > kMaxSymbolsPerByte * (end - base))
    fail(ErrorCode::kCorrupt, name, "analog window" + wname + " larger than its chunks can hold");
  out->reset(f0, fn, N, C > 0 && S > 0 ? S * C : 0, ps.words);
  Grid g;
  g.mode = h.mode;
  g.step = h.step;
  out->valid = wi.valid;
  if (!h.transform_output) dequantise_window(g, wi, &out->xyz);
  for (size_t i = 0; i < fn * N; ++i)
    if (wi.valid[i]) {
      if (h.transform_output) std::copy(&tout_xyz[i * 3], &tout_xyz[i * 3 + 3], &out->xyz[i * 3]);
      keep_valid_off_origin(h.source_format, h.lossless, &out->xyz[i * 3]);
    }
  if (ps.words) {
    Chunk cc = next("C3DW", true);
    const std::string cwhat = (name.empty() ? "" : name + ": ") + "chunk C3DW" + wname;
    ByteReader cr(cc.payload, cc.size, cwhat);
    open(cc, &cr);
    decode_c3d_words(cc.payload + cr.offset(), cc.size - cr.offset(), wi.valid.data(), fn * N, N,
                     ps.take.c3d->point_scale, out->residual.data(), out->camera_mask.data(),
                     cwhat);
  }
  if (C > 0 && S > 0) {
    Chunk ac = next("ANLG", true);
    const std::string awhat = (name.empty() ? "" : name + ": ") + "chunk ANLG" + wname;
    ByteReader ar(ac.payload, ac.size, awhat);
    open(ac, &ar);
    if (fn * S * C > kMaxSymbolsPerByte * ac.size)
      fail(ErrorCode::kCorrupt, awhat, "analog window larger than its chunk can hold");
    decode_analog(ac.payload + ar.offset(), ac.size - ar.offset(), fn * S, static_cast<int>(C),
                  out->analog.data(), awhat);
  }
}

// A .capz as a frame source: a range decodes the windows it touches (the last one decoded is
// kept, so reading in window-sized steps decodes each window once).
class CapzSource : public FrameSource {
 public:
  CapzSource(std::unique_ptr<StreamBytes> bytes, const std::string& name, bool whole)
      : bytes_(std::move(bytes)), name_(name), ps_(parse_stream(*bytes_, name)) {
    if (whole) check_tiling(ps_, bytes_->size(), name_);
    header_ = ps_.take;
  }
  bool has_sample_words() const override { return ps_.words; }
  size_t preferred_block() const override { return ps_.h.window_frames; }
  uint64_t bytes_read() const override { return bytes_->bytes_read(); }
  const Parsed& parsed() const { return ps_; }

  void read(size_t first, size_t count, FrameBlock* out) override {
    const size_t F = ps_.take.frames, N = ps_.take.points;
    clip(&first, &count);
    const size_t S = ps_.h.analog_samples_per_frame, C = ps_.h.analog_channels;
    const size_t A = C > 0 && S > 0 ? S * C : 0;
    const size_t W = ps_.h.window_frames;
    // A block that is exactly one window is handed over without a copy: swapped with the
    // caller's block (whose buffers the next decode refills), so it is no longer cached.
    if (count > 0 && first % W == 0 && count == std::min<size_t>(W, F - first)) {
      decode(first / W);
      std::swap(*out, win_);
      have_ = false;
      return;
    }
    out->reset(first, count, N, A, ps_.words);
    for (size_t f = first; f < first + count;) {
      const size_t w = f / W;
      decode(w);
      const size_t lo = f - win_.first, hi = std::min(win_.frames, first + count - win_.first);
      const size_t o = f - first, n = hi - lo;
      std::copy_n(&win_.xyz[lo * N * 3], n * N * 3, &out->xyz[o * N * 3]);
      std::copy_n(&win_.valid[lo * N], n * N, &out->valid[o * N]);
      if (ps_.words) {
        std::copy_n(&win_.residual[lo * N], n * N, &out->residual[o * N]);
        std::copy_n(&win_.camera_mask[lo * N], n * N, &out->camera_mask[o * N]);
      }
      std::copy_n(win_.analog.data() + lo * A, n * A, out->analog.data() + o * A);
      f += n;
    }
  }

 private:
  void decode(size_t w) {
    if (have_ && cached_ == w) return;
    have_ = false;
    decode_window(*bytes_, name_, ps_, w, &win_);
    cached_ = w;
    have_ = true;
  }

  std::unique_ptr<StreamBytes> bytes_;
  std::string name_;
  Parsed ps_;
  FrameBlock win_;
  size_t cached_ = 0;
  bool have_ = false;
};

Take decode_range(const uint8_t* data, size_t size, size_t first, size_t count,
                  const std::string& name) {
  std::unique_ptr<StreamBytes> mem(new MemoryBytes(data, size));
  CapzSource src(std::move(mem), name, false);
  const Parsed& ps = src.parsed();
  const size_t F = ps.take.frames;
  first = std::min(first, F);
  count = std::min(count, F - first);
  if (first == 0 && count == F) check_tiling(ps, size, name);
  FrameBlock b;
  src.read(first, count, &b);
  Take t = ps.take;
  t.frames = count;
  t.xyz = std::move(b.xyz);
  t.valid = std::move(b.valid);
  t.analog.values = std::move(b.analog);
  if (ps.words) {
    t.c3d = std::make_shared<C3DExtra>(*ps.take.c3d);
    t.c3d->residual = std::move(b.residual);
    t.c3d->camera_mask = std::move(b.camera_mask);
  }
  if (first > 0 || count < F) {  // slice the per-frame metadata
    t.first_frame += static_cast<long>(first);
    if (t.trc) {
      auto x = std::make_shared<TRCExtra>(*t.trc);
      if (x->times.size() == F)
        x->times = std::vector<double>(x->times.begin() + static_cast<long>(first),
                                       x->times.begin() + static_cast<long>(first + count));
      if (x->frame_numbers.size() == F)
        x->frame_numbers =
            std::vector<long>(x->frame_numbers.begin() + static_cast<long>(first),
                              x->frame_numbers.begin() + static_cast<long>(first + count));
      t.trc = x;
    }
    if (t.pcd && t.pcd->frame_names.size() == F) {
      auto x = std::make_shared<PCDExtra>(*t.pcd);
      x->frame_names =
          std::vector<std::string>(x->frame_names.begin() + static_cast<long>(first),
                                   x->frame_names.begin() + static_cast<long>(first + count));
      t.pcd = x;
    }
  }
  return t;
}

}  // namespace

std::unique_ptr<FrameSource> open_capz_frames(const std::string& path) {
  std::unique_ptr<StreamBytes> file(new FileBytes(path));
  return std::unique_ptr<FrameSource>(new CapzSource(std::move(file), path, true));
}

Take decompress(const uint8_t* data, size_t size, const std::string& name) {
  return decode_range(data, size, 0, std::numeric_limits<size_t>::max(), name);
}

Take decompress_frames(const uint8_t* data, size_t size, size_t first, size_t count,
                       const std::string& name) {
  return decode_range(data, size, first, count, name);
}

bool is_capz(const uint8_t* data, size_t size) {
  return size >= 9 && std::memcmp(data, kCapzMagic, 9) == 0;
}

StreamInfo describe(const uint8_t* data, size_t size, const std::string& name) {
  MemoryBytes bytes(data, size);
  Parsed ps = parse_stream(bytes, name);
  StreamInfo si;
  si.major = data[9];
  si.minor = ps.minor;
  si.source_format = ps.h.source_format;
  si.source_name = ps.take.source;
  si.frames = ps.take.frames;
  si.points = ps.take.points;
  si.window_frames = ps.h.window_frames;
  si.windows = ps.h.windows();
  si.mode = ps.h.transform_output ? "transform-output" : mode_name(ps.h.mode);
  si.transform_output = ps.h.transform_output;
  si.kg_target = ps.h.kg_target;
  if (ps.h.codec == 0) {
    si.codec = "none";
  } else {
    const TransformDecoder* c = find_decoder(ps.h.codec);
    si.codec = c ? c->name() : "id " + std::to_string(ps.h.codec);
  }
  si.lossless = ps.h.lossless;
  si.step = ps.h.mode == PosMode::kDecimal ? 1.0 / ps.h.step : ps.h.step;
  si.max_error = ps.h.max_error;
  si.rate = ps.take.rate;
  si.units = ps.take.units;
  si.analog_channels = ps.take.analog.channels;
  si.analog_samples_per_frame = ps.take.analog.samples_per_frame;
  si.chunk_bytes = ps.chunk_bytes;
  for (size_t off = ps.first_window_offset; off < ps.index_offset;) {  // the window chunks
    Chunk k = read_chunk(data, size, off, name);
    si.chunk_bytes[k.type] += k.end - k.offset;
    off = k.end;
  }
  return si;
}

double parse_length(const std::string& text, const std::string& take_units,
                    const std::string& assume_units) {
  std::string s;
  for (char c : text)
    if (!std::isspace(static_cast<unsigned char>(c))) s.push_back(c);
  size_t used = 0;
  double v = 0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    fail(ErrorCode::kInvalidParameter, "", "'" + text + "' is not a length (e.g. 0.1mm)");
  }
  if (!(v >= 0) || !std::isfinite(v))
    fail(ErrorCode::kInvalidParameter, "", "'" + text + "': a length must be a finite number >= 0");
  std::string unit = s.substr(used);
  if (unit.empty()) return v;
  const double from = units_to_metres(unit);
  if (from == 0)
    fail(ErrorCode::kInvalidParameter, "", "'" + text + "': unknown unit '" + unit + "'");
  const std::string& tu = take_units.empty() ? assume_units : take_units;
  const double to = units_to_metres(tu);
  if (to == 0)
    fail(ErrorCode::kInvalidParameter, "",
         "'" + text + "' has a unit but the data's units are " +
             (tu.empty()
                  ? std::string("unknown (say them with --units mm|cm|m, or give a bare number)")
                  : "'" + tu + "', which capz does not know"));
  return v * from / to;
}

}  // namespace capz

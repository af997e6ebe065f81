// Encoder stage: choosing the grid (grid_choice.h).
#include "codec/grid_choice.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include "capz/error.h"
#include "coding/analog/analog_repeat.h"
#include "coding/c3d_words.h"

namespace capz {
namespace {

// True when grid g reproduces coordinate x exactly (bit for bit).
template <PosMode M>
inline bool grid_exact_as(const Grid& g, double x) {
  const double v = M == PosMode::kDecimal ? x * g.step : x / g.step;
  if (!(std::fabs(v) <= kMaxGridIndex)) return false;
  return same_bits(dequantise_as<M>(g, round_to_int(v), 0), x);
}

// Exact lossless grids in the order the encoder prefers them (docs/FORMAT.md 16.1): the int16
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

}  // namespace

bool c3d_int16(const Take& t) {
  return t.c3d && !t.c3d->float_storage && t.c3d->point_scale > 0;
}

double written_int16_scale(const Take& t) {
  return c3d_int16(t) ? static_cast<double>(static_cast<float>(t.c3d->point_scale)) : 0.0;
}

TakeScan start_scan(const Take& hdr, const CompressOptions& opts) {
  TakeScan s;
  s.candidates = lossless_candidates(hdr, opts.lossless);
  s.exact.assign(s.candidates.size(), 1);
  s.words_on_grid = hdr.c3d && hdr.c3d->point_scale > 0;
  s.kg = !opts.lossless && opts.kg_error > 0;
  s.lossless = opts.lossless;
  s.ray_track = is_frame_files(hdr.format);
  if (s.ray_track) {
    s.ray_last.assign(hdr.points * 3, 0.0);
    s.ray_seen.assign(hdr.points, 0);
  }
  if (hdr.analog.channels > 0 && hdr.analog.samples_per_frame > 0) {
    s.analog_S = static_cast<size_t>(hdr.analog.samples_per_frame);
    s.analog_repeats.assign(static_cast<size_t>(hdr.analog.channels), 0);
  }
  return s;
}

bool on_rays(const TakeScan& s) {
  return s.ray_moved >= 64 && 2 * s.ray_on >= s.ray_moved;
}

namespace {
// Counts, in TakeScan::ray_moved / ray_on, the valid samples of b that moved since their
// point's last valid position, and those of them that stayed on its ray from the origin: the
// cross product of the two positions at most 2^-16 of the product of their lengths, the dot
// product positive (FORMAT.md 8.3, "how the encoder chooses").
void scan_rays(const FrameBlock& b, TakeScan* s) {
  if (b.points * 3 != s->ray_last.size()) return;  // a block of another shape: not a sequence
  for (size_t f = 0; f < b.frames; ++f)
    for (size_t p = 0; p < b.points; ++p) {
      if (!b.valid[f * b.points + p]) continue;
      const double* x = &b.xyz[(f * b.points + p) * 3];
      double* c = &s->ray_last[p * 3];
      if (s->ray_seen[p] && (x[0] != c[0] || x[1] != c[1] || x[2] != c[2])) {
        ++s->ray_moved;
        const double cx = x[1] * c[2] - x[2] * c[1], cy = x[2] * c[0] - x[0] * c[2],
                     cz = x[0] * c[1] - x[1] * c[0];
        const double nx = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
        const double nc = c[0] * c[0] + c[1] * c[1] + c[2] * c[2];
        const double dot = x[0] * c[0] + x[1] * c[1] + x[2] * c[2];
        if (dot > 0 && (cx * cx + cy * cy + cz * cz) <= std::ldexp(nx * nc, -32)) ++s->ray_on;
      }
      std::copy(x, x + 3, c);
      s->ray_seen[p] = 1;
    }
}
}  // namespace

bool analog_repeats_worth(const TakeScan& s, size_t frames) {
  for (size_t k : s.analog_repeats)
    if (k >= 2 && k * 10 >= frames) return true;
  return false;
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
  const size_t n = b.total_points();  // a ragged block's too
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
    const bool zeros = s->zeros_listed && g.mode == PosMode::kDecimal;
    with_mode(g.mode, [&](auto m) {
      for (size_t i = 0; i < n; ++i)
        if (b.valid[i])
          for (size_t k = i * 3; k < i * 3 + 3; ++k)
            if (!grid_exact_as<decltype(m)::value>(g, b.xyz[k]) && !(zeros && b.xyz[k] == 0)) {
              s->exact[c] = 0;
              return;
            }
    });
  }
  if (s->ray_track) scan_rays(b, s);
  if (words && s->words_on_grid && !residuals_on_grid(b.residual, b.valid, point_scale))
    s->words_on_grid = false;
  const size_t C = s->analog_repeats.size();
  if (C && b.analog.size() == b.frames * s->analog_S * C)
    for (size_t c = 0; c < C; ++c)
      s->analog_repeats[c] +=
          analog::count_varying_repeats(b.analog.data() + c, C, b.frames, s->analog_S);
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

namespace {

// A C3D stores every coordinate off its int16 grid as float32, so writing the decoded take
// rounds it once more, by up to half a float32 ulp at the largest coordinate. The grid keeps
// that much of the bound in reserve, so the bound holds in the written file, not only in the
// decoded doubles (bigparlove.c3d, with coordinates near 2^18 mm, missed 0.03 mm by 0.00125
// mm without it). Returns 0 for outputs that store the decoded doubles exactly.
double output_rounding_reserve(const Take& t, const TakeScan& s, double bound) {
  // TRC writers keep every decoded double (their printing has its own room, trc_print_room);
  // PCD writers do too, except for frames whose x y z were float32 (FORMAT.md 5.5), which are
  // written back as float32.
  if (t.format != Format::kC3D && !float32_frames(t)) return 0;
  return float32_half_ulp(s.max_abs + bound);
}

// A grid step for `bound` with the output's rounding reserve taken off.
double reserved_step(const Take& t, const TakeScan& s, double bound) {
  const double r = output_rounding_reserve(t, s, bound);
  if (!(bound > r)) {
    // "%g": a coordinate of 1e30 in six digits, not in thirty-one.
    char msg[320];
    std::snprintf(msg, sizeof msg,
                  "max error %g is below the float32 resolution of %s at coordinates up to %g "
                  "(float32 values %g apart there): use --lossless, or a max error above %g",
                  bound, t.format == Format::kC3D ? "a C3D" : "the frame files written back",
                  s.max_abs, 2 * r, r);
    fail(ErrorCode::kInvalidParameter, t.source, msg);
  }
  return grid_step_for_bound(bound - r);
}

}  // namespace

bool float32_frames(const Take& t) {
  if (t.format == Format::kBinFolder) return true;
  if (!is_frame_files(t.format)) return false;
  const std::vector<PCDField>* fields = t.file_fields();
  if (!fields || fields->empty()) return t.pcd != nullptr;  // PCD's default: x y z F 4
  for (const PCDField& f : *fields)
    if (f.name == "x") return f.size == 4;
  return false;
}

double float32_half_ulp(double m) {
  int e = 0;
  std::frexp(m, &e);  // magnitude in [2^(e-1), 2^e): float32 ulp 2^(e-24)
  return std::ldexp(1.0, e - 25);
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

namespace {

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

}  // namespace

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

double grid_per_unit(const Grid& g) {
  if (g.step <= 0) return 0;
  if (g.mode == PosMode::kGrid || g.mode == PosMode::kFloat32Grid) return 1.0 / g.step;
  return g.mode == PosMode::kDecimal ? g.step : 0;
}

void bound_hints(const Grid& g, ScanHints* h) {
  if (g.mode != PosMode::kGrid || g.lossless || !(g.bound > 0) || !(g.step > 0)) return;
  h->bound = g.bound;
  h->step = g.step;
}

WindowInts quantise_window(const FrameBlock& b, const Grid& g) {
  WindowInts w;
  w.frames = b.frames;
  w.points = b.points;
  const size_t n = b.total_points();  // a ragged block's too
  w.valid = b.valid;
  w.q.assign(n * 3, 0);
  if (g.mode == PosMode::kFloat64) w.lo.assign(n * 3, 0);
  // Transform output (grid mode, step 0, FORMAT.md 4.3) quantises nothing: q stays 0. Dividing
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
}  // namespace capz

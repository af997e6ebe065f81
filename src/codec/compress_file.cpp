// capz/compress_file.h: what `capz compress` does between its options and its report.
#include "capz/tool/compress_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/tool/file.h"
#include "codec/grid_choice.h"
#include "coding/quantiser.h"

namespace capz {

namespace {

// The extreme values kept per axis side: a default bound (below) may leave out the kStray
// farthest of them, and needs the one after.
constexpr size_t kStray = 16;

// One pass over the source: the bounding box of the valid samples, how many there are, and per
// axis the kStray + 1 least (low, ascending) and greatest (high, descending) coordinates.
struct ValidExtent {
  double lo[3] = {1e308, 1e308, 1e308}, hi[3] = {-1e308, -1e308, -1e308};
  size_t valid = 0;
  std::vector<double> low[3], high[3];
};

// Keeps v among the kStray + 1 first of *x in the order `before`.
template <class Before>
void keep_extreme(std::vector<double>* x, double v, Before before) {
  if (x->size() > kStray && !before(v, x->back())) return;
  x->insert(std::upper_bound(x->begin(), x->end(), v, before), v);
  if (x->size() > kStray + 1) x->pop_back();
}

ValidExtent valid_extent(FrameSource& src) {
  ValidExtent e;
  FrameBlock b;
  const size_t F = src.header().frames, B = src.preferred_block();
  for (size_t f = 0; f < F; f += B) {
    src.read(f, std::min(B, F - f), &b);
    for (size_t i = 0; i < b.total_points(); ++i)
      if (b.valid[i]) {
        ++e.valid;
        for (int a = 0; a < 3; ++a) {
          const double v = b.xyz[i * 3 + static_cast<size_t>(a)];
          e.lo[a] = std::min(e.lo[a], v);
          e.hi[a] = std::max(e.hi[a], v);
          keep_extreme(&e.low[a], v, std::less<double>());
          keep_extreme(&e.high[a], v, std::greater<double>());
        }
      }
  }
  return e;
}

// 1e-4 of the diagonal of the box lo..hi (1e-4 when it is a point).
double diagonal_bound(const double* lo, const double* hi) {
  double d2 = 0;
  for (int a = 0; a < 3; ++a) d2 += hi[a] > lo[a] ? (hi[a] - lo[a]) * (hi[a] - lo[a]) : 0;
  return d2 > 0 ? 1e-4 * std::sqrt(d2) : 1e-4;
}

// Default bound for data without units: 1e-4 of the bounding-box diagonal of the valid samples.
double unitless_default_bound(const ValidExtent& e) {
  return diagonal_bound(e.lo, e.hi);
}

// The default bound of a box that leaves out a few far samples: k = min(kStray, valid / 1000)
// samples at each end of each axis. 0 unless that box's diagonal is below 1/100 of the whole
// box's: a stray point (a driver's 1e30, one far return) would otherwise set the bound for all.
double stray_free_bound(const ValidExtent& e) {
  const size_t k = std::min(kStray, e.valid / 1000);
  if (k == 0) return 0;
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lo[a] = e.low[a][k], hi[a] = e.high[a][k];
  const double b = diagonal_bound(lo, hi);
  return b < unitless_default_bound(e) / 100 ? b : 0;
}

// v to 4 significant digits, then t's units (if any).
std::string length_text(const Take& t, double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf + (t.units.empty() ? std::string() : " " + t.units);
}

// The largest |coordinate| of the valid samples.
double largest_magnitude(const ValidExtent& e) {
  double m = 0;
  for (int a = 0; a < 3; ++a) m = std::max({m, std::fabs(e.lo[a]), std::fabs(e.hi[a])});
  return m;
}

// Whether the frame files written back resolve bound b at the largest magnitude: float32 frames
// would otherwise move a coordinate by more.
bool float32_holds(const Take& t, const ValidExtent& e, double b) {
  return !float32_frames(t) || b > float32_half_ulp(largest_magnitude(e) + b);
}

// Whether bound b holds for every valid sample of t: float32_holds, and the grid's integers
// reach it (the grid step is at least b / 2 there; bounded_grid's test is on the step).
bool bound_fits(const Take& t, const ValidExtent& e, double b) {
  return float32_holds(t, e, b) &&
         largest_magnitude(e) / b < static_cast<double>(kMaxGridIndex) / 2;
}

// The default bound for t when it can hold in float32 frames: 0 for frames whose coordinates
// are farther from the origin than float32 resolves that bound (UTM eastings and northings),
// whose default is then lossless (their float32 values kept; docs/CLI.md, --units). With a few
// far samples (stray_free_bound), the bound of the box without them, doubled up to 3 times
// until it holds at the far samples too, else 0 (lossless); *note then says so.
double default_bound(const Take& t, const ValidExtent& e, std::string* note) {
  const double b = unitless_default_bound(e), s = stray_free_bound(e);
  if (s == 0 && float32_holds(t, e, b)) return b;
  if (s == 0) {
    const double half = float32_half_ulp(largest_magnitude(e) + b);
    *note = "float32 coordinates up to " + length_text(t, largest_magnitude(e)) +
            " from the origin are " + length_text(t, 2 * half) +
            " apart there, coarser than the default bound (1e-4 of the box's diagonal, " +
            length_text(t, b) + "): kept lossless; a --max-error above " + length_text(t, half) +
            " gives a bound";
    return 0;
  }
  const std::string far = "a few points lie far outside the others (up to " +
                          length_text(t, largest_magnitude(e)) + " from the origin), so the " +
                          "default bound is not 1e-4 of the whole box's diagonal (" +
                          length_text(t, b) + ")";
  for (double k = 1; k <= 8; k *= 2)
    if (bound_fits(t, e, k * s)) {
      *note = far + " but of the others' box's" +
              (k > 1 ? ", times " + std::to_string(static_cast<int>(k)) + " to hold at the far ones"
                     : std::string()) +
              ": " + length_text(t, k * s) + "; --max-error overrides";
      return k * s;
    }
  *note = far + ", and the others' box's (" + length_text(t, s) +
          ") cannot hold at the far ones: kept lossless; --max-error overrides";
  return 0;
}

}  // namespace

std::string dropped_coordinates_note(const CompressStats& stats) {
  if (stats.dropped_coordinates == 0) return "";
  return std::to_string(stats.dropped_coordinates) +
         " samples marked absent (negative residual) hold coordinates, which are not kept at a "
         "bound (--lossless keeps them)";
}

CompressInput open_compress_input(const std::string& path, bool whole, const std::string& units) {
  return open_compress_input(path, whole, units, ReadOptions());
}

CompressInput open_compress_input(const std::string& path, bool whole, const std::string& units,
                                  const ReadOptions& read) {
  CompressInput input;
  if (whole) {
    input.take = std::make_unique<Take>(read_take(path, read));
    input.source = take_frames(*input.take);
  } else {
    input.source = open_frames(path, read);
  }
  Take& h = input.source->edit_header();
  if (!units.empty() && (units_to_metres(h.units) == 0 || h.units_assumed)) {
    h.units = units;
    h.units_assumed = false;
  }
  if (whole) {
    input.take->units = h.units;
    input.take->units_assumed = h.units_assumed;
  }
  return input;
}

std::string set_compress_target(FrameSource& source, const CompressTarget& target,
                                CompressOptions* opts) {
  const int targets =
      (target.lossless ? 1 : 0) + (target.kg_error ? 1 : 0) + (target.max_error ? 1 : 0);
  if (targets > 1)
    fail(ErrorCode::kUsage, "", "give only one of --max-error, --kg-error, --lossless");
  opts->lossless = false;
  opts->kg_error = 0;
  opts->max_error = 0;
  const Take& take = source.header();
  // Assumed units (PCD, PLY, .bin) keep the default of data without units when no bound is
  // given: the bytes of every such take capz coded before it assumed metres.
  const bool unitless = take.units.empty() || (take.units_assumed && !target.max_error);
  ValidExtent extent;
  std::string note;
  if (target.lossless) {
    opts->lossless = true;
  } else if (target.kg_error) {
    opts->kg_error = *target.kg_error;
    if (!(opts->kg_error > 0)) fail(ErrorCode::kInvalidParameter, "", "--kg-error must be > 0");
  } else if (unitless && (extent = valid_extent(source)).valid == 0) {
    opts->max_error = 1;  // no positions to bound (analog-only take): any bound will do
  } else if (!target.max_error && unitless) {
    opts->max_error = default_bound(take, extent, &note);
    // Not with --point-order any, which a lossless archive refuses: the bound then says why.
    if (opts->max_error == 0 && opts->any_point_order) {
      const double s = stray_free_bound(extent);
      opts->max_error = s > 0 ? s : unitless_default_bound(extent);
      note.clear();
    }
    opts->lossless = opts->max_error == 0;
  } else {
    opts->max_error = parse_length(target.max_error ? *target.max_error : "0.1mm", take.units);
    if (!(opts->max_error > 0))
      fail(ErrorCode::kInvalidParameter, "", "--max-error must be > 0 (or use --lossless)");
  }
  return note;
}

void compress_input(CompressInput& input, const CompressOptions& opts, const std::string& out,
                    bool overwrite, CompressStats* stats) {
  if (input.source->header().units_assumed) {  // the archive keeps what the file said: none
    input.source->edit_header().units.clear();
    input.source->edit_header().units_assumed = false;
    if (input.take) input.take->units.clear(), input.take->units_assumed = false;
  }
  if (opts.codec == "auto")
    write_file(out, compress(*input.take, opts, stats), overwrite);
  else
    compress_stream(*input.source, opts, out, overwrite, stats);
}

std::string compress_file(const std::string& in, const std::string& out,
                          const CompressTarget& target, const CompressOptions& opts,
                          const std::string& units, bool overwrite, CompressStats* stats,
                          const ReadOptions& read) {
  if (!units.empty() && units_to_metres(units) == 0)
    fail(ErrorCode::kInvalidParameter, "", "--units: unknown unit '" + units + "'");
  check_output_free(out, overwrite);
  CompressInput input = open_compress_input(in, opts.codec == "auto", units, read);
  CompressOptions o = opts;
  const std::string note = set_compress_target(*input.source, target, &o);
  compress_input(input, o, out, overwrite, stats);
  return note;
}

}  // namespace capz

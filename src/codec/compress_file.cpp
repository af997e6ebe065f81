// capz/compress_file.h: what `capz compress` does between its options and its report.
#include "capz/tool/compress_file.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/tool/file.h"
#include "codec/grid_choice.h"

namespace capz {

namespace {

// One pass over the source: the bounding box of the valid samples and how many there are.
struct ValidExtent {
  double lo[3] = {1e308, 1e308, 1e308}, hi[3] = {-1e308, -1e308, -1e308};
  size_t valid = 0;
};

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
          e.lo[a] = std::min(e.lo[a], b.xyz[i * 3 + a]);
          e.hi[a] = std::max(e.hi[a], b.xyz[i * 3 + a]);
        }
      }
  }
  return e;
}

// Default bound for data without units: 1e-4 of the bounding-box diagonal of the valid samples.
double unitless_default_bound(const ValidExtent& e) {
  double d2 = 0;
  for (int a = 0; a < 3; ++a)
    d2 += e.hi[a] > e.lo[a] ? (e.hi[a] - e.lo[a]) * (e.hi[a] - e.lo[a]) : 0;
  return d2 > 0 ? 1e-4 * std::sqrt(d2) : 1e-4;
}

// The default bound for t when it can hold in float32 frames: 0 for frames whose coordinates
// are farther from the origin than float32 resolves that bound (UTM eastings and northings),
// whose default is then lossless (their float32 values kept; docs/CLI.md, --units).
double default_bound(const Take& t, const ValidExtent& e) {
  const double b = unitless_default_bound(e);
  double m = 0;
  for (int a = 0; a < 3; ++a) m = std::max({m, std::fabs(e.lo[a]), std::fabs(e.hi[a])});
  return float32_frames(t) && !(b > float32_half_ulp(m + b)) ? 0 : b;
}

}  // namespace

CompressInput open_compress_input(const std::string& path, bool whole, const std::string& units) {
  CompressInput input;
  if (whole) {
    input.take = std::make_unique<Take>(read_take(path));
    input.source = take_frames(*input.take);
  } else {
    input.source = open_frames(path);
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

void set_compress_target(FrameSource& source, const CompressTarget& target, CompressOptions* opts) {
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
  if (target.lossless) {
    opts->lossless = true;
  } else if (target.kg_error) {
    opts->kg_error = *target.kg_error;
    if (!(opts->kg_error > 0)) fail(ErrorCode::kInvalidParameter, "", "--kg-error must be > 0");
  } else if (unitless && (extent = valid_extent(source)).valid == 0) {
    opts->max_error = 1;  // no positions to bound (analog-only take): any bound will do
  } else if (!target.max_error && unitless) {
    opts->max_error = default_bound(take, extent);
    // Not with --point-order any, which a lossless archive refuses: the bound then says why.
    if (opts->max_error == 0 && opts->any_point_order)
      opts->max_error = unitless_default_bound(extent);
    opts->lossless = opts->max_error == 0;
  } else {
    opts->max_error = parse_length(target.max_error ? *target.max_error : "0.1mm", take.units);
    if (!(opts->max_error > 0))
      fail(ErrorCode::kInvalidParameter, "", "--max-error must be > 0 (or use --lossless)");
  }
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

void compress_file(const std::string& in, const std::string& out, const CompressTarget& target,
                   const CompressOptions& opts, const std::string& units, bool overwrite,
                   CompressStats* stats) {
  if (!units.empty() && units_to_metres(units) == 0)
    fail(ErrorCode::kInvalidParameter, "", "--units: unknown unit '" + units + "'");
  check_output_free(out, overwrite);
  CompressInput input = open_compress_input(in, opts.codec == "auto", units);
  CompressOptions o = opts;
  set_compress_target(*input.source, target, &o);
  compress_input(input, o, out, overwrite, stats);
}

}  // namespace capz

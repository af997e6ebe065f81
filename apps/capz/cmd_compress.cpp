// capz compress IN [-o OUT] [--max-error E | --kg-error X | --lossless] [--codec NAME] ...
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "capz/codec.h"
#include "capz/file.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "compress_common.h"

namespace capz_cli {

namespace {

// One pass over the source: the bounding box of the valid samples and how many there are.
struct ValidExtent {
  double lo[3] = {1e308, 1e308, 1e308}, hi[3] = {-1e308, -1e308, -1e308};
  size_t valid = 0;
};
ValidExtent valid_extent(capz::FrameSource& src) {
  ValidExtent e;
  capz::FrameBlock b;
  const size_t F = src.header().frames, B = src.preferred_block();
  for (size_t f = 0; f < F; f += B) {
    src.read(f, std::min(B, F - f), &b);
    for (size_t i = 0; i < b.frames * b.points; ++i)
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

// The options of `capz compress` (besides the common ones and IN).
po::options_description compress_options() {
  po::options_description o("compress options");
  o.add_options()("output,o", po::value<std::string>(), "output file (default IN.capz)")(
      "max-error,e", po::value<std::string>(),
      "per-coordinate bound: a length with a unit (0.1mm, 0.05cm, 0.0001m, 0.01in) or a bare "
      "number in the data's own units. Default 0.1mm. For data without units (PCD folders, "
      "unless --units is given) the default is 1e-4 x the bounding-box diagonal of the data, "
      "and a bound with a unit needs --units")(
      "kg-error", po::value<double>(),
      "instead of a bound: KG error target in percent; the "
      "grid is chosen so the achieved KG error is at or just under it")(
      "lossless",
      "every stored coordinate back exactly: int16 C3D integers, float32 bits, "
      "TRC decimals")(
      "codec", po::value<std::string>()->default_value("none"),
      "transform stage in front of the coder: none (temporal prediction only), a "
      "transform codec built in (ts, pdct), or auto (tries each on the take and keeps the "
      "smallest; encoding takes about as long as all of them together)")(
      "codec-opt", po::value<std::vector<std::string>>(), "codec option key=value (repeatable)")(
      "clusters", po::value<int>()->default_value(0),
      "clusters for the transform codec (0 = its default, -1 = search)")(
      "units", po::value<std::string>(),
      "units of data that has none (PCD folders) or whose units capz cannot read: mm, cm or m")(
      "window", po::value<size_t>()->default_value(0),
      "frames per independently decodable window, 1..8192; 0 (default): 1024, or with codec "
      "none up to 8192 for takes of fewer than 64 points (about 2^16 samples a window)")(
      "no-check",
      "skip decoding each window after writing it (the bound then rests on the "
      "quantiser alone)")("force,f", "overwrite OUT if it exists")(
      "threads,T", po::value<int>()->default_value(1),
      "worker threads coding windows in parallel (0: all cores); the output is the same "
      "for every count")(
      "rm",
      "remove IN (a file) after the output, read back from disk and decoded, reproduced it "
      "within the bound")("json", "print the report as one JSON object");
  return o;
}

// The input: C3D, TRC and PCD inputs stream (the file is read a window at a time, twice: a scan
// that fixes the grid, then the coding pass), so memory stays bounded by the window. codec auto
// compares whole-take encodings and reads the take whole (`whole`, which `source` then reads).
struct Input {
  capz::Take whole;
  std::unique_ptr<capz::FrameSource> source;
  double read_cpu_seconds = 0;
};

// Opens IN; `units` (--units, may be empty) is given to data that has none, or whose units capz
// cannot read (a POINT:UNITS naming several different units, a name it does not know).
void open_input(const std::string& in, bool whole, const std::string& units, Input* input) {
  const double c_read = thread_cpu_seconds();
  if (whole) {
    input->whole = capz::read_take(in);
    input->source = capz::take_frames(input->whole);
  } else {
    input->source = capz::open_frames(in);
  }
  input->read_cpu_seconds = thread_cpu_seconds() - c_read;
  if (!units.empty() && capz::units_to_metres(input->source->header().units) == 0)
    input->source->edit_header().units = units;
  if (whole) input->whole.units = input->source->header().units;
}

// Codec, clusters, window, check and --codec-opt from the options.
void set_coding_options(const po::variables_map& vm, capz::CompressOptions* opts) {
  opts->codec = vm["codec"].as<std::string>();
  opts->clusters = vm["clusters"].as<int>();
  opts->window_frames = vm["window"].as<size_t>();
  opts->check = vm.count("no-check") == 0;
  opts->threads = vm["threads"].as<int>();
  if (vm.count("codec-opt"))
    for (const auto& kv : vm["codec-opt"].as<std::vector<std::string>>()) {
      auto eq = kv.find('=');
      if (eq == std::string::npos) throw po::error("--codec-opt wants key=value, got '" + kv + "'");
      opts->codec_options[kv.substr(0, eq)] = kv.substr(eq + 1);
    }
}

// The error target: --lossless, --kg-error, --max-error, or the default bound (0.1 mm; for data
// without units 1e-4 of the valid samples' bounding-box diagonal, which reads the source once).
void set_target(const po::variables_map& vm, capz::FrameSource& source,
                capz::CompressOptions* opts) {
  const capz::Take& take = source.header();
  ValidExtent extent;
  if (vm.count("lossless")) {
    opts->lossless = true;
  } else if (vm.count("kg-error")) {
    opts->kg_error = vm["kg-error"].as<double>();
    if (!(opts->kg_error > 0))
      capz::fail(capz::ErrorCode::kInvalidParameter, "", "--kg-error must be > 0");
  } else if (take.units.empty() && (extent = valid_extent(source)).valid == 0) {
    opts->max_error = 1;  // no positions to bound (analog-only take): any bound will do
  } else if (!vm.count("max-error") && take.units.empty()) {
    opts->max_error = unitless_default_bound(extent);
  } else {
    opts->max_error = capz::parse_length(
        vm.count("max-error") ? vm["max-error"].as<std::string>() : "0.1mm", take.units);
    if (!(opts->max_error > 0))
      capz::fail(capz::ErrorCode::kInvalidParameter, "",
                 "--max-error must be > 0 (or use --lossless)");
  }
}

// Compresses the input into `out`; returns the encoding's thread CPU seconds.
double encode(Input& input, capz::CompressOptions opts, const std::string& out, bool force,
              capz::CompressStats* st) {
  const double c_enc = thread_cpu_seconds();
  Progress progress("compress");
  opts.progress = [&](size_t d, size_t t) { progress(d, t); };
  if (opts.codec == "auto")
    capz::write_file(out, capz::compress(input.whole, opts, st), force);
  else
    capz::compress_stream(*input.source, opts, out, force, st);
  return thread_cpu_seconds() - c_enc;
}

// What the report says besides the take, the options and the stats.
struct Report {
  std::string in, out;
  uint64_t in_bytes = 0;
  double t_read = 0, t_enc = 0;  // thread CPU seconds
  double ratio = 0;              // IN's bytes / OUT's
  double mbps = 0;               // raw float32 position MB encoded per CPU second
};

void report_json(const Report& r, const capz::Take& take, const capz::CompressOptions& opts,
                 const capz::CompressStats& st) {
  Json j;
  j.begin_object();
  j.member("input", r.in);
  j.member("output", r.out);
  j.member("input_bytes", r.in_bytes);
  j.member("output_bytes", static_cast<uint64_t>(st.bytes));
  j.member("ratio", r.ratio);
  j.member("frames", static_cast<uint64_t>(take.frames));
  j.member("points", static_cast<uint64_t>(take.points));
  j.member("units", take.units);
  j.member("bpvf", st.bpvf);
  j.member("mode", st.mode);
  j.member("codec", st.codec);
  j.member("lossless", st.lossless);
  j.member("grid_step", st.step);
  j.member("max_error_target", opts.max_error);
  j.member("kg_error_target", opts.kg_error);
  json_error_stats(&j, st.error);
  j.member("position_bytes", static_cast<uint64_t>(st.position_bytes));
  j.member("analog_bytes", static_cast<uint64_t>(st.analog_bytes));
  j.member("rotation_bytes", static_cast<uint64_t>(st.rotation_bytes));
  j.member("other_bytes", static_cast<uint64_t>(st.other_bytes));
  j.member("raw_float32_position_bytes", static_cast<uint64_t>(st.raw_bytes));
  j.member("read_cpu_seconds", r.t_read);
  j.member("encode_cpu_seconds", r.t_enc);
  j.member("encode_checked", opts.check);
  j.member("encode_mb_per_s", r.mbps);
  j.end_object();
  std::printf("%s\n", j.str().c_str());
}

void report_text(const Report& r, const capz::Take& take, const capz::CompressOptions& opts,
                 const capz::CompressStats& st) {
  if (g_verbosity >= 1) {
    const std::string u = take.units.empty() ? "" : " " + take.units;
    std::string err = st.lossless ? "lossless (" + st.mode + ")"
                                  : "max error " + num(st.error.max_abs) + u + " per coordinate (" +
                                        num(st.error.max_error) + u + " Euclidean), KG " +
                                        num(st.error.kg_error) + "%";
    if (opts.codec == "auto") err += ", codec " + st.codec;
    std::printf("%s -> %s: %s -> %s (ratio %s), %s bpvf, %s\n", r.in.c_str(), r.out.c_str(),
                human_size(r.in_bytes).c_str(), human_size(st.bytes).c_str(), num(r.ratio).c_str(),
                num(st.bpvf).c_str(), err.c_str());
  }
  if (g_verbosity >= 2) {
    std::printf(
        "  %zu frames x %zu points, %s coding, grid step %s%s; positions %zu B (x%s vs "
        "raw float32), analog %zu B, rotations %zu B, other %zu B\n",
        take.frames, take.points, st.mode.c_str(), num(st.step, 6).c_str(),
        take.units.empty() ? "" : (" " + take.units).c_str(), st.position_bytes,
        num(st.position_bytes
                ? static_cast<double>(st.raw_bytes) / static_cast<double>(st.position_bytes)
                : 0)
            .c_str(),
        st.analog_bytes, st.rotation_bytes, st.other_bytes);
    std::printf("  cpu: read %.3f s, encode%s %.3f s (%s MB/s of raw float32 positions)\n",
                r.t_read, opts.check ? "+check" : "", r.t_enc, num(r.mbps).c_str());
  }
}

}  // namespace

int cmd_compress(const Args& args) {
  po::variables_map vm;
  std::string in;
  if (!parse_single_input(
          args, "capz compress IN [-o OUT] [--max-error E | --kg-error X | --lossless] [options]",
          "Compresses IN (a .c3d, a .trc or a folder of .pcd frames) to a .capz.\n"
          "Error bounds are per coordinate: every valid coordinate comes back within the\n"
          "bound (a point's Euclidean error is then at most sqrt(3) times it); the report\n"
          "gives both, with the KG error and bits per vertex per frame (bpvf). Gaps,\n"
          "analog channels, labels, rate, units, C3D parameters and events come back exactly.",
          compress_options(), "IN", &vm, &in))
    return 0;
  const int targets = (vm.count("lossless") ? 1 : 0) + (vm.count("kg-error") ? 1 : 0) +
                      (vm.count("max-error") ? 1 : 0);
  if (targets > 1) throw po::error("give only one of --max-error, --kg-error, --lossless");
  const std::string units = vm.count("units") ? vm["units"].as<std::string>() : "";
  if (!units.empty() && capz::units_to_metres(units) == 0)
    capz::fail(capz::ErrorCode::kInvalidParameter, "", "--units: unknown unit '" + units + "'");
  const bool force = vm.count("force") != 0;
  Report r;
  r.in = in;
  r.out = vm.count("output") ? vm["output"].as<std::string>() : strip_slashes(in) + ".capz";
  capz::check_output_free(r.out, force);
  if (vm.count("rm") && fs::is_directory(in))
    capz::fail(capz::ErrorCode::kUsage, in, "--rm removes files only, not PCD folders");

  Input input;
  open_input(in, vm["codec"].as<std::string>() == "auto", units, &input);
  r.t_read = input.read_cpu_seconds;
  capz::CompressOptions opts;
  set_coding_options(vm, &opts);
  const capz::Take& take = input.source->header();
  set_target(vm, *input.source, &opts);

  capz::CompressStats st;
  r.t_enc = encode(input, opts, r.out, force, &st);
  r.in_bytes = path_size(in);
  r.ratio = st.bytes ? static_cast<double>(r.in_bytes) / static_cast<double>(st.bytes) : 0;
  r.mbps = r.t_enc > 0 ? static_cast<double>(st.raw_bytes) / 1e6 / r.t_enc : 0;
  if (vm.count("rm")) {
    check_written(r.out, in, take);  // like zstd: only a verified output lets IN go
    std::error_code ec;
    fs::remove(in, ec);
    if (ec)
      capz::fail(capz::ErrorCode::kIo, in, "could not remove after compressing: " + ec.message());
  }
  if (vm.count("json"))
    report_json(r, take, opts, st);
  else
    report_text(r, take, opts, st);
  return 0;
}

}  // namespace capz_cli

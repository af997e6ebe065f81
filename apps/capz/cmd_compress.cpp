// capz compress IN... [-o OUT | -c | --output-dir-mirror DIR | --output-dir-flat DIR] [-r] [-T N]
//                [--max-error E | --kg-error X | --lossless] [--codec NAME] ...
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "batch.h"
#include "capz/codec.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "capz/tool/compress_file.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "compress_common.h"
#include "pipe.h"

namespace capz_cli {

namespace {

// The options of `capz compress` (besides the common ones and IN).
po::options_description compress_options() {
  po::options_description o("compress options");
  add_batch_options(&o, true, "output file (a single input; default IN.capz)");
  o.add_options()(
      "max-error,e", po::value<std::string>(),
      "per-coordinate bound: a length with a unit (0.1mm, 0.05cm, 0.0001m, 0.01in) or a bare "
      "number in the data's own units. Default 0.1mm. PCD, PLY and .bin frames carry no units: "
      "metres are assumed (--units overrides), and without --max-error the default is 1e-4 x "
      "the bounding-box diagonal of the data, as for data without units")(
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
      "units of data that has none or assumed ones (PCD, PLY, .bin frames: metres assumed) or "
      "whose units capz cannot read: mm, cm or m")(
      "window", po::value<size_t>()->default_value(0),
      "frames per independently decodable window, 1..8192; 0 (default): 1024, or with codec "
      "none up to 8192 for takes of fewer than 64 points (about 2^16 samples a window)")(
      "no-check",
      "skip decoding each window after writing it (the bound then rests on the "
      "quantiser alone)")(
      "drop-fields",
      "leave the point fields of PCD frames (rgb, intensity, normals, ...) out of the archive; "
      "by default every field is kept, lossless")(
      "point-order", po::value<std::string>()->default_value("kept"),
      "kept (default): every frame keeps its points' order; any: the archive may reorder the "
      "points of each frame of a scan (frames of their own point counts, or one sweep), each "
      "with its fields, and codes them in the laser's firing order (smaller); gaps move after "
      "each frame's points. Not with --lossless")(
      "attr-error", po::value<std::vector<std::string>>()->composing(),
      "bounds for float point fields, NAME=B[,NAME=B...] in each field's units (NAME: a field, "
      "or NAME_* as normal for normal_x/y/z); the others stay lossless")(
      "analog-max-error", po::value<std::vector<std::string>>()->composing(),
      "bounds for analog channels, KEY=B[,KEY=B...] in each channel's physical units (KEY: a "
      "channel label such as Fz1, or a unit such as N, Nmm, V, which bounds every channel in "
      "it; a label wins over its unit); the others stay lossless. Not with --lossless")(
      "rm",
      "remove IN (a file) after the output, read back from disk and decoded, reproduced it "
      "within the bound")("json", "print the report as one JSON object");
  add_bin_fields_option(&o);
  return o;
}

// The input (capz/compress_file.h) and the thread CPU seconds opening it took.
struct Input {
  capz::CompressInput in;
  double read_cpu_seconds = 0;
};

// Opens IN; `units` (--units, may be empty) is given to data that has none, or whose units capz
// cannot read (a POINT:UNITS naming several different units, a name it does not know).
void open_input(const std::string& in, bool whole, const std::string& units,
                const capz::ReadOptions& read, Input* input) {
  const double c_read = cpu_seconds();
  input->in = capz::open_compress_input(in, whole, units, read);
  input->read_cpu_seconds = cpu_seconds() - c_read;
}

// --NAME KEY=B[,KEY=B...] (repeatable) into *out.
void parse_bounds(const po::variables_map& vm, const std::string& name, const std::string& key,
                  std::map<std::string, double>* out) {
  if (!vm.count(name)) return;
  for (const auto& list : vm[name].as<std::vector<std::string>>()) {
    size_t at = 0;
    while (at <= list.size()) {
      const size_t comma = std::min(list.find(',', at), list.size());
      const std::string kv = list.substr(at, comma - at);
      at = comma + 1;
      const size_t eq = kv.find('=');
      const std::string num = eq == std::string::npos ? std::string() : kv.substr(eq + 1);
      char* end = nullptr;
      const double b = std::strtod(num.c_str(), &end);
      if (eq == std::string::npos || eq == 0 || num.empty() || *end != '\0')
        throw po::error("--" + name + " wants " + key + "=BOUND[," + key + "=BOUND...], got '" +
                        kv + "'");
      (*out)[kv.substr(0, eq)] = b;
    }
  }
}

// Codec, clusters, window, check and --codec-opt from the options.
void set_coding_options(const po::variables_map& vm, capz::CompressOptions* opts) {
  opts->codec = vm["codec"].as<std::string>();
  opts->clusters = vm["clusters"].as<int>();
  opts->window_frames = vm["window"].as<size_t>();
  opts->check = vm.count("no-check") == 0;
  opts->drop_fields = vm.count("drop-fields") > 0;
  const std::string order = vm["point-order"].as<std::string>();
  if (order != "kept" && order != "any")
    throw po::error("--point-order wants kept or any, got '" + order + "'");
  opts->any_point_order = order == "any";
  parse_bounds(vm, "attr-error", "NAME", &opts->attr_error);
  parse_bounds(vm, "analog-max-error", "KEY", &opts->analog_max_error);
  if (vm.count("codec-opt"))
    for (const auto& kv : vm["codec-opt"].as<std::vector<std::string>>()) {
      auto eq = kv.find('=');
      if (eq == std::string::npos) throw po::error("--codec-opt wants key=value, got '" + kv + "'");
      opts->codec_options[kv.substr(0, eq)] = kv.substr(eq + 1);
    }
}

// The error target: --lossless, --kg-error, --max-error, or the default bound
// (capz::set_compress_target).
// Returns the default bound's note (capz::set_compress_target), or "".
std::string set_target(const po::variables_map& vm, capz::FrameSource& source,
                       capz::CompressOptions* opts) {
  capz::CompressTarget target;
  target.lossless = vm.count("lossless") != 0;
  if (vm.count("kg-error")) target.kg_error = vm["kg-error"].as<double>();
  if (vm.count("max-error")) target.max_error = vm["max-error"].as<std::string>();
  return capz::set_compress_target(source, target, opts);
}

// Compresses the input into `out`; returns the encoding's CPU seconds: of the process when the
// file is coded `alone` on window threads, else of the calling thread.
// `progress`: the per-frame progress line (a single input; a batch shows its own).
// The reader's warnings, as info lists them and convert prints them (unless -q).
void print_warnings(const std::string& in, const std::vector<std::string>& warnings) {
  if (g_verbosity > 0)
    for (const std::string& w : warnings) file_note("capz compress: warning: " + in + ": " + w);
}

double encode(Input& input, capz::CompressOptions opts, const std::string& out, bool force,
              bool progress_line, bool alone, capz::CompressStats* st) {
  const bool workers = alone && opts.threads > 1;
  const double c_enc = cpu_seconds(workers);
  Progress progress("compress");
  if (progress_line) opts.progress = [&](size_t d, size_t t) { progress(d, t); };
  capz::compress_input(input.in, opts, out, force, st);
  return cpu_seconds(workers) - c_enc;
}

// What the report says besides the take, the options and the stats.
struct Report {
  std::string in, out;
  std::string units;       // the take's units as read (assumed ones included), before coding
  std::string units_note;  // "units m (assumed: ...)" when the reader assumed them, else empty
  uint64_t in_bytes = 0;
  double t_read = 0, t_enc = 0;  // thread CPU seconds
  double ratio = 0;              // IN's bytes / OUT's
  double mbps = 0;               // raw float32 position MB encoded per CPU second
};

std::string report_json(const Report& r, const capz::Take& take, const capz::CompressOptions& opts,
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
  j.member("units", r.units);
  j.member("units_assumed", !r.units_note.empty());
  j.member("bpvf", st.bpvf);
  j.member("mode", st.mode);
  if (!st.float32_split_windows.empty()) {  // windows per float32 split exponent, as info's
    j.key("float32_split_windows");
    j.begin_object();
    for (const auto& kv : st.float32_split_windows)
      j.member(std::to_string(kv.first), static_cast<uint64_t>(kv.second));
    j.end_object();
  }
  j.member("codec", st.codec);
  j.member("lossless", st.lossless);
  j.member("grid_step", st.step);
  j.member("max_error_target", opts.max_error);
  j.member("kg_error_target", opts.kg_error);
  json_error_stats(&j, st.error);
  j.member("position_bytes", static_cast<uint64_t>(st.position_bytes));
  j.member("analog_bytes", static_cast<uint64_t>(st.analog_bytes));
  j.member("rotation_bytes", static_cast<uint64_t>(st.rotation_bytes));
  j.member("attribute_bytes", static_cast<uint64_t>(st.attribute_bytes));
  j.member("other_bytes", static_cast<uint64_t>(st.other_bytes));
  j.member("raw_float32_position_bytes", static_cast<uint64_t>(st.raw_bytes));
  j.member("read_cpu_seconds", r.t_read);
  j.member("encode_cpu_seconds", r.t_enc);
  j.member("encode_checked", opts.check);
  j.member("encode_mb_per_s", r.mbps);
  j.end_object();
  return j.str() + "\n";
}

std::string report_text(const Report& r, const capz::Take& take, const capz::CompressOptions& opts,
                        const capz::CompressStats& st) {
  std::string text;
  if (g_verbosity >= 1) {
    const std::string u = r.units.empty() ? "" : " " + r.units;
    std::string err =
        st.lossless ? "lossless (" + positions_text(st.mode, st.float32_split_windows, u) + ")"
        : std::isnan(st.error.max_abs)  // a ragged take with --no-check: no decode to measure
            ? "max error not measured (--no-check), bound " + num(opts.max_error) + u
            : "max error " + num(st.error.max_abs) + u + " per coordinate (" +
                  num(st.error.max_error) + u + " Euclidean), KG " + num(st.error.kg_error) + "%";
    if (opts.codec == "auto") err += ", codec " + st.codec;
    if (!r.units_note.empty()) err += "; " + r.units_note;
    text += strprintf("%s -> %s: %s -> %s (ratio %s), %s bpvf, %s\n", r.in.c_str(), r.out.c_str(),
                      human_size(r.in_bytes).c_str(), human_size(st.bytes).c_str(),
                      num(r.ratio).c_str(), num(st.bpvf).c_str(), err.c_str());
  }
  if (g_verbosity >= 2) {
    text += strprintf(
        "  %zu frames x %zu points%s, %s coding, grid step %s%s; positions %zu B (x%s vs "
        "raw float32), analog %zu B, rotations %zu B, point fields %zu B, other %zu B\n",
        take.frames, take.ragged() ? take.total_points() : take.points,
        take.ragged() ? " in all" : "", st.mode.c_str(), num(st.step, 6).c_str(),
        r.units.empty() ? "" : (" " + r.units).c_str(), st.position_bytes,
        num(st.position_bytes
                ? static_cast<double>(st.raw_bytes) / static_cast<double>(st.position_bytes)
                : 0)
            .c_str(),
        st.analog_bytes, st.rotation_bytes, st.attribute_bytes, st.other_bytes);
    text += strprintf("  cpu: read %.3f s, encode%s %.3f s (%s MB/s of raw float32 positions)\n",
                      r.t_read, opts.check ? "+check" : "", r.t_enc, num(r.mbps).c_str());
  }
  return text;
}

// What every file of one `capz compress` shares.
struct Settings {
  po::variables_map vm;
  BatchSettings batch;
  std::string units;       // --units, may be empty
  capz::ReadOptions read;  // --bin-fields
  bool single = false;     // one input: the per-frame progress line
};

// stdin's bytes must be a C3D or a TRC: the format comes from them (the spool has no name).
void check_take_stream(const std::string& spool) {
  const capz::Format f = capz::detect_format(spool);
  if (f == capz::Format::kC3D || f == capz::Format::kTRC) return;
  const std::vector<uint8_t> head = capz::read_file(spool);
  if (capz::is_capz(head.data(), head.size()))
    capz::fail(capz::ErrorCode::kNotOurFormat, "stdin",
               "is a .capz archive, not a take (use capz decompress)");
  capz::fail(capz::ErrorCode::kNotOurFormat, "stdin",
             "not a C3D or TRC stream (a PCD sequence is a folder: give the folder)");
}

// --rm, once OUT has proved it gives IN back: a file is removed; a PCD, PLY or .bin folder loses
// the frame files the take was read from, and the folder itself when nothing else is left in it.
void remove_input(const std::string& in, const capz::Take& take) {
  std::error_code ec;
  if (!fs::is_directory(in)) {
    fs::remove(in, ec);
    if (ec)
      capz::fail(capz::ErrorCode::kIo, in, "could not remove after compressing: " + ec.message());
    return;
  }
  const std::vector<std::string>* names = take.pcd   ? &take.pcd->frame_names
                                          : take.ply ? &take.ply->frame_names
                                          : take.bin ? &take.bin->frame_names
                                                     : nullptr;
  if (!names)
    capz::fail(capz::ErrorCode::kUsage, in,
               "--rm: a folder that is not a PCD, PLY or .bin sequence");
  for (const std::string& name : *names) {
    const fs::path f = fs::path(in) / name;
    fs::remove(f, ec);
    if (ec)
      capz::fail(capz::ErrorCode::kIo, f.string(),
                 "could not remove after compressing: " + ec.message());
  }
  if (fs::is_empty(in, ec) && !ec) {
    fs::remove(in, ec);
    if (ec)
      capz::fail(capz::ErrorCode::kIo, in, "could not remove after compressing: " + ec.message());
  } else if (g_verbosity > 0) {
    file_note("capz compress: note: " + in + ": its " + std::to_string(names->size()) +
              " frame files removed; the folder is kept, as it holds other files");
  }
}

// compress's output for job (from IN, spooled when it is stdin), checked free; sets r.in and r.out.
void choose_output(const Job& job, const Settings& s, PipeSpace* space, std::string* in,
                   Report* r) {
  if (job.from_stdin) check_take_stream(*in = space->spool_stdin("stdin"));
  r->in = job.from_stdin ? "stdin" : *in;
  if (job.to_stdout) {
    refuse_terminal_stdout("a .capz archive");
    r->out = space->path("stdout.capz");
    return;
  }
  r->out = !job.output.empty()
               ? job.output
               : place_output(
                     s.batch, job,
                     fs::path(capz::without_trailing_slashes(*in)).filename().string() + ".capz");
  claim_output(r->out, *in);
  capz::check_output_free(r->out, s.batch.force);
}

// The notes of a compress (at the default verbosity, the analog bounds' always): labels or units
// --analog-max-error matched none of, and the coordinates left out of the grid.
void print_compress_notes(const std::string& in, const capz::CompressStats& st) {
  for (const std::string& k : st.analog_unmatched)
    file_note("capz compress: note: " + in + ": --analog-max-error " + k +
              " names no analog channel's label or unit; those stay lossless");
  const std::string dropped = capz::dropped_coordinates_note(st);
  if (!dropped.empty() && g_verbosity > 0) file_note("capz compress: note: " + in + ": " + dropped);
}

// The batch's record of one compressed file (*rp: its report so far).
FileRecord compress_record(const Job& job, const po::variables_map& vm, Report* rp,
                           const capz::Take& take, const capz::CompressOptions& opts,
                           const capz::CompressStats& st) {
  Report& r = *rp;  // r.out becomes "stdout" for stdout
  FileRecord rec;
  rec.input = r.in;
  const capz::OriginalInfo original = capz::original_info(r.out);
  if (original.hashed) rec.checksum = original.hash_hex;
  if (job.to_stdout) {
    copy_to_stdout(r.out);
    r.out = "stdout";
  }
  rec.output = r.out;
  rec.bytes_in = r.in_bytes;
  rec.bytes_out = st.bytes;
  rec.ratio = r.ratio;
  rec.lossless = st.lossless;
  rec.bound = st.lossless ? 0 : opts.kg_error > 0 ? FileRecord::kNone : opts.max_error;
  rec.units = r.units;
  rec.max_error = st.error.max_abs;
  rec.text = vm.count("json") ? report_json(r, take, opts, st) : report_text(r, take, opts, st);
  return rec;
}

FileRecord compress_file(const Job& job, const Settings& s, PipeSpace* space) {
  const po::variables_map& vm = s.vm;
  if (vm.count("rm") && (job.from_stdin || job.to_stdout))
    capz::fail(capz::ErrorCode::kUsage, "", "--rm does not apply to stdin or stdout");
  std::string in = job.input;
  Report r;
  choose_output(job, s, space, &in, &r);
  if (vm.count("rm") && vm.count("drop-fields"))
    capz::fail(capz::ErrorCode::kUsage, in,
               "--rm with --drop-fields: the archive would not give the input back");

  Input input;
  open_input(in, vm["codec"].as<std::string>() == "auto", s.units, s.read, &input);
  r.t_read = input.read_cpu_seconds;
  capz::CompressOptions opts;
  set_coding_options(vm, &opts);
  // -T: job.threads is what this file may use inside the library (1 while a batch codes several
  // files at once): the windows of the take coded in parallel.
  opts.threads = static_cast<int>(job.threads);
  const capz::Take& take = input.in.source->header();
  print_warnings(r.in, take.warnings);  // the header's (a .bin record guessed from the names)
  const std::string bound_note = set_target(vm, *input.in.source, &opts);
  if (!bound_note.empty() && g_verbosity > 0)
    file_note("capz compress: note: " + r.in + ": " + bound_note);
  r.units = take.units;
  if (take.units_assumed) r.units_note = "units " + capz::units_text(take);

  capz::CompressStats st;
  r.t_enc = encode(input, opts, r.out, s.batch.force, s.single, job.alone, &st);
  print_warnings(r.in, input.in.source->frame_warnings());  // found reading the frames
  print_compress_notes(r.in, st);
  r.in_bytes = path_size(in);
  r.ratio = st.bytes ? static_cast<double>(r.in_bytes) / static_cast<double>(st.bytes) : 0;
  r.mbps = r.t_enc > 0 ? static_cast<double>(st.raw_bytes) / 1e6 / r.t_enc : 0;
  if (vm.count("rm")) {
    check_written(r.out, in, take);  // like zstd: only a verified output lets IN go
    remove_input(in, take);
  }
  return compress_record(job, vm, &r, take, opts, st);
}

}  // namespace

int cmd_compress(const Args& args) {
  Settings s;
  std::vector<std::string> inputs;
  if (!parse_inputs(
          args,
          "capz compress IN... [-o OUT | -c | --output-dir-mirror DIR | --output-dir-flat DIR]\n"
          "                    [-r] [-T N] [--max-error E | --kg-error X | --lossless] [options]",
          "Compresses each IN (a .c3d, a .trc, a folder of .pcd, .ply or .bin frames, or one\n"
          "such frame file) to a .capz, by default IN.capz beside it. '-' (or no IN while\n"
          "stdin is a pipe) reads one C3D or TRC stream from stdin and writes the archive to\n"
          "stdout. -r walks folders: every .c3d and .trc in them, and every folder holding\n"
          ".pcd, .ply or .bin frames as one sequence.\n"
          "Error bounds are per coordinate: every valid coordinate comes back within the\n"
          "bound (a point's Euclidean error is then at most sqrt(3) times it); the report\n"
          "gives both, with the KG error and bits per vertex per frame (bpvf). Gaps,\n"
          "analog channels (unless --analog-max-error bounds them), labels, rate, units, C3D\n"
          "parameters and events come back exactly.\n"
          "A file that fails is reported and the others go on; the exit status is then the\n"
          "first failure's.",
          compress_options(), "IN", true, &s.vm, &inputs))
    return 0;
  const po::variables_map& vm = s.vm;
  const int targets = (vm.count("lossless") ? 1 : 0) + (vm.count("kg-error") ? 1 : 0) +
                      (vm.count("max-error") ? 1 : 0);
  if (targets > 1) throw po::error("give only one of --max-error, --kg-error, --lossless");
  s.units = vm.count("units") ? vm["units"].as<std::string>() : "";
  s.read = read_options(vm);
  if (!s.units.empty() && capz::units_to_metres(s.units) == 0)
    capz::fail(capz::ErrorCode::kInvalidParameter, "", "--units: unknown unit '" + s.units + "'");
  {
    capz::CompressOptions check;  // a bad --codec-opt is a usage error before any file
    set_coding_options(vm, &check);
  }
  s.batch = batch_settings(vm, true);
  std::vector<Job> jobs = expand_inputs(inputs, InputKind::kTakes, s.batch);
  s.single = jobs.size() == 1;
  return run_batch("compress", s.batch, std::move(jobs), [&s](const Job& job) {
    return with_pipe_space(job, [&](PipeSpace* p) { return compress_file(job, s, p); });
  });
}

}  // namespace capz_cli

// capz decompress X.capz... [-o OUT | -c | --output-dir-mirror DIR | --output-dir-flat DIR] [-r]
//                  [-T N] [--frames FIRST:COUNT]
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>

#include "batch.h"
#include "capz/codec.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "capz/tool/original.h"
#include "compress_common.h"
#include "pipe.h"

namespace capz_cli {

namespace {

// Whether `s` ends in the extension `e` (lower case) in any case: walk.C3D ends in .c3d.
bool ends_with(const std::string& s, const std::string& e) {
  if (s.size() <= e.size()) return false;
  const size_t at = s.size() - e.size();
  for (size_t i = 0; i < e.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(s[at + i])) != e[i]) return false;
  return true;
}

// Default output: X.capz -> X when X names the source's format (take.c3d.capz -> take.c3d,
// walk.C3D.capz -> walk.C3D, frames.capz -> frames/ for a PCD folder); else the source's own
// name beside X.capz. Extensions are recognised in any case.
// A one-frame take from a single frame file comes back as that file (scan.pcd.capz ->
// scan.pcd).
std::string default_output(const std::string& in, const capz::Take& take) {
  std::string stem = ends_with(in, ".capz") ? in.substr(0, in.size() - 5) : in;
  const capz::Format f = take.format;
  const char* frame_ext = f == capz::Format::kPCDFolder   ? ".pcd"
                          : f == capz::Format::kPLYFolder ? ".ply"
                          : f == capz::Format::kBinFolder ? ".bin"
                                                          : nullptr;
  if ((f == capz::Format::kC3D && ends_with(stem, ".c3d")) ||
      (f == capz::Format::kTRC && ends_with(stem, ".trc")) ||
      (frame_ext && take.frames == 1 && ends_with(stem, frame_ext)))
    return stem;
  if (frame_ext && stem != in && !ends_with(stem, ".c3d") && !ends_with(stem, ".trc"))
    return stem + "/";
  const std::string dir = fs::path(in).parent_path().string();
  std::string name = take.source.empty() ? fs::path(stem).filename().string() : take.source;
  if (f == capz::Format::kC3D && !ends_with(name, ".c3d")) name += ".c3d";
  if ((f == capz::Format::kTRC || f == capz::Format::kUnknown) && !ends_with(name, ".trc"))
    name += ".trc";
  if (frame_ext && !(take.frames == 1 && ends_with(name, frame_ext))) name += "/";
  return dir.empty() ? name : dir + "/" + name;
}

// True when OUT names one frame file (.pcd, .ply, .bin, any case), not a folder.
bool one_frame_file(const std::string& out) {
  std::error_code ec;
  return (ends_with(out, ".pcd") || ends_with(out, ".ply") || ends_with(out, ".bin")) &&
         !std::filesystem::is_directory(out, ec);
}

// True when OUT names the source's own format: .c3d / .trc (any case); frames of PCD, PLY or
// .bin, `folder` being the format OUT is written in: a folder, or one file of a one-frame take
// (which rebuild_original writes as that file).
bool same_format(const std::string& out, const capz::Take& take, capz::Format folder) {
  const capz::Format f = take.format;
  const bool frames = f == capz::Format::kPCDFolder || f == capz::Format::kPLYFolder ||
                      f == capz::Format::kBinFolder;
  return (f == capz::Format::kC3D && ends_with(out, ".c3d")) ||
         (f == capz::Format::kTRC && ends_with(out, ".trc")) ||
         (frames && folder == f && (take.frames == 1 || !one_frame_file(out)));
}

// What every file of one `capz decompress` shares.
struct Settings {
  po::variables_map vm;
  BatchSettings batch;
};

// --frames FIRST:COUNT: decimal digits, COUNT -1 for to the end (as many as there are). A COUNT
// of 0 asks for nothing: a usage error, before any file.
void parse_frames(const std::string& fr, size_t* first, size_t* count) {
  const auto number = [](const std::string& digits, size_t* v) {
    if (digits.empty() || digits.size() > 18 ||
        digits.find_first_not_of("0123456789") != digits.npos)
      return false;
    *v = static_cast<size_t>(std::stoull(digits));
    return true;
  };
  const size_t colon = fr.find(':');
  const std::string c = colon == fr.npos ? "" : fr.substr(colon + 1);
  if (colon == fr.npos || !number(fr.substr(0, colon), first) ||
      !(c == "-1" ? (*count = std::numeric_limits<size_t>::max(), true) : number(c, count)))
    throw po::error("--frames wants FIRST:COUNT (COUNT -1: to the end), got '" + fr + "'");
  if (*count == 0)
    throw po::error("--frames " + fr + " asks for no frames (COUNT 1 or more, -1: to the end)");
}

// "20 frames (0..19)", "1 frame (0)", "no frames".
std::string frames_text(size_t frames) {
  if (frames == 0) return "no frames";
  return std::to_string(frames) +
         (frames == 1 ? " frame (0" : " frames (0.." + std::to_string(frames - 1)) + ")";
}

// Where the take goes: stdout (through a file of the source's format in `space`), -o, or its
// default name placed by the batch settings. Claims it and checks it is free.
std::string choose_output(const Job& job, const Settings& s, const std::string& in,
                          const capz::Take& take, PipeSpace* space) {
  if (job.to_stdout) {
    if (take.format == capz::Format::kPCDFolder)
      capz::fail(capz::ErrorCode::kUsage, in,
                 "holds a PCD sequence, a folder: it cannot go to stdout (give -o DIR)");
    if (take.format == capz::Format::kC3D) refuse_terminal_stdout("a C3D file");
    return space->path(take.format == capz::Format::kC3D ? "stdout.c3d" : "stdout.trc");
  }
  std::string out = job.output;
  if (out.empty()) {
    const std::string beside = default_output(in, take);
    const bool folder = !beside.empty() && beside.back() == '/';
    out = place_output(
        s.batch, job,
        fs::path(capz::without_trailing_slashes(beside)).filename().string() + (folder ? "/" : ""));
  }
  claim_output(out, in);
  // A folder of an archive tree takes frames beside its own.
  capz::check_output_free(capz::without_trailing_slashes(out), s.batch.force,
                          capz::frames_go_beside);
  return out;
}

// What a decode wrote: the output's path and the take's shape, units and point fields.
struct Written {
  std::string out;
  size_t frames = 0, points = 0;          // points: per frame, 0 for frames of their own counts
  size_t total_points = 0;                // over all frames
  std::string shape;                      // shape_text
  std::string units, fields;              // fields: capz::field_names
  std::vector<std::string> dropped;       // what out's format does not keep (capz::dropped_by)
  void take_shape(const capz::Take& t) {  // once out is chosen (a header has frame offsets)
    frames = t.frames;
    points = t.points;
    total_points = t.total_points();
    shape = shape_text(t);
    units = t.units;
    fields = capz::field_names(t);
    const capz::Format f = capz::format_for_output(out);
    if (f != capz::Format::kUnknown) dropped = capz::dropped_by(t, f);
  }
};

// --frames: the range decoded into memory (only the windows it touches), then written.
Written decode_range(const Job& job, const Settings& s, const std::string& in,
                     const capz::DecompressOptions& dopts, const capz::WriteOptions& wo,
                     PipeSpace* space) {
  size_t a = 0, n = 0;
  parse_frames(s.vm["frames"].as<std::string>(), &a, &n);
  std::vector<uint8_t> bytes = capz::read_file(in);
  capz::Take take = capz::decompress_frames(bytes.data(), bytes.size(), a, n, in, dopts);
  if (take.frames == 0)  // FIRST at or past the end: what the take has (COUNT 0 was refused)
    capz::fail(capz::ErrorCode::kUsage, in,
               "--frames " + s.vm["frames"].as<std::string>() + " is past the end: the take has " +
                   frames_text(capz::describe(bytes.data(), bytes.size(), in).frames));
  Written w;
  w.out = choose_output(job, s, in, take, space);
  capz::write_take(take, w.out, wo);
  w.take_shape(take);
  return w;
}

// The whole take, decoded and written window by window. The original's own format from an
// archive with its residue: the original file rebuilt (byte for byte when lossless, FORMAT.md
// 4.4, 5.4); any other output, and PCD frames asked in another encoding or without their fields,
// through the writer.
Written decode_whole(const Job& job, const Settings& s, const std::string& in,
                     const capz::DecompressOptions& dopts, const capz::WriteOptions& wo,
                     PipeSpace* space) {
  std::unique_ptr<capz::FrameSource> src = capz::open_capz_frames(in, dopts);
  const capz::Take& take = src->header();
  Written w;
  w.out = choose_output(job, s, in, take, space);
  w.take_shape(take);
  if (same_format(w.out, take, capz::output_format(take, w.out, wo)) && wo.pcd_encoding.empty() &&
      wo.ply_encoding.empty() && !wo.drop_fields && !wo.trc_delimiter &&
      capz::can_rebuild(capz::original_info(in), take.format == capz::Format::kC3D)) {
    src.reset();
    capz::rebuild_original(in, w.out, s.batch.force, dopts);
  } else {
    capz::write_frames(*src, w.out, wo);
  }
  return w;
}

// The file's line (or JSON object with --json) for the record.
std::string record_text(const Settings& s, const FileRecord& rec, const Written& w, double t_dec,
                        double mbps) {
  if (s.vm.count("json")) {
    Json j;
    j.begin_object();
    j.member("input", rec.input);
    j.member("output", rec.output);
    j.member("frames", static_cast<uint64_t>(w.frames));
    j.member("points", static_cast<uint64_t>(w.points));
    j.member("total_points", static_cast<uint64_t>(w.total_points));
    j.member("decode_cpu_seconds", t_dec);
    j.member("decode_mb_per_s", mbps);
    j.end_object();
    return j.str() + "\n";
  }
  if (g_verbosity < 1) return "";
  std::string text =
      strprintf("%s -> %s: %s\n", rec.input.c_str(), rec.output.c_str(), w.shape.c_str());
  if (g_verbosity >= 2)
    text += strprintf("  cpu: decode %.3f s (%s MB/s of raw float32 positions)\n", t_dec,
                      num(mbps).c_str());
  return text;
}

FileRecord decompress_file(const Job& job, const Settings& s, PipeSpace* space) {
  const po::variables_map& vm = s.vm;
  std::string in = job.input;
  if (job.from_stdin) {
    in = space->spool_stdin("stdin");
    const std::vector<uint8_t> head = capz::read_file(in);
    if (!capz::is_capz(head.data(), head.size()))
      capz::fail(capz::ErrorCode::kNotOurFormat, "stdin", "not a .capz archive");
  }
  // -T: job.threads is what this file may use inside the library (windows decoded ahead).
  capz::DecompressOptions dopts;
  dopts.threads = static_cast<int>(job.threads);
  dopts.memory_limit = memlimit(vm);
  capz::WriteOptions wo;
  wo.overwrite = s.batch.force;
  wo.drop_fields = vm.count("drop-fields") > 0;
  if (vm.count("pcd-data")) wo.pcd_encoding = vm["pcd-data"].as<std::string>();
  wo.trc_delimiter = trc_delimiter(vm, 0);
  const bool workers = job.alone && dopts.threads > 1;
  const double c0 = cpu_seconds(workers);
  Written w = vm.count("frames") ? decode_range(job, s, in, dopts, wo, space)
                                 : decode_whole(job, s, in, dopts, wo, space);
  const std::string name = job.from_stdin ? "stdin" : in;
  if (wo.drop_fields && capz::format_for_output(w.out) != capz::Format::kPCDFolder &&
      g_verbosity >= 1 && !w.fields.empty())
    file_note("capz decompress: note: " + name + ": dropped point fields: " + w.fields);
  if (g_verbosity >= 1)
    for (const std::string& d : w.dropped)
      file_note("capz decompress: note: " + name + ": " +
                capz::format_name(capz::format_for_output(w.out)) + " does not keep " + d);
  const double t_dec = cpu_seconds(workers) - c0;
  const double raw = static_cast<double>(w.total_points * 12);
  const double mbps = t_dec > 0 ? raw / 1e6 / t_dec : 0;

  FileRecord rec;
  rec.units = w.units;
  rec.input = job.from_stdin ? "stdin" : in;
  rec.bytes_in = path_size(in);
  rec.bytes_out = output_size(capz::without_trailing_slashes(w.out));
  rec.ratio = rec.bytes_in ? static_cast<double>(rec.bytes_out) / static_cast<double>(rec.bytes_in)
                           : FileRecord::kNone;
  if (!s.batch.report.empty()) {  // the bound, for --report (the archive read whole once more)
    const std::vector<uint8_t> bytes = capz::read_file(in);
    const capz::StreamInfo info = capz::describe(bytes.data(), bytes.size(), in);
    rec.lossless = info.lossless;
    rec.bound = info.lossless ? 0 : info.transform_output ? FileRecord::kNone : info.max_error;
  }
  const capz::OriginalInfo original = capz::original_info(in);
  if (original.hashed) rec.checksum = original.hash_hex;
  rec.output = w.out;
  if (job.to_stdout) {
    copy_to_stdout(w.out);
    rec.output = "stdout";
  }
  rec.text = record_text(s, rec, w, t_dec, mbps);
  return rec;
}

}  // namespace

int cmd_decompress(const Args& args) {
  po::options_description o("decompress options");
  add_batch_options(&o, true, "output .c3d, .trc, or a folder for PCD frames (a single input)");
  o.add_options()("frames", po::value<std::string>(),
                  "decode only frames FIRST:COUNT (0-based; COUNT -1: to the end); only "
                  "the windows they touch are read")(
      "pcd-data", po::value<std::string>(),
      "PCD output: ascii, binary or binary_compressed (default: the source's)")(
      "drop-fields",
      "write a C3D or TRC from an archive of PCD frames with point fields by leaving the fields "
      "out; without it that is an error naming them")("json",
                                                      "print the report as one JSON object");
  add_trc_delimiter_option(&o, "the source's");
  add_memlimit_option(&o);
  Settings s;
  std::vector<std::string> inputs;
  if (!parse_inputs(
          args,
          "capz decompress X.capz... [-o OUT | -c | --output-dir-mirror DIR | --output-dir-flat "
          "DIR]\n                         [-r] [-T N] [--frames FIRST:COUNT] [--pcd-data E] "
          "[--drop-fields] [--trc-delimiter tab|comma]\n                         [--memlimit SIZE] "
          "[-f]",
          "Decompresses each X.capz to OUT: a .c3d, a .trc or a folder of PCD frames, chosen\n"
          "by OUT's name. By default the source's format and name: take.c3d.capz -> take.c3d,\n"
          "frames.capz -> frames/ (never overwritten without -f). '-' (or no X.capz while\n"
          "stdin is a pipe) reads an archive from stdin and writes its source's format (C3D\n"
          "or TRC) to stdout. -r walks folders for .capz files. A file that fails is\n"
          "reported and the others go on; the exit status is then the first failure's.",
          o, "X.capz", true, &s.vm, &inputs))
    return 0;
  if (s.vm.count("frames")) {
    size_t a = 0, n = 0;
    parse_frames(s.vm["frames"].as<std::string>(), &a, &n);  // a bad range: before any file
  }
  if (s.vm.count("pcd-data")) {  // a bad encoding: before any file
    const std::string e = s.vm["pcd-data"].as<std::string>();
    if (e != "ascii" && e != "binary" && e != "binary_compressed")
      capz::fail(capz::ErrorCode::kInvalidParameter, "",
                 "--pcd-data must be ascii, binary or binary_compressed, not '" + e + "'");
  }
  trc_delimiter(s.vm, 0);  // a bad delimiter: before any file
  memlimit(s.vm);          // a bad size: before any file
  s.batch = batch_settings(s.vm, true);
  std::vector<Job> jobs = expand_inputs(inputs, InputKind::kArchives, s.batch);
  return run_batch("decompress", s.batch, std::move(jobs), [&s](const Job& job) {
    return with_pipe_space(job, [&](PipeSpace* p) { return decompress_file(job, s, p); });
  });
}

}  // namespace capz_cli

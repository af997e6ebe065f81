// capz decompress X.capz [-o OUT] [--frames FIRST:COUNT]
#include <cctype>
#include <cstdio>
#include <memory>

#include "capz/codec.h"
#include "capz/io.h"
#include "capz/original.h"
#include "capz/stream.h"
#include "compress_common.h"

namespace capz_cli {

namespace {

bool ends_with(const std::string& s, const std::string& e) {
  return s.size() > e.size() && s.compare(s.size() - e.size(), e.size(), e) == 0;
}

// Default output: X.capz -> X when X names the source's format (take.c3d.capz -> take.c3d,
// frames.capz -> frames/ for a PCD folder); else the source's own name beside X.capz.
std::string default_output(const std::string& in, const capz::Take& take) {
  std::string stem = ends_with(in, ".capz") ? in.substr(0, in.size() - 5) : in;
  const capz::Format f = take.format;
  if ((f == capz::Format::kC3D && ends_with(stem, ".c3d")) ||
      (f == capz::Format::kTRC && ends_with(stem, ".trc")))
    return stem;
  if (f == capz::Format::kPCDFolder && stem != in && !ends_with(stem, ".c3d") &&
      !ends_with(stem, ".trc"))
    return stem + "/";
  const std::string dir = fs::path(in).parent_path().string();
  std::string name = take.source.empty() ? fs::path(stem).filename().string() : take.source;
  if (f == capz::Format::kC3D && !ends_with(name, ".c3d")) name += ".c3d";
  if ((f == capz::Format::kTRC || f == capz::Format::kUnknown) && !ends_with(name, ".trc"))
    name += ".trc";
  if (f == capz::Format::kPCDFolder) name += "/";
  return dir.empty() ? name : dir + "/" + name;
}

// True when OUT names the source's own format (.c3d / .trc, any case).
bool same_format(const std::string& out, capz::Format f) {
  std::string lower = out;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return (f == capz::Format::kC3D && ends_with(lower, ".c3d")) ||
         (f == capz::Format::kTRC && ends_with(lower, ".trc"));
}

}  // namespace

int cmd_decompress(const Args& args) {
  po::options_description o("decompress options");
  o.add_options()("output,o", po::value<std::string>(),
                  "output .c3d, .trc, or a folder for PCD frames")(
      "frames", po::value<std::string>(),
      "decode only frames FIRST:COUNT (0-based); only the "
      "windows they touch are read")("force,f", "overwrite OUT if it exists")(
      "threads,T", po::value<int>()->default_value(1),
      "worker threads decoding windows in parallel (0: all cores)")(
      "json", "print the report as one JSON object");
  po::variables_map vm;
  std::string in;
  if (!parse_single_input(
          args, "capz decompress X.capz [-o OUT] [--frames FIRST:COUNT] [-f]",
          "Decompresses X.capz to OUT: a .c3d, a .trc or a folder of PCD frames, chosen by\n"
          "OUT's name. By default the source's format and name: take.c3d.capz -> take.c3d,\n"
          "frames.capz -> frames/ (never overwritten without -f).",
          o, "X.capz", &vm, &in))
    return 0;
  const bool force = vm.count("force") != 0;
  std::string out = vm.count("output") ? vm["output"].as<std::string>() : "";
  if (!out.empty()) capz::check_output_free(out, force);

  const double c0 = thread_cpu_seconds();
  capz::WriteOptions wo;
  wo.overwrite = force;
  capz::DecompressOptions dopts;
  dopts.threads = vm["threads"].as<int>();
  size_t frames = 0, points = 0;
  if (vm.count("frames")) {  // a range: decoded into memory (only the windows it touches)
    const std::string fr = vm["frames"].as<std::string>();
    unsigned long long a = 0, n = 0;
    char extra;
    if (std::sscanf(fr.c_str(), "%llu:%llu%c", &a, &n, &extra) != 2)
      throw po::error("--frames wants FIRST:COUNT, got '" + fr + "'");
    std::vector<uint8_t> bytes = capz::read_file(in);
    capz::Take take = capz::decompress_frames(bytes.data(), bytes.size(), a, n, in);  // serial
    if (out.empty()) {
      out = default_output(in, take);
      capz::check_output_free(strip_slashes(out), force);
    }
    capz::write_take(take, out, wo);
    frames = take.frames;
    points = take.points;
  } else {  // the whole take: decoded and written window by window
    std::unique_ptr<capz::FrameSource> src = capz::open_capz_frames(in, dopts);
    const capz::Take& take = src->header();
    if (out.empty()) {
      out = default_output(in, take);
      capz::check_output_free(strip_slashes(out), force);
    }
    frames = take.frames;
    points = take.points;
    // The original's own format from an archive with its residue: the original file rebuilt
    // (byte for byte when lossless, FORMAT.md 4.4); any other output through the writer.
    if (same_format(out, take.format) &&
        capz::can_rebuild(capz::original_info(in), take.format == capz::Format::kC3D)) {
      src.reset();
      capz::rebuild_original(in, out, force, dopts);
    } else {
      std::unique_ptr<capz::FrameSink> sink =
          capz::create_frame_sink(take, src->has_sample_words(), out, wo);
      capz::copy_frames(*src, *sink, src->preferred_block());
    }
  }
  const double t_dec = thread_cpu_seconds() - c0;
  const double raw = static_cast<double>(frames * points * 12);
  const double mbps = t_dec > 0 ? raw / 1e6 / t_dec : 0;
  if (vm.count("json")) {
    Json j;
    j.begin_object();
    j.member("input", in);
    j.member("output", out);
    j.member("frames", static_cast<uint64_t>(frames));
    j.member("points", static_cast<uint64_t>(points));
    j.member("decode_cpu_seconds", t_dec);
    j.member("decode_mb_per_s", mbps);
    j.end_object();
    std::printf("%s\n", j.str().c_str());
  } else if (g_verbosity >= 1) {
    std::printf("%s -> %s: %zu frames x %zu points\n", in.c_str(), out.c_str(), frames, points);
    if (g_verbosity >= 2)
      std::printf("  cpu: decode %.3f s (%s MB/s of raw float32 positions)\n", t_dec,
                  num(mbps).c_str());
  }
  return 0;
}

}  // namespace capz_cli

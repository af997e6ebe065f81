// capz decompress X.capz [-o OUT] [--frames FIRST:COUNT]
#include <boost/program_options.hpp>
#include <cstdio>
#include <iostream>

#include "capz/codec.h"
#include "capz/io.h"
#include "compress_common.h"

namespace po = boost::program_options;

namespace capz_cli {

// Default output: X.capz -> X when X names the source's format (take.c3d.capz -> take.c3d),
// else the source's own name next to X.capz.
static std::string default_output(const std::string& in, const capz::Take& take) {
  std::string stem = in;
  if (stem.size() > 5 && stem.compare(stem.size() - 5, 5, ".capz") == 0)
    stem = stem.substr(0, stem.size() - 5);
  const capz::Format f = take.format;
  auto ends_with = [&](const char* e) {
    std::string x(e);
    return stem.size() > x.size() && stem.compare(stem.size() - x.size(), x.size(), x) == 0;
  };
  if ((f == capz::Format::kC3D && ends_with(".c3d")) || (f == capz::Format::kTRC && ends_with(".trc")) ||
      (f == capz::Format::kPCDFolder && !ends_with(".c3d") && !ends_with(".trc") && stem != in))
    return stem;
  std::string dir = fs::path(in).parent_path().string();
  std::string name = take.source.empty() ? fs::path(stem).filename().string() : take.source;
  if (f == capz::Format::kC3D && !(name.size() > 4 && name.substr(name.size() - 4) == ".c3d")) name += ".c3d";
  if (f == capz::Format::kTRC && !(name.size() > 4 && name.substr(name.size() - 4) == ".trc")) name += ".trc";
  if (f == capz::Format::kUnknown) name += ".trc";
  return dir.empty() ? name : dir + "/" + name;
}

int cmd_decompress(const Args& args) {
  std::string in, out, frames;
  po::options_description o(
      "usage: capz decompress X.capz [-o OUT] [options]\n"
      "OUT is a .c3d, a .trc or a folder for PCD frames; by default the source's format and\n"
      "name (take.c3d.capz -> take.c3d). Never overwrites without -f.\n\noptions");
  o.add_options()
      ("help,h", "show this help")
      ("output,o", po::value(&out), "output .c3d, .trc or folder")
      ("frames", po::value(&frames), "decode only frames FIRST:COUNT (0-based; only the windows "
       "they touch are read)")
      ("force,f", "overwrite OUT if it exists")
      ("quiet,q", "print nothing but errors")
      ("verbose,v", "print timings");
  po::options_description hidden;
  hidden.add_options()("input", po::value(&in));
  po::options_description all;
  all.add(o).add(hidden);
  po::positional_options_description pos;
  pos.add("input", 1);
  po::variables_map vm;
  po::store(po::command_line_parser(args).options(all).positional(pos).run(), vm);
  po::notify(vm);
  if (vm.count("help")) {
    std::cout << o << "\n";
    return 0;
  }
  if (vm.count("quiet")) g_verbosity = 0;
  if (vm.count("verbose")) g_verbosity = 2;
  if (in.empty()) capz::fail(capz::ErrorCode::kUsage, "", "no input given (see capz decompress --help)");
  const bool force = vm.count("force") != 0;
  if (!out.empty()) capz::check_output_free(out, force);

  std::vector<uint8_t> bytes = capz::read_file(in);
  auto t0 = std::chrono::steady_clock::now();
  capz::Take take;
  if (!frames.empty()) {
    unsigned long long a = 0, n = 0;
    char extra;
    if (std::sscanf(frames.c_str(), "%llu:%llu%c", &a, &n, &extra) != 2)
      capz::fail(capz::ErrorCode::kUsage, "", "--frames wants FIRST:COUNT, got '" + frames + "'");
    take = capz::decompress_frames(bytes.data(), bytes.size(), a, n, in);
  } else {
    take = capz::decompress(bytes.data(), bytes.size(), in);
  }
  const double t_dec = seconds_since(t0);
  if (out.empty()) {
    out = default_output(in, take);
    capz::check_output_free(out, force);
  }
  capz::WriteOptions wo;
  wo.overwrite = force;
  capz::write_take(take, out, wo);
  if (g_verbosity >= 1)
    std::printf("%s -> %s: %zu frames x %zu points\n", in.c_str(), out.c_str(), take.frames, take.points);
  if (g_verbosity >= 2)
    std::printf("  decode %.3f s (%s MB/s of raw float32 positions)\n", t_dec,
                num(take.frames * take.points * 12 / 1e6 / t_dec, 4).c_str());
  return 0;
}

}  // namespace capz_cli

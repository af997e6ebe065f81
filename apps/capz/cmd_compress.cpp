// capz compress IN [-o OUT] [--max-error E | --kg-error X | --lossless] [--codec NAME] ...
#include <boost/program_options.hpp>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "capz/codec.h"
#include "capz/io.h"
#include "compress_common.h"

namespace po = boost::program_options;

namespace capz_cli {

int cmd_compress(const Args& args) {
  std::string in, out, max_error = "0.1mm", units;
  double kg = 0;
  std::string codec = "none";
  std::vector<std::string> codec_opts;
  int clusters = 0;
  size_t window = 1024;
  po::options_description o(
      "usage: capz compress IN [-o OUT] [options]\n"
      "IN is a .c3d, a .trc or a folder of .pcd frames. OUT defaults to IN.capz.\n"
      "Error targets are per coordinate: every valid coordinate comes back within the bound\n"
      "(a point's Euclidean error is then at most sqrt(3) times it; both are reported).\n\n"
      "options");
  o.add_options()
      ("help,h", "show this help")
      ("output,o", po::value(&out), "output file (default IN.capz)")
      ("max-error,e", po::value(&max_error),
       "per-coordinate bound: a length with a unit (0.1mm, 0.05cm, 0.0001m, 0.01in) or a bare "
       "number in the data's own units. Default 0.1mm; for data without units (PCD folders, "
       "unless --units is given) the default is 1e-4 x the bounding-box diagonal of the data")
      ("kg-error", po::value(&kg), "instead of a bound: KG error target in percent; the grid "
       "is chosen so the achieved KG error is at or just under it")
      ("lossless", "every stored coordinate back exactly (int16 C3D integers, float bits, "
       "TRC decimals)")
      ("codec", po::value(&codec), "transform stage in front of the coder: none (default: "
       "temporal prediction only), ts, pdct (when built in)")
      ("codec-opt", po::value(&codec_opts), "codec option key=value (repeatable; see docs/CLI.md)")
      ("clusters", po::value(&clusters), "clusters for the transform codec (0 = its default, -1 = search)")
      ("units", po::value(&units), "units of data that has none (PCD folders): mm, cm or m")
      ("window", po::value(&window), "frames per independently decodable window (1..8192, default 1024)")
      ("no-check", "skip decoding the output to verify it (faster)")
      ("force,f", "overwrite OUT if it exists")
      ("rm", "remove IN (a file) after a successful, verified compression")
      ("quiet,q", "print nothing but errors")
      ("verbose,v", "also print sizes per stream and timings");
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
  if (in.empty()) capz::fail(capz::ErrorCode::kUsage, "", "no input given (see capz compress --help)");
  const int targets = (vm.count("lossless") ? 1 : 0) + (vm.count("kg-error") ? 1 : 0) +
                      (vm.count("max-error") ? 1 : 0);
  if (targets > 1)
    capz::fail(capz::ErrorCode::kUsage, "", "give one of --max-error, --kg-error, --lossless");
  if (!units.empty() && capz::units_to_metres(units) == 0)
    capz::fail(capz::ErrorCode::kInvalidParameter, "", "--units: unknown unit '" + units + "'");
  const bool force = vm.count("force") != 0;
  if (out.empty()) out = strip_slashes(in) + ".capz";
  capz::check_output_free(out, force);
  if (vm.count("rm") && fs::is_directory(in))
    capz::fail(capz::ErrorCode::kUsage, in, "--rm removes files only, not PCD folders");

  auto t0 = std::chrono::steady_clock::now();
  capz::Take take = capz::read_take(in);
  const double t_read = seconds_since(t0);
  if (take.units.empty() && !units.empty()) take.units = units;

  capz::CompressOptions opts;
  opts.codec = codec;
  opts.clusters = clusters;
  opts.window_frames = window;
  opts.check = vm.count("no-check") == 0;
  for (const auto& kv : codec_opts) {
    auto eq = kv.find('=');
    if (eq == std::string::npos)
      capz::fail(capz::ErrorCode::kUsage, "", "--codec-opt wants key=value, got '" + kv + "'");
    opts.codec_options[kv.substr(0, eq)] = kv.substr(eq + 1);
  }
  std::string bound_text;
  if (vm.count("lossless")) {
    opts.lossless = true;
  } else if (vm.count("kg-error")) {
    if (!(kg > 0)) capz::fail(capz::ErrorCode::kInvalidParameter, "", "--kg-error must be > 0");
    opts.kg_error = kg;
  } else if (take.units.empty() && !vm.count("max-error")) {
    // Unitless data: 1e-4 of the bounding-box diagonal.
    double lo[3] = {1e308, 1e308, 1e308}, hi[3] = {-1e308, -1e308, -1e308};
    for (size_t i = 0; i < take.frames * take.points; ++i)
      if (take.valid[i])
        for (int a = 0; a < 3; ++a) {
          lo[a] = std::min(lo[a], take.xyz[i * 3 + a]);
          hi[a] = std::max(hi[a], take.xyz[i * 3 + a]);
        }
    double d2 = 0;
    for (int a = 0; a < 3; ++a) d2 += hi[a] > lo[a] ? (hi[a] - lo[a]) * (hi[a] - lo[a]) : 0;
    opts.max_error = d2 > 0 ? 1e-4 * std::sqrt(d2) : 1e-4;
  } else {
    opts.max_error = capz::parse_length(max_error, take.units);
    if (!(opts.max_error > 0))
      capz::fail(capz::ErrorCode::kInvalidParameter, "", "--max-error must be > 0 (or use --lossless)");
  }

  capz::CompressStats st;
  std::vector<uint8_t> bytes;
  auto t1 = std::chrono::steady_clock::now();
  {
    Progress progress("compress");
    opts.progress = [&](size_t d, size_t t) { progress(d, t); };
    bytes = capz::compress(take, opts, &st);
  }
  const double t_enc = seconds_since(t1);
  capz::AtomicFile f(out, force);
  f.write(bytes);
  f.commit();
  if (vm.count("rm")) {
    std::error_code ec;
    fs::remove(in, ec);
    if (ec) capz::fail(capz::ErrorCode::kIo, in, "could not remove after compressing: " + ec.message());
  }

  if (g_verbosity >= 1) {
    const uint64_t in_bytes = vm.count("rm") ? 0 : input_bytes(in);
    const std::string u = take.units.empty() ? "" : " " + take.units;
    std::string err;
    if (st.lossless) {
      err = "lossless (" + st.mode + ")";
    } else {
      err = "max error " + num(st.error.max_abs) + u + " per coordinate (" +
            num(st.error.max_error) + u + " Euclidean), KG " + num(st.error.kg_error) + "%";
    }
    std::printf("%s -> %s: %llu -> %zu bytes (ratio %s), %s bpvf, %s\n", in.c_str(), out.c_str(),
                static_cast<unsigned long long>(in_bytes), st.bytes,
                num(static_cast<double>(in_bytes) / static_cast<double>(st.bytes), 4).c_str(),
                num(st.bpvf, 4).c_str(), err.c_str());
  }
  if (g_verbosity >= 2) {
    std::printf("  %zu frames x %zu points, %s, grid step %s%s, %zu bytes: positions %zu, analog %zu, "
                "other %zu; raw float32 positions %zu bytes (x%s)\n",
                take.frames, take.points, st.mode.c_str(), num(st.step, 6).c_str(),
                take.units.empty() ? "" : (" " + take.units).c_str(), st.bytes, st.position_bytes,
                st.analog_bytes, st.other_bytes, st.raw_bytes,
                num(st.position_bytes ? static_cast<double>(st.raw_bytes) / st.position_bytes : 0).c_str());
    std::printf("  read %.3f s, encode%s %.3f s (%s MB/s of raw float32 positions)\n", t_read,
                opts.check ? "+check" : "", t_enc, num(st.raw_bytes / 1e6 / t_enc, 4).c_str());
  }
  return 0;
}

}  // namespace capz_cli

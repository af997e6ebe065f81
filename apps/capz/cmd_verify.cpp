// capz verify X.capz [--against ORIGINAL]
#include <boost/program_options.hpp>
#include <cstdio>
#include <iostream>

#include "capz/codec.h"
#include "capz/io.h"
#include "capz/metrics.h"
#include "compress_common.h"

namespace po = boost::program_options;

namespace capz_cli {

int cmd_verify(const Args& args) {
  std::string in, against;
  po::options_description o(
      "usage: capz verify X.capz [--against ORIGINAL]\n"
      "Decodes X.capz completely (every CRC and every window). With --against, compares it to\n"
      "the original and prints max error (per coordinate and Euclidean), RMSE, KG error and\n"
      "bpvf; exits 5 if the stated bound does not hold or the gap masks differ.\n\noptions");
  o.add_options()
      ("help,h", "show this help")
      ("against,a", po::value(&against), "the original .c3d, .trc or PCD folder")
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
  if (in.empty()) capz::fail(capz::ErrorCode::kUsage, "", "no input given (see capz verify --help)");

  std::vector<uint8_t> bytes = capz::read_file(in);
  auto t0 = std::chrono::steady_clock::now();
  capz::StreamInfo si = capz::describe(bytes.data(), bytes.size(), in);
  capz::Take b = capz::decompress(bytes.data(), bytes.size(), in);
  const double t_dec = seconds_since(t0);
  const double bp = capz::bpvf(bytes.size(), b.frames, b.points);
  if (against.empty()) {
    if (g_verbosity >= 1)
      std::printf("%s: ok, %zu frames x %zu points, %s bpvf, %s\n", in.c_str(), b.frames, b.points,
                  num(bp).c_str(), si.lossless ? "lossless" : ("bound " + num(si.max_error) + " " + si.units).c_str());
    return 0;
  }
  capz::Take a = capz::read_take(against);
  if (a.frames != b.frames || a.points != b.points)
    capz::fail(capz::ErrorCode::kCorrupt, in, "decodes to " + std::to_string(b.frames) + " x " +
                                                  std::to_string(b.points) + ", the original has " +
                                                  std::to_string(a.frames) + " x " + std::to_string(a.points));
  capz::ErrorStats e = capz::compare(a, b);
  const std::string u = a.units.empty() ? "" : " " + a.units;
  bool ok = e.mask_mismatches == 0;
  if (si.lossless) ok = ok && e.max_abs == 0;
  else if (si.max_error > 0) ok = ok && e.max_abs <= si.max_error;
  if (g_verbosity >= 1) {
    std::printf("%s vs %s: max error %s%s per coordinate (%s%s Euclidean), RMSE %s%s, KG %s%%, "
                "%s bpvf, gaps %s\n",
                in.c_str(), against.c_str(), num(e.max_abs).c_str(), u.c_str(),
                num(e.max_error).c_str(), u.c_str(), num(e.rmse).c_str(), u.c_str(),
                num(e.kg_error).c_str(), num(bp).c_str(),
                e.mask_mismatches ? (std::to_string(e.mask_mismatches) + " differ").c_str() : "identical");
    if (!ok)
      std::printf("FAILED: %s\n", e.mask_mismatches ? "gap masks differ"
                                                   : ("the bound " + num(si.max_error) + u + " does not hold").c_str());
  }
  if (g_verbosity >= 2) std::printf("  decode %.3f s\n", t_dec);
  return ok ? 0 : 5;
}

}  // namespace capz_cli

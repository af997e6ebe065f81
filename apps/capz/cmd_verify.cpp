// capz verify X.capz [--against ORIGINAL]
#include <cstdio>

#include "capz/codec.h"
#include "capz/file.h"
#include "capz/io.h"
#include "capz/metrics.h"
#include "capz/verify.h"
#include "compress_common.h"

namespace capz_cli {

int cmd_verify(const Args& args) {
  po::options_description o("verify options");
  o.add_options()("against,a", po::value<std::string>(), "the original .c3d, .trc or PCD folder")(
      "json", "print the report as one JSON object");
  add_memlimit_option(&o);
  po::variables_map vm;
  std::string in;
  if (!parse_single_input(
          args, "capz verify X.capz [--against ORIGINAL] [--json] [--memlimit SIZE]",
          "Decodes X.capz completely (every CRC, every window). With --against, compares\n"
          "the result with the original and prints the max error (per coordinate and\n"
          "Euclidean), RMSE, KG error and bpvf. Exit status 5 when the stream is damaged\n"
          "or does not keep its promise: the gap mask, every valid coordinate bit for bit\n"
          "(lossless), within the stored bound, or for a --kg-error transform stream within\n"
          "its KG target, and the metadata, analog values, rotations (bit for bit) and\n"
          "format extras exactly.",
          o, "X.capz", &vm, &in))
    return 0;

  capz::DecompressOptions dopts;
  dopts.memory_limit = memlimit(vm);
  std::vector<uint8_t> bytes = capz::read_file(in);
  const double c0 = cpu_seconds();
  capz::StreamInfo si = capz::describe(bytes.data(), bytes.size(), in);
  capz::Take b = capz::decompress(bytes.data(), bytes.size(), in, dopts);
  const double t_dec = cpu_seconds() - c0;
  const double bp = capz::bpvf(bytes.size(), b.frames, b.points);
  const std::string u = b.units.empty() ? "" : " " + b.units;
  const std::string bound = si.lossless           ? "lossless"
                            : si.transform_output ? "KG target " + num(si.kg_target) + "%"
                                                  : "bound " + num(si.max_error) + u;

  capz::ErrorStats e;
  double analog_use = 0;
  bool ok = true;
  std::string why;
  const bool against = vm.count("against") != 0;
  if (against) {
    const std::string orig = vm["against"].as<std::string>();
    capz::Take a = capz::read_take(orig);
    // Data without units (a PCD folder) took them from compress --units: not a difference.
    if (a.units.empty()) a.units = b.units;
    if (a.frames != b.frames || a.points != b.points)
      capz::fail(capz::ErrorCode::kCorrupt, in,
                 "decodes to " + std::to_string(b.frames) + " frames x " +
                     std::to_string(b.points) + " points, " + orig + " has " +
                     std::to_string(a.frames) + " x " + std::to_string(a.points));
    const capz::PromiseResult r = capz::check_promise(a, b, capz::promise_of(si));
    e = r.error;
    analog_use = r.analog_bound_use;
    ok = r.holds;
    why = r.why;
  }
  if (vm.count("json")) {
    Json j;
    j.begin_object();
    j.member("input", in);
    j.member("ok", ok);
    j.member("frames", static_cast<uint64_t>(b.frames));
    j.member("points", static_cast<uint64_t>(b.points));
    j.member("bytes", static_cast<uint64_t>(bytes.size()));
    j.member("bpvf", bp);
    j.member("lossless", si.lossless);
    j.member("bound", si.max_error);
    if (si.transform_output) j.member("kg_target", si.kg_target);
    if (against) {
      j.member("against", vm["against"].as<std::string>());
      json_error_stats(&j, e);
      if (!si.analog_bounds.empty()) j.member("analog_bound_use", analog_use);
      if (!ok) j.member("breach", why);
    }
    j.member("decode_cpu_seconds", t_dec);
    j.end_object();
    std::printf("%s\n", j.str().c_str());
  } else if (g_verbosity >= 1) {
    if (!against) {
      std::printf("%s: ok, %zu frames x %zu points, %s bpvf, %s\n", in.c_str(), b.frames, b.points,
                  num(bp).c_str(), bound.c_str());
    } else {
      std::printf(
          "%s: max error %s%s per coordinate (%s%s Euclidean), RMSE %s%s, KG %s%%, %s bpvf, "
          "gaps %s; %s %s\n",
          in.c_str(), num(e.max_abs).c_str(), u.c_str(), num(e.max_error).c_str(), u.c_str(),
          num(e.rmse).c_str(), u.c_str(), num(e.kg_error).c_str(), num(bp).c_str(),
          e.mask_mismatches ? (std::to_string(e.mask_mismatches) + " differ").c_str() : "identical",
          bound.c_str(), ok ? "holds" : ("DOES NOT HOLD: " + why).c_str());
      if (!si.analog_bounds.empty() && ok)
        std::printf(
            "  analog: the lossy channels within their bounds (largest error %s of its "
            "bound)\n",
            num(analog_use, 3).c_str());
    }
    if (g_verbosity >= 2) std::printf("  cpu: decode %.3f s\n", t_dec);
  }
  return ok ? 0 : 5;
}

}  // namespace capz_cli

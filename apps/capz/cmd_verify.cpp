// capz verify X.capz [--against ORIGINAL]
#include <algorithm>
#include <cstdio>
#include <memory>

#include "capz/codec.h"
#include "capz/io.h"
#include "capz/metrics.h"
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "capz/tool/verify.h"
#include "compress_common.h"

namespace capz_cli {

namespace {

// What the decoded take gave against the original (--against): the errors, the largest share of
// a lossy analog channel's bound used, whether the promise holds (why not), and the original's
// point fields that the archive does not hold.
struct Verdict {
  capz::ErrorStats e;
  double analog_use = 0;
  bool ok = true;
  std::string why;
  std::vector<std::string> dropped_fields;
};

// The names of the original's point fields when the archive holds none (their layouts are
// then taken out of *a). The encoder codes every field of a take or refuses it unless asked to
// leave them out (compress --drop-fields), so an archive without fields made from a take with
// fields was asked for that: not a difference. An archive with other fields than the original
// is one.
std::vector<std::string> drop_left_out_fields(capz::Take* a, const capz::Take& b) {
  std::vector<std::string> names;
  if (!b.attributes.empty()) return names;
  for (const capz::PointAttribute& f : a->attributes) names.push_back(f.name);
  a->attributes.clear();
  return names;
}

// The original's header *a against the archive's b: units taken from b where a has none or
// assumed ones (they came from compress --units, or none was stored: not a difference); throws
// kCorrupt when the shapes differ.
void match_original(const std::string& in, const std::string& orig, const capz::Take& b,
                    capz::Take* a) {
  if (a->units.empty() || a->units_assumed) a->units = b.units, a->units_assumed = false;
  if (!capz::same_frame_counts(*a, b)) {
    const std::string sa = shape_text(*a), sb = shape_text(b);
    capz::fail(capz::ErrorCode::kCorrupt, in,
               "decodes to " + sb + ", " + orig + " has " + sa +
                   (sa == sb ? " (the frames' point counts differ)" : ""));
  }
}

// The archive decoded window by window (every chunk's CRC, every window), and with `orig` the
// original read a block of the same frames at a time beside it, checked by the library's rule
// (PromiseCheck): memory is bounded by the archive's window, not by the take. *t_dec: the CPU
// seconds of decoding are added to it.
Verdict check_stream(const std::string& in, const std::string& orig, capz::FrameSource& dec,
                     const capz::StreamInfo& si, double* t_dec) {
  Verdict v;
  const capz::Take& b = dec.header();
  std::unique_ptr<capz::FrameSource> src;
  capz::Take a;
  if (!orig.empty()) {
    // A .bin original in the record the archive holds (a declared one).
    const bool bin = capz::detect_format(orig) == capz::Format::kBinFolder;
    src = capz::open_frames(orig, bin ? capz::read_options_of(b) : capz::ReadOptions());
    a = src->header();
    match_original(in, orig, b, &a);
    v.dropped_fields = drop_left_out_fields(&a, b);
  }
  capz::PromiseCheck check(capz::promise_of(si));
  if (src) check.header(a, b);
  const size_t block = std::max<size_t>(1, dec.preferred_block());
  capz::FrameBlock x, y;
  for (size_t f = 0; f < b.frames; f += block) {
    const double c0 = cpu_seconds();
    dec.read(f, block, &y);
    *t_dec += cpu_seconds() - c0;
    if (!src) continue;
    src->read(f, block, &x);
    if (!v.dropped_fields.empty()) x.attributes.clear();
    check.frames(x, y);
  }
  if (!src) return v;
  check.finish();
  v.e = check.error();
  v.analog_use = check.analog_bound_use();
  v.ok = check.holds();
  v.why = check.why();
  return v;
}

// What the command prints: one JSON object, or a line (and more with -v).
struct Report {
  std::string in;
  bool has_against = false;  // --against ORIGINAL given
  std::string against;
  const capz::StreamInfo* si = nullptr;
  const capz::Take* b = nullptr;
  size_t bytes = 0;
  double bpvf = 0, t_dec = 0;
  Verdict v;
  capz::OriginalInfo original;  // rebuilt (original.exact): --against a lossless archive
};

void print_json(const Report& r) {
  const capz::StreamInfo& si = *r.si;
  Json j;
  j.begin_object();
  j.member("input", r.in);
  j.member("ok", r.v.ok);
  j.member("frames", static_cast<uint64_t>(r.b->frames));
  j.member("points", static_cast<uint64_t>(r.b->points));
  j.member("total_points", static_cast<uint64_t>(r.b->total_points()));
  j.member("bytes", static_cast<uint64_t>(r.bytes));
  j.member("bpvf", r.bpvf);
  j.member("lossless", si.lossless);
  j.member("bound", si.max_error);
  if (si.transform_output) j.member("kg_target", si.kg_target);
  if (r.has_against) {
    j.member("against", r.against);
    json_error_stats(&j, r.v.e);
    if (!si.analog_bounds.empty()) j.member("analog_bound_use", r.v.analog_use);
    if (!r.v.ok) j.member("breach", r.v.why);
    j.member_strings("dropped_fields", r.v.dropped_fields);
    j.member("original_rebuilt", r.original.exact);
  }
  j.member("decode_cpu_seconds", r.t_dec);
  j.end_object();
  std::printf("%s\n", j.str().c_str());
}

void print_text(const Report& r) {
  const capz::StreamInfo& si = *r.si;
  const capz::Take& b = *r.b;
  const capz::ErrorStats& e = r.v.e;
  bool assumed = false;  // metres for PCD, PLY and .bin frames stored without units
  const std::string units = archive_units(b.format, b.units, &assumed);
  const std::string u = units.empty() ? "" : " " + units;
  const std::string bound = si.lossless           ? "lossless"
                            : si.transform_output ? "KG target " + num(si.kg_target) + "%"
                                                  : "bound " + num(si.max_error) + u;
  if (!r.has_against) {
    std::printf("%s: ok, %s, %s bpvf, %s\n", r.in.c_str(), shape_text(b).c_str(),
                num(r.bpvf).c_str(), bound.c_str());
  } else {
    std::printf(
        "%s: max error %s%s per coordinate (%s%s Euclidean), RMSE %s%s, KG %s%%, %s bpvf, "
        "gaps %s; %s %s\n",
        r.in.c_str(), num(e.max_abs).c_str(), u.c_str(), num(e.max_error).c_str(), u.c_str(),
        num(e.rmse).c_str(), u.c_str(), num(e.kg_error).c_str(), num(r.bpvf).c_str(),
        e.mask_mismatches ? (std::to_string(e.mask_mismatches) + " differ").c_str() : "identical",
        bound.c_str(), r.v.ok ? "holds" : ("DOES NOT HOLD: " + r.v.why).c_str());
    if (!si.analog_bounds.empty() && r.v.ok)
      std::printf(
          "  analog: the lossy channels within their bounds (largest error %s of its "
          "bound)\n",
          num(r.v.analog_use, 3).c_str());
    if (r.original.exact)
      std::printf("  original: rebuilt from the residue, %s bytes, xxh3-128 %s as recorded\n",
                  std::to_string(r.original.size).c_str(), r.original.hash_hex.c_str());
    if (!r.v.dropped_fields.empty()) {
      std::string names;
      for (const std::string& n : r.v.dropped_fields) names += (names.empty() ? "" : " ") + n;
      std::printf(
          "  fields: %s not in the archive (left out by compress --drop-fields), not compared\n",
          names.c_str());
    }
  }
  if (g_verbosity >= 2) std::printf("  cpu: decode %.3f s\n", r.t_dec);
}

}  // namespace

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
          "format extras exactly; for a lossless archive with its original's checksum, the\n"
          "original's bytes rebuilt from the residue, their size and hash checked, as test\n"
          "does, and that hash the --against file's own. Point fields that the archive does\n"
          "not hold (compress --drop-fields) are named and not compared.",
          o, "X.capz", &vm, &in))
    return 0;

  capz::DecompressOptions dopts;
  dopts.memory_limit = memlimit(vm);
  const double c0 = cpu_seconds();
  const capz::StreamInfo si = capz::describe_file(in);
  Report r;
  r.in = in;
  r.si = &si;
  r.bytes = static_cast<size_t>(path_size(in));
  r.bpvf = capz::bpvf(r.bytes, 1, si.total_points);  // frames x points, or ragged
  if (vm.count("against")) {
    r.has_against = true;
    r.against = vm["against"].as<std::string>();
  }
  // Window by window: memory bounded by the archive's window, not by the take (an archive of
  // one frame decodes in the shape a reader gives one frame file: capz_source.h).
  std::unique_ptr<capz::FrameSource> dec = capz::open_capz_frames(in, dopts);
  r.t_dec = cpu_seconds() - c0;
  r.b = &dec->header();
  r.v = check_stream(in, r.against, *dec, si, &r.t_dec);
  if (r.has_against && r.v.ok) {  // a lossless archive: the original's bytes too, as test does,
    r.original = capz::original_info(in);  // and they are the --against file's
    const double c1 = cpu_seconds();
    const std::string differs =
        r.original.exact ? capz::rebuilds_file(in, r.against, dopts) : std::string();
    if (!differs.empty()) r.v.ok = false, r.v.why = r.against + ": " + differs;
    r.t_dec += cpu_seconds() - c1;
  }
  if (vm.count("json"))
    print_json(r);
  else if (g_verbosity >= 1)
    print_text(r);
  return r.v.ok ? 0 : 5;
}

}  // namespace capz_cli

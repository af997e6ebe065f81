// capz test FILE.capz... and capz list FILE.capz... (-r, -T, --report): checking and listing
// archives.
#include <algorithm>
#include <cstdio>
#include <memory>

#include "batch.h"
#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "capz/tool/original.h"
#include "compress_common.h"

namespace capz_cli {

namespace {

// Parses a command whose positionals are one or more archives (folders with -r) into jobs.
// With `limit`, also --memlimit, the decoder's memory limit, into *limit.
bool parse_archives(const Args& args, const std::string& usage, const std::string& description,
                    BatchSettings* settings, std::vector<Job>* jobs, uint64_t* limit = nullptr) {
  po::options_description o("options");
  add_batch_options(&o, false, "");
  if (limit) add_memlimit_option(&o);
  po::variables_map vm;
  std::vector<std::string> inputs;
  if (!parse_inputs(args, usage, description, o, "FILE.capz", false, &vm, &inputs)) return false;
  if (std::find(inputs.begin(), inputs.end(), "-") != inputs.end())
    throw po::error("archives are read from files, not from stdin ('-')");
  if (limit) *limit = memlimit(vm);
  *settings = batch_settings(vm, false);
  *jobs = expand_inputs(inputs, InputKind::kArchives, *settings);
  return true;
}

// The archive's size, bound and the original's checksum, for --report.
void describe_record(const std::string& path, const std::vector<uint8_t>& bytes, FileRecord* r) {
  const capz::StreamInfo s = capz::describe(bytes.data(), bytes.size(), path);
  const capz::OriginalInfo o = capz::original_info(path);
  r->bytes_in = bytes.size();
  r->lossless = s.lossless;
  r->bound = s.lossless ? 0 : s.transform_output ? FileRecord::kNone : s.max_error;
  r->units = s.units;
  if (o.hashed) {
    r->checksum = o.hash_hex;
    r->bytes_out = o.size;
    if (bytes.size() > 0)
      r->ratio = static_cast<double>(o.size) / static_cast<double>(bytes.size());
  }
}

// Decodes every window (every CRC and chunk checked) and, where the archive is exact, rebuilds
// the original in memory-bounded passes checking its size and hash (at a bound, where the
// archive can rebuild a C3D, its size). Returns the line to print.
std::string test_one(const std::string& path, const capz::DecompressOptions& opts) {
  std::unique_ptr<capz::FrameSource> src = capz::open_capz_frames(path, opts);
  const size_t F = src->header().frames, B = src->preferred_block();
  capz::FrameBlock block;
  for (size_t f0 = 0; f0 < F; f0 += B) src->read(f0, B, &block);
  const bool c3d = src->header().format == capz::Format::kC3D;
  src.reset();
  const capz::OriginalInfo info = capz::original_info(path);
  std::string line = path + ": OK, " + std::to_string(F) + " frames decoded";
  if (info.exact) {
    capz::test_original(path, opts);
    line += ", original rebuilt (" + std::to_string(info.size) + " bytes, xxh3-128 " +
            info.hash_hex + ")";
  } else if (capz::can_rebuild(info, c3d)) {
    capz::test_original(path, opts);  // at a bound: the original's head and tail around regenerated
                                      // frames, its size checked
    line += ", not lossless: original rebuilt at the bound (" + std::to_string(info.size) +
            " bytes, size checked)";
  } else if (info.hashed) {
    line += ", not lossless: original bytes not rebuilt";
  }
  return line;
}

}  // namespace

int cmd_test(const Args& args) {
  BatchSettings settings;
  std::vector<Job> jobs;
  capz::DecompressOptions opts;
  if (!parse_archives(args,
                      "capz test FILE.capz... [-r] [-T N] [--report FILE.jsonl] [--memlimit SIZE]",
                      "Decodes every archive (every chunk and CRC checked) and, where it is\n"
                      "lossless with a checksum, rebuilds the original bytes and checks their\n"
                      "size and hash. Writes nothing; one line per file; exit status 1 on any\n"
                      "fault. -r walks folders for .capz files.",
                      &settings, &jobs, &opts.memory_limit))
    return 0;
  return run_batch(
      "test", settings, std::move(jobs),
      [&settings, &opts](const Job& job) {
        FileRecord r;
        r.text = test_one(job.input, opts) + "\n";
        if (!settings.report.empty()) describe_record(job.input, capz::read_file(job.input), &r);
        return r;
      },
      true);
}

int cmd_list(const Args& args) {
  BatchSettings settings;
  std::vector<Job> jobs;
  if (!parse_archives(args, "capz list FILE.capz... [-r] [-T N] [--report FILE.jsonl]",
                      "One line per archive: source name and format, frames, points, analog\n"
                      "channels, mode and bound, ratio (archive / original size, when the\n"
                      "archive records it) and the original's XXH3-128 ('-' when it has none).\n"
                      "-r walks folders for .capz files.",
                      &settings, &jobs))
    return 0;
  return run_batch(
      "list", settings, std::move(jobs),
      [](const Job& job) {
        FileRecord r;
        const std::string& f = job.input;
        const std::vector<uint8_t> bytes = capz::read_file(f);
        const capz::StreamInfo s = capz::describe(bytes.data(), bytes.size(), f);
        const capz::OriginalInfo o = capz::original_info(f);
        describe_record(f, bytes, &r);
        const std::string bound = s.lossless           ? "lossless"
                                  : s.transform_output ? "kg " + number(s.kg_target) + "%"
                                                       : "max-error " + number(s.max_error);
        char ratio[32] = "-";
        if (o.hashed && o.size > 0)
          std::snprintf(ratio, sizeof ratio, "%.4f",
                        static_cast<double>(bytes.size()) / static_cast<double>(o.size));
        // Frames of their own counts: the points of all frames, as info says them.
        const std::string points =
            s.ragged ? std::to_string(s.total_points) + " in all" : std::to_string(s.points);
        r.text =
            strprintf("%s: %s (%s) frames %zu points %s analog %d %s %s ratio %s xxh3-128 %s\n",
                      f.c_str(), s.source_name.c_str(), capz::format_name(s.source_format),
                      s.frames, points.c_str(), s.analog_channels, s.mode.c_str(), bound.c_str(),
                      ratio, o.hashed ? o.hash_hex.c_str() : "-");
        return r;
      },
      true);
}

}  // namespace capz_cli

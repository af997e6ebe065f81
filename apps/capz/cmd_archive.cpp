// capz test FILE.capz... and capz list FILE.capz...: checking and listing archives.
#include <cstdio>
#include <memory>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/io.h"
#include "capz/original.h"
#include "capz/stream.h"
#include "compress_common.h"

namespace capz_cli {

namespace {

// Parses a command whose positionals are one or more archives.
bool parse_archives(const Args& args, const std::string& usage, const std::string& description,
                    std::vector<std::string>* files) {
  po::options_description o("options");
  po::options_description positionals;
  positionals.add_options()("input", po::value<std::vector<std::string>>(), "FILE.capz");
  po::positional_options_description pos;
  pos.add("input", -1);
  po::variables_map vm;
  if (!parse_args(args, usage, description, o, positionals, pos, &vm)) return false;
  if (!vm.count("input")) throw po::error("missing FILE.capz");
  *files = vm["input"].as<std::vector<std::string>>();
  return true;
}

// Decodes every window (every CRC and chunk checked) and, where the archive is exact, rebuilds
// the original in memory-bounded passes checking its size and hash (at a bound, where the
// archive can rebuild a C3D, its size). Returns the line to print.
std::string test_one(const std::string& path) {
  std::unique_ptr<capz::FrameSource> src = capz::open_capz_frames(path);
  const size_t F = src->header().frames, B = src->preferred_block();
  capz::FrameBlock block;
  for (size_t f0 = 0; f0 < F; f0 += B) src->read(f0, B, &block);
  const bool c3d = src->header().format == capz::Format::kC3D;
  src.reset();
  const capz::OriginalInfo info = capz::original_info(path);
  std::string line = path + ": OK, " + std::to_string(F) + " frames decoded";
  if (info.exact) {
    capz::test_original(path);
    line += ", original rebuilt (" + std::to_string(info.size) + " bytes, xxh3-128 " +
            info.hash_hex + ")";
  } else if (capz::can_rebuild(info, c3d)) {
    capz::test_original(path);  // at a bound: the original's head and tail around regenerated
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
  std::vector<std::string> files;
  if (!parse_archives(args, "capz test FILE.capz...",
                      "Decodes every archive (every chunk and CRC checked) and, where it is\n"
                      "lossless with a checksum, rebuilds the original bytes and checks their\n"
                      "size and hash. Writes nothing; one line per file; exit status 1 on any\n"
                      "fault.",
                      &files))
    return 0;
  int faults = 0;
  for (const std::string& f : files) {
    try {
      std::printf("%s\n", test_one(f).c_str());
    } catch (const capz::Error& e) {
      std::printf("%s: FAILED: %s\n", f.c_str(), e.what());
      ++faults;
    }
  }
  return faults ? 1 : 0;
}

int cmd_list(const Args& args) {
  std::vector<std::string> files;
  if (!parse_archives(args, "capz list FILE.capz...",
                      "One line per archive: source name and format, frames, points, analog\n"
                      "channels, mode and bound, ratio (archive / original size, when the\n"
                      "archive records it) and the original's XXH3-128 ('-' when it has none).",
                      &files))
    return 0;
  int faults = 0;
  for (const std::string& f : files) {
    try {
      const std::vector<uint8_t> bytes = capz::read_file(f);
      const capz::StreamInfo s = capz::describe(bytes.data(), bytes.size(), f);
      const capz::OriginalInfo o = capz::original_info(f);
      const std::string bound = s.lossless           ? "lossless"
                                : s.transform_output ? "kg " + number(s.kg_target) + "%"
                                                     : "max-error " + number(s.max_error);
      char ratio[32] = "-";
      if (o.hashed && o.size > 0)
        std::snprintf(ratio, sizeof ratio, "%.4f",
                      static_cast<double>(bytes.size()) / static_cast<double>(o.size));
      std::printf("%s: %s (%s) frames %zu points %zu analog %d %s %s ratio %s xxh3-128 %s\n",
                  f.c_str(), s.source_name.c_str(), capz::format_name(s.source_format), s.frames,
                  s.points, s.analog_channels, s.mode.c_str(), bound.c_str(), ratio,
                  o.hashed ? o.hash_hex.c_str() : "-");
    } catch (const capz::Error& e) {
      std::printf("%s: FAILED: %s\n", f.c_str(), e.what());
      ++faults;
    }
  }
  return faults ? 1 : 0;
}

}  // namespace capz_cli

#include <boost/program_options/errors.hpp>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>
#if defined(__GLIBC__)  // set by any libc header above
#include <malloc.h>
#endif

#include "capz/error.h"
#include "capz/tool/file.h"
#include "capz/version.h"
#include "cli_util.h"
#include "commands.h"

namespace capz_cli {
int g_verbosity = 1;
}

namespace {

struct Command {
  const char* name;
  int (*run)(const capz_cli::Args&);
  const char* summary;
};

const Command kCommands[] = {
    {"compress", capz_cli::cmd_compress, "compress a .c3d, .trc or PCD folder to .capz"},
    {"decompress", capz_cli::cmd_decompress, "decompress a .capz to .c3d, .trc or a PCD folder"},
    {"info", capz_cli::cmd_info, "describe a .c3d, .trc, PCD folder or .capz"},
    {"convert", capz_cli::cmd_convert, "convert between .c3d, .trc and PCD folders"},
    {"verify", capz_cli::cmd_verify, "decode a .capz and report its error against the original"},
    {"test", capz_cli::cmd_test, "check .capz archives: every chunk, CRC and the original's hash"},
    {"list", capz_cli::cmd_list, "one line per .capz: source, frames, points, mode, ratio, hash"},
};

void usage(std::FILE* out) {
  std::fprintf(out,
               "capz — compressor for motion-capture takes and point-cloud sequences\n\n"
               "usage: capz <command> [options]   (capz <command> --help for its options)\n\n"
               "commands:\n");
  for (const auto& c : kCommands) std::fprintf(out, "  %-11s %s\n", c.name, c.summary);
  std::fprintf(out,
               "\nexit status: 0 ok, 1 usage, 2 io, 3 not our format, 4 unsupported version,\n"
               "5 corrupt input, 6 invalid parameter, 7 internal error, 8 memory limit\n"
               "(see docs/CLI.md)\n");
}

}  // namespace

int main(int argc, char** argv) {
  // First, before any thread: an interrupted run leaves no temporary behind (docs/CLI.md).
  capz::remove_temporaries_on_signals();
#if defined(__GLIBC__)
  // Each window allocates and frees the same few large buffers. By default glibc serves those
  // with mmap and returns them on free, so every window pays fresh page faults (about a sixth
  // of the CPU time of compressing AlbertoREAL.c3d). Keeping up to 64 MiB of freed heap for
  // reuse removes that; memory stays bounded by the window.
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 64 << 20);
#endif
  if (argc < 2) {
    usage(stderr);
    return 1;
  }
  std::string name = argv[1];
  if (name == "-h" || name == "--help" || name == "help") {
    usage(stdout);
    return 0;
  }
  if (name == "--version" || name == "-V") {
    std::printf(
        "capz %s, writes format %d.%d (%d.%d for ragged frames and PLY or .bin sources), reads "
        "%d.%d\n",
        capz::version_string(), capz::kFormatWritten.major, capz::kFormatWritten.minor,
        capz::kFormatScans.major, capz::kFormatScans.minor, capz::kFormatNewestRead.major,
        capz::kFormatNewestRead.minor);
    return 0;
  }
  capz_cli::Args args(argv + 2, argv + argc);
  for (const auto& c : kCommands) {
    if (name != c.name) continue;
    try {
      return c.run(args);
    } catch (const capz::Error& e) {
      std::fprintf(stderr, "capz %s: error: %s\n", c.name, capz_cli::printable(e.what()).c_str());
      return static_cast<int>(e.code());
    } catch (const boost::program_options::error& e) {
      std::fprintf(stderr, "capz %s: error: %s (see capz %s --help)\n", c.name, e.what(), c.name);
      return 1;
    } catch (const std::bad_alloc&) {
      std::fprintf(stderr, "capz %s: error: out of memory\n", c.name);
      return 7;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "capz %s: internal error: %s\n", c.name,
                   capz_cli::printable(e.what()).c_str());
      return 7;
    }
  }
  std::fprintf(stderr, "capz: unknown command '%s'\n\n", name.c_str());
  usage(stderr);
  return 1;
}

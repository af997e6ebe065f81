// capz_rotation_takes OUTDIR
// Writes the rotation takes of issue #38 (item 2) to OUTDIR, deterministically, with the C3D
// writer of tests/support/rotation_c3d.h (not capz's): the benchmark's inputs
// (docs/BENCHMARKS.md) and the same files tests/roundtrip/test_rotation_takes.cpp builds.
#include <cstdio>
#include <string>

#include "capz/error.h"
#include "capz/file.h"
#include "support/rotation_c3d.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: capz_rotation_takes OUTDIR\n");
    return 1;
  }
  try {
    for (const capz_test::NamedRotationTake& t : capz_test::rotation_takes()) {
      const std::string path = std::string(argv[1]) + "/" + t.name + ".c3d";
      capz::write_file(path, capz_test::make_rotation_c3d(t.spec), true);
      std::printf("%s\n", path.c_str());
    }
  } catch (const capz::Error& e) {
    std::fprintf(stderr, "capz_rotation_takes: %s\n", e.what());
    return 1;
  }
  return 0;
}

// Issue 14 conformance: every shared C3D capz reads comes back byte for byte from its Take as a
// --lossless .capz gives it back plus the residue (src/io/residue/). Each file is listed with
// its result and residue size; a file the reader refuses is listed as such (not a failure: the
// C3D conformance test holds the list of refused files).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/stream.h"
#include "core/hash.h"
#include "core/input_file.h"
#include "io/residue/c3d_residue.h"
#include "io/residue/trc_residue.h"
#include "test_util.h"

using namespace capz;
namespace fs = std::filesystem;

namespace {

const std::string kC3DRoot = std::string(CAPZ_SHARED_DATA) + "/c3d";
const std::string kDataRoot = std::string(CAPZ_SHARED_DATA);

std::vector<std::string> files_with(const std::string& root, const std::string& ext) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    std::string x = e.path().extension().string();
    std::transform(x.begin(), x.end(), x.begin(), ::tolower);
    if (e.is_regular_file() && x == ext) out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

struct Result {
  bool exact = false;
  size_t residue = 0, windows = 0;
};

// Residue from the file and its frames as read; rebuild from the frames a --lossless .capz gives
// back, in windows of `block` frames; exact when the rebuilt bytes hash as the original.
Result round_trip(const std::string& path, bool trc, const std::string& capz_path, size_t block) {
  Result r;
  auto src = trc ? open_trc_frames(path) : open_c3d_frames(path);
  const residue::FileResidue res = trc ? residue::encode_trc_residue(path, *src, block)
                                       : residue::encode_c3d_residue(path, *src, block);
  r.residue = res.bytes();
  r.windows = r.residue - res.file_part.size();
  CompressOptions opts;
  opts.lossless = true;
  compress_stream(*src, opts, capz_path, true);
  auto back = open_capz_frames(capz_path);
  Hasher h;
  auto write = [&](const uint8_t* p, size_t n) { h.update(p, n); };
  if (trc)
    residue::rebuild_trc(res, *back, block, write, path, InputFile(path).size());
  else
    residue::rebuild_c3d(res, *back, block, write, path, InputFile(path).size());
  r.exact = h.digest() == hash128_file(path);
  return r;
}

// Lists every file of `ext` under `root` with its result; returns the number the reader refused.
size_t check_all(const std::string& root, const std::string& ext, bool trc) {
  capz_test::TempDir dir("capz_residue_conf");
  size_t exact = 0, refused = 0;
  std::vector<std::string> files = files_with(root, ext);
  EXPECT_FALSE(files.empty());
  for (const auto& path : files) {
    const std::string name = fs::relative(path, root).generic_string();
    std::unique_ptr<FrameSource> probe;
    try {
      probe = trc ? open_trc_frames(path) : open_c3d_frames(path);  // the reader's verdict
    } catch (const Error& e) {
      std::printf("  %-66s refused by the reader: %s\n", name.c_str(), e.what());
      ++refused;
      continue;
    }
    Result r = round_trip(path, trc, dir.file("probe.capz"), 256);
    std::printf("  %-66s %s  residue %zu bytes (windows %zu)\n", name.c_str(),
                r.exact ? "exact" : "DIFFERS", r.residue, r.windows);
    EXPECT_TRUE(r.exact) << name;
    // Patches would make any regeneration exact; these need none: one trial in every processor
    // form and storage, regenerated right byte for byte.
    if (name.rfind("c3dorg/sample_01/", 0) == 0 || name.rfind("c3dorg/sample_02/", 0) == 0) {
      EXPECT_EQ(r.windows, 0u) << name;
    }
    exact += r.exact;
  }
  std::printf("  %zu files: %zu exact, %zu refused by the reader\n", files.size(), exact, refused);
  return refused;
}

}  // namespace

TEST(ResidueConformance, EveryReadableSharedC3DRebuildsByteForByte) {
  if (!fs::is_directory(kC3DRoot)) GTEST_SKIP() << "shared C3D data not found at " << kC3DRoot;
  // Empty.c3d (0 bytes) and simple.c3d (processor type 0) are refused by the reader.
  EXPECT_LE(check_all(kC3DRoot, ".c3d", false), 2u);
}

TEST(ResidueConformance, EveryReadableSharedTRCRebuildsByteForByte) {
  if (!fs::is_directory(kDataRoot + "/trc"))
    GTEST_SKIP() << "shared TRC data not found at " << kDataRoot << "/trc";
  // btkdata's Empty.trc (0 bytes) and Truncated.trc (no header values) are refused.
  EXPECT_LE(check_all(kDataRoot, ".trc", true), 2u);
}

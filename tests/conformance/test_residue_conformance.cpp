// Issue 14 conformance: every shared C3D and TRC capz reads, compressed --lossless from its path,
// comes back byte for byte from the .capz alone (docs/FORMAT.md 7, 14). Each file is listed with
// its result and residue size; a file the reader refuses is listed as such (not a failure: the
// C3D conformance test holds the list of refused files). At a bound, every C3D comes back with
// everything but its coordinates exact (issue 14 item 3).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/file.h"
#include "capz/io.h"
#include "capz/original.h"
#include "capz/stream.h"
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
  size_t residue = 0, windows = 0, archive = 0;
};

// The wired path (FORMAT.md 7, 14): the file compressed --lossless from its path (HASH, C3DR/TRCR,
// C3DP/TRCP written, the encoder's self-check on), the original rebuilt from the .capz alone by
// rebuild_original (size and hash checked), then compared with the file byte for byte.
Result round_trip(const std::string& path, bool trc, const std::string& capz_path,
                  const std::string& out_path) {
  Result r;
  {
    auto src = trc ? open_trc_frames(path) : open_c3d_frames(path);
    CompressOptions opts;
    opts.lossless = true;
    compress_stream(*src, opts, capz_path, true);
  }
  const std::vector<uint8_t> z = read_file(capz_path);
  const StreamInfo info = describe(z.data(), z.size(), capz_path);
  auto bytes = [&](const char* t) {
    auto it = info.chunk_bytes.find(t);
    return it == info.chunk_bytes.end() ? size_t{0} : it->second;
  };
  r.windows = bytes("C3DP") + bytes("TRCP");
  r.residue = bytes("HASH") + bytes("C3DR") + bytes("TRCR") + r.windows;
  r.archive = z.size();
  rebuild_original(capz_path, out_path, true);
  r.exact = read_file(out_path) == read_file(path);
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
    Result r;
    try {
      r = round_trip(path, trc, dir.file("probe.capz"), dir.file(trc ? "out.trc" : "out.c3d"));
    } catch (const Error& e) {
      ADD_FAILURE() << name << ": " << e.what();
      continue;
    }
    std::printf("  %-66s %s  exactness %zu of %zu bytes (%.3f%%; windows %zu)\n", name.c_str(),
                r.exact ? "exact" : "DIFFERS", r.residue, r.archive,
                100.0 * static_cast<double>(r.residue) / static_cast<double>(r.archive), r.windows);
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

// Reads the C3D or TRC at `path` into *orig, archives it at 0.1 mm in its units (a bare 0.1,
// file units, where they are unknown) through its frame source into z, rebuilds the original
// into `out` (its size checked) and reads that into *back. False when the reader refuses the
// file (the lossless test lists those) or, with a failure added, when a step throws.
bool archive_and_rebuild(const std::string& path, const std::string& name, bool c3d,
                         const std::string& z, const std::string& out, Take* orig, Take* back,
                         CompressOptions* opts) {
  try {
    *orig = read_take(path);
  } catch (const Error&) {
    return false;
  }
  opts->max_error = units_to_metres(orig->units) > 0 ? parse_length("0.1mm", orig->units) : 0.1;
  try {
    auto src = c3d ? open_c3d_frames(path) : open_trc_frames(path);
    compress_stream(*src, *opts, z, true);
    EXPECT_TRUE(can_rebuild(original_info(z), c3d)) << name;
    rebuild_original(z, out, true);
    *back = read_take(out);
  } catch (const Error& e) {
    ADD_FAILURE() << name << ": " << e.what();
    return false;
  }
  return true;
}

// Issue 14 item 3: a C3D archived at a bound and rebuilt (what `capz decompress` writes) reads
// back with the same shape, parameters, analog samples, 4th words, gaps and rotations, and its
// coordinates within the bound (plus the float32 rounding of float files). Returns the number of
// files checked.
size_t check_bounded_c3d() {
  capz_test::TempDir dir("capz_residue_bound");
  size_t checked = 0;
  for (const auto& path : files_with(kC3DRoot, ".c3d")) {
    const std::string name = fs::relative(path, kC3DRoot).generic_string();
    const std::string z = dir.file("b.capz"), out = dir.file("b.c3d");
    Take orig, back;
    CompressOptions opts;
    if (!archive_and_rebuild(path, name, true, z, out, &orig, &back, &opts)) continue;
    ++checked;
    if (back.frames != orig.frames || back.points != orig.points || !orig.c3d || !back.c3d ||
        back.c3d->groups.size() != orig.c3d->groups.size()) {
      ADD_FAILURE() << name << ": shape or parameter groups differ";
      continue;
    }
    EXPECT_EQ(back.valid, orig.valid) << name;
    EXPECT_EQ(back.c3d->residual, orig.c3d->residual) << name;
    EXPECT_EQ(back.c3d->camera_mask, orig.c3d->camera_mask) << name;
    // Its parameter section says 12 blocks from block 2, but the frames start at block 12: the
    // reader takes parameters from the first frames' bytes, whose coordinates a bound changes.
    const bool params_overlap_frames = name == "c3dorg/sample_18/bad_parameter_section.c3d";
    for (size_t g = 0; g < orig.c3d->groups.size() && !params_overlap_frames; ++g) {
      const C3DGroup &a = orig.c3d->groups[g], &b = back.c3d->groups[g];
      EXPECT_EQ(a.params.size(), b.params.size()) << name << " group " << a.name;
      for (size_t k = 0; k < std::min(a.params.size(), b.params.size()); ++k)
        EXPECT_EQ(a.params[k].data, b.params[k].data)
            << name << " " << a.name << ":" << a.params[k].name;
    }
    const bool same_analog =
        orig.analog.values.size() == back.analog.values.size() &&
        std::equal(orig.analog.values.begin(), orig.analog.values.end(), back.analog.values.begin(),
                   [](double x, double y) { return std::memcmp(&x, &y, sizeof x) == 0; });
    EXPECT_TRUE(same_analog) << name << ": analog samples differ";
    EXPECT_EQ(back.rotations.matrices, orig.rotations.matrices) << name;
    double worst = 0;
    for (size_t i = 0; i < orig.frames * orig.points; ++i) {
      if (!orig.valid[i]) continue;
      for (int a = 0; a < 3; ++a) {
        const double x = orig.xyz[3 * i + a], y = back.xyz[3 * i + a];
        const double room = orig.c3d->float_storage
                                ? std::fabs(static_cast<double>(std::nextafter(
                                                static_cast<float>(std::fabs(x)), INFINITY)) -
                                            std::fabs(static_cast<double>(static_cast<float>(x))))
                                : 0.0;
        EXPECT_LE(std::fabs(x - y), opts.max_error + room) << name << " sample " << i;
        worst = std::max(worst, std::fabs(x - y));
        if (std::fabs(x - y) > opts.max_error + room) break;
      }
    }
    std::printf("  %-66s bound %.4g: max error %.4g, all else exact\n", name.c_str(),
                opts.max_error, worst);
  }
  return checked;
}

// The same for TRC (5.0: TRCP at every target): the rebuilt file's header lines are the
// original's bytes, times, frame numbers and gaps read back the same, and every coordinate as
// printed is within the bound. Returns the number of files checked.
size_t check_bounded_trc() {
  capz_test::TempDir dir("capz_residue_bound_trc");
  size_t checked = 0;
  for (const auto& path : files_with(kDataRoot, ".trc")) {
    const std::string name = fs::relative(path, kDataRoot).generic_string();
    const std::string z = dir.file("b.capz"), out = dir.file("b.trc");
    Take orig, back;
    CompressOptions opts;
    if (!archive_and_rebuild(path, name, false, z, out, &orig, &back, &opts)) continue;
    ++checked;
    const std::vector<uint8_t> a = read_file(path), b = read_file(out);
    auto head = [](const std::vector<uint8_t>& t) {  // the five header lines
      size_t at = 0;
      for (int k = 0; k < 5 && at < t.size(); ++at)
        if (t[at] == '\n') ++k;
      return std::vector<uint8_t>(t.begin(), t.begin() + static_cast<long>(at));
    };
    EXPECT_EQ(head(a), head(b)) << name;
    if (back.frames != orig.frames || back.points != orig.points || !orig.trc || !back.trc) {
      ADD_FAILURE() << name << ": shape differs";
      continue;
    }
    EXPECT_EQ(back.valid, orig.valid) << name;
    EXPECT_EQ(back.trc->times, orig.trc->times) << name;
    EXPECT_EQ(back.trc->frame_numbers, orig.trc->frame_numbers) << name;
    double worst = 0;
    for (size_t i = 0; i < orig.xyz.size(); ++i)
      if (orig.valid[i / 3]) worst = std::max(worst, std::fabs(orig.xyz[i] - back.xyz[i]));
    EXPECT_LE(worst, opts.max_error) << name;
    std::printf("  %-66s bound %.4g: max error %.4g as printed, all else exact\n", name.c_str(),
                opts.max_error, worst);
  }
  return checked;
}
}  // namespace

TEST(ResidueConformance, EverySharedC3DAtABoundKeepsAllButItsCoordinates) {
  if (!fs::is_directory(kC3DRoot)) GTEST_SKIP() << "shared C3D data not found at " << kC3DRoot;
  EXPECT_GE(check_bounded_c3d(), 110u);
}

TEST(ResidueConformance, EverySharedTRCAtABoundKeepsAllButItsCoordinates) {
  if (!fs::is_directory(kDataRoot + "/trc"))
    GTEST_SKIP() << "shared TRC data not found at " << kDataRoot << "/trc";
  EXPECT_GE(check_bounded_trc(), 20u);
}

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

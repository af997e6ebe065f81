// Format 3.0's position coder on real files where its predictors and contexts matter
// (docs/BENCHMARKS.md, run 5): coarse bounds on smooth takes (the smooth predictor, the zero-run
// phase contexts, longer windows for few points) hold the bound and code smaller than the
// quantise + linear prediction + xz reference coder measured there. (The looped horse-gallop
// sequence, the period predictor's case, is in test_roundtrip.cpp's lossless cases.)
#include <gtest/gtest.h>

#include "capz/codec.h"
#include "capz/io.h"
#include "capz/metrics.h"
#include "test_util.h"

namespace capz {
namespace {

struct Coarse {
  const char* path;  // under the shared real data
  double mm;         // bound in millimetres
  size_t reference;  // the reference coder's bytes at that bound (docs/bench/results.csv)
};

TEST(Format3Real, GivenCoarseBoundsOnSmoothTakesThenWithinBoundAndUnderReferenceCoder) {
  const Coarse cases[] = {
      {"trc/opensim/constraintTest.trc", 3, 39508},
      {"c3d/c3dorg/sample_22/BKINtechnologies.c3d", 3, 1144},
      {"c3d/c3dorg/sample_00/NexGen Ergonomics/test1.c3d", 0.3, 1368},
  };
  for (const Coarse& c : cases) {
    SCOPED_TRACE(c.path);
    const std::string path = capz_test::shared_data_or_skip(c.path);
    if (path.empty()) return;  // skipped (no shared data) or failed (a file missing from it)
    Take t = read_take(path);
    CompressOptions o;
    o.max_error = parse_length(std::to_string(c.mm) + "mm", t.units);
    CompressStats st;
    std::vector<uint8_t> bytes = compress(t, o, &st);
    Take b = decompress(bytes.data(), bytes.size(), path);
    EXPECT_LE(compare(t, b).max_abs, o.max_error);
    // The benchmark compares positions and gap mask (POSW, MASK) plus HEAD (68 B), INDX (at
    // least 33 B) and the 11-byte magic: about 120 B more than position_bytes.
    EXPECT_LT(st.position_bytes + 120, c.reference);
  }
}

}  // namespace
}  // namespace capz

// FORMAT.md "Zero first": which of the scan block's 558 contexts code their values as plain
// hybrid tokens, which as zero-first flags, and which zero first (scan::value_kind), read
// from the format's lists.
#include <gtest/gtest.h>

#include "coding/scan_shared.h"

namespace capz {
namespace {

TEST(ScanValueKinds, GivenEveryContextThenTheKindFormatLists) {
  ASSERT_EQ(scan::kContexts, 558);
  const auto in = [](int c, int lo, int hi) { return c >= lo && c <= hi; };
  for (int c = 0; c < scan::kContexts; ++c) {
    scan::ValueKind want = scan::ValueKind::kZeroFirst;
    if (in(c, 12, 27) || in(c, 175, 198) || in(c, 124, 147) || in(c, 148, 150) || in(c, 153, 168))
      want = scan::ValueKind::kPlain;
    if (in(c, 0, 1) || in(c, 367, 518)) want = scan::ValueKind::kFlag;
    EXPECT_EQ(static_cast<int>(scan::value_kind(c)), static_cast<int>(want)) << "context " << c;
  }
}

}  // namespace
}  // namespace capz

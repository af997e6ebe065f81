// codec/scan_window_check.h: the scan encoder's self-check of each window, in place and beside
// the next window's coding (a worker thread). Both give the same measures; a window that does not
// come back as read throws the same error, beside at the next check or at finish().
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/metrics.h"
#include "capz/stream.h"
#include "codec/decoder.h"
#include "codec/scan_window_check.h"
#include "codec/stream_reader.h"
#include "synthetic.h"

namespace capz {
namespace {

struct Stream {
  Take t =
      capz_test::with_u2_field(capz_test::synthetic_sweeps(5, 150, 37, 5, 40, 3, 0.3, 7, 23, 5),
                               "ring", [](size_t i) { return i % 2 ? 0 : i / 2 % 16; });
  CompressOptions o;
  std::vector<uint8_t> bytes;
  Stream() {
    o.max_error = 0.001;
    o.window_frames = 2;  // three windows, the last of one frame
    bytes = compress(t, o);
  }
};

// Every window of s checked by a WindowChecks (beside or in place) against the frames as read,
// window `moved`'s first valid x moved by 1 m (none: SIZE_MAX). Returns the error's message, or
// empty; *acc gets the measures.
std::string check_all(const Stream& s, bool beside, size_t moved, ErrorAccumulator* acc) {
  MemoryBytes mb(s.bytes.data(), s.bytes.size());
  const ParsedStream ps = parse_stream(mb, "test");
  std::unique_ptr<FrameSource> src = take_frames(s.t);
  try {
    WindowChecks checks(s.t, ps, s.o.max_error, false, beside, acc);
    EXPECT_EQ(checks.beside(), beside);
    for (size_t w = 0; w * 2 < s.t.frames; ++w) {
      FrameBlock b;
      src->read(2 * w, std::min<size_t>(2, s.t.frames - 2 * w), &b);
      std::vector<std::vector<uint8_t>> fields = b.attributes;
      if (w == moved) {
        size_t i = 0;
        while (!b.valid[i]) ++i;
        b.xyz[3 * i] += 1.0;
      }
      size_t base = 0, end = 0;
      window_extent(ps, s.bytes.size(), w, &base, &end);
      checks.check(w, s.bytes.data() + base, end - base, base, &b, &fields);
    }
    checks.finish();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::kInternal);
    return e.what();
  }
  return std::string();
}

TEST(ScanWindowCheck, BesideTheNextWindowMeasuresAsInPlace) {
  const Stream s;
  ErrorAccumulator in_place, beside;
  EXPECT_EQ(check_all(s, false, SIZE_MAX, &in_place), "");
  EXPECT_EQ(check_all(s, true, SIZE_MAX, &beside), "");
  const ErrorStats a = in_place.finish(), b = beside.finish();
  EXPECT_GT(a.max_abs, 0.0);
  EXPECT_LE(a.max_abs, 0.001);
  EXPECT_EQ(std::memcmp(&a.max_abs, &b.max_abs, sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(&a.rmse, &b.rmse, sizeof(double)), 0);
}

TEST(ScanWindowCheck, AWindowNotAsReadThrowsTheSameErrorBesideAsInPlace) {
  const Stream s;
  for (size_t moved : {size_t{0}, size_t{2}}) {  // a check followed by another, and the last
    ErrorAccumulator a, b;
    const std::string in_place = check_all(s, false, moved, &a);
    EXPECT_NE(in_place.find("self-check: coordinate"), std::string::npos) << in_place;
    EXPECT_EQ(check_all(s, true, moved, &b), in_place);
  }
}

}  // namespace
}  // namespace capz

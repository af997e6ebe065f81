// Fuzz target: compress_stream, the windowed encoder behind `capz compress`. A take built from the
// fuzz bytes (fuzz_take.h says how) is read through an in-memory FrameSource and compressed to a
// scratch file. The file must hold exactly the bytes compress() makes of the whole take (the
// contract in capz/stream.h), and decode within the bound (fuzz_take.h's check_round_trip). When
// compress() refuses the options, compress_stream must refuse them with the same code and leave
// no file; kInvalidParameter (an impossible target) is the only refusal that is not a finding.
// With data[1] bit 3 (and no rotations or analog: bits 6, 7 clear) the take is a PCD folder's
// instead (no labels, metres assumed; organized 2 rows with bit 5 when its points are even), and
// bit 4 asks --point-order any: the encoder's choices between POSW and the scan coder for frames
// of one count (settled order, reordered frames, the lossless trial). Such a stream must then
// decode within the promise its description makes (capz verify's check: reordered frames as
// sets).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/stream.h"
#include "capz/tool/verify.h"
#include "core/atomic_file.h"
#include "fuzz_take.h"
#include "fuzz_temp_file.h"

namespace {

// The code compress() or compress_stream() throws, or -1 when it returns.
template <typename F>
int error_code_of(F&& f, std::string* what) {
  try {
    f();
  } catch (const capz::Error& e) {
    *what = e.what();
    return static_cast<int>(e.code());
  }
  return -1;
}

// The case's take as a PCD folder's frames (see the top of the file); false when it stays as it is.
bool as_frame_files(uint8_t b, capz_fuzz::RoundTripCase* c) {
  if ((b & 0xC0) || !(b & 0x08)) return false;
  capz::Take& t = c->take;
  t.format = capz::Format::kPCDFolder;
  t.source = "fuzz_frames";
  t.labels.clear();
  t.units = "m";
  t.units_assumed = true;
  t.pcd = std::make_shared<capz::PCDExtra>();
  t.pcd->fields = {{"x", 'F', 4, 1}, {"y", 'F', 4, 1}, {"z", 'F', 4, 1}};
  const bool organized = (b & 0x20) && t.points % 2 == 0;
  t.pcd->width = organized ? t.points / 2 : t.points;
  t.pcd->height = organized ? 2 : 1;
  for (size_t f = 0; f < t.frames; ++f) t.pcd->frame_names.push_back(std::to_string(f) + ".pcd");
  c->opts.any_point_order = (b & 0x10) != 0;
  return true;
}

// A frame-file case's stream decodes within the promise its description makes.
void check_promise_holds(const capz::Take& t, const std::vector<uint8_t>& bytes) {
  const capz::Take d = capz::decompress(bytes.data(), bytes.size(), "round trip");
  const capz::PromiseResult r =
      capz::check_promise(t, d, capz::promise_of(capz::describe(bytes.data(), bytes.size())));
  if (!r.holds) {
    std::fprintf(stderr, "the promise breaks: %s\n", r.why.c_str());
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const capz_fuzz::TempFile out("compress_stream");
  capz_fuzz::RoundTripCase c;
  if (!capz_fuzz::round_trip_case(data, size, &c)) return 0;
  const bool frame_files = as_frame_files(data[1], &c);
  out.remove();
  std::vector<uint8_t> whole;
  std::string whole_error, stream_error;
  const int whole_code =
      error_code_of([&] { whole = capz::compress(c.take, c.opts); }, &whole_error);
  std::unique_ptr<capz::FrameSource> src = capz::take_frames(c.take);
  const int stream_code =
      error_code_of([&] { capz::compress_stream(*src, c.opts, out.path(), true); }, &stream_error);
  if (whole_code != stream_code) {
    std::fprintf(stderr, "compress: %s\ncompress_stream: %s\n",
                 whole_code < 0 ? "ok" : whole_error.c_str(),
                 stream_code < 0 ? "ok" : stream_error.c_str());
    std::abort();
  }
  if (stream_code >= 0) {
    CAPZ_FUZZ_CHECK(!std::filesystem::exists(out.path()));
    if (stream_code == static_cast<int>(capz::ErrorCode::kInvalidParameter)) return 0;
    std::fprintf(stderr, "compress_stream failed: %s\n", stream_error.c_str());
    std::abort();
  }
  const std::vector<uint8_t> bytes = capz::read_file(out.path());
  if (bytes != whole) {
    std::fprintf(stderr, "compress_stream wrote %zu bytes, compress %zu (or other bytes)\n",
                 bytes.size(), whole.size());
    std::abort();
  }
  if (frame_files)
    check_promise_holds(c.take, bytes);
  else
    capz_fuzz::check_round_trip(c, bytes);
  return 0;
}

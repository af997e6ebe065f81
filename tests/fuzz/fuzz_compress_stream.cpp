// Fuzz target: compress_stream, the windowed encoder behind `capz compress`. A take built from the
// fuzz bytes (fuzz_take.h says how) is read through an in-memory FrameSource and compressed to a
// scratch file. The file must hold exactly the bytes compress() makes of the whole take (the
// contract in capz/stream.h), and decode within the bound (fuzz_take.h's check_round_trip). When
// compress() refuses the options, compress_stream must refuse them with the same code and leave
// no file; kInvalidParameter (an impossible target) is the only refusal that is not a finding.
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

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const capz_fuzz::TempFile out("compress_stream");
  capz_fuzz::RoundTripCase c;
  if (!capz_fuzz::round_trip_case(data, size, &c)) return 0;
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
  capz_fuzz::check_round_trip(c, bytes);
  return 0;
}

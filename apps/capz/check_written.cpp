// `capz compress --rm`: the written archive, read back from disk and decoded, against the input
// read again from disk, a block of frames at a time (memory bounded by the archive's window, as
// for compress itself), by the library's rule (capz/verify.h).
#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "capz/tool/verify.h"
#include "compress_common.h"

namespace capz_cli {

namespace {

// "" when OUT reproduces IN as OUT's header promises, else what differs first.
std::string written_difference(const std::string& out, const std::string& in,
                               const capz::Take& in_header) {
  const capz::StreamInfo info = capz::describe_file(out);  // a chunk at a time
  // Lossless: the archive must rebuild IN's bytes, proved through the checksum.
  if (info.lossless && capz::original_info(out).hashed) return capz::rebuilds_file(out, in);
  capz::PromiseCheck check(capz::promise_of(info));
  // (An archive of one frame decodes in the shape a reader gives one frame file: capz_source.h.)
  std::unique_ptr<capz::FrameSource> dec = capz::open_capz_frames(out);
  if (!check.header(in_header, dec->header())) return check.why();
  std::unique_ptr<capz::FrameSource> src =
      capz::open_frames(in, capz::read_options_of(in_header));  // IN again
  if (src->header().frames != in_header.frames || src->header().points != in_header.points ||
      src->header().frame_offsets != in_header.frame_offsets)
    return "IN changed while it was compressed";
  const size_t block = std::max<size_t>(1, dec->preferred_block());
  capz::FrameBlock a, b;
  for (size_t f = 0; f < in_header.frames; f += block) {
    src->read(f, block, &a);
    dec->read(f, block, &b);
    if (!check.frames(a, b)) return check.why();
  }
  check.finish();
  return check.why();
}

}  // namespace

void check_written(const std::string& out, const std::string& in, const capz::Take& in_header) {
  before_reading_back(out);
  std::string what;
  try {
    what = written_difference(out, in, in_header);
  } catch (const capz::Error& e) {
    what = e.what();
  }
  if (what.empty()) return;
  std::error_code ec;
  fs::remove(out, ec);  // known not to reproduce IN: no archive that looks good is left behind
  capz::fail(capz::ErrorCode::kCorrupt, in,
             "kept despite --rm: " + out + " read back from disk does not reproduce it (" + what +
                 "); " + out + (ec ? " could not be removed: " + ec.message() : " removed"));
}

}  // namespace capz_cli

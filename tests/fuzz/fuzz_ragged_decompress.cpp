// Fuzz target: the container path of streams of ragged frames (format 1.1: HEAD feature bit 3,
// SCNW chunks; docs/FORMAT.md "Scans (format 1.1)"), decompress, describe and decompress_frames.
// Byte 0 picks the mode; the rest is, with byte 0 even, a whole stream, decoded as given and with
// every chunk CRC made valid; with byte 0 odd, the scan geometry payload of one window, which the
// target frames as a valid 1.1 stream of that many frames (HEAD, META, SCNW, INDX) so that
// mutations of the payload reach the decoder through the container. Decoding may throw
// capz::Error; anything else is a finding, and so is a take of the wrong shape, a frame range
// that disagrees with the whole decode, a description that disagrees with it (a stream of one
// ragged frame is a fixed take of one frame to both, capz_fuzz::decoded_shape_matches), and (odd
// mode) a payload that the geometry decoder accepts but the stream built around it does not decode
// to.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/container.h"
#include "coding/meta.h"
#include "coding/scan_geometry.h"
#include "fuzz_common.h"
#include "fuzz_util_capz.h"

namespace {

constexpr size_t kMaxPoints = size_t{1} << 16;  // keeps each input fast
constexpr double kStep = 0.001;

// Frames [first, first + 3) read alone agree with the whole decode, frame counts and bits.
void check_range(const uint8_t* data, size_t size, const capz::Take& t, size_t first) {
  const capz::Take part =
      capz::decompress_frames(data, size, first, 3, "fuzz.capz", capz_fuzz::decode_options());
  capz_fuzz::check_take_shape(part);
  CAPZ_FUZZ_CHECK(part.frames == std::min<size_t>(3, t.frames - first));
  CAPZ_FUZZ_CHECK(part.ragged() == t.ragged());
  for (size_t f = 0; f < part.frames; ++f)
    CAPZ_FUZZ_CHECK(part.frame_points(f) == t.frame_points(first + f));
  const size_t p0 = t.frame_begin(first);
  CAPZ_FUZZ_CHECK(std::equal(part.valid.begin(), part.valid.end(), t.valid.begin() + p0));
  CAPZ_FUZZ_CHECK(part.xyz.empty() ||
                  std::memcmp(part.xyz.data(), &t.xyz[3 * p0], part.xyz.size() * 8) == 0);
}

// Decodes a whole stream; returns whether it decoded (into *out when given).
bool decode(const uint8_t* data, size_t size, capz::Take* out = nullptr) {
  capz::Take t;
  try {
    t = capz::decompress(data, size, "fuzz.capz", capz_fuzz::decode_options());
  } catch (const capz::Error&) {
    return false;
  }
  capz_fuzz::check_take_shape(t);
  const capz::StreamInfo si = capz::describe(data, size, "fuzz.capz");  // decodes: must describe
  CAPZ_FUZZ_CHECK(capz_fuzz::decoded_shape_matches(si.frames, si.ragged, si.total_points, t));
  if (t.frames > 0) check_range(data, size, t, data[size - 1] % t.frames);
  if (out) *out = std::move(t);
  return true;
}

// A format 1.1 stream of one window whose SCNW carries `geo` (frames and total read from it), or
// empty when the payload's counts cannot be read or exceed the limits.
std::vector<uint8_t> frame_payload(const uint8_t* geo, size_t size) {
  std::vector<uint32_t> counts;
  uint64_t total = 0;
  try {
    capz::ByteReader r(geo, size, "fuzz scan");
    const uint64_t F = r.varint();
    if (F == 0 || F > capz::kMaxWindowFrames) return {};
    for (uint64_t f = 0; f < F; ++f) {
      const uint64_t n = r.varint();
      total += n;
      if (n > kMaxPoints || total > kMaxPoints) return {};
      counts.push_back(static_cast<uint32_t>(n));
    }
  } catch (const capz::Error&) {
    return {};
  }
  capz::StreamHeader h;
  h.frames = counts.size();
  h.window_frames = static_cast<uint32_t>(counts.size());
  h.source_format = capz::Format::kPCDFolder;
  h.mode = capz::PosMode::kGrid;
  h.step = kStep;
  h.max_error = kStep / 2;
  h.ragged = true;
  capz::Take meta;  // a PCD folder of x y z frames
  meta.format = capz::Format::kPCDFolder;
  meta.frames = counts.size();
  meta.pcd = std::make_shared<capz::PCDExtra>();
  for (size_t f = 0; f < counts.size(); ++f)
    meta.pcd->frame_names.push_back(std::to_string(f) + ".pcd");
  std::vector<uint8_t> out;
  capz::write_file_header(&out, capz::kFormatScans.minor);
  capz::append_chunk(&out, "HEAD", capz::encode_header(h));
  capz::append_chunk(&out, "META", capz::encode_meta(meta, false));
  capz::ByteWriter w;
  w.varint(0);
  w.varint(total);
  w.u8(0);  // gaps: NaN (FORMAT.md "Origin points")
  std::vector<uint8_t> scnw = std::move(w.buffer());
  scnw.insert(scnw.end(), geo, geo + size);
  const size_t at = out.size();
  capz::append_chunk(&out, "SCNW", scnw);
  capz::append_chunk(&out, "INDX", capz::encode_index({capz::IndexEntry{at, out.size() - at}}));
  return out;
}

// The geometry decoder and the stream around its payload agree: a payload it accepts decodes,
// through the container, to its counts, gaps and integers times the step.
void check_framed(const uint8_t* geo, size_t size) {
  const std::vector<uint8_t> stream = frame_payload(geo, size);
  if (stream.empty()) return;
  capz::ScanGeometry g;
  bool geo_ok = true;
  try {
    g = capz::decode_scan_geometry(geo, size, "fuzz scan", kMaxPoints);
  } catch (const capz::Error&) {
    geo_ok = false;
  }
  capz::Take t;
  const bool ok = decode(stream.data(), stream.size(), &t);
  CAPZ_FUZZ_CHECK(ok == geo_ok);
  if (!ok) return;
  CAPZ_FUZZ_CHECK((t.ragged() || t.frames == 1) && t.frames == g.counts.size());
  for (size_t f = 0; f < t.frames; ++f) CAPZ_FUZZ_CHECK(t.frame_points(f) == g.counts[f]);
  CAPZ_FUZZ_CHECK(t.valid == g.valid);
  for (size_t i = 0; i < t.xyz.size(); ++i)
    CAPZ_FUZZ_CHECK(!t.valid[i / 3] || t.xyz[i] == static_cast<double>(g.q[i]) * kStep);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint8_t* rest = data + 1;
  const size_t n = size - 1;
  if (data[0] & 1) {
    check_framed(rest, n);
    return 0;
  }
  decode(rest, n);
  const std::vector<uint8_t> fixed = capz_fuzz::with_fixed_crcs(rest, n);
  if (fixed != std::vector<uint8_t>(rest, rest + n)) decode(fixed.data(), fixed.size());
  return 0;
}

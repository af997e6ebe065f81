// `capz compress --rm`: the written archive, read back from disk and decoded, against the input
// read again from disk, a block of frames at a time (memory bounded by the archive's window, as
// for compress itself).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/io.h"
#include "capz/metrics.h"
#include "capz/stream.h"
#include "compress_common.h"

namespace capz_cli {

namespace {

// Equal values, or both NaN (a NaN's payload bits are not part of what a take promises).
bool same_value(double a, double b) {
  return a == b || (std::isnan(a) && std::isnan(b));
}
bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

template <typename T, typename Eq>
bool same_vector(const std::vector<T>& a, const std::vector<T>& b, Eq eq) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (!eq(a[i], b[i])) return false;
  return true;
}

// The C3D extras of the header a .capz keeps: "" when `a` and `b` agree, else what differs.
std::string c3d_difference(const capz::C3DExtra& a, const capz::C3DExtra& b) {
  if (capz::encode_c3d_parameters(a) != capz::encode_c3d_parameters(b))
    return "the C3D parameter section differs";
  if (a.max_interpolation_gap != b.max_interpolation_gap || a.processor != b.processor ||
      a.float_storage != b.float_storage || a.point_scale != b.point_scale ||
      a.header_events_label_range != b.header_events_label_range)
    return "the C3D header fields differ";
  if (a.header_events.size() != b.header_events.size()) return "the C3D header events differ";
  for (size_t i = 0; i < a.header_events.size(); ++i) {
    const capz::C3DHeaderEvent &x = a.header_events[i], &y = b.header_events[i];
    if (x.time != y.time || x.display != y.display || x.label != y.label)
      return "C3D header event " + std::to_string(i) + " differs";
  }
  return "";
}

// Everything but the per-frame arrays (FrameSource::header()).
std::string header_difference(const capz::Take& a, const capz::Take& b) {
  if (a.frames != b.frames || a.points != b.points)
    return "decodes to " + std::to_string(b.frames) + " frames x " + std::to_string(b.points) +
           " points instead of " + std::to_string(a.frames) + " x " + std::to_string(a.points);
  if (!same_value(a.rate, b.rate) || a.units != b.units || a.first_frame != b.first_frame)
    return "the rate, units or first frame differ";
  if (a.labels != b.labels || a.descriptions != b.descriptions)
    return "the point labels or descriptions differ";
  const capz::Analog &p = a.analog, &q = b.analog;
  if (p.channels != q.channels || p.samples_per_frame != q.samples_per_frame ||
      !same_value(p.rate, q.rate) || p.labels != q.labels)
    return "the analog channel layout differs";
  if (a.c3d) {
    if (!b.c3d) return "the C3D extras are missing";
    std::string d = c3d_difference(*a.c3d, *b.c3d);
    if (!d.empty()) return d;
  }
  if (a.trc) {
    if (!b.trc) return "the TRC extras are missing";
    if (!same_vector(a.trc->times, b.trc->times, same_value) ||
        a.trc->frame_numbers != b.trc->frame_numbers)
      return "the TRC time or frame columns differ";
  }
  if (a.pcd) {
    if (!b.pcd) return "the PCD extras are missing";
    if (a.pcd->frame_names != b.pcd->frame_names) return "the PCD frame names differ";
  }
  return "";
}

// One block of frames, input `a` against decoded `b`.
std::string block_difference(const capz::FrameBlock& a, const capz::FrameBlock& b,
                             const capz::StreamInfo& promise) {
  if (a.valid != b.valid) return "the gap mask differs";
  const size_t n = a.frames * a.points;
  for (size_t i = 0; i < n; ++i) {
    if (!a.valid[i]) continue;
    for (size_t k = i * 3; k < i * 3 + 3; ++k) {
      const double x = a.xyz[k], y = b.xyz[k];
      const bool ok = promise.transform_output ? std::isfinite(y)
                      : promise.lossless       ? same_bits(x, y)
                                               : std::fabs(x - y) <= promise.max_error;
      if (!ok)
        return "coordinate " + num(x, 17) + " at frame " + std::to_string(a.first + i / a.points) +
               ", point " + std::to_string(i % a.points) + " comes back as " + num(y, 17) +
               (promise.lossless ? " (lossless)" : " (bound " + num(promise.max_error, 6) + ")");
    }
  }
  if (a.residual != b.residual || a.camera_mask != b.camera_mask)
    return "the C3D residual/camera words differ";
  if (!same_vector(a.analog, b.analog, same_value)) return "the analog values differ";
  return "";
}

// Test hook (tests/cli): flips one bit of OUT on disk before it is read back, as a disk returning
// bad data would, so a test can see --rm keep its input when the check fails. Unset in real use.
void test_flip_written_byte(const std::string& out) {
  const char* at = std::getenv("CAPZ_TEST_FLIP_WRITTEN_BYTE");
  if (!at) return;
  std::FILE* f = std::fopen(out.c_str(), "r+b");
  if (!f) return;
  const long i = std::strtol(at, nullptr, 10);
  if (std::fseek(f, i, SEEK_SET) == 0) {
    const int c = std::fgetc(f);
    if (c != EOF && std::fseek(f, i, SEEK_SET) == 0) std::fputc(c ^ 0x10, f);
  }
  std::fclose(f);
}

// "" when OUT reproduces IN as OUT's header promises, else what differs first.
std::string written_difference(const std::string& out, const std::string& in,
                               const capz::Take& in_header) {
  capz::StreamInfo promise;
  {
    const std::vector<uint8_t> bytes = capz::read_file(out);
    promise = capz::describe(bytes.data(), bytes.size(), out);
  }
  std::unique_ptr<capz::FrameSource> dec = capz::open_capz_frames(out);
  std::string what = header_difference(in_header, dec->header());
  if (!what.empty()) return what;
  std::unique_ptr<capz::FrameSource> src = capz::open_frames(in);  // IN again, from disk
  if (src->header().frames != in_header.frames || src->header().points != in_header.points)
    return "IN changed while it was compressed";
  const size_t block = std::max<size_t>(1, dec->preferred_block());
  capz::ErrorAccumulator acc;  // the KG error a transform-output stream promises
  capz::FrameBlock a, b;
  for (size_t f = 0; f < in_header.frames; f += block) {
    src->read(f, block, &a);
    dec->read(f, block, &b);
    if (a.frames != b.frames) return "frame count differs at frame " + std::to_string(f);
    what = block_difference(a, b, promise);
    if (!what.empty()) return what;
    acc.add(a.frames, a.points, a.xyz.data(), b.xyz.data(), a.valid.data());
  }
  if (promise.transform_output) {
    const double kg = acc.finish().kg_error;
    if (!(kg <= promise.kg_target * (1 + 1e-9)))
      return "KG error " + num(kg, 6) + "% over its target " + num(promise.kg_target, 6) + "%";
  }
  return "";
}

}  // namespace

void check_written(const std::string& out, const std::string& in, const capz::Take& in_header) {
  test_flip_written_byte(out);
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

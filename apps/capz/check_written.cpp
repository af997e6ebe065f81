// `capz compress --rm`: the written archive, read back from disk and decoded, against the input.
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/io.h"
#include "capz/metrics.h"
#include "compress_common.h"

namespace capz_cli {

namespace {

// Equal values, or both NaN (a NaN's payload bits are not part of what a take promises).
bool same_value(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

template <typename T, typename Eq>
bool same_vector(const std::vector<T>& a, const std::vector<T>& b, Eq eq) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (!eq(a[i], b[i])) return false;
  return true;
}

std::string sample_name(const capz::Take& t, size_t i) {
  return "frame " + std::to_string(i / t.points) + ", point " + std::to_string(i % t.points);
}

// The C3D extras a .capz keeps: "" when `a` and `b` agree, else what differs first.
std::string c3d_difference(const capz::C3DExtra& a, const capz::C3DExtra& b) {
  if (capz::encode_c3d_parameters(a) != capz::encode_c3d_parameters(b))
    return "the C3D parameter section differs";
  if (a.residual != b.residual || a.camera_mask != b.camera_mask)
    return "the C3D residual/camera words differ";
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

}  // namespace

std::string written_take_difference(const capz::Take& a, const capz::Take& b,
                                    const capz::StreamInfo& promise) {
  const bool lossless = promise.lossless;
  const double bound = promise.max_error;
  if (a.frames != b.frames || a.points != b.points)
    return "decodes to " + std::to_string(b.frames) + " frames x " + std::to_string(b.points) +
           " points instead of " + std::to_string(a.frames) + " x " + std::to_string(a.points);
  if (a.valid != b.valid) return "the gap mask differs";
  if (promise.transform_output) {  // only the KG target is promised (FORMAT.md 3.1)
    for (size_t i = 0; i < a.frames * a.points; ++i)
      if (a.valid[i])
        for (size_t k = i * 3; k < i * 3 + 3; ++k)
          if (!std::isfinite(b.xyz[k])) return "a coordinate at " + sample_name(a, i) + " is not finite";
    const double kg = capz::compare(a, b).kg_error;
    if (!(kg <= promise.kg_target * (1 + 1e-9)))
      return "KG error " + num(kg, 6) + "% over its target " + num(promise.kg_target, 6) + "%";
  }
  for (size_t i = 0; i < a.frames * a.points && !promise.transform_output; ++i) {
    if (!a.valid[i]) continue;
    for (size_t k = i * 3; k < i * 3 + 3; ++k) {
      const double x = a.xyz[k], y = b.xyz[k];
      if (lossless ? !same_bits(x, y) : !(std::fabs(x - y) <= bound))
        return "coordinate " + num(x, 17) + " at " + sample_name(a, i) + " comes back as " +
               num(y, 17) + (lossless ? " (lossless)" : " (bound " + num(bound, 6) + ")");
    }
  }
  if (!same_value(a.rate, b.rate) || a.units != b.units || a.first_frame != b.first_frame)
    return "the rate, units or first frame differ";
  if (a.labels != b.labels || a.descriptions != b.descriptions)
    return "the point labels or descriptions differ";
  const capz::Analog &p = a.analog, &q = b.analog;
  if (p.channels != q.channels || p.samples_per_frame != q.samples_per_frame ||
      !same_value(p.rate, q.rate) || p.labels != q.labels ||
      !same_vector(p.values, q.values, same_value))
    return "the analog channels differ";
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

void check_written(const std::string& out, const std::string& in, const capz::Take& input) {
  std::vector<uint8_t> bytes = capz::read_file(out);
  // Test hook (tests/cli): flip one bit of what was read, as a disk returning bad data would, so a
  // test can see --rm keep its input when the check fails. Unset in any real use.
  if (const char* at = std::getenv("CAPZ_TEST_FLIP_WRITTEN_BYTE")) {
    const size_t i = std::strtoull(at, nullptr, 10);
    if (i < bytes.size()) bytes[i] ^= 0x10;
  }
  std::string what;
  try {
    const capz::StreamInfo si = capz::describe(bytes.data(), bytes.size(), out);
    const capz::Take back = capz::decompress(bytes.data(), bytes.size(), out);
    what = written_take_difference(input, back, si);
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

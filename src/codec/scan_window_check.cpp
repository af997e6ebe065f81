// The scan encoder's window checks (scan_window_check.h).
#include "codec/scan_window_check.h"

#include <cmath>
#include <string>
#include <utility>

#include "capz/error.h"
#include "codec/decoder.h"
#include "codec/grid_choice.h"
#include "coding/quantiser.h"

namespace capz {

void check_window(const Take& t, const FrameBlock& b, const FrameBlock& d, double bound,
                  bool exact) {
  const bool f32 = float32_frames(t);
  bool counts = d.frames == b.frames && d.ragged() && d.valid.size() == b.valid.size();
  for (size_t k = 0; counts && k < b.frames; ++k) counts = d.frame_points(k) == b.frame_points(k);
  if (!counts) fail(ErrorCode::kInternal, t.source, "self-check: frame counts differ");
  for (size_t i = 0; i < d.valid.size(); ++i) {
    if (d.valid[i] != b.valid[i]) fail(ErrorCode::kInternal, t.source, "self-check: gaps differ");
    if (!d.valid[i]) continue;
    for (size_t a = 0; a < 3; ++a) {
      const double x = b.xyz[3 * i + a], y = d.xyz[3 * i + a];
      const double y32 = f32 ? static_cast<double>(static_cast<float>(y)) : y;
      if (exact ? !same_bits(x, y) : !(std::fabs(y - x) <= bound && std::fabs(y32 - x) <= bound))
        fail(ErrorCode::kInternal, t.source,
             "self-check: coordinate " + std::to_string(x) + " comes back as " + std::to_string(y) +
                 ", off by more than " + std::to_string(bound));
    }
  }
}

void check_fields(const Take& t, const std::vector<std::vector<uint8_t>>& fields,
                  const FrameBlock& d) {
  if (d.attributes.size() != fields.size())
    fail(ErrorCode::kInternal, t.source, "self-check: the fields come back as another number");
  for (size_t a = 0; a < fields.size(); ++a)
    if (d.attributes[a] != fields[a])
      fail(ErrorCode::kInternal, t.source,
           "self-check: field " + t.attributes[a].name + " does not come back byte for byte");
}

WindowChecks::WindowChecks(const Take& t, const StreamContext& ctx, double bound, bool exact,
                           bool beside, ErrorAccumulator* acc)
    : t_(t), ctx_(ctx), bound_(bound), exact_(exact), acc_(acc) {
  if (beside) pool_.reset(new ThreadPool(1));
}

WindowChecks::~WindowChecks() {
  if (done_.valid()) done_.wait();
}

void WindowChecks::run(size_t w, const uint8_t* bytes, size_t size, size_t base,
                       const FrameBlock& b, const std::vector<std::vector<uint8_t>>& fields) {
  decode_window_chunks(ctx_, w, bytes, base, base + size, &d_);
  check_window(t_, b, d_, bound_, exact_);
  check_fields(t_, fields, d_);
  acc_->add_ragged(b.frames, d_.frame_offsets.data(), b.xyz.data(), d_.xyz.data(), b.valid.data());
}

void WindowChecks::check(size_t w, const uint8_t* bytes, size_t size, size_t base, FrameBlock* b,
                         std::vector<std::vector<uint8_t>>* fields) {
  if (!pool_) return run(w, bytes, size, base, *b, *fields);
  finish();
  std::swap(b_, *b);
  bytes_.assign(bytes, bytes + size);
  fields_.swap(*fields);
  done_ =
      pool_->submit([this, w, base] { run(w, bytes_.data(), bytes_.size(), base, b_, fields_); });
}

void WindowChecks::finish() {
  if (done_.valid()) done_.get();
}

}  // namespace capz

// The .capz frame source (capz_source.h). Part of the decoder library.
#include "io/capz_source.h"

#include <algorithm>

#include "codec/decoder.h"

namespace capz {

CapzSource::CapzSource(std::unique_ptr<StreamBytes> bytes, const std::string& name, bool whole)
    : bytes_(std::move(bytes)), name_(name), ps_(parse_stream(*bytes_, name)) {
  if (whole) check_tiling(ps_, bytes_->size(), name_);
  header_ = ps_.take;
}

void CapzSource::read(size_t first, size_t count, FrameBlock* out) {
  const size_t F = ps_.take.frames, N = ps_.take.points;
  clip(&first, &count);
  const size_t S = ps_.h.analog_samples_per_frame, C = ps_.h.analog_channels;
  const size_t A = C > 0 && S > 0 ? S * C : 0;
  const size_t W = ps_.h.window_frames;
  const size_t R = ps_.take.rotations.per_frame();  // rotations per frame
  // A block that is exactly one window is handed over without a copy: swapped with the
  // caller's block (whose buffers the next decode refills), so it is no longer cached.
  if (count > 0 && first % W == 0 && count == std::min<size_t>(W, F - first)) {
    decode(first / W);
    std::swap(*out, win_);
    have_ = false;
    return;
  }
  out->reset(first, count, N, A, ps_.words, R);
  const std::vector<PointAttribute>& attrs = ps_.take.attributes;
  out->attributes.resize(attrs.size());
  for (size_t a = 0; a < attrs.size(); ++a)
    out->attributes[a].assign(count * N * attrs[a].bytes_per_point(), 0);
  for (size_t f = first; f < first + count;) {
    const size_t w = f / W;
    decode(w);
    const size_t lo = f - win_.first, hi = std::min(win_.frames, first + count - win_.first);
    const size_t o = f - first, n = hi - lo;
    // Through data(): a take may have no points (rotations only), and element access into an
    // empty vector is undefined even for a copy of nothing.
    std::copy_n(win_.xyz.data() + lo * N * 3, n * N * 3, out->xyz.data() + o * N * 3);
    std::copy_n(win_.valid.data() + lo * N, n * N, out->valid.data() + o * N);
    if (ps_.words) {
      std::copy_n(win_.residual.data() + lo * N, n * N, out->residual.data() + o * N);
      std::copy_n(win_.camera_mask.data() + lo * N, n * N, out->camera_mask.data() + o * N);
    }
    std::copy_n(win_.analog.data() + lo * A, n * A, out->analog.data() + o * A);
    std::copy_n(win_.rotation_matrices.data() + lo * R * 16, n * R * 16,
                out->rotation_matrices.data() + o * R * 16);
    std::copy_n(win_.rotation_reliability.data() + lo * R, n * R,
                out->rotation_reliability.data() + o * R);
    for (size_t a = 0; a < attrs.size(); ++a) {
      const size_t bpp = attrs[a].bytes_per_point();
      std::copy_n(win_.attributes[a].data() + lo * N * bpp, n * N * bpp,
                  out->attributes[a].data() + o * N * bpp);
    }
    f += n;
  }
}

void CapzSource::decode(size_t w) {
  if (have_ && cached_ == w) return;
  have_ = false;
  decode_window(*bytes_, ps_, w, &win_);
  cached_ = w;
  have_ = true;
}

std::unique_ptr<FrameSource> open_capz_frames(const std::string& path) {
  std::unique_ptr<StreamBytes> file(new FileBytes(path));
  return std::unique_ptr<FrameSource>(new CapzSource(std::move(file), path, true));
}

}  // namespace capz

// The .capz frame source (capz_source.h). Part of the decoder library.
#include "codec/capz_source.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "capz/error.h"
#include "codec/decoder.h"
#include "coding/buffers.h"

namespace capz {

CapzSource::CapzSource(std::unique_ptr<StreamBytes> bytes, const std::string& name, bool whole,
                       int threads, uint64_t memory_limit)
    : bytes_(std::move(bytes)),
      name_(name),
      ps_(parse_stream(*bytes_, name)),
      memory_limit_(effective_memory_limit(memory_limit, bytes_->size())) {
  if (whole) check_tiling(ps_, bytes_->size(), name_);
  if (ps_.h.ragged) {  // "Scans (format 1.1)": x y z doubles, a flag and the fields, a point
    uint64_t per_point = 25;
    for (const PointAttribute& a : ps_.take.attributes) per_point += a.bytes_per_point();
    if (ps_.h.lossless && ps_.h.mode == PosMode::kFloat32) per_point += 12;  // a raw window's bits
    if (ps_.h.lossless && ps_.h.mode == PosMode::kFloat64) per_point += 24;
    ps_.max_points =
        static_cast<size_t>(std::min<uint64_t>(memory_limit_ / per_point, uint64_t{1} << 40));
    if (memory_limit_ == 0) ps_.max_points = size_t{1} << 40;
    ps_.take.frame_offsets = ragged_frame_offsets(*bytes_, ps_);
  }
  header_ = ps_.take;
  if (ragged_reads_fixed(ps_)) ragged_as_fixed();
  const size_t T = std::min(resolve_threads(threads), ps_.index.size());
  if (T > 1 && ps_.index.size() > 1) ahead_cap_ = T + 1;
  // The window kept, and those decoded ahead, each with its buffers.
  const double window = static_cast<double>(
      std::min<uint64_t>(ps_.h.window_frames, std::max<uint64_t>(ps_.take.frames, 1)));
  check_memory(window * static_cast<double>(1 + ahead_cap_),
               ahead_cap_ ? "its windows decoded ahead" : "a window");
  if (ahead_cap_) pool_.reset(new ThreadPool(T));
}

void CapzSource::ragged_as_fixed() {
  ragged_as_fixed_ = true;
  const size_t shape = organized_points(ps_);  // every frame's count (checked when listed)
  header_.points = shape ? shape : header_.frame_offsets.at(1);
  header_.frame_offsets.clear();
  header_.labels.clear();  // frame files' points have no labels (take.h)
  if (shape == 0 && header_.pcd && header_.pcd->width != header_.points) {
    auto x = std::make_shared<PCDExtra>(*header_.pcd);
    x->width = header_.points;
    x->height = 1;
    header_.pcd = x;
  }
}

double CapzSource::frame_bytes() const {
  double attribute_bytes = 0;
  for (const PointAttribute& a : ps_.take.attributes)
    attribute_bytes += static_cast<double>(a.bytes_per_point());
  return FrameBlock::frame_bytes(static_cast<double>(ps_.take.points),
                                 static_cast<double>(ps_.h.analog_samples_per_frame) *
                                     static_cast<double>(ps_.h.analog_channels),
                                 ps_.words, static_cast<double>(ps_.take.rotations.per_frame()),
                                 attribute_bytes);
}

void CapzSource::check_memory(double frames, const char* what) const {
  if (memory_limit_ == 0) return;
  const double need = frames * frame_bytes();
  if (need <= static_cast<double>(memory_limit_)) return;
  // KiB below 1 MiB, else MiB; one decimal below 10 of the unit; what is needed rounded up and
  // the limit down, so that the two never print the same.
  auto size = [](double v, bool up) {
    const bool kib = v < 1048576;
    const double u = v / (kib ? 1024.0 : 1048576.0), scale = u < 10 ? 10.0 : 1.0;
    const double r = (up ? std::ceil(u * scale) : std::floor(u * scale)) / scale;
    char buf[48];
    std::snprintf(buf, sizeof buf, scale > 1 ? "%.1f %s" : "%.0f %s", r, kib ? "KiB" : "MiB");
    return std::string(buf);
  };
  fail(ErrorCode::kMemoryLimit, name_,
       "decoding " + std::string(what) + " needs " + size(need, true) +
           " of samples, above the memory limit of " +
           size(static_cast<double>(memory_limit_), false) +
           " (--memlimit, or memory_limit in the API, raises it)");
}

CapzSource::~CapzSource() {
  pool_.reset();
}

// Frames [first, first + count) of a ragged stream (clipped), window by window.
void CapzSource::read_ragged(size_t first, size_t count, FrameBlock* out) {
  const std::vector<size_t>& off = ps_.take.frame_offsets;
  if (off[first + count] - off[first] > ps_.max_points)
    fail(ErrorCode::kMemoryLimit, name_, "these frames' points exceed the memory limit");
  const size_t W = ps_.h.window_frames;
  if (count > 0 && first % W == 0 && count == std::min<size_t>(W, ps_.take.frames - first)) {
    hand_over(first / W, out);  // exactly one window, as in read()
    return;
  }
  // The block's shape (FrameBlock::reset_ragged's), its arrays sized, not zeroed: every point
  // of the range is copied in below.
  FrameBlock& b = *out;
  b.first = first;
  b.frames = count;
  b.points = 0;
  b.frame_offsets.assign(1, 0);
  for (size_t f = first; f < first + count; ++f)
    b.frame_offsets.push_back(b.frame_offsets.back() + off[f + 1] - off[f]);
  const size_t total = b.frame_offsets.back();
  size_for_overwrite(&b.xyz, total * 3);
  size_for_overwrite(&b.valid, total);
  for (auto* v : {&b.residual, &b.rotation_matrices, &b.rotation_reliability}) v->clear();
  b.camera_mask.clear();
  b.analog.clear();
  b.file_bytes.clear();
  b.file_bytes_at = 0;
  const std::vector<PointAttribute>& attrs = ps_.take.attributes;
  b.attributes.resize(attrs.size());
  for (size_t a = 0; a < attrs.size(); ++a)
    size_for_overwrite(&b.attributes[a], total * attrs[a].bytes_per_point());
  for (size_t f = first; f < first + count;) {
    decode(f / ps_.h.window_frames);
    const size_t lo = f - win_.first, hi = std::min(win_.frames, first + count - win_.first);
    const size_t p0 = win_.frame_offsets[lo], n = win_.frame_offsets[hi] - p0;
    const size_t o = off[f] - off[first];
    std::copy_n(win_.xyz.data() + p0 * 3, n * 3, out->xyz.data() + o * 3);
    std::copy_n(win_.valid.data() + p0, n, out->valid.data() + o);
    for (size_t a = 0; a < attrs.size(); ++a) {  // flattened, as the points (take.h)
      const size_t bpp = attrs[a].bytes_per_point();
      std::copy_n(win_.attributes[a].data() + p0 * bpp, n * bpp,
                  out->attributes[a].data() + o * bpp);
    }
    f += hi - lo;
  }
}

void CapzSource::read(size_t first, size_t count, FrameBlock* out) {
  const size_t F = ps_.take.frames, N = ps_.take.points;
  clip(&first, &count);
  if (ps_.h.ragged) {
    read_ragged(first, count, out);
    if (ragged_as_fixed_) {  // the block of the fixed take (capz_source.h)
      out->points = header_.points;
      out->frame_offsets.clear();
    }
    return;
  }
  const size_t S = ps_.h.analog_samples_per_frame, C = ps_.h.analog_channels;
  const size_t A = C > 0 && S > 0 ? S * C : 0;
  const size_t W = ps_.h.window_frames;
  const size_t R = ps_.take.rotations.per_frame();  // rotations per frame
  if (count > 0 && first % W == 0 && count == std::min<size_t>(W, F - first)) {
    hand_over(first / W, out);  // exactly one window
    return;
  }
  // The block, besides the window(s) kept (checked when the source was opened).
  check_memory(static_cast<double>(count) + static_cast<double>(std::min<size_t>(W, F)) *
                                                static_cast<double>(1 + ahead_cap_),
               "these frames");
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

// A block that is exactly one window is handed over without a copy: swapped with the caller's
// block, so it is no longer cached. Unless it is cached already, it is decoded into the caller's
// block's buffers (whose frames the read replaces): their capacity is reused, and the caller's
// previous window and this one are not both held (a window's worth of memory less, touched
// afresh, on a take of more than one window).
void CapzSource::hand_over(size_t w, FrameBlock* out) {
  if (!(have_ && cached_ == w)) {
    std::swap(*out, win_);
    have_ = false;
  }
  decode(w);
  std::swap(*out, win_);
  have_ = false;
}

void CapzSource::decode(size_t w) {
  if (have_ && cached_ == w) return;
  have_ = false;
  if (pool_)
    decode_ahead(w);
  else
    decode_window(*bytes_, ps_, w, &win_, &ints_);
  cached_ = w;
  have_ = true;
  if (after_window_) after_window_(w);
}

// Window w from the workers: the windows after it are submitted too, up to ahead_cap_. A read
// that is not the next window ahead starts again from it.
void CapzSource::decode_ahead(size_t w) {
  if (!ahead_.empty() && ahead_.front()->w != w) drop_ahead();
  if (ahead_.empty()) next_ = w;
  while (ahead_.size() < ahead_cap_ && next_ < ps_.index.size()) submit(next_++);
  std::unique_ptr<Ahead> a = std::move(ahead_.front());
  ahead_.pop_front();
  if (ahead_.size() < ahead_cap_ && next_ < ps_.index.size()) submit(next_++);
  if (a->done.valid()) a->done.get();
  const std::exception_ptr error = a->error;
  if (!error) std::swap(win_, a->block);
  spare_.push_back(std::move(a));
  if (error) std::rethrow_exception(error);
}

// Fetching the chunks (this thread: the stream's bytes are read in order) and handing them to a
// worker. A fault found on the way is kept for when window w is read, as a serial read meets it.
void CapzSource::submit(size_t w) {
  std::unique_ptr<Ahead> a;
  if (spare_.empty()) {
    a.reset(new Ahead);
  } else {
    a = std::move(spare_.back());
    spare_.pop_back();
  }
  a->w = w;
  a->error = nullptr;
  a->done = std::future<void>();
  try {
    window_extent(ps_, bytes_->size(), w, &a->base, &a->end);
    const uint8_t* p = bytes_->get(a->base, a->end - a->base);
    a->chunks.assign(p, p + (a->end - a->base));
    Ahead* q = a.get();
    a->done = pool_->submit([this, q] {
      try {
        decode_window_chunks(ps_, q->w, q->chunks.data(), q->base, q->end, &q->block, &q->ints);
      } catch (...) {
        q->error = std::current_exception();
      }
    });
  } catch (...) {
    a->error = std::current_exception();
  }
  ahead_.push_back(std::move(a));
}

void CapzSource::drop_ahead() {
  for (std::unique_ptr<Ahead>& a : ahead_) {
    if (a->done.valid()) a->done.wait();
    spare_.push_back(std::move(a));
  }
  ahead_.clear();
}

std::unique_ptr<FrameSource> open_capz_frames(const std::string& path,
                                              const DecompressOptions& opts) {
  std::unique_ptr<StreamBytes> file(new FileBytes(path));
  return std::unique_ptr<FrameSource>(
      new CapzSource(std::move(file), path, true, opts.threads, opts.memory_limit));
}

}  // namespace capz

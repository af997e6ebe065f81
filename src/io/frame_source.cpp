// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// Frame sources and sinks (include/capz/stream.h): C3D read by frame ranges, an in-memory take,
// a C3D, a TRC and folders of frame files written block by block, and the whole-take fallback.
#include <algorithm>
#include <functional>
#include <memory>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "core/atomic_file.h"
#include "core/input_file.h"
#include "io/bin_folder.h"
#include "io/c3d_internal.h"
#include "io/pcd_folder.h"
#include "io/ply.h"
#include "io/take_source.h"
#include "io/trc_internal.h"

namespace capz {

void FrameBlock::reset(size_t first_frame, size_t n, size_t n_points, size_t analog_per_frame,
                       bool words, size_t rotations_per_frame) {
  first = first_frame;
  frames = n;
  points = n_points;
  xyz.assign(n * n_points * 3, 0.0);
  valid.assign(n * n_points, 0);
  residual.assign(words ? n * n_points : 0, 0.0f);
  camera_mask.assign(words ? n * n_points : 0, 0);
  analog.assign(n * analog_per_frame, 0.0);
  rotation_matrices.assign(n * rotations_per_frame * 16, 0.0f);
  rotation_reliability.assign(n * rotations_per_frame, 0.0f);
  attributes.clear();
  file_bytes.clear();
  frame_offsets.clear();
}

void FrameBlock::reset_ragged(size_t first_frame, const std::vector<size_t>& counts) {
  reset(first_frame, counts.size(), 0, 0, false, 0);
  frame_offsets = offsets_of_counts(counts);
  xyz.assign(frame_offsets.back() * 3, 0.0);
  valid.assign(frame_offsets.back(), 0);
}

double FrameBlock::frame_bytes(double N, double analog_per_frame, bool words, double R,
                               double attribute_bytes_per_point) {
  // The arrays reset sizes, in its order, per frame.
  double b = N * 3 * sizeof(double) + N * sizeof(uint8_t);  // xyz, valid
  if (words) b += N * sizeof(float) + N * sizeof(uint8_t);  // residual, camera_mask
  b += analog_per_frame * sizeof(double);
  b += R * 16 * sizeof(float) + R * sizeof(float);  // rotation matrices, reliability
  return b + N * attribute_bytes_per_point;         // attributes
}

namespace {

// Analog values per frame as the coder and the writers see them (0 without channels).
size_t analog_per_frame(const Take& t) {
  return t.analog.channels > 0 && t.analog.samples_per_frame > 0
             ? static_cast<size_t>(t.analog.channels) *
                   static_cast<size_t>(t.analog.samples_per_frame)
             : 0;
}

// The take's metadata without its per-frame arrays.
Take header_of(const Take& t) {
  Take h;
  h.source = t.source;
  h.format = t.format;
  h.frames = t.frames;
  h.points = t.points;
  h.frame_offsets = t.frame_offsets;
  h.units_assumed = t.units_assumed;
  h.rate = t.rate;
  h.units = t.units;
  h.first_frame = t.first_frame;
  h.labels = t.labels;
  h.descriptions = t.descriptions;
  h.analog.channels = t.analog.channels;
  h.analog.samples_per_frame = t.analog.samples_per_frame;
  h.analog.rate = t.analog.rate;
  h.analog.labels = t.analog.labels;
  h.rotations.segments = t.rotations.segments;  // the layout; the samples come in blocks
  h.rotations.samples_per_frame = t.rotations.samples_per_frame;
  h.rotations.rate = t.rotations.rate;
  h.rotations.labels = t.rotations.labels;
  for (const PointAttribute& a : t.attributes) {  // the layouts; the values come in blocks
    PointAttribute l = a;
    l.data.clear();
    h.attributes.push_back(std::move(l));
  }
  if (t.c3d) {
    auto x = std::make_shared<C3DExtra>();
    x->processor = t.c3d->processor;
    x->float_storage = t.c3d->float_storage;
    x->point_scale = t.c3d->point_scale;
    x->max_interpolation_gap = t.c3d->max_interpolation_gap;
    x->groups = t.c3d->groups;
    x->header_events = t.c3d->header_events;
    x->header_events_label_range = t.c3d->header_events_label_range;
    h.c3d = x;
  }
  h.trc = t.trc;
  h.pcd = t.pcd;
  h.ply = t.ply;
  h.bin = t.bin;
  h.warnings = t.warnings;
  return h;
}

// ---------------------------------------------------------------------------------------------
class C3DSource : public FrameSource {
 public:
  explicit C3DSource(const std::string& path) : file_(path) {
    const size_t size = static_cast<size_t>(file_.size());
    std::vector<uint8_t> head(std::min<size_t>(size, c3d::kBlock));
    file_.read_at(0, head.data(), head.size());
    const size_t extent = c3d::header_extent(head.data(), head.size(), size);
    if (extent > head.size()) {
      const size_t had = head.size();
      head.resize(extent);
      file_.read_at(had, head.data() + had, extent - had);
    }
    header_ = c3d::read_header(head.data(), head.size(), size, path, &lay_);
  }
  bool has_sample_words() const override { return true; }
  void read(size_t first, size_t count, FrameBlock* out) override {
    clip(&first, &count);
    const size_t rot_per_frame = header_.rotations.per_frame();
    // Sized, not zeroed: decode_frames and decode_c3d_rotations write every value.
    const size_t N = lay_.points, A = lay_.analog_values;
    out->first = first;
    out->frames = count;
    out->points = N;
    out->frame_offsets.clear();
    out->xyz.resize(count * N * 3);
    out->valid.resize(count * N);
    out->residual.resize(count * N);
    out->camera_mask.resize(count * N);
    out->analog.resize(count * A);
    out->rotation_matrices.resize(count * rot_per_frame * 16);
    out->rotation_reliability.resize(count * rot_per_frame);
    out->attributes.clear();
    // The file's bytes of the frames are kept in the block (FrameBlock::file_bytes, the
    // residue's original), read and decoded in pieces of about 64 KB, each decoded while it is
    // still in the cache the read wrote it to.
    const size_t piece =
        std::max<size_t>(1, (size_t{64} << 10) / std::max<size_t>(1, lay_.per_frame));
    out->file_bytes_at = lay_.data_offset + first * lay_.per_frame;
    out->file_bytes.resize(count * lay_.per_frame);
    size_t wide = 0;
    for (size_t f = 0; f < count; f += piece) {
      const size_t n = std::min(piece, count - f);
      uint8_t* bytes = out->file_bytes.data() + f * lay_.per_frame;
      file_.read_at(out->file_bytes_at + f * lay_.per_frame, bytes, n * lay_.per_frame);
      c3d::decode_frames(lay_, bytes, n, out->xyz.data() + f * N * 3, out->valid.data() + f * N,
                         out->residual.data() + f * N, out->camera_mask.data() + f * N,
                         out->analog.data() + f * A, &wide);
    }
    if (rot_per_frame > 0) {  // the frames' part of the rotation section (after the frames)
      buf_.resize(count * lay_.rot_per_frame);
      file_.read_at(lay_.rot_offset + first * lay_.rot_per_frame, buf_.data(), buf_.size());
      c3d::decode_c3d_rotations(lay_, buf_.data(), count * rot_per_frame,
                                out->rotation_matrices.data(), out->rotation_reliability.data());
    }
    if (first == scanned_to_) {  // count each frame once, on the first pass in order
      wide_ += wide;
      scanned_to_ = first + count;
    }
  }
  std::vector<std::string> frame_warnings() const override {
    if (wide_ == 0) return {};
    return {c3d::wide_word4_warning(wide_)};
  }
  uint64_t bytes_read() const override { return file_.bytes_read(); }
  std::string original_file() const override { return file_.path(); }

 private:
  InputFile file_;
  c3d::DataLayout lay_;
  std::vector<uint8_t> buf_;
  size_t wide_ = 0, scanned_to_ = 0;
};

class TakeSource : public FrameSource {
 public:
  // `owned` keeps a take read here alive; else `take` must outlive the source. hand_over (with
  // `owned`): see handing_take_frames.
  TakeSource(const Take& take, std::unique_ptr<Take> owned, bool hand_over = false)
      : owned_(std::move(owned)), take_(take), hand_over_(hand_over && owned_) {
    header_ = header_of(take);
    std::string fault = take.shape_fault();
    if (!fault.empty()) fail(ErrorCode::kInvalidParameter, take.source, "take arrays: " + fault);
    fault = point_field_fault(take);
    if (!fault.empty()) fail(ErrorCode::kInvalidParameter, take.source, fault);
    const size_t n = take.total_points();
    words_ = !take.ragged() && take.c3d && take.c3d->residual.size() == n &&
             take.c3d->camera_mask.size() == n;
    analog_ = analog_per_frame(take);
    rotations_ = take.rotations.per_frame();
    if ((take.ragged() && (analog_ > 0 || rotations_ > 0)) ||
        take.analog.values.size() < take.frames * analog_)
      fail(ErrorCode::kInvalidParameter, take.source,
           "take arrays do not match its frame and point counts");
    const Rotations& r = take.rotations;
    if (r.segments < 0 || (r.segments > 0 && r.samples_per_frame < 1) ||
        r.matrices.size() != take.frames * rotations_ * 16 ||
        r.reliability.size() != take.frames * rotations_ ||
        (!r.labels.empty() && r.labels.size() != static_cast<size_t>(r.segments)))
      fail(ErrorCode::kInvalidParameter, take.source,
           "rotation arrays or labels do not match frames x samples per frame x segments");
    for (const PointAttribute& a : take.attributes)
      if (a.size < 1 || a.count < 1 || a.data.size() != n * a.bytes_per_point())
        fail(ErrorCode::kInvalidParameter, take.source,
             "point field '" + a.name + "' does not hold frames x points values");
  }
  bool has_sample_words() const override { return words_; }
  void read(size_t first, size_t count, FrameBlock* out) override {
    clip(&first, &count);
    if (take_.ragged()) return read_ragged(first, count, out);
    const size_t N = take_.points;
    out->frame_offsets.clear();
    out->first = first;
    out->frames = count;
    out->points = N;
    const auto cut = [&](const auto& v, size_t per, auto* dst) {
      dst->assign(v.begin() + static_cast<long>(first * per),
                  v.begin() + static_cast<long>((first + count) * per));
    };
    cut(take_.xyz, N * 3, &out->xyz);
    cut(take_.valid, N, &out->valid);
    if (words_) {
      cut(take_.c3d->residual, N, &out->residual);
      cut(take_.c3d->camera_mask, N, &out->camera_mask);
    } else {
      out->residual.clear();
      out->camera_mask.clear();
    }
    cut(take_.analog.values, analog_, &out->analog);
    cut(take_.rotations.matrices, rotations_ * 16, &out->rotation_matrices);
    cut(take_.rotations.reliability, rotations_, &out->rotation_reliability);
    out->file_bytes.clear();
    out->attributes.resize(take_.attributes.size());
    for (size_t a = 0; a < take_.attributes.size(); ++a)
      cut(take_.attributes[a].data, N * take_.attributes[a].bytes_per_point(), &out->attributes[a]);
  }

 private:
  // Frames of a ragged take: the points between their offsets (no words, analog or rotations).
  void read_ragged(size_t first, size_t count, FrameBlock* out) {
    if (handed_)
      fail(ErrorCode::kInternal, take_.source, "a take's frames read after they were handed out");
    if (hand_over_ && first == 0 && count == take_.frames) return hand_ragged(out);
    const std::vector<size_t>& o = take_.frame_offsets;
    out->reset(first, count, 0, 0, false, 0);
    out->frame_offsets.assign(o.begin() + static_cast<long>(first),
                              o.begin() + static_cast<long>(first + count + 1));
    for (size_t& v : out->frame_offsets) v -= o[first];
    const size_t b = o[first], e = o[first + count];
    const auto cut = [&](const auto& v, size_t per, auto* dst) {
      dst->assign(v.begin() + static_cast<long>(b * per), v.begin() + static_cast<long>(e * per));
    };
    cut(take_.xyz, 3, &out->xyz);
    cut(take_.valid, 1, &out->valid);
    out->attributes.resize(take_.attributes.size());
    for (size_t a = 0; a < take_.attributes.size(); ++a)
      cut(take_.attributes[a].data, take_.attributes[a].bytes_per_point(), &out->attributes[a]);
  }

  // All the frames of an owned take: its arrays moved into the block, not copied.
  void hand_ragged(FrameBlock* out) {
    out->reset(0, take_.frames, 0, 0, false, 0);
    out->frame_offsets = take_.frame_offsets;
    out->xyz.swap(owned_->xyz);
    out->valid.swap(owned_->valid);
    out->attributes.resize(take_.attributes.size());
    for (size_t a = 0; a < take_.attributes.size(); ++a)
      out->attributes[a].swap(owned_->attributes[a].data);
    handed_ = true;
  }

  std::unique_ptr<Take> owned_;
  const Take& take_;
  bool hand_over_ = false, handed_ = false;
  bool words_ = false;
  size_t analog_ = 0, rotations_ = 0;  // analog values and rotations per frame
};

// ---------------------------------------------------------------------------------------------
// A take grown block by block from a source's header and its frames (read_all_frames,
// WholeTakeSink).
class TakeCollector {
 public:
  TakeCollector(const Take& header, bool words, const std::string& name)
      : take_(header), words_(words), name_(name) {
    if (take_.ragged()) take_.frame_offsets.assign(1, 0);  // grows block by block
    take_.xyz.clear();
    take_.valid.clear();
    take_.analog.values.clear();
    take_.rotations.matrices.clear();
    take_.rotations.reliability.clear();
    for (PointAttribute& a : take_.attributes) a.data.clear();
    if (take_.c3d) {
      take_.c3d = std::make_shared<C3DExtra>(*header.c3d);
      take_.c3d->residual.clear();
      take_.c3d->camera_mask.clear();
    }
  }
  void add(const FrameBlock& b) {
    if (b.ragged() != take_.ragged())
      fail(ErrorCode::kInternal, name_, "a block of another shape than the take's");
    for (size_t k = 0; k < b.frames && b.ragged(); ++k)
      take_.frame_offsets.push_back(take_.frame_offsets.back() + b.frame_points(k));
    take_.xyz.insert(take_.xyz.end(), b.xyz.begin(), b.xyz.end());
    take_.valid.insert(take_.valid.end(), b.valid.begin(), b.valid.end());
    take_.analog.values.insert(take_.analog.values.end(), b.analog.begin(), b.analog.end());
    Rotations& r = take_.rotations;
    r.matrices.insert(r.matrices.end(), b.rotation_matrices.begin(), b.rotation_matrices.end());
    r.reliability.insert(r.reliability.end(), b.rotation_reliability.begin(),
                         b.rotation_reliability.end());
    if (b.attributes.size() != take_.attributes.size())
      fail(ErrorCode::kInternal, name_, "a block without the take's point fields");
    for (size_t a = 0; a < take_.attributes.size(); ++a)
      take_.attributes[a].data.insert(take_.attributes[a].data.end(), b.attributes[a].begin(),
                                      b.attributes[a].end());
    if (words_ && take_.c3d) {
      take_.c3d->residual.insert(take_.c3d->residual.end(), b.residual.begin(), b.residual.end());
      take_.c3d->camera_mask.insert(take_.c3d->camera_mask.end(), b.camera_mask.begin(),
                                    b.camera_mask.end());
    }
  }
  const Take& take() const { return take_; }
  Take release() { return std::move(take_); }

 private:
  Take take_;
  bool words_;
  std::string name_;
};

// Collects the frames and writes the whole take at commit (C3D files whose int16 scale must
// come from the data).
class WholeTakeSink : public FrameSink {
 public:
  WholeTakeSink(const Take& header, bool words, const std::string& path, const WriteOptions& opts)
      : take_(header, words, path), path_(path), opts_(opts) {}
  void write(const FrameBlock& b) override { take_.add(b); }
  void commit() override { write_take(take_.take(), path_, opts_); }

 private:
  TakeCollector take_;
  std::string path_;
  WriteOptions opts_;
};

// A C3D written as it comes: header and parameters at the first block, then frames.
class C3DSink : public FrameSink {
 public:
  C3DSink(const Take& header, bool words, const std::string& path, const WriteOptions& opts)
      : header_(header), words_(words), path_(path), opts_(opts) {
    c3d::check_c3d_limits(header_, path_);
    check_output_free(path, opts.overwrite);
    scan_.scale = c3d::c3d_known_scale(header_);
  }
  bool wants_prescan() const override {
    return !known_float_ && c3d::c3d_needs_scan(header_, opts_);
  }
  void prescan(const FrameBlock& b) override {
    scan_.add(b.frames * b.points, b.xyz.data(), b.valid.data(), b.analog.size(), b.analog.data());
  }
  // int16 output at the take's own scale: the prescan only decides whether every value fits
  // (else the file is float). Here that is assumed, and each block gets the prescan's checks
  // at the same scale (analog by scan_.add, positions while encode_c3d_frames rounds them)
  // before it is written; the first block that does not fit discards the file. For a .capz
  // source this saves decoding every window twice.
  bool skip_prescan() override {
    if (written_ != 0 || file_ || opts_.c3d_float || !header_.c3d || header_.c3d->float_storage ||
        scan_.scale == 0)
      return false;
    optimistic_ = true;
    return true;
  }
  bool needs_rewrite() const override { return rewrite_; }
  void write(const FrameBlock& b) override {
    bool fits = true;
    if (optimistic_) {  // the prescan's analog check here, its position check while rounding
      scan_.add(0, nullptr, nullptr, b.analog.size(), b.analog.data());
      fits = scan_.fits;
    }
    rewrite_ = false;
    if (fits) {
      start();
      if (b.first != written_ || b.points != plan_.points || written_ + b.frames > plan_.frames)
        fail(ErrorCode::kInternal, path_,
             "frames written out of order or beyond the header's count");
      buf_.assign(b.frames * plan_.per_frame, 0);
      c3d::encode_c3d_frames(plan_, b.frames, b.xyz.data(), b.valid.data(),
                             words_ ? b.residual.data() : nullptr,
                             words_ ? b.camera_mask.data() : nullptr, b.analog.data(), buf_.data(),
                             optimistic_ ? &fits : nullptr);
    }
    if (!fits) {      // the file cannot be int16 at the take's scale: float storage, then
      file_.reset();  // (the temporary file is removed, nothing was committed)
      written_ = 0;
      optimistic_ = false;
      rewrite_ = true;
      // What a prescan of every frame would conclude, without one (the plan reads only the
      // scale and the fit when the scale is known): every frame is written again, once.
      scan_ = c3d::C3DWriteScan();
      scan_.scale = c3d::c3d_known_scale(header_);
      scan_.fits = false;
      known_float_ = true;
      return;
    }
    file_->write(buf_);
    write_rotations(b);
    written_ += b.frames;
  }
  void commit() override {
    start();
    if (written_ != plan_.frames)
      fail(ErrorCode::kInternal, path_,
           std::to_string(written_) + " of " + std::to_string(plan_.frames) + " frames written");
    if (plan_.rot_bytes > 0) {  // zeros from the frames' end up to the rotations' block
      buf_.assign(plan_.rot_offset - plan_.head.size() - written_ * plan_.per_frame, 0);
      file_->write(buf_);
    }
    file_->commit();
  }

 private:
  // The block's rotations go straight to their place in the rotation section, which follows
  // every frame (the plan knows where): memory stays bounded by the block, and the frames
  // written later fill the file up to it.
  void write_rotations(const FrameBlock& b) {
    const size_t per_frame = header_.rotations.per_frame();
    const size_t n = b.frames * per_frame;
    if (b.rotation_matrices.size() != n * 16 || b.rotation_reliability.size() != n)
      fail(ErrorCode::kInternal, path_, "a block's rotations do not match its frames");
    if (n == 0) return;
    rot_buf_.resize(n * c3d::kRotationBytes);
    c3d::encode_c3d_rotations(b.rotation_matrices.data(), b.rotation_reliability.data(), n,
                              rot_buf_.data());
    file_->write_at(plan_.rot_offset + b.first * per_frame * c3d::kRotationBytes, rot_buf_.data(),
                    rot_buf_.size());
  }

  void start() {  // header and parameters, once every prescan block has been seen
    if (file_) return;
    plan_ = c3d::plan_c3d_file(header_, words_, opts_, scan_, path_);
    file_.reset(new AtomicFile(path_, opts_.overwrite));
    file_->write(plan_.head);
  }

  Take header_;
  bool words_;
  std::string path_;
  WriteOptions opts_;
  c3d::C3DWriteScan scan_;
  c3d::C3DFilePlan plan_;
  std::unique_ptr<AtomicFile> file_;
  std::vector<uint8_t> buf_, rot_buf_;
  size_t written_ = 0;
  bool optimistic_ = false;   // writing without a prescan (skip_prescan)
  bool known_float_ = false;  // a block did not fit int16: float storage, no prescan needed
  bool rewrite_ = false;
};

// A TRC written as it comes: the header lines at once, then rows.
class TRCSink : public FrameSink {
 public:
  TRCSink(const Take& header, const std::string& path, const WriteOptions& opts)
      : header_(header),
        path_(path),
        delim_(trc::output_delimiter(header, opts.trc_delimiter, path)),
        width_(delim_ == ',' ? trc::comma_width(header, path) : 0) {
    file_.reset(new AtomicFile(path, opts.overwrite));
    text_ = trc::header_text(header_, path_, delim_);
  }
  void write(const FrameBlock& b) override {
    if (b.first != written_ || b.points != header_.points || written_ + b.frames > header_.frames)
      fail(ErrorCode::kInternal, path_, "frames written out of order or beyond the header's count");
    trc::append_rows(header_, b.first, b.frames, b.xyz.data(), b.valid.data(), delim_, width_,
                     &text_);
    file_->write(text_.data(), text_.size());
    text_.clear();
    written_ += b.frames;
  }
  void commit() override {
    if (written_ != header_.frames)
      fail(ErrorCode::kInternal, path_,
           std::to_string(written_) + " of " + std::to_string(header_.frames) + " frames written");
    file_->write(text_.data(), text_.size());
    file_->commit();
  }

 private:
  Take header_;
  std::string path_;
  char delim_;
  size_t width_;
  std::unique_ptr<AtomicFile> file_;
  std::string text_;
  size_t written_ = 0;
};

}  // namespace

std::unique_ptr<FrameSource> open_c3d_frames(const std::string& path) {
  return std::unique_ptr<FrameSource>(new C3DSource(path));
}

std::unique_ptr<FrameSource> take_frames(const Take& take) {
  return std::unique_ptr<FrameSource>(new TakeSource(take, nullptr));
}

std::unique_ptr<FrameSource> handing_take_frames(Take take) {
  std::unique_ptr<Take> t(new Take(std::move(take)));
  const Take& ref = *t;
  return std::unique_ptr<FrameSource>(new TakeSource(ref, std::move(t), true));
}

std::unique_ptr<FrameSource> open_frames(const std::string& path) {
  const Format f = detect_format(path);
  if (f == Format::kC3D) return open_c3d_frames(path);
  if (f == Format::kTRC) return open_trc_frames(path);
  if (f == Format::kPCDFolder) return open_pcd_frames(path);
  if (f == Format::kPLYFolder) return open_ply_frames(path);
  if (f == Format::kBinFolder) return open_bin_frames(path);
  std::unique_ptr<Take> t(new Take(read_take(path)));
  const Take& ref = *t;
  return std::unique_ptr<FrameSource>(new TakeSource(ref, std::move(t)));
}

std::unique_ptr<FrameSource> open_frames(const std::string& path, const ReadOptions& opts) {
  if (opts.bin_fields.empty()) return open_frames(path);
  const std::vector<PCDField> record = declared_bin_record(path, opts);
  return open_bin_frames(path, &record);
}

std::unique_ptr<FrameSink> create_frame_sink(const Take& header, bool words,
                                             const std::string& path, const WriteOptions& opts) {
  const std::string target = without_trailing_slashes(path);
  const bool int16_from_data = c3d::c3d_known_scale(header) == 0 && header.c3d &&
                               !header.c3d->float_storage && !opts.c3d_float;
  const Format f = path.empty() ? Format::kUnknown : output_format(header, path, opts);
  if (f != Format::kUnknown) check_fields_fit(header, f, target, opts);
  if (f == Format::kC3D && !int16_from_data)
    return std::unique_ptr<FrameSink>(new C3DSink(header, words, target, opts));
  if (f == Format::kTRC) {
    check_output_free(target, opts.overwrite);
    return std::unique_ptr<FrameSink>(new TRCSink(header, target, opts));
  }
  // Folders of frame files, file by file as the blocks come; a single frame file from its block.
  const char* ext = frame_extension(f);
  if (*ext) {
    check_output_free(target, opts.overwrite, frames_go_beside);
    // path, not target: a trailing '/' says a folder (a folder named "x.ply/")
    if (f == Format::kPCDFolder) return pcd_folder_sink(header, path, opts);
    if (f == Format::kPLYFolder) return ply_folder_sink(header, path, opts);
    return bin_folder_sink(header, path, opts);
  }
  return std::unique_ptr<FrameSink>(new WholeTakeSink(header, words, path, opts));
}

void copy_frames(FrameSource& source, FrameSink& sink, size_t block) {
  const size_t F = source.header().frames;
  if (block == 0) block = 1;
  FrameBlock b;
  bool prescan = sink.wants_prescan() && !sink.skip_prescan();
  for (bool done = false; !done;) {
    if (prescan)
      for (size_t f = 0; f < F; f += block) {
        source.read(f, std::min(block, F - f), &b);
        sink.prescan(b);
      }
    done = true;
    for (size_t f = 0; f < F && done; f += block) {
      source.read(f, std::min(block, F - f), &b);
      sink.write(b);
      done = !sink.needs_rewrite();
    }
    prescan = sink.wants_prescan();  // before a rewrite, if the sink still needs one
  }
  sink.commit();
}

Take read_all_frames(FrameSource& source, const std::function<void(size_t, size_t)>& progress,
                     size_t block) {
  const Take& h = source.header();
  TakeCollector c(h, source.has_sample_words(), h.source);
  if (block == 0)  // (a source may prefer 0: at least one frame a read)
    block = std::max<size_t>(1, std::min<size_t>(source.preferred_block(), 64));
  // The take grows block by block (not sized for every file up front), so memory follows what
  // has been read and checked, not what the headers announce.
  FrameBlock b;
  for (size_t f = 0; f < h.frames; f += block) {
    const size_t n = std::min(block, h.frames - f);
    source.read(f, n, &b);
    c.add(b);
    if (progress) progress(f + n, h.frames);
  }
  Take t = c.release();
  for (const std::string& w : source.frame_warnings()) t.warnings.push_back(w);
  return t;
}

void write_frames(FrameSource& source, const std::string& path, const WriteOptions& opts,
                  size_t block) {
  std::unique_ptr<FrameSink> sink =
      create_frame_sink(source.header(), source.has_sample_words(), path, opts);
  copy_frames(source, *sink, block ? block : source.preferred_block());
}

}  // namespace capz

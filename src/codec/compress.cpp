// compress() and compress_stream() (capz/codec.h, capz/stream.h): the encoder driver run on a
// take or a frame source, once per codec, or for every codec under "auto".
#include <algorithm>
#include <memory>
#include <utility>

#include "capz/codec.h"
#include "capz/error.h"
#include "capz/stream.h"
#include "capz/tool/original.h"
#include "codec/encode_settings.h"
#include "codec/encoder.h"
#include "codec/registry.h"
#include "codec/residue_writer.h"
#include "codec/scan_encoder.h"
#include "codec/stream_reader.h"
#include "coding/container.h"
#include "coding/meta.h"
#include "core/atomic_file.h"
#include "io/frame_files.h"
#include "io/pcd_frame_writer.h"

namespace capz {

size_t auto_window_frames(size_t points) {
  size_t w = 1024;
  while (w < 8192 && w * points < (size_t{1} << 16)) w *= 2;
  return w;
}

namespace {

// What the encoder refuses of scans (format 1.1): --point-order any with --lossless. Throws
// kInvalidParameter.
void refuse_scans(const Take& t, const CompressOptions& opts) {
  if (opts.any_point_order && opts.lossless)  // FORMAT.md "Points reordered": bit 0 clear
    fail(ErrorCode::kInvalidParameter, t.source,
         "--point-order any with --lossless: a lossless archive gives the frame files back byte "
         "for byte, in their order; give --max-error, or keep the order");
}

// Whether a ragged take's frames are PLY or .bin frames, whose point layout META stores is
// settled first (settle_frame_layout; also without point fields).
bool settles_layout(const Take& take) {
  return !take.pcd && (take.format == Format::kPLYFolder || take.format == Format::kBinFolder);
}

// A ragged take given up (its arrays go to the coder's window, not copied: a one-frame take's
// x y z once in memory, not three times), PLY or .bin frames with their layout settled.
// original, organized: as compress_ragged's.
std::vector<uint8_t> compress_ragged_frames(Take&& take, const CompressOptions& opts,
                                            CompressStats* stats,
                                            const std::string& original = std::string(),
                                            bool organized = false) {
  // Its fields stay: a ring field guides the geometry coder, --drop-fields or not.
  if (settles_layout(take)) settle_frame_layout(&take, opts.drop_fields);
  return compress_ragged(std::move(take), opts, stats, original, organized);
}
// The same for a take the caller keeps: read where it is, or copied when its layout is settled.
std::vector<uint8_t> compress_ragged_frames(const Take& take, const CompressOptions& opts,
                                            CompressStats* stats,
                                            const std::string& original = std::string(),
                                            bool organized = false) {
  if (settles_layout(take))
    return compress_ragged_frames(Take(take), opts, stats, original, organized);
  return compress_ragged(take, opts, stats, original, organized);
}

// An organized cloud (PCD HEIGHT above 1): its layout kept through the scan coder (FORMAT.md
// "Ragged frames: HEAD and the window chunk").
bool organized_cloud(const Take& t) {
  return t.pcd && t.pcd->height > 1;
}

// A one-frame unorganized point cloud (a single LiDAR sweep, a depth camera's cloud with its
// NaN pixels dropped) may code smaller as a ragged take of one frame (format 1.1's scan coder
// finds the sensor's rings and firing order) than through POSW, whose predictors look at earlier
// frames: the encoder tries both and keeps the smaller stream. Not for transform codecs or KG
// targets (the scan coder has neither). An organized frame keeps its layout (frames of one
// organized shape): so not with --point-order any, which would move its points, nor --lossless
// (a lossless ragged stream has frames of their own counts, FORMAT.md "Ragged frames: HEAD and
// the window chunk").
bool scan_candidate(const Take& t, const CompressOptions& o) {
  const bool frame_files = is_frame_files(t.format);
  const bool unorganized = !organized_cloud(t);
  return !t.ragged() && t.frames == 1 && t.points > 1 && frame_files &&
         (unorganized || !o.any_point_order) && (o.codec.empty() || o.codec == "none") &&
         (o.lossless || o.max_error > 0) && t.analog.channels == 0 && t.rotations.segments == 0;
}

// The frame offsets of `frames` frames of n points each.
void uniform_offsets(size_t frames, size_t n, std::vector<size_t>* offsets) {
  offsets->resize(frames + 1);
  for (size_t f = 0; f <= frames; ++f) (*offsets)[f] = f * n;
}

// t as a ragged take of its frames (take.h: no labels, no shared point count).
Take as_ragged(Take t) {
  uniform_offsets(t.frames, t.points, &t.frame_offsets);
  t.points = 0;
  t.labels.clear();
  return t;
}

// The scan coder's stream of t's one frame (its report in *st when st is not null), or empty
// when the scan coder does not take it.
std::vector<uint8_t> one_frame_scan(Take t, const CompressOptions& opts, CompressStats* st,
                                    const std::string& original = std::string()) {
  const bool organized = organized_cloud(t);
  try {
    return compress_ragged_frames(as_ragged(std::move(t)), opts, st, original, organized);
  } catch (const Error& e) {
    if (e.code() != ErrorCode::kInvalidParameter) throw;
    return {};
  }
}

// The scan coder's stream of t's one frame when it is smaller than `fixed` (then *stats is its
// report), else empty. A take the scan coder does not take leaves `fixed` as it is.
std::vector<uint8_t> smaller_as_scan(const Take& t, const CompressOptions& opts,
                                     const std::vector<uint8_t>& fixed, CompressStats* stats) {
  CompressStats st;
  std::vector<uint8_t> scan = one_frame_scan(t, opts, stats ? &st : nullptr);
  if (scan.empty() || scan.size() >= fixed.size()) return {};
  if (stats) *stats = st;
  return scan;
}

// Frames [0, k) of `source` in memory, their per-frame metadata cut to them.
Take prefix_take(FrameSource& source, size_t k) {
  Take t = source.header();
  FrameBlock b;
  source.read(0, k, &b);
  slice_frame_metadata(0, k, t.frames, &t);
  t.frames = k;
  t.xyz = std::move(b.xyz);
  t.valid = std::move(b.valid);
  for (size_t a = 0; a < t.attributes.size() && a < b.attributes.size(); ++a)
    t.attributes[a].data = std::move(b.attributes[a]);
  return t;
}

// The fixed stream of `source` coded without its self-check, META as it is (coding 0) and, with
// attr_empty, the fields not coded, with positions_bound POSW's residuals not entropy-coded
// (EncoderTuning): its size less META's payload, plus the 1 byte any coding of META takes, is at
// most the size of the stream as the encoder writes it (INDX's offsets are fixed width). *meta:
// that stream's META chunk; returns the stream's size.
size_t fixed_bound(FrameSource& source, const CompressOptions& opts, bool attr_empty,
                   bool positions_bound, std::vector<uint8_t>* stream, Chunk* meta) {
  stream->clear();
  CompressOptions unchecked = opts;
  unchecked.check = false;
  EncoderTuning raw;
  raw.meta_raw = true;
  raw.attr_empty = attr_empty;
  raw.positions_bound = positions_bound;
  StreamOut mem(stream);
  encode_source(source, unchecked, raw, &mem, nullptr);
  const std::string what = source.header().source + " (size bound)";
  const Chunk head = read_chunk(stream->data(), stream->size(), kFileHeaderBytes, what);
  *meta = read_chunk(stream->data(), stream->size(), head.end, what);
  if (meta->type != "META" || meta->size > stream->size())
    fail(ErrorCode::kInternal, what, "no META after HEAD");
  return stream->size();
}

// The fixed take's stream of a one-frame source (the source itself: a lossless stream carries
// its residue), or the scan coder's when it is smaller (smaller_as_scan). The scan stream is
// coded first; the fixed stream is then bounded from below before it is coded (fixed_bound),
// cheapest bound first: with neither META nor the point fields coded and of the positions'
// residuals only their raw bits (the bits below their tokens: 3.2 to 5.9 times the scan stream's
// size on the shared single sweeps at 1 mm), then with the positions coded, then with the fields
// coded (the fields' LZMA and predictive trials: about three fifths of a pandar64 sweep's encode
// with its fields), then with META's fields coded alone, which makes the size exact. A scan stream
// under a bound is the smaller, as it is under the exact size. Only when the fixed stream is the
// smaller is it coded again, whole and checked, as always.
std::vector<uint8_t> one_frame_choice(FrameSource& source, const CompressOptions& opts,
                                      CompressStats* stats) {
  const std::string what = source.header().source + " (size bound)";
  const bool fields = !source.header().attributes.empty();  // else the two bounds are one
  CompressStats st;  // the frame moved into the scan coder's take, not copied
  std::vector<uint8_t> scan = one_frame_scan(prefix_take(source, source.header().frames), opts,
                                             stats ? &st : nullptr, residue_original(source, opts));
  // The scan stream with its report, when it is under `size`.
  const auto scan_under = [&](size_t size) {
    if (scan.size() >= size) return false;
    if (stats) *stats = st;
    return true;
  };
  if (!scan.empty()) {
    std::vector<uint8_t> bound;
    Chunk meta;
    if (scan_under(fixed_bound(source, opts, true, true, &bound, &meta) - meta.size + 1))
      return scan;
    for (const bool attr_empty : {true, false}) {
      if ((!attr_empty || fields) &&
          scan_under(fixed_bound(source, opts, attr_empty, false, &bound, &meta) - meta.size + 1))
        return scan;
    }
    // META coded as the encoder codes it (dictionary: C3D takes only): the fixed stream's size.
    const size_t coded = code_meta_fields(decode_meta_fields(meta, what), false).size();
    if (scan_under(bound.size() - meta.size + coded)) return scan;
  }
  std::vector<uint8_t> fixed;
  {
    StreamOut mem(&fixed);
    encode_source(source, opts, EncoderTuning(), &mem, stats);
  }
  return !scan.empty() && scan_under(fixed.size()) ? scan : fixed;
}

// Frames of one count through the scan coder, as frames of one organized shape (FORMAT.md
// "Ragged frames: HEAD and the window chunk"): an organized LiDAR sequence (Ouster's and
// Velodyne's ROS drivers write HEIGHT beams x WIDTH columns, a point without a return at NaN or
// 0 0 0) codes smaller that way than through POSW, whose prediction from the point of the same
// index in the frame before fails as the sensor turns; a mesh animation's or a static sensor's
// frames code smaller through POSW. For the coders and the sources the scan coder takes
// (scan_candidate's). With --point-order any an unorganized take's frames are coded as frames of
// their own counts that happen to be equal (keeps_shape), each reordered as the scan coder
// chooses; an organized take keeps its layout, so its order, and stays fixed.
bool fixed_scan_candidate(const Take& t, const CompressOptions& o) {
  return !t.ragged() && t.frames >= 2 && t.points > 1 && is_frame_files(t.format) &&
         (o.codec.empty() || o.codec == "none") && (o.lossless || o.max_error > 0) &&
         (!o.any_point_order || !organized_cloud(t)) && t.analog.channels == 0 &&
         t.rotations.segments == 0;
}

// The options a take is coded with: --point-order any leaves an organized cloud's order as it is
// (its layout gives each point its pixel; FORMAT.md "Ragged frames: HEAD and the window chunk":
// a stream of one shape keeps its order), so it is coded as with the order kept, both coders
// tried: never larger than asking for the order kept.
CompressOptions settled_order(const Take& t, const CompressOptions& o) {
  CompressOptions s = o;
  if (!t.ragged() && organized_cloud(t)) s.any_point_order = false;
  return s;
}

// Whether a fixed_scan_candidate's scan stream keeps the frames' shape (META's layout W x H,
// decoded as the fixed take): not when its points may be reordered (FORMAT.md "Ragged frames:
// HEAD and the window chunk": a stream of one shape keeps its order), whose layout is 0 x 1.
bool keeps_shape(const CompressOptions& o) {
  return !o.any_point_order;
}

// A fixed source's frames as a ragged take's, every frame of the source's count (take.h: no
// labels, no shared point count), for encode_ragged.
class FixedAsRagged : public FrameSource {
 public:
  explicit FixedAsRagged(FrameSource& fixed) : fixed_(fixed), n_(fixed.header().points) {
    header_ = fixed.header();
    header_.points = 0;
    header_.labels.clear();
    uniform_offsets(header_.frames, n_, &header_.frame_offsets);
  }
  bool has_sample_words() const override { return false; }
  size_t preferred_block() const override { return fixed_.preferred_block(); }
  uint64_t bytes_read() const override { return fixed_.bytes_read(); }
  std::string original_file() const override { return fixed_.original_file(); }
  void read(size_t first, size_t count, FrameBlock* out) override {
    fixed_.read(first, count, out);
    uniform_offsets(out->frames, n_, &out->frame_offsets);
    out->points = 0;
  }

 private:
  FrameSource& fixed_;
  size_t n_;
};

// Frames [0, k) of a fixed take in memory (k at most its frames): prefix_take's of a take read
// already.
Take first_frames(Take t, size_t k) {
  slice_frame_metadata(0, k, t.frames, &t);
  t.frames = k;
  t.xyz.resize(k * t.points * 3);
  t.valid.resize(k * t.points);
  for (PointAttribute& a : t.attributes)
    if (!a.data.empty()) a.data.resize(k * t.points * a.bytes_per_point());
  return t;
}

// Fixed take t coded through POSW, with opts as they are (its report in *stats when not null).
std::vector<uint8_t> posw_stream(const Take& t, const CompressOptions& opts,
                                 CompressStats* stats = nullptr,
                                 const EncoderTuning& tuning = EncoderTuning()) {
  std::unique_ptr<FrameSource> s = take_frames(t);  // holds t by reference
  std::vector<uint8_t> bytes;
  StreamOut mem(&bytes);
  encode_source(*s, opts, tuning, &mem, stats);
  return bytes;
}

// The size of POSW's stream of t for a trial (fixed_scan_choice, posw_without_trial): its fields'
// LZMA transforms estimated (EncoderTuning::attr_estimate), not each coded in full. The stream
// itself is coded again if kept.
size_t posw_trial_size(const Take& t, const CompressOptions& opts) {
  EncoderTuning trial;
  trial.attr_estimate = true;
  return posw_stream(t, opts, nullptr, trial).size();
}

// Fixed take t coded through the scan coder, with opts as they are (its report in *stats when not
// null); empty when the scan coder does not take it.
std::vector<uint8_t> scan_stream(Take t, const CompressOptions& opts, CompressStats* stats) {
  try {
    return compress_ragged_frames(as_ragged(std::move(t)), opts, stats, std::string(),
                                  keeps_shape(opts));
  } catch (const Error& e) {
    if (e.code() != ErrorCode::kInvalidParameter) throw;
  }
  return {};
}

// Fixed take t coded through POSW (*fixed) and through the scan coder (*scan, empty when it does
// not take it), with opts as they are; their reports in *fixed_stats and *scan_stats when those
// are not null.
void coded_both(Take t, const CompressOptions& opts, std::vector<uint8_t>* fixed,
                std::vector<uint8_t>* scan, CompressStats* fixed_stats = nullptr,
                CompressStats* scan_stats = nullptr) {
  *fixed = posw_stream(t, opts, fixed_stats);
  *scan = scan_stream(std::move(t), opts, scan_stats);
}

// The sizes of fixed take t coded through POSW (a trial's: posw_trial_size) and through the scan
// coder (0 when it does not take it), with opts as they are (fixed_scan_choice gives them
// unchecked).
std::pair<size_t, size_t> coded_sizes(Take t, const CompressOptions& opts) {
  const size_t fixed = posw_trial_size(t, opts);
  return {fixed, scan_stream(std::move(t), opts, nullptr).size()};
}

// Frames coded both ways, unchecked, on a prefix of the source (at most a window of either
// coder in memory).
constexpr size_t kPrefixFrames = 4;
// fixed_scan_choice's margin for reordered scan frames.
constexpr double kAnyMargin = 0.8;

// Whether a lossless fixed take t (2 frames or more) keeps POSW without the rest of the scan
// coder's trial, which costs about 15 times POSW's coding there (the float32 split's trials of
// `E`: docs/lab/2026-11-30-lossless-organized.md), its frames coded as opts say. *first: frame
// 0's sizes (POSW's, and the scan coder's when it was coded, else 0: fixed_scan_choice's estimate
// reuses them).
// - Frames that are not sweeps by their layout (neither organized nor with a gap in frame 0): a
//   mesh's vertices, or a sensor's sweeps of one count without gaps. The scan coder's frame 0
//   tells them apart: at least 8/10 of POSW's keeps POSW (the shared mesh animations 0.96-1.00:
//   no sensor geometry), below goes on (sweeps 0.46-0.65;
//   docs/lab/2026-11-30-lossless-fixed-count.md). A frame 0 with 1/200 of its points at exactly
//   0 0 0 (a sensor's padding for no return: the scan coder's gaps) goes on whatever its size
//   (Livox-like frames: 0.99 of POSW there in docs/lab/2026-11-30-user-inputs-2.md, the whole
//   take 0.77 of POSW's archive in docs/lab/2026-12-01-padded-fixed-count.md).
// - Sweeps: POSW's second frame under 6/10 of its first keeps POSW (a still sensor: per-index
//   prediction pays).
// Frame 0's points at exactly +0 +0 +0 (origin_point).
size_t origin_points(const Take& t) {
  size_t n = 0;
  for (size_t i = 0; i < t.points; ++i) n += origin_point(&t.xyz[3 * i]);
  return n;
}

bool posw_without_trial(const Take& t, const CompressOptions& opts,
                        std::pair<size_t, size_t>* first) {
  const bool gaps = std::find(t.valid.begin(), t.valid.begin() + static_cast<long>(t.points),
                              uint8_t{0}) != t.valid.begin() + static_cast<long>(t.points);
  const size_t one = posw_trial_size(first_frames(t, 1), opts);
  *first = {one, 0};
  if (!organized_cloud(t) && !gaps) {
    first->second = scan_stream(first_frames(t, 1), opts, nullptr).size();
    if (first->second != 0 && 200 * origin_points(t) >= t.points) return false;
    return first->second == 0 || 10 * first->second >= 8 * one;
  }
  const size_t two = posw_trial_size(first_frames(t, 2), opts);
  return 10 * (two - std::min(one, two)) < 6 * one;
}

// The stream of a source (fixed_scan_candidate) of at most kPrefixFrames frames: coded whole
// both ways, checked as opts say (*stats: the report of the stream kept), and the scan coder's
// kept when it is smaller (fixed_scan_choice's rule for such a take): the trial's bytes are the
// stream's, not coded a third time.
std::vector<uint8_t> short_fixed_choice(FrameSource& source, const CompressOptions& opts,
                                        CompressStats* stats) {
  std::vector<uint8_t> fixed, scan;
  CompressStats fixed_stats, scan_stats;
  coded_both(prefix_take(source, source.header().frames), opts, &fixed, &scan,
             stats ? &fixed_stats : nullptr, stats ? &scan_stats : nullptr);
  const bool scan_wins = !scan.empty() && scan.size() < fixed.size();
  if (stats) *stats = scan_wins ? scan_stats : fixed_stats;
  return scan_wins ? scan : fixed;
}

// Whether a take (fixed_scan_candidate) is coded both ways whole, the smaller kept
// (short_fixed_choice): a short one at a bound. A lossless stream needs its residue, which those
// in-memory codings lack: fixed_scan_choice chooses for it, and the kind chosen is coded again.
bool short_choice(const Take& t, const CompressOptions& opts) {
  return t.frames <= kPrefixFrames && !opts.lossless;
}

// Whether `source` (fixed_scan_candidate) codes smaller through the scan coder than through
// POSW. Its size is estimated from its first frame's and its first kPrefixFrames' (k): for either
// coder, s(1) + (F - 1) (s(k) - s(1)) / (k - 1), the first frame and then the others at the
// prefix's cost a frame (docs/lab/2026-11-30-fixed-count-scans.md); a source of at most k frames
// is coded whole both ways (short_fixed_choice's rule, for a lossless source, whose stream is then
// coded again with its residue).
bool fixed_scan_choice(FrameSource& source, const CompressOptions& opts) {
  CompressOptions o = opts;
  o.check = false;
  o.progress = nullptr;
  const size_t F = source.header().frames, k = std::min(F, kPrefixFrames);
  Take head = prefix_take(source, k);     // read once: the first frame's take is cut from it
  std::pair<size_t, size_t> known{0, 0};  // frame 0's sizes that posw_without_trial coded
  if (o.lossless && posw_without_trial(head, o, &known)) return false;
  if (k == F) {
    const std::pair<size_t, size_t> whole = coded_sizes(std::move(head), o);
    return whole.second != 0 && whole.second < whole.first;
  }
  Take frame0 = first_frames(head, 1);
  const std::pair<size_t, size_t> prefix = coded_sizes(std::move(head), o);
  if (prefix.second == 0) return false;
  std::pair<size_t, size_t> first = known;
  if (!first.first)  // at a bound
    first = coded_sizes(std::move(frame0), o);
  else if (!first.second)  // lossless sweeps: POSW's coded already
    first.second = scan_stream(std::move(frame0), o, nullptr).size();
  if (first.second == 0) return false;
  const auto estimate = [&](size_t one, size_t all) {
    return static_cast<double>(one) + static_cast<double>(F - 1) *
                                          (static_cast<double>(all) - static_cast<double>(one)) /
                                          static_cast<double>(k - 1);
  };
  const double scan = estimate(first.second, prefix.second),
               posw = estimate(first.first, prefix.first);
  if (!o.any_point_order || scan >= posw) return scan < posw;
  // Reordered (--point-order any), the scan coder's frames are mostly octree frames, each coded
  // on its own cells: its prefix's cost a frame is its cost a frame. POSW's later frames cost less
  // than its prefix's on long mesh animations (pcow at 1 cm: 377,410 B estimated, 265,172 coded),
  // so the reordered scan coder is taken under kAnyMargin of POSW, and above it where the order
  // kept would take the scan coder too (whose windows reordering only makes smaller): never
  // where the order kept keeps POSW on a near tie (docs/lab/2026-11-30-fixed-count-any.md).
  if (scan < kAnyMargin * posw) return true;
  CompressOptions kept = opts;
  kept.any_point_order = false;
  return fixed_scan_choice(source, kept);
}

std::vector<uint8_t> compress_with_codec(const Take& take, const CompressOptions& opts,
                                         const EncoderTuning& tuning, CompressStats* stats,
                                         bool allow_tout = true) {
  refuse_scans(take, opts);
  if (take.ragged()) return compress_ragged_frames(take, opts, stats);
  if (take.xyz.size() != take.frames * take.points * 3 ||
      take.valid.size() != take.frames * take.points)
    fail(ErrorCode::kInvalidParameter, take.source,
         "take arrays do not match its frame and point counts");
  const bool analog = take.analog.channels > 0 && take.analog.samples_per_frame > 0;
  if (analog && take.analog.values.size() !=
                    take.frames * static_cast<size_t>(take.analog.samples_per_frame) *
                        static_cast<size_t>(take.analog.channels))
    fail(ErrorCode::kInvalidParameter, take.source,
         "analog values do not match frames x samples x channels");
  std::unique_ptr<FrameSource> src = take_frames(take);
  std::vector<uint8_t> bytes;
  StreamOut out(&bytes);
  encode_source(*src, opts, tuning, &out, stats, allow_tout);
  return bytes;
}

// One codec; a transform-output stream that misses the KG target goes through the grid.
std::vector<uint8_t> compress_one(const Take& take, const CompressOptions& opts,
                                  const EncoderTuning& tuning, CompressStats* stats) {
  try {
    return compress_with_codec(take, opts, tuning, stats);
  } catch (const TransformMissedTarget&) {
    return compress_with_codec(take, opts, tuning, stats, false);
  }
}
}  // namespace

// "auto" tries every candidate stage on the whole take and keeps the smallest stream: the plain
// coder ("none") first, then each registered transform. A transform that cannot run on this
// take (e.g. pdct on fewer than 3 points) is skipped, never fatal, so auto is never worse than
// "none". Encode time is the sum of all candidates' (about 3x), decode time is the winner's.
std::vector<uint8_t> compress_tuned(const Take& take, const CompressOptions& opts,
                                    const EncoderTuning& tuning, CompressStats* stats) {
  if (opts.codec != "auto") return compress_one(take, opts, tuning, stats);
  // Options are checked before any trial: a mistyped key is the user's error, not a reason to
  // skip a codec. Under auto a key must name its codec ("ts.lpc_order=2").
  for (const auto& kv : opts.codec_options)
    if (kv.first.find('.') == std::string::npos)
      fail(ErrorCode::kInvalidParameter, take.source,
           "--codec auto: name the codec of option '" + kv.first + "' (e.g. ts." + kv.first + ")");
  for (const TransformCodec* c : all_codecs()) {
    TransformParams p;
    p.clusters = opts.clusters;
    p.options = options_for(*c, opts.codec_options);
    c->check_params(p);
  }
  CompressOptions o = opts;
  o.codec = "none";
  o.codec_options.clear();
  CompressStats best_stats;
  std::vector<uint8_t> best = compress_with_codec(take, o, tuning, &best_stats);
  if (!opts.lossless) {
    for (const TransformCodec* c : all_codecs()) {
      o.codec = c->name();
      o.codec_options = opts.codec_options;
      CompressStats st;
      std::vector<uint8_t> out;
      try {
        out = compress_one(take, o, tuning, &st);
      } catch (const Error& e) {
        if (e.code() != ErrorCode::kInvalidParameter) throw;
        continue;  // this stage does not apply to the take
      }
      if (out.size() < best.size()) {
        best.swap(out);
        best_stats = st;
      }
    }
  }
  if (stats) *stats = best_stats;
  return best;
}

// A ragged take made of arrays (no frame-file format: Python's Take.from_arrays with a list of
// frames) as the PCD folder capz writes of it (pcd_frame_plan's layout: x y z float32 when every
// valid coordinate is one, else float64, then its fields; the writer's frame names), which is what
// its archive decodes to. The scan coder codes frames of their own counts of frame files only.
Take as_pcd_frames(const Take& t) {
  Take p = t;
  p.format = Format::kPCDFolder;
  p.pcd = std::make_shared<PCDExtra>();
  p.pcd->fields = pcd_frame_plan(t, "binary", std::nullopt).layout.fields;
  p.pcd->frame_names = frame_output_names(t, ".pcd");
  return p;
}

std::vector<uint8_t> compress(const Take& take, const CompressOptions& asked,
                              CompressStats* stats) {
  if (take.ragged() && take.format == Format::kUnknown && take.analog.channels == 0 &&
      take.rotations.segments == 0 && take.shape_fault().empty())
    return compress(as_pcd_frames(take), asked, stats);
  refuse_scans(take, asked);
  const CompressOptions opts = settled_order(take, asked);
  if (fixed_scan_candidate(take, opts) && take.xyz.size() == take.frames * take.points * 3 &&
      take.valid.size() == take.frames * take.points) {  // else compress_with_codec refuses it
    std::unique_ptr<FrameSource> src = take_frames(take);
    if (short_choice(take, opts)) return short_fixed_choice(*src, opts, stats);
    if (fixed_scan_choice(*src, opts))
      return compress_ragged_frames(as_ragged(take), opts, stats, std::string(), keeps_shape(opts));
  }
  std::vector<uint8_t> fixed = compress_tuned(take, opts, EncoderTuning(), stats);
  if (!scan_candidate(take, opts)) return fixed;
  std::vector<uint8_t> scan = smaller_as_scan(take, opts, fixed, stats);
  return scan.empty() ? fixed : scan;
}

namespace {

// A lossless archive of frame files (PCD, PLY, .bin) is rebuilt from its temporary file by the
// decoder itself, its size and hash against HASH's, before it is renamed into place. The
// encoder's self-check rebuilds each window with the residue decoder it built from its own view
// of the take; this one reads the stream as `capz decompress` will, so that a disagreement
// between the two views (an archive that compresses but does not decompress) never reaches the
// output. Costs one decode (p20 --lossless: 8.62 -> 9.21 user s, one run each).
void commit_rebuilt(AtomicFile* file, const FrameSource& source, const CompressOptions& opts) {
  if (opts.lossless && opts.check && is_frame_files(source.header().format)) {
    const std::string& tmp = file->temp_path();
    if (can_rebuild(original_info(tmp), false)) {
      try {
        test_original(tmp);
      } catch (const Error& e) {
        fail(ErrorCode::kInternal, source.header().source,
             std::string("self-check failed: the archive does not rebuild the frame files "
                         "through the decoder (") +
                 e.what() + "; please report this, --no-check skips the check)");
      }
    }
  }
  file->commit();
}

}  // namespace

void compress_stream(FrameSource& source, const CompressOptions& asked, const std::string& path,
                     bool overwrite, CompressStats* stats) {
  refuse_scans(source.header(), asked);
  const CompressOptions opts = settled_order(source.header(), asked);
  if (source.header().ragged()) {  // two passes, a window in memory (encode_ragged)
    settle_frame_layout(&source.edit_header(), opts.drop_fields);
    AtomicFile file(path, overwrite);
    StreamOut out(&file);
    encode_ragged(source, opts, &out, stats, residue_original(source, opts));
    commit_rebuilt(&file, source, opts);
    return;
  }
  // A stream coded in memory (both codings of a short source, of one frame), written whole.
  const auto write = [&](std::vector<uint8_t> bytes) {
    AtomicFile file(path, overwrite);
    StreamOut out(&file);
    out.flush(&bytes);
    commit_rebuilt(&file, source, opts);
  };
  if (fixed_scan_candidate(source.header(), opts) && short_choice(source.header(), opts))
    return write(short_fixed_choice(source, opts, stats));
  if (fixed_scan_candidate(source.header(), opts) && fixed_scan_choice(source, opts)) {
    FixedAsRagged ragged(source);  // frames of one count, as ragged frames (encode_ragged)
    settle_frame_layout(&ragged.edit_header(), opts.drop_fields);
    AtomicFile file(path, overwrite);
    StreamOut out(&file);
    encode_ragged(ragged, opts, &out, stats, residue_original(source, opts), keeps_shape(opts));
    commit_rebuilt(&file, source, opts);
    return;
  }
  if (scan_candidate(source.header(), opts))  // one frame: both codings in memory
    return write(one_frame_choice(source, opts, stats));
  if (opts.codec == "auto")
    fail(ErrorCode::kInvalidParameter, source.header().source,
         "codec auto compares whole-take encodings and is not streamed");
  try {
    AtomicFile file(path, overwrite);
    StreamOut out(&file);
    encode_source(source, opts, EncoderTuning(), &out, stats);
    commit_rebuilt(&file, source, opts);
  } catch (const TransformMissedTarget&) {  // a second pass through the grid (compress_one)
    AtomicFile file(path, overwrite);
    StreamOut out(&file);
    encode_source(source, opts, EncoderTuning(), &out, stats, false);
    commit_rebuilt(&file, source, opts);
  }
}

}  // namespace capz

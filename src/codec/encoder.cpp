// The encoder driver (encoder.h): resolve the options, scan the take, choose the grid, write the
// header, then encode and check each window, and sum up the stats.
#include "codec/encoder.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <deque>
#include <exception>
#include <future>
#include <map>
#include <memory>
#include <string>

#include "capz/error.h"
#include "capz/tool/verify.h"
#include "codec/decoder.h"
#include "codec/encode_settings.h"
#include "codec/grid.h"
#include "codec/grid_choice.h"
#include "codec/registry.h"
#include "codec/residue_writer.h"
#include "codec/stream_reader.h"
#include "codec/transform_output.h"
#include "codec/window_error.h"
#include "coding/analog/analog_codec.h"
#include "coding/analog/analog_quant.h"
#include "coding/attributes.h"
#include "coding/bytes.h"
#include "coding/c3d_words.h"
#include "coding/container.h"
#include "coding/mask.h"
#include "coding/meta.h"
#include "coding/positions.h"
#include "coding/rotations.h"
#include "core/thread_pool.h"

namespace capz {

void StreamOut::flush(std::vector<uint8_t>* buf) {
  if (mem_) {
    mem_->insert(mem_->end(), buf->begin(), buf->end());
  } else {
    file_->write(*buf);
  }
  size_ += buf->size();
  buf->clear();
}

std::map<std::string, std::string> options_for(const TransformCodec& codec,
                                               const std::map<std::string, std::string>& all) {
  std::map<std::string, std::string> mine;
  for (const auto& kv : all) {
    const size_t dot = kv.first.find('.');
    if (dot == std::string::npos) {
      mine[kv.first] = kv.second;
      continue;
    }
    const std::string prefix = kv.first.substr(0, dot);
    if (!find_codec(prefix))
      fail(ErrorCode::kInvalidParameter, "",
           "--codec-opt " + kv.first + ": '" + prefix + "' is not a codec (ts, pdct)");
    if (prefix == codec.name()) mine[kv.first.substr(dot + 1)] = kv.second;
  }
  return mine;
}

namespace {

std::vector<uint8_t> with_window_index(size_t w, uint8_t flag, const std::vector<uint8_t>& body) {
  ByteWriter b;
  b.varint(w);
  if (flag != 0xFF) b.u8(flag);
  b.bytes(body);
  return std::move(b.buffer());
}

// What the options resolve to for this take, before anything is read.
struct Plan {
  size_t W = 0;                           // frames per window
  bool words = false;                     // C3D 4th words are coded (C3DW)
  double point_scale = 0;                 // the take's POINT:SCALE (0 without C3D)
  const TransformCodec* codec = nullptr;  // the transform stage, nullptr for none
  // Only a KG target and a transform: the transform's reconstruction is the output, no grid and
  // no bound layer (FORMAT.md 4.3 "transform output"); the transform meets the KG target itself.
  bool tout = false;
  double written_scale = 0;  // with tout: the int16 scale `capz decompress` writes at, or 0
  bool analog = false;
  size_t S = 0, C = 0;  // analog samples per frame and channels (0 without analog)
  size_t R = 0, G = 0;  // rotation samples per frame and segments (0 without rotations)
};

Plan resolve(const FrameSource& source, const CompressOptions& opts, bool allow_tout) {
  const Take& take = source.header();
  const std::string& src = take.source;
  // Up to 8192 frames a window keeps even an all-gap window above the decoder's plausibility
  // floor of one byte per 2900 samples (docs/FORMAT.md 3.6).
  if (opts.window_frames > 8192)
    fail(ErrorCode::kInvalidParameter, src, "window size must be 1 .. 8192 frames");
  Plan p;
  const size_t F = take.frames, N = take.points;
  // Transform codecs keep 1024-frame windows by default (their cost grows with the window).
  const bool plain = opts.codec.empty() || opts.codec == "none";
  p.W = opts.window_frames ? opts.window_frames : plain ? auto_window_frames(N) : 1024;
  p.words = source.has_sample_words();
  p.point_scale = take.c3d ? take.c3d->point_scale : 0;
  if (!plain) {
    p.codec = find_codec(opts.codec);
    if (!p.codec) fail(ErrorCode::kInvalidParameter, src, "unknown codec '" + opts.codec + "'");
  } else if (!opts.codec_options.empty()) {
    fail(ErrorCode::kInvalidParameter, src,
         "--codec-opt " + opts.codec_options.begin()->first + ": codec none takes no options");
  }
  p.tout = allow_tout && !opts.lossless && opts.kg_error > 0 && p.codec && N > 0 && F > 0;
  p.written_scale = p.tout ? written_int16_scale(take) : 0.0;
  p.analog = take.analog.channels > 0 && take.analog.samples_per_frame > 0;
  p.S = p.analog ? static_cast<size_t>(take.analog.samples_per_frame) : 0;
  p.C = p.analog ? static_cast<size_t>(take.analog.channels) : 0;
  // A window holds at most kMaxWindowAnalogValues analog values (32 MiB of doubles): fewer
  // frames a window when a frame has many, so that coding, and decoding under the default
  // memory limit, keep a window's memory bounded whatever the take's analog layout.
  if (p.analog) p.W = std::max<size_t>(1, std::min(p.W, kMaxWindowAnalogValues / (p.S * p.C)));
  if (take.rotations.per_frame() > 0) {
    p.R = static_cast<size_t>(take.rotations.samples_per_frame);
    p.G = static_cast<size_t>(take.rotations.segments);
  }
  return p;
}

// One window in the pipeline: everything the coding of window w reads and writes, so windows are
// coded on worker threads independently of each other (docs/ARCHITECTURE.md "Threads").
struct Window {
  size_t w = 0;
  FrameBlock block;                   // the frames as read from the source
  FrameBlock back;                    // the frames as the decoder gives them back (with opts.check)
  WindowInts wi;                      // the window's integers on the grid, with its gap mask
  std::vector<double> rec;            // the reconstruction the decoder must produce (valid samples)
  std::vector<uint8_t> buf;           // the window's chunks, as they go into the stream
  double centred = 0, kg_budget = 0;  // transform output: centred energy, squared-error budget
  size_t position_bytes = 0, analog_bytes = 0, rotation_bytes = 0, attribute_bytes = 0;
  size_t other_bytes = 0;
  std::exception_ptr error;  // what coding the window threw, rethrown when it is emitted
  std::future<void> done;    // ready when a worker has coded it (invalid: coded in place)
};

// Half a unit of the last decimal a TRC source printed its coordinates with (a hair more, for
// the double arithmetic): what the TRC writer's rounding may add; 0 for other sources.
double trc_print_room(const Take& t) {
  if (t.format != Format::kTRC || !t.trc || t.trc->decimals < 0) return 0;
  return 0.5 * std::pow(10.0, -t.trc->decimals) * (1.0 + 0x1p-20);
}

// The quantiser's view of each channel of a take with lossy analog channels (FORMAT.md 16.3);
// empty when every channel is lossless.
std::vector<analog::ChannelBound> analog_channel_bounds(const Take& t) {
  std::vector<analog::ChannelBound> out;
  if (!t.analog.lossy()) return out;
  const std::vector<AnalogPhysics> phys = analog_physics(t);
  out.resize(phys.size());
  for (size_t c = 0; c < phys.size(); ++c) {
    analog::ChannelBound& b = out[c];
    b.bound = c < t.analog.bounds.size() ? t.analog.bounds[c] : 0;
    b.factor = c < t.analog.factors.size() ? t.analog.factors[c] : 1;
    b.offset = phys[c].offset;
    b.integers = phys[c].integers;
    b.lo = phys[c].lo;
    b.hi = phys[c].hi;
  }
  return out;
}

class Encoder {
 public:
  // original: residue_original(source, opts), taken before settle_fields.
  Encoder(FrameSource& source, const CompressOptions& opts, const EncoderTuning& tuning,
          StreamOut* out, bool allow_tout, const std::string& original)
      : source_(source),
        take_(source.header()),
        opts_(opts),
        tuning_(tuning),
        out_(out),
        plan_(resolve(source, opts, allow_tout)),
        residue_(ResidueWriter::open(original, source.header(), opts.check)) {}

  void run(CompressStats* stats) {
    if (plan_.analog) {
      hints_ = analog_hints(take_);
      abounds_ = analog_channel_bounds(take_);
    }
    scan();
    choose_grid();
    set_transform_params();
    write_header();
    code_windows();
    if (residue_) residue_->finish();
    std::vector<uint8_t> buf;
    append_chunk(&buf, "INDX", encode_index(index_));
    other_bytes_ += buf.size();
    out_->flush(&buf);
    if (stats) fill_stats(stats);
  }

 private:
  // Pass 1: what the grid and the per-take coding choices depend on.
  void scan() {
    scan_ = start_scan(take_, opts_);
    if (!plan_.tout) cache_kg_coordinates(take_, tuning_.kg_cache_bytes, &scan_);
    const size_t F = take_.frames, W = plan_.W;
    FrameBlock block;
    for (size_t f0 = 0; f0 < F; f0 += W) {
      source_.read(f0, std::min(W, F - f0), &block);
      scan_block(block, take_.source, plan_.words, plan_.point_scale, &scan_);
    }
  }

  void choose_grid() {
    if (plan_.tout) {
      g_.mode = PosMode::kGrid;  // step 0, bound 0: nothing is quantised
    } else if (opts_.lossless) {
      g_ = lossless_grid(scan_);
    } else if (opts_.kg_error > 0) {
      FrameBlock block;  // scratch
      g_ = kg_grid(source_, scan_, opts_.kg_error, plan_.W, &block);
      std::vector<double>().swap(scan_.kg_coords);  // not needed by the coding pass
    } else if (opts_.max_error > 0 && std::isfinite(opts_.max_error)) {
      // A TRC written back prints each coordinate rounded to the source's decimals (the TRC
      // writer), which moves it by up to half a unit of the last decimal: the grid keeps that
      // room so the written file holds the bound too. A bound within that room is below the
      // file's own precision: the file's decimal grid (lossless) is the only output within it.
      const double room = trc_print_room(take_);
      if (room > 0 && opts_.max_error <= room)
        g_ = lossless_grid(scan_);
      else
        g_ = bounded_grid(take_, scan_, opts_.max_error - room);
    } else {
      fail(ErrorCode::kInvalidParameter, take_.source,
           "no error target: give a positive max error, a KG error target, or lossless");
    }
  }

  void set_transform_params() {
    tparams_.max_error = plan_.tout ? 0.0 : g_.bound > 0 ? g_.bound : g_.step / 2;
    tparams_.grid_step = g_.step;
    tparams_.kg_error = opts_.kg_error;
    tparams_.clusters = opts_.clusters;
    if (plan_.codec) {
      tparams_.options = options_for(*plan_.codec, opts_.codec_options);
      plan_.codec->check_params(tparams_);
    }
    if (g_.mode != PosMode::kGrid) plan_.codec = nullptr;  // float-bit lossless: prediction only
  }

  // HEAD and META; the decoder's context for the self-check is read back from them.
  void write_header() {
    StreamHeader h;
    h.frames = take_.frames;
    h.points = static_cast<uint32_t>(take_.points);
    h.window_frames = static_cast<uint32_t>(plan_.W);
    h.source_format = take_.format;
    h.bin_record_declared = declares_bin_record(take_, opts_.drop_fields);
    h.mode = g_.mode;
    h.codec = plan_.codec ? plan_.codec->id() : 0;
    // FORMAT.md 5.7: with a lossy analog channel the stream is not lossless, whatever its
    // positions are.
    h.lossless = g_.lossless && abounds_.empty();
    h.transform_output = plan_.tout;
    h.kg_target = plan_.tout ? opts_.kg_error : 0.0;
    h.step = g_.step;
    h.max_error = g_.bound;
    h.analog_channels = static_cast<uint32_t>(plan_.C);
    h.analog_samples_per_frame = static_cast<uint32_t>(plan_.S);
    h.rotation_segments = static_cast<uint32_t>(plan_.G);
    h.rotation_samples_per_frame = static_cast<uint32_t>(plan_.R);
    // Candidates the scan makes worth trying (every coding is allowed in every stream):
    // predictor 10 for points the scan found on their rays (FORMAT.md 7.1), repeat lists for
    // analog channels repeating whole frames (7.2), META's dictionary for C3D takes (8.1).
    if (on_rays(scan_)) ray_ = ray_kind(g_.mode);
    analog_repeats_ = plan_.analog && analog_repeats_worth(scan_, take_.frames);
    const std::vector<uint8_t> meta_payload =
        tuning_.meta_raw ? encode_meta_raw(take_, plan_.words)
                         : encode_meta(take_, plan_.words, take_.c3d != nullptr);
    std::vector<uint8_t> buf;
    // "Scans (format 1.1)": PLY and .bin frames are a frame-file source (HEAD feature bit 4).
    write_file_header(&buf, h.frame_file_source() ? kFormatScans.minor : kFormatWritten.minor);
    append_chunk(&buf, "HEAD", encode_header(h));
    const size_t meta_at = buf.size();
    append_chunk(&buf, "META", meta_payload);
    if (residue_) residue_->file_chunks(&buf, h.lossless);
    if (opts_.check) {
      Promise p;
      p.kind = plan_.tout    ? Promise::Kind::kKgTarget
               : g_.lossless ? Promise::Kind::kLossless
                             : Promise::Kind::kBound;
      p.max_error = g_.bound;
      p.analog_bounds = take_.analog.bounds;
      p.analog_factors = take_.analog.factors;
      p.kg_target = plan_.tout ? opts_.kg_error : 0.0;
      promise_ = p;
      const std::string what = take_.source + " (self-check)";
      const Chunk head = read_chunk(buf.data(), buf.size(), kFileHeaderBytes, what);
      const Chunk meta = read_chunk(buf.data(), buf.size(), meta_at, what);
      const StreamFeatures f = check_file_header(buf.data(), buf.size(), what);
      ctx_ = read_context(decode_header(head, what, f), meta, f, what);
    }
    other_bytes_ = buf.size();
    out_->flush(&buf);
  }

  // The windows in order, read serially from the source, coded by opts.threads workers (in
  // place with one), emitted in order: at most threads + 1 windows are in flight. Whatever a
  // window throws is rethrown when its turn to be emitted comes, after every earlier window, so
  // the stream and the error are those of a serial run.
  void code_windows() {
    const size_t F = take_.frames, W = plan_.W;
    // No more workers than windows (a short take starts none).
    const size_t T = std::min(resolve_threads(opts_.threads), (F + W - 1) / W);
    std::deque<std::unique_ptr<Window>> flight, spare;
    // Declared after the windows: destroyed first, it joins the workers before the windows go.
    std::unique_ptr<ThreadPool> pool(T > 1 ? new ThreadPool(T) : nullptr);
    const size_t cap = T > 1 ? T + 1 : 1;
    std::exception_ptr read_error;
    for (size_t w = 0, f0 = 0; f0 < F || !flight.empty();) {
      if (f0 < F && !read_error && flight.size() < cap) {
        std::unique_ptr<Window> win;
        if (spare.empty()) {
          win.reset(new Window);
        } else {
          win = std::move(spare.front());
          spare.pop_front();
        }
        win->w = w;
        win->error = nullptr;
        try {
          source_.read(f0, std::min(W, F - f0), &win->block);
        } catch (...) {  // rethrown after the windows before it
          read_error = std::current_exception();
          continue;
        }
        Window* p = win.get();
        if (pool)
          win->done = pool->submit([this, p] { code(p); });
        else
          code(p);
        flight.push_back(std::move(win));
        ++w;
        f0 += W;
        continue;
      }
      if (flight.empty()) break;  // only after a read error
      std::unique_ptr<Window> win = std::move(flight.front());
      flight.pop_front();
      if (win->done.valid()) win->done.get();
      emit(win.get());
      spare.push_back(std::move(win));
    }
    if (read_error) std::rethrow_exception(read_error);
  }

  // What a worker does with a window: encode, check the bound, decode and compare.
  void code(Window* win) {
    try {
      encode_window(win);
      check_bound(*win);
      if (opts_.check) check_window(win);
    } catch (...) {
      win->error = std::current_exception();
    }
  }

  // Window w into the stream, in order: its error stats, its residue chunk, its INDX entry.
  void emit(Window* win) {
    if (win->error) std::rethrow_exception(win->error);
    const FrameBlock& b = win->block;
    acc_.add(b.frames, take_.points, b.xyz.data(), win->rec.data(), win->wi.valid.data());
    IndexEntry ie;
    ie.offset = out_->size();
    if (residue_) residue_->window_chunk(win->w, b, opts_.check ? &win->back : nullptr, &win->buf);
    ie.bytes = win->buf.size();
    index_.push_back(ie);
    position_bytes_ += win->position_bytes;
    analog_bytes_ += win->analog_bytes;
    rotation_bytes_ += win->rotation_bytes;
    attribute_bytes_ += win->attribute_bytes;
    other_bytes_ += win->other_bytes;
    out_->flush(&win->buf);
    if (opts_.progress)
      opts_.progress(std::min((win->w + 1) * plan_.W, take_.frames), take_.frames);
  }

  // The transform's reconstruction of the window (codec_bytes: its payload), rerun with a lower
  // target when transform output written to an int16 C3D would miss the KG target.
  void run_transform(const Window& win, std::vector<uint8_t>* codec_bytes,
                     std::vector<double>* recon) const {
    const FrameBlock& block = win.block;
    const WindowInts& wi = win.wi;
    const size_t fn = block.frames, N = take_.points;
    std::vector<double> filled = fill_gaps(fn, N, block.xyz.data(), block.valid.data());
    PositionsView view{fn, N, filled.data(), wi.valid.data()};
    TransformParams wp = tparams_;
    for (int attempt = 0;; ++attempt) {
      codec_bytes->clear();  // encode appends
      recon->clear();
      plan_.codec->encode(view, wp, codec_bytes, recon);
      if (recon->size() != fn * N * 3)
        throw Error(ErrorCode::kInternal, std::string("codec ") + plan_.codec->name() +
                                              " returned a reconstruction of the wrong size");
      // Transform output decompressed to an int16 C3D is rounded once more to the file's
      // scale, which adds error the codec did not see. When the rounded window misses the KG
      // target, the codec is run again with the target lowered by what the rounding added
      // (squared errors add: e_t^2 + rounding = target^2), at most three times; the check
      // then holds both the decoded and the written values to the target.
      if (!plan_.tout || plan_.written_scale == 0 || attempt == 3) break;
      const double e_t = window_sq_error(fn, N, block.xyz.data(), recon->data(), wi.valid.data());
      const double e_w = window_sq_error(fn, N, block.xyz.data(), recon->data(), wi.valid.data(),
                                         plan_.written_scale);
      if (e_w <= win.kg_budget || !(win.centred > 0)) break;
      const double room = win.kg_budget - std::max(0.0, e_w - e_t);
      if (!(room > 0)) break;  // the rounding alone exceeds the target: the grid fallback
      wp.kg_error = 100 * std::sqrt(0.98 * room / win.centred);
    }
  }

  // The window's chunks into win->buf, its reconstruction into win->rec.
  void encode_window(Window* win) const {
    if (take_.attributes.empty()) win->block.attributes.clear();  // none, or left out (drop_fields)
    const FrameBlock& block = win->block;
    const size_t w = win->w, fn = block.frames, N = take_.points;
    win->wi = quantise_window(block, g_);
    const WindowInts& wi = win->wi;
    std::vector<uint8_t> codec_bytes;
    std::vector<int32_t> tpred;
    std::vector<double> recon;
    // With transform output: the window's centred energy and its squared-error budget.
    win->centred = plan_.tout ? centred_sq_window(fn, N, block.xyz.data(), wi.valid.data()) : 0;
    win->kg_budget = opts_.kg_error / 100 * (opts_.kg_error / 100) * win->centred;
    if (plan_.codec && N > 0) {
      run_transform(*win, &codec_bytes, &recon);
      if (!plan_.tout) tpred = grid_prediction(recon, g_.step);
    }
    std::vector<uint8_t>& buf = win->buf;
    buf.clear();
    const bool gaps = std::find(wi.valid.begin(), wi.valid.end(), 0) != wi.valid.end();
    const bool f64 = g_.mode == PosMode::kFloat64;
    const std::vector<uint8_t> pos = plan_.tout ? transform_only_positions(codec_bytes)
                                     : tuning_.positions_bound
                                         ? encode_positions_bound(wi, codec_bytes, tpred, f64, ray_)
                                         : encode_positions(wi, codec_bytes, tpred, f64, ray_);
    append_chunk(&buf, "POSW", with_window_index(w, gaps ? 1 : 0, pos));
    if (gaps)
      append_chunk(&buf, "MASK", with_window_index(w, 0xFF, encode_mask(wi.valid.data(), fn, N)));
    win->position_bytes = buf.size();
    if (plan_.words) {
      const size_t before = buf.size();
      const std::vector<uint8_t> cw =
          encode_c3d_words(block.residual.data(), block.camera_mask.data(), wi.valid.data(), fn * N,
                           N, plan_.point_scale, plan_.words && scan_.words_on_grid);
      append_chunk(&buf, "C3DW", with_window_index(w, 0xFF, cw));
      win->other_bytes = buf.size() - before;
    }
    if (plan_.analog) {
      const size_t before = buf.size();
      const double* rows = block.analog.data();
      std::vector<double> moved;  // FORMAT.md 16.3: the bounded channels quantised
      AnalogHints hints = hints_;
      if (!abounds_.empty()) {
        moved = block.analog;
        analog::quantise_window(moved.data(), fn * plan_.S, abounds_, &hints.channel);
        rows = moved.data();
      }
      const std::vector<uint8_t> an = encode_analog_window(
          rows, fn * plan_.S, take_.analog.channels, hints, analog_repeats_ ? plan_.S : 0);
      append_chunk(&buf, "ANLG", with_window_index(w, 0xFF, an));
      win->analog_bytes = buf.size() - before;
    }
    if (plan_.G > 0) append_rotations(win);
    if (!take_.attributes.empty()) append_attributes(win);
    reconstruct(block.frames, wi, recon, &win->rec);
  }

  // ROTW (FORMAT.md 12): the window's rotation samples, lossless whatever the bound.
  void append_rotations(Window* win) const {
    const FrameBlock& block = win->block;
    std::vector<uint8_t>* buf = &win->buf;
    const size_t samples = block.frames * plan_.R, n = samples * plan_.G;
    if (block.rotation_matrices.size() != n * 16 || block.rotation_reliability.size() != n)
      fail(ErrorCode::kInternal, take_.source, "a block's rotations do not match its frames");
    const size_t before = buf->size();
    const std::vector<uint8_t> rot = encode_rotations(
        block.rotation_matrices.data(), block.rotation_reliability.data(), samples, plan_.G);
    append_chunk(buf, "ROTW", with_window_index(win->w, 0xFF, rot));
    win->rotation_bytes = buf->size() - before;
  }

  // ATTR (FORMAT.md 13): the window's point fields, lossless whatever the bound but for the
  // float fields given a bound of their own (--attr-error), quantised where that codes smaller
  // (encode_attributes_within: the block then holds the values the decoder gives back).
  void append_attributes(Window* win) const {
    std::vector<uint8_t>* buf = &win->buf;
    const size_t before = buf->size();
    if (tuning_.attr_empty) {  // EncoderTuning: a size bound
      append_chunk(buf, "ATTR", with_window_index(win->w, 0xFF, {}));
      win->attribute_bytes = buf->size() - before;
      return;
    }
    const std::vector<uint8_t> at = encode_attributes_within(
        attribute_specs(take_.pcd->fields), attribute_bounds(*take_.pcd), &win->block.attributes,
        win->wi.valid.data(), win->block.frames, take_.points, take_.pcd->width,
        // FORMAT.md 7.3: predictors 10 and 11 are candidates for an unorganized
        // cloud's fields (an organized one has its pixel neighbours).
        take_.pcd->height == 1 && !plan_.tout ? win->wi.q.data() : nullptr, tuning_.attr_estimate,
        nullptr, tuning_.attr_estimate);
    append_chunk(buf, "ATTR", with_window_index(win->w, 0xFF, at));
    win->attribute_bytes = buf->size() - before;
  }

  // The reconstruction the decoder will produce for the window's valid samples.
  void reconstruct(size_t frames, const WindowInts& wi, const std::vector<double>& recon,
                   std::vector<double>* rec) const {
    const size_t n = frames * take_.points;
    if (plan_.tout) {
      rec->assign(n * 3, 0.0);
      for (size_t i = 0; i < n; ++i)
        if (wi.valid[i]) std::copy(&recon[i * 3], &recon[i * 3 + 3], &(*rec)[i * 3]);
    } else {
      dequantise_all(g_, wi, rec);  // gap samples: q = 0 (quantise_window) gives 0.0
    }
    for (size_t i = 0; i < n; ++i)
      if (wi.valid[i]) keep_valid_off_origin(take_.format, g_.lossless, &(*rec)[i * 3]);
  }

  [[noreturn]] void check_failed(size_t w, const std::string& what) const {
    fail(ErrorCode::kInternal, take_.source,
         "self-check failed in window " + std::to_string(w) + ": " + what +
             " (please report this; --no-check skips the check)");
  }

  // The promise of the stream for the window: every valid coordinate back exactly (lossless),
  // within the bound, or (transform output) the window within the KG target. (The window's error
  // stats are added when it is emitted, in window order.) With the self-check on, the
  // per-coordinate part is left to check_window, which holds what the decoder gives back to the
  // same rule (PromiseCheck) and requires it to be this reconstruction bit for bit.
  void check_bound(const Window& win) const {
    const size_t w = win.w, fn = win.block.frames, N = take_.points;
    const double* orig = win.block.xyz.data();
    const std::vector<double>& rec = win.rec;
    const uint8_t* valid = win.wi.valid.data();
    for (size_t i = 0; i < (opts_.check ? 0 : fn * N); ++i) {
      if (!valid[i]) continue;
      for (size_t k = i * 3; k < i * 3 + 3; ++k)
        if (!std::isfinite(rec[k]))
          check_failed(w, "a valid coordinate reconstructs to a non-finite value");
      if (plan_.tout) continue;  // transform output promises no bound
      for (size_t k = i * 3; k < i * 3 + 3; ++k) {
        const bool ok =
            g_.lossless ? same_bits(rec[k], orig[k]) : std::fabs(rec[k] - orig[k]) <= g_.bound;
        if (!ok)
          check_failed(w, "coordinate " + std::to_string(orig[k]) + " comes back as " +
                              std::to_string(rec[k]));
      }
    }
    if (plan_.tout) {  // each window within the KG target makes the take meet it (FORMAT.md 4.3)
      if (window_sq_error(fn, N, orig, rec.data(), valid) > win.kg_budget ||
          (plan_.written_scale > 0 &&
           window_sq_error(fn, N, orig, rec.data(), valid, plan_.written_scale) > win.kg_budget))
        throw TransformMissedTarget();
    }
  }

  // Runs the decoder on the window's chunks: what it gives must keep the stream's promise
  // (capz/verify.h, the rule `verify` and `--rm` use) and be, bit for bit, what the encoder
  // reconstructed and measured. The window's file offset is not known until it is emitted, so
  // offsets in the decoder's messages count from the window's first byte.
  void check_window(Window* win) const {
    const size_t w = win->w;
    FrameBlock& back = win->back;
    try {
      decode_window_chunks(ctx_, w, win->buf.data(), 0, win->buf.size(), &back);
    } catch (const Error& e) {
      check_failed(w, std::string("the decoder rejects the window: ") + e.what());
    }
    PromiseCheck promise(promise_, false);  // emit() measures the same samples (rec)
    if (!promise.frames(win->block, back)) check_failed(w, promise.why());
    const size_t n = win->block.frames * take_.points;
    // Arrays equal as a whole (the usual case: gaps are 0.0 in both) need no test per sample.
    if (n > 0 && back.xyz.size() == n * 3 && win->rec.size() == n * 3 &&
        std::memcmp(back.xyz.data(), win->rec.data(), n * 24) == 0)
      return;
    for (size_t i = 0; i < n; ++i)
      if (win->wi.valid[i] && std::memcmp(&back.xyz[i * 3], &win->rec[i * 3], 24) != 0)
        check_failed(w, "positions decode differently than the encoder reconstructed them");
  }

  void fill_stats(CompressStats* stats) const {
    const size_t F = take_.frames, N = take_.points;
    stats->bytes = out_->size();
    stats->raw_bytes = F * N * 12;
    stats->bpvf = bpvf(out_->size(), F, N);
    stats->step = g_.mode == PosMode::kDecimal                                      ? 1.0 / g_.step
                  : (g_.mode == PosMode::kGrid || g_.mode == PosMode::kFloat32Grid) ? g_.step
                                                                                    : 0;
    stats->mode = plan_.tout ? "transform-output" : mode_name(g_.mode);
    stats->lossless = g_.lossless;
    stats->codec = plan_.codec ? plan_.codec->name() : "none";
    stats->error = acc_.finish();
    stats->position_bytes = position_bytes_;
    stats->analog_bytes = analog_bytes_;
    stats->rotation_bytes = rotation_bytes_;
    stats->attribute_bytes = attribute_bytes_;
    stats->dropped_coordinates = residue_ ? residue_->dropped_coordinates() : 0;
    stats->other_bytes = other_bytes_ + (residue_ ? residue_->bytes() - residue_->file_bytes() : 0);
  }

  FrameSource& source_;
  const Take& take_;
  const CompressOptions& opts_;
  const EncoderTuning& tuning_;
  StreamOut* out_;
  Plan plan_;
  TakeScan scan_;
  Grid g_;
  TransformParams tparams_;
  RayKind ray_ = RayKind::kNone;  // predictor 10 a candidate (FORMAT.md 7.1)
  bool analog_repeats_ = false;   // channels may name repeated frames (FORMAT.md 7.2)
  StreamContext ctx_;             // what the decoder reads from HEAD and META (with opts.check)
  Promise promise_;  // the stream's promise, checked on what the decoder gives (each window)
  std::unique_ptr<ResidueWriter> residue_;     // HASH and residue chunks (an original file only)
  AnalogHints hints_;                          // what the C3D parameters say of the analog channels
  std::vector<analog::ChannelBound> abounds_;  // per channel with a lossy one (FORMAT.md 5.7)
  ErrorAccumulator acc_;
  std::vector<IndexEntry> index_;
  size_t position_bytes_ = 0, analog_bytes_ = 0, rotation_bytes_ = 0, other_bytes_ = 0;
  size_t attribute_bytes_ = 0;
};

}  // namespace

void encode_source(FrameSource& source, const CompressOptions& opts, const EncoderTuning& tuning,
                   StreamOut* out, CompressStats* stats, bool allow_transform_output) {
  const std::string original = residue_original(source, opts);  // before the fields settle
  settle_fields(source, opts);
  set_field_bounds(source, opts);
  std::vector<std::string> unmatched = set_analog_bounds(source, opts);
  Encoder(source, opts, tuning, out, allow_transform_output, original).run(stats);
  if (stats) stats->analog_unmatched = std::move(unmatched);
}

}  // namespace capz

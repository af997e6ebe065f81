// capz — C3D writer: Intel (processor 84) files.
// Decoder library (capz_decode): builds without PCL and without the transform encoders.
//
// Contract:
//   - Storage: int16 when the source C3D was int16 (and !opts.c3d_float), re-quantised with the
//     source's |POINT:SCALE|: stored = round(x / scale), which gives back the integer the file
//     held. If a valid coordinate or an analog value does not fit int16 that way (a take changed
//     since it was read), the file is written as float instead. Otherwise float storage, with
//     the source's scale magnitude (or max |coordinate| / 32000 for a take not read from C3D).
//   - Gaps: x = y = z = 0 and 4th word -1. A valid sample's 4th word is
//     (camera_mask & 0x7f) << 8 | round(residual / scale) clamped to 0..255 (0 when the take has
//     no residuals). A valid sample at exactly (0, 0, 0) reads back as a gap (see the reader).
//   - Parameters: every group and parameter of take.c3d in order, with descriptions and locks;
//     updated only where the data says otherwise: POINT:USED, FRAMES, DATA_START, SCALE, RATE,
//     UNITS, LABELS/LABELS2..., DESCRIPTIONS...; ANALOG:USED, LABELS..., RATE; TRIAL:ACTUAL_START_
//     FIELD / ACTUAL_END_FIELD when the frames pass 65535 or the stored ones disagree. A take not
//     read from C3D gets a fresh POINT / ANALOG / TRIAL section.
//   - More than 65535 frames: header last frame 65535, POINT:FRAMES as float, TRIAL fields set.
//   - Rotations (take.rotations): the ROTATION group (USED, RATIO, RATE, LABELS, DATA_START),
//     and from the block after the frames (zero padding between) per point frame, per sample,
//     per segment the 16 matrix float32s (column-major) and the reliability float32, each
//     written with the bits the take holds.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <type_traits>

#include "capz/error.h"
#include "capz/io.h"
#include "core/atomic_file.h"
#include "io/c3d_internal.h"

namespace capz {
namespace c3d {

namespace {

void check_take(const Take& t, const std::string& name) {
  const size_t n = t.frames * t.points;
  if (t.xyz.size() != n * 3 || t.valid.size() != n)
    fail(ErrorCode::kInternal, name,
         "take has " + std::to_string(t.xyz.size()) + " coordinates and " +
             std::to_string(t.valid.size()) + " validity flags for " + std::to_string(t.frames) +
             " frames x " + std::to_string(t.points) + " points");
  const Analog& a = t.analog;
  if (a.channels < 0 || a.samples_per_frame < 0 ||
      a.values.size() !=
          t.frames * static_cast<size_t>(a.channels) * static_cast<size_t>(a.samples_per_frame))
    fail(ErrorCode::kInternal, name, "analog values do not match frames x samples x channels");
  check_c3d_rotations(t, name);
}

}  // namespace

void check_c3d_rotations(const Take& t, const std::string& name) {
  const Rotations& r = t.rotations;
  const size_t rn = r.samples(t.frames) * static_cast<size_t>(std::max(0, r.segments));
  if (r.segments < 0 || (r.segments > 0 && r.samples_per_frame < 1) ||
      r.matrices.size() != rn * 16 || r.reliability.size() != rn)
    fail(ErrorCode::kInternal, name,
         "rotation arrays do not match frames x samples per frame x segments");
}

void check_c3d_limits(const Take& t, const std::string& name) {
  const Analog& a = t.analog;
  if (a.channels < 0 || a.samples_per_frame < 0)
    fail(ErrorCode::kInternal, name, "negative analog channel or sample count");
  if (t.points > 65535)
    fail(ErrorCode::kUsage, name,
         std::to_string(t.points) + " points: a C3D file holds at most 65535");
  if (static_cast<size_t>(a.channels) * static_cast<size_t>(a.samples_per_frame) > 65535)
    fail(ErrorCode::kUsage, name, "more than 65535 analog values per frame: C3D cannot hold them");
  const Rotations& r = t.rotations;
  if (r.segments < 0 || r.segments > 65535 || r.samples_per_frame > 65535 ||
      (r.segments > 0 && r.samples_per_frame < 1))
    fail(ErrorCode::kUsage, name,
         std::to_string(r.segments) + " rotation segments x " +
             std::to_string(r.samples_per_frame) +
             " samples per frame: a C3D holds 1..65535 of each");
}

namespace {

// std::lround without the libm call (the writer rounds every coordinate of a take): for
// |x| < 2^52, truncation and x - trunc(x) are exact, so this is lround's result (halves away
// from zero); larger or non-finite x go to std::lround itself.
inline long lround_fast(double x) {
  if (!(std::fabs(x) < 0x1p52)) return std::lround(x);
  const long t = static_cast<long>(x);
  const double d = x - static_cast<double>(t);
  return t + (d >= 0.5) - (d <= -0.5);
}

bool fits_int16(double v, double scale) {
  const double x = v / scale;
  if (!(std::fabs(x) < 65536.0)) return false;  // round(x) is beyond int16, or x not finite
  const long q = lround_fast(x);
  return q >= -32768 && q <= 32767;
}

std::vector<std::string> padded(std::vector<std::string> v, size_t n) {
  v.resize(n);
  return v;
}

// Labels as the reader derives them (base, base2, ... cut or padded to n).
bool same_list(const C3DExtra& x, const char* group, const char* base,
               const std::vector<std::string>& want, size_t n) {
  if (!x.param(group, base)) return false;
  return padded(string_list(x, group, base), n) == padded(want, n);
}

// GROUP:USED as the reader counts it (int16 read unsigned); -1 when absent.
long used_count(const C3DExtra& x, const char* group) {
  const C3DParameter* p = x.param(group, "USED");
  if (!p || p->type != 2 || p->data.size() < 2) return -1;
  return static_cast<uint16_t>(p->as_ints()[0]);
}

void put_header_u16(std::vector<uint8_t>& h, int word, uint32_t v) {
  put_u16le(static_cast<uint16_t>(v), &h[2 * (word - 1)]);
}
void put_header_f32(std::vector<uint8_t>& h, int word, float v) {
  put_f32le(v, &h[2 * (word - 1)]);
}

}  // namespace

void C3DWriteScan::add(size_t count, const double* xyz, const uint8_t* valid, size_t analog_count,
                       const double* analog) {
  for (size_t i = 0; i < count; ++i)
    if (valid[i])
      for (int a = 0; a < 3; ++a) {
        const double v = xyz[3 * i + a];
        max_abs = std::max(max_abs, std::fabs(v));
        if (fits && scale > 0 && !fits_int16(v, scale)) fits = false;
      }
  for (size_t k = 0; k < analog_count && fits; ++k) {
    const double v = analog[k];
    if (!(std::isfinite(v) && v == std::round(v) && v >= -32768 && v <= 65535)) fits = false;
  }
}

double c3d_known_scale(const Take& take) {
  const double scale = take.c3d ? take.c3d->point_scale : 0;
  return std::isfinite(scale) && scale > 0 ? static_cast<float>(scale) : 0;
}

double c3d_scale_from_data(double max_abs) {
  return static_cast<float>(max_abs > 0 && std::isfinite(max_abs) ? max_abs / 32000.0 : 1.0);
}

bool c3d_needs_scan(const Take& take, const WriteOptions& opts) {
  const bool float_storage = opts.c3d_float || !take.c3d || take.c3d->float_storage;
  return !float_storage || c3d_known_scale(take) == 0;
}

namespace {

// The ROTATION group for the take's rotations (or, for a group read from the file, what keeps
// it consistent when the take has none: USED 0): USED, RATIO, RATE, LABELS updated where the
// take says otherwise, DATA_START added with 0 (filled in once the layout is known). `x` holds
// the parameters as read; the group is left out when neither has rotations.
void set_rotation_params(const Take& take, const C3DExtra& x, std::vector<C3DGroup>& groups) {
  const Rotations& r = take.rotations;
  if (r.segments == 0 && !x.group("ROTATION")) return;
  C3DGroup& g = ensure_group(groups, "ROTATION", "Rotation (4x4 transform) signals");
  set_int16(ensure_param(g, "USED", "Number of rotation signals"), r.segments);
  set_int16(ensure_param(g, "DATA_START", "Number of the first block of rotation data"), 0);
  const int ratio = std::max(1, r.samples_per_frame);
  // RATIO kept or added unless RATE alone says it (ezc3d reads RATE / point rate then).
  const double rate = number_param(x, "ROTATION", "RATE", 0);
  const bool rate_says =
      rate > 0 && take.rate > 0 && std::lround(rate / take.rate) == static_cast<long>(ratio);
  if (x.param("ROTATION", "RATIO") || !rate_says)
    set_int16(ensure_param(g, "RATIO", "Rotation samples per point frame"), ratio);
  if (r.rate > 0 && rate != static_cast<double>(static_cast<float>(r.rate)))
    set_float(ensure_param(g, "RATE", "Rotation sample rate"), static_cast<float>(r.rate));
  const size_t n = static_cast<size_t>(r.segments);
  if (n > 0 && (used_count(x, "ROTATION") != static_cast<long>(n) ||
                !same_list(x, "ROTATION", "LABELS", r.labels, n)))
    set_string_list(g, "LABELS", padded(r.labels, n), "Rotation signal labels");
}

// The ANALOG group: USED, LABELS..., RATE where the take says otherwise; for a take not read from
// a C3D (`fresh_take`) with channels also the SCALE, OFFSET and GEN_SCALE readers need.
void set_analog_params(const Take& take, const C3DExtra& x, bool fresh_take,
                       std::vector<C3DGroup>& groups) {
  const Analog& an = take.analog;
  const size_t channels = static_cast<size_t>(an.channels);
  const bool src = !fresh_take;
  if (channels > 0 || !src || x.group("ANALOG")) {
    C3DGroup& ag = ensure_group(groups, "ANALOG", "Analog data parameters");
    const bool fresh = !x.param("ANALOG", "USED");
    set_int16(ensure_param(ag, "USED", "Number of analog channels"), static_cast<int>(channels));
    if (channels > 0 || fresh) {
      if (used_count(x, "ANALOG") != static_cast<long>(channels) ||
          !same_list(x, "ANALOG", "LABELS", an.labels, channels))
        set_string_list(ag, "LABELS", padded(an.labels, channels), "Analog channel labels");
      double have = number_param(x, "ANALOG", "RATE", -1);
      if (have != static_cast<double>(static_cast<float>(an.rate)))
        set_float(ensure_param(ag, "RATE", "Analog sample rate"), static_cast<float>(an.rate));
    }
    if (channels > 0 && !src) {  // a fresh section: what readers need to scale analog
      std::vector<uint8_t> d(channels * 4);
      for (size_t c = 0; c < channels; ++c) put_f32le(1.0f, &d[4 * c]);
      C3DParameter& p = ensure_param(ag, "SCALE", "Analog scale factors");
      p.type = 4;
      p.dims = {static_cast<int>(channels)};
      p.data = d;
    }
    if (channels > 0 && !src)
      set_int16_array(ensure_param(ag, "OFFSET", "Analog offsets"), std::vector<int>(channels, 0));
    if (channels > 0 && !src)
      set_float(ensure_param(ag, "GEN_SCALE", "Analog general scale factor"), 1.0f);
  }
}

// TRIAL:ACTUAL_START_FIELD / ACTUAL_END_FIELD for frames first .. first + F - 1, written when the
// take passes frame 65535, the stored pair disagrees, or the take was not read from a C3D.
void set_trial_params(const C3DExtra& x, bool fresh_take, long first, size_t F,
                      std::vector<C3DGroup>& groups) {
  const bool src = !fresh_take;
  const long last = first + static_cast<long>(F) - 1;
  const bool long_take = F > 65535 || last > 65535;
  long tr_start = -1, tr_end = -1;
  if (const C3DParameter* p = x.param("TRIAL", "ACTUAL_START_FIELD"))
    if (p->type == 2 && !p->data.empty()) {
      auto v = p->as_ints();
      tr_start =
          static_cast<uint16_t>(v[0]) + 65536L * (v.size() > 1 ? static_cast<uint16_t>(v[1]) : 0);
    }
  if (const C3DParameter* p = x.param("TRIAL", "ACTUAL_END_FIELD"))
    if (p->type == 2 && !p->data.empty()) {
      auto v = p->as_ints();
      tr_end =
          static_cast<uint16_t>(v[0]) + 65536L * (v.size() > 1 ? static_cast<uint16_t>(v[1]) : 0);
    }
  const bool have = tr_start >= 0 && tr_end >= 0;
  const bool consistent =
      have && tr_end - tr_start + 1 == static_cast<long>(F) && (!long_take || tr_start == first);
  if (!src || long_take || (have && !consistent)) {
    C3DGroup& tg = ensure_group(groups, "TRIAL", "Trial parameters");
    if (!consistent) {
      long s = std::max(0L, first), e = std::max(s - 1, last);
      if (F == 0) e = s;  // nothing to count; keep a valid pair
      set_int16_array(ensure_param(tg, "ACTUAL_START_FIELD", "First frame (low, high word)"),
                      {static_cast<int>(s & 0xffff), static_cast<int>((s >> 16) & 0xffff)});
      set_int16_array(ensure_param(tg, "ACTUAL_END_FIELD", "Last frame (low, high word)"),
                      {static_cast<int>(e & 0xffff), static_cast<int>((e >> 16) & 0xffff)});
    }
  }
}

// The 512-byte header block for `plan` (its counts, storage and scale), the first data block and
// the frames first .. first + F - 1, with the source's header events.
std::vector<uint8_t> header_block(const Take& take, const C3DFilePlan& plan, size_t data_start) {
  const C3DExtra* src = take.c3d.get();
  const size_t F = plan.frames, N = plan.points, analog_total = plan.analog_total;
  const size_t spf =
      take.analog.channels > 0 ? static_cast<size_t>(take.analog.samples_per_frame) : 0;
  const bool float_storage = plan.float_storage;
  const double scale = plan.scale;
  const long first = take.first_frame;
  const long last = first + static_cast<long>(F) - 1;
  const bool long_take = F > 65535 || last > 65535;
  std::vector<uint8_t> header(kBlock, 0);
  header[0] = 2;
  header[1] = 0x50;
  long h_first = std::min(65535L, std::max(0L, first));
  long h_last = long_take ? 65535L : std::max(h_first - 1, last);
  if (F == 0 && h_first == 0) h_first = 1, h_last = 0;
  put_header_u16(header, 2, static_cast<uint32_t>(N));
  put_header_u16(header, 3, static_cast<uint32_t>(analog_total));
  put_header_u16(header, 4, static_cast<uint32_t>(h_first));
  put_header_u16(header, 5, static_cast<uint32_t>(h_last));
  put_header_u16(header, 6,
                 static_cast<uint32_t>(src ? std::max(0, src->max_interpolation_gap) : 0));
  put_header_f32(header, 7, static_cast<float>(float_storage ? -scale : scale));
  put_header_u16(header, 9, static_cast<uint32_t>(data_start));
  put_header_u16(header, 10, static_cast<uint32_t>(spf));
  put_header_f32(header, 11, static_cast<float>(take.rate));
  if (!src || src->header_events_label_range) put_header_u16(header, 150, 12345);
  if (src) {
    size_t nev = std::min<size_t>(18, src->header_events.size());
    put_header_u16(header, 151, static_cast<uint32_t>(nev));
    for (size_t i = 0; i < nev; ++i) {
      const C3DHeaderEvent& e = src->header_events[i];
      put_header_f32(header, 153 + 2 * static_cast<int>(i), e.time);
      header[376 + i] = e.display ? 1 : 0;
      for (size_t k = 0; k < 4; ++k)
        header[396 + 4 * i + k] = k < e.label.size() ? e.label[k] : ' ';
    }
  }
  return header;
}

// The POINT group: counts, scale (negative for float storage), rate, units, labels and
// descriptions, each kept as the source stored it when it already says the same.
void set_point_params(const Take& take, const C3DExtra& x, bool float_storage, double scale,
                      std::vector<C3DGroup>& groups) {
  const size_t F = take.frames, N = take.points;
  C3DGroup& point = ensure_group(groups, "POINT", "3-D point parameters");
  set_int16(ensure_param(point, "USED", "Number of 3-D points"), static_cast<int>(N));
  {
    C3DParameter& p = ensure_param(point, "FRAMES", "Number of 3-D frames");
    if (F > 65535 || p.type == 4)
      set_float(p, static_cast<float>(F));
    else
      set_int16(p, static_cast<int>(F));
  }
  set_int16(ensure_param(point, "DATA_START", "Number of the first block of 3-D data"), 0);
  {
    C3DParameter& p = ensure_param(point, "SCALE", "3-D scale factor");
    float want = static_cast<float>(float_storage ? -scale : scale);
    if (!(p.type == 4 && p.data.size() == 4 && get_f32le(p.data.data()) == want))
      set_float(p, want);
  }
  if (take.rate > 0 || !x.param("POINT", "RATE")) {
    double have = number_param(x, "POINT", "RATE", -1);
    if (have != static_cast<double>(static_cast<float>(take.rate)) || !x.param("POINT", "RATE"))
      set_float(ensure_param(point, "RATE", "3-D frame rate"), static_cast<float>(take.rate));
  }
  if (!take.units.empty() || !x.param("POINT", "UNITS")) {
    // Kept as stored (an array of units per point, padding, capitals) while the reader derives
    // the take's units from it.
    if (!x.param("POINT", "UNITS") || point_units(x) != take.units)
      set_string(ensure_param(point, "UNITS", "3-D units"), take.units);
  }
  // Labels are rebuilt when they differ from what the reader derives, or when the count of
  // points changed (then continuations beyond the new count go too).
  const bool points_changed = used_count(x, "POINT") != static_cast<long>(N);
  if (points_changed || !same_list(x, "POINT", "LABELS", take.labels, N))
    set_string_list(point, "LABELS", padded(take.labels, N), "3-D point labels");
  if (!take.descriptions.empty() &&
      (points_changed || !same_list(x, "POINT", "DESCRIPTIONS", take.descriptions, N)))
    set_string_list(point, "DESCRIPTIONS", padded(take.descriptions, N), "3-D point descriptions");
}

// The parameter groups for `take` (the source's `src`, updated where the take says otherwise; a
// fresh POINT / ANALOG / TRIAL section when src is null), the DATA_STARTs still 0.
std::vector<C3DGroup> parameter_groups(const Take& take, const C3DExtra* src, bool float_storage,
                                       double scale) {
  std::vector<C3DGroup> groups;
  C3DExtra x;
  if (src) groups = src->groups;
  x.groups = groups;  // for lookups of what was read
  set_point_params(take, x, float_storage, scale, groups);
  set_analog_params(take, x, !src, groups);
  set_trial_params(x, !src, take.first_frame, take.frames, groups);
  set_rotation_params(take, x, groups);
  return groups;
}

}  // namespace

C3DFilePlan plan_c3d_file(const Take& take, bool have_res, const WriteOptions& opts,
                          const C3DWriteScan& scan, const std::string& name) {
  check_c3d_limits(take, name);
  const size_t F = take.frames, N = take.points;
  const Analog& an = take.analog;
  const size_t channels = static_cast<size_t>(an.channels);
  const size_t spf = channels ? static_cast<size_t>(an.samples_per_frame) : 0;
  const size_t analog_total = channels * spf;
  const C3DExtra* src = take.c3d.get();

  // ---- storage and scale ----
  bool float_storage = opts.c3d_float || !src || src->float_storage;
  double scale = c3d_known_scale(take);
  if (scale == 0) scale = c3d_scale_from_data(scan.max_abs);
  // The int16 fit is known only when the scan used this scale.
  if (!float_storage && !(scan.scale == scale && scan.fits)) float_storage = true;

  // ---- parameters ----
  std::vector<C3DGroup> groups = parameter_groups(take, src, float_storage, scale);

  // The DATA_STARTs' values do not change the section's size: encode, then fill them in. The
  // rotations start at the block after the frames.
  const size_t per_frame = (N * 4 + analog_total) * (float_storage ? 4 : 2);
  std::vector<uint8_t> params = encode_parameter_section(groups);
  const size_t data_start = 2 + params.size() / kBlock;
  if (data_start > 65535) fail(ErrorCode::kUsage, name, "parameter section too large");
  set_int16(*find_param(*find_group(groups, "POINT"), "DATA_START"), static_cast<int>(data_start));
  const size_t rot_start = data_start + (F * per_frame + kBlock - 1) / kBlock;
  if (C3DGroup* rg = find_group(groups, "ROTATION")) {
    if (rot_start > 65535)
      fail(ErrorCode::kUsage, name,
           "the rotations would start at block " + std::to_string(rot_start) +
               ": ROTATION:DATA_START cannot point past block 65535");
    set_int16(*find_param(*rg, "DATA_START"), static_cast<int>(rot_start));
  }
  params = encode_parameter_section(groups);

  C3DFilePlan plan;
  plan.float_storage = float_storage;
  plan.scale = scale;
  plan.have_res = have_res;
  plan.points = N;
  plan.analog_total = analog_total;
  plan.per_frame = per_frame;
  plan.frames = F;
  const Rotations& rot = take.rotations;
  if (rot.segments > 0) {
    plan.rot_offset = (rot_start - 1) * kBlock;
    plan.rot_bytes = rot.samples(F) * static_cast<size_t>(rot.segments) * kRotationBytes;
  }
  const std::vector<uint8_t> header = header_block(take, plan, data_start);
  plan.head.resize(header.size() + params.size());
  std::copy(header.begin(), header.end(), plan.head.begin());
  std::copy(params.begin(), params.end(), plan.head.begin() + static_cast<long>(header.size()));
  return plan;
}

void encode_c3d_frames(const C3DFilePlan& plan, size_t count, const double* xyz,
                       const uint8_t* valid, const float* residual, const uint8_t* camera,
                       const double* analog, uint8_t* out, bool* points_fit) {
  bool fit = true;
  const size_t N = plan.points, analog_total = plan.analog_total;
  const bool float_storage = plan.float_storage;
  const double scale = plan.scale;
  const size_t elem = float_storage ? 4 : 2;
  uint8_t* d = out;
  // One loop per storage and words layout (fixed for the file), so the per-sample path has no
  // branch on them.
  auto frames_as = [&](auto float_tag, auto res_tag) {
    constexpr bool kFloat = decltype(float_tag)::value, kRes = decltype(res_tag)::value;
    for (size_t f = 0; f < count; ++f) {
      for (size_t p = 0; p < N; ++p, d += 4 * elem) {
        const size_t i = f * N + p;
        const bool v = valid[i] != 0;
        uint32_t word4 = 0;
        if (kRes && v) {
          float r = residual[i];
          long low = r > 0 ? lround_fast(r / scale) : 0;
          word4 = (static_cast<uint32_t>(camera[i] & 0x7f) << 8) |
                  static_cast<uint32_t>(std::min(255L, std::max(0L, low)));
        }
        const double* c = &xyz[3 * i];
        if (kFloat) {
          for (int a = 0; a < 3; ++a) put_f32le(v ? static_cast<float>(c[a]) : 0.0f, d + 4 * a);
          put_f32le(v ? static_cast<float>(word4) : -1.0f, d + 12);
        } else if (v) {
          for (int a = 0; a < 3; ++a) {
            const long q = lround_fast(c[a] / scale);
            fit = fit && q >= -32768 && q <= 32767;  // = fits_int16(c[a], scale)
            // Out of range only at a bound (a value at the int16 limit decoded a count beyond
            // it): clamped, never wrapped. The original was in range, so the clamped value lies
            // between it and the decoded one and stays within the bound. The writer rewrites
            // the file as float then (points_fit); a rebuild keeps the original's int16 form.
            const long qc = std::min(32767L, std::max(-32768L, q));
            put_u16le(static_cast<uint16_t>(static_cast<int16_t>(qc)), d + 2 * a);
          }
          put_u16le(static_cast<uint16_t>(word4), d + 6);
        } else {
          for (int a = 0; a < 3; ++a) put_u16le(0, d + 2 * a);
          put_u16le(0xffff, d + 6);
        }
      }
      const double* av = analog + f * analog_total;
      for (size_t k = 0; k < analog_total; ++k, d += elem) {
        if (kFloat)
          put_f32le(static_cast<float>(av[k]), d);
        else
          put_u16le(static_cast<uint16_t>(static_cast<int32_t>(lround_fast(av[k]))), d);
      }
    }
  };
  using Yes = std::true_type;
  using No = std::false_type;
  if (float_storage)
    plan.have_res ? frames_as(Yes(), Yes()) : frames_as(Yes(), No());
  else
    plan.have_res ? frames_as(No(), Yes()) : frames_as(No(), No());
  if (points_fit) *points_fit = fit;
}

void encode_c3d_rotations(const float* matrices, const float* reliability, size_t count,
                          uint8_t* out) {
  for (size_t i = 0; i < count; ++i, out += kRotationBytes) {
    for (size_t k = 0; k < 16; ++k) put_f32le(matrices[i * 16 + k], out + 4 * k);
    put_f32le(reliability[i], out + 64);
  }
}

std::vector<uint8_t> encode_c3d_file(const Take& take, const WriteOptions& opts,
                                     const std::string& name) {
  check_take(take, name);
  const size_t F = take.frames, N = take.points;
  const C3DExtra* src = take.c3d.get();
  const bool have_res = src && src->residual.size() == F * N && src->camera_mask.size() == F * N;
  C3DWriteScan scan;
  scan.scale = c3d_known_scale(take);
  scan.add(F * N, take.xyz.data(), take.valid.data(), take.analog.values.size(),
           take.analog.values.data());
  if (scan.scale == 0) {  // an int16 scale from the data: check the fit at that scale
    const double m = scan.max_abs;
    scan = C3DWriteScan();
    scan.scale = c3d_scale_from_data(m);
    scan.add(F * N, take.xyz.data(), take.valid.data(), take.analog.values.size(),
             take.analog.values.data());
  }
  C3DFilePlan plan = plan_c3d_file(take, have_res, opts, scan, name);
  const size_t frames_end = plan.head.size() + F * plan.per_frame;
  std::vector<uint8_t> out(plan.rot_bytes > 0 ? plan.rot_offset + plan.rot_bytes : frames_end, 0);
  std::copy(plan.head.begin(), plan.head.end(), out.begin());
  encode_c3d_frames(plan, F, take.xyz.data(), take.valid.data(),
                    have_res ? src->residual.data() : nullptr,
                    have_res ? src->camera_mask.data() : nullptr, take.analog.values.data(),
                    out.data() + plan.head.size());
  if (plan.rot_bytes > 0)
    encode_c3d_rotations(take.rotations.matrices.data(), take.rotations.reliability.data(),
                         plan.rot_bytes / kRotationBytes, out.data() + plan.rot_offset);
  return out;
}

}  // namespace c3d

std::shared_ptr<C3DExtra> new_c3d_parameters(const Take& take, const std::string& name) {
  c3d::check_c3d_limits(take, name);
  c3d::C3DWriteScan scan;
  scan.add(take.frames * take.points, take.xyz.data(), take.valid.data(), 0, nullptr);
  auto x = std::make_shared<C3DExtra>();
  x->float_storage = true;
  x->point_scale = 0;  // not known: the writer takes it from the data, as for the take alone
  x->header_events_label_range = true;
  x->groups = c3d::parameter_groups(take, nullptr, true, c3d::c3d_scale_from_data(scan.max_abs));
  return x;
}

void write_c3d(const Take& take, const std::string& path, const WriteOptions& opts) {
  refuse_ragged(take, "the C3D writer (a C3D frame holds a fixed number of points)", path);
  check_output_free(path, opts.overwrite);
  std::vector<uint8_t> bytes = c3d::encode_c3d_file(take, opts, path);
  AtomicFile out(path, opts.overwrite);
  out.write(bytes);
  out.commit();
}

}  // namespace capz

// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// capz — C3D reader.
//
// Accepts Intel (84), DEC (85) and MIPS (86) files with int16 or float storage. What the reader
// decides when the file is inconsistent, in order:
//   - layout (points, analog values per frame, storage type, data start) comes from the header,
//     which is what every writer fills in; a parameter that disagrees is reported as a warning;
//   - frames: header last - first + 1, unless the header is clearly saturated (last frame 65535)
//     or the parameters say more than 65535 frames; then TRIAL:ACTUAL_START_FIELD/END_FIELD
//     (two int16 words each: low, high) or POINT:FRAMES (int16 read unsigned, or float);
//   - a data section shorter than the frames need: the complete frames present are read and a
//     warning says "header says N frames, file holds M". No count read from the file is used to
//     allocate before it has been checked against the bytes that are really there.
// Gaps (valid = 0, xyz = 0, residual = -1, camera mask = 0): a negative 4th word (int16, or float
// in float files), a NaN or infinite coordinate, or x = y = z = 0 exactly (several vendors mark
// missing markers that way; a real marker at the exact origin is read as a gap too).
// The 4th word of a valid sample: the low byte times |POINT:SCALE| is the residual, the high byte
// the camera mask. In float files the float holds that int16 (its fraction is dropped); a float
// of 32768..65535 is a negative int16 (a gap), one above 65535 is no int16 at all and is read as
// valid with residual 0 (Biogesta writes 1.7e38 for every valid sample).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>

#include "capz/error.h"
#include "capz/io.h"
#include "core/atomic_file.h"
#include "io/c3d_internal.h"

namespace capz {

namespace {

using c3d::kBlock;

std::string trim(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\0')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\0')) --e;
  return s.substr(b, e - b);
}

std::string upper(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// A parameter holding a count stored as int16 but meant unsigned (0..65535), or as a float.
// Returns -1 when absent or not numeric.
long count_param(const C3DExtra& x, const char* group, const char* name) {
  const C3DParameter* p = x.param(group, name);
  if (!p || p->data.empty()) return -1;
  if (p->type == 2) return static_cast<uint16_t>(p->as_ints()[0]);
  if (p->type == 1) return p->data[0];
  if (p->type == 4) {
    float f = p->as_floats()[0];
    if (!(f >= 0) || f > 4.0e9f) return -1;
    return static_cast<long>(f);
  }
  return -1;
}

// TRIAL:ACTUAL_START_FIELD / END_FIELD: two int16 words (low, high) forming one 32-bit number.
long trial_field(const C3DExtra& x, const char* name) {
  const C3DParameter* p = x.param("TRIAL", name);
  if (!p || p->type != 2 || p->data.empty()) return -1;
  auto v = p->as_ints();
  long lo = static_cast<uint16_t>(v[0]);
  long hi = v.size() > 1 ? static_cast<uint16_t>(v[1]) : 0;
  return lo + 65536L * hi;
}

}  // namespace

namespace c3d {

namespace {

// Where parameter entries must start before, from the header block (data[0..17]) of a file of
// `size` bytes. The data start word is read in both byte orders: the processor is not known
// yet; the smaller plausible value past the parameters bounds them.
size_t parameter_limit(const uint8_t* data, size_t size) {
  const size_t param_offset = (static_cast<size_t>(data[0]) - 1) * kBlock;
  size_t limit = size;
  for (uint16_t ds : {static_cast<uint16_t>(data[16] | (data[17] << 8)),
                      static_cast<uint16_t>((data[16] << 8) | data[17])}) {
    size_t off = ds > 0 ? (static_cast<size_t>(ds) - 1) * kBlock : 0;
    if (off > param_offset) limit = std::min(limit, off);
  }
  return limit;
}

}  // namespace

size_t header_extent(const uint8_t* data, size_t avail, size_t size) {
  if (avail < kBlock || data[0] == 0) return std::min(size, kBlock);
  // Entries start before the limit but may run past it (a section without terminator).
  return std::min(size, parameter_limit(data, size) + kHeaderSlack);
}

Take read_header(const uint8_t* data, size_t avail, size_t size, const std::string& name,
                 DataLayout* out) {
  if (size == 0) fail(ErrorCode::kNotOurFormat, name, "empty file (0 bytes), not a C3D file");
  if (size < 2 || data[1] != 0x50) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "not a C3D file (byte 2 is 0x%02x, a C3D header has 0x50)",
                  size < 2 ? 0 : data[1]);
    fail(ErrorCode::kNotOurFormat, name, buf);
  }
  if (size < kBlock || avail < kBlock)
    fail(ErrorCode::kCorrupt, name,
         "truncated: " + std::to_string(size) + " bytes, the C3D header alone needs 512");
  if (data[0] == 0) fail(ErrorCode::kCorrupt, name, "header points to parameter block 0");

  const size_t param_offset = (static_cast<size_t>(data[0]) - 1) * kBlock;
  const size_t limit = parameter_limit(data, size);
  c3d::ParameterSection sec = c3d::parse_parameter_section(data, avail, param_offset, limit, name);
  const c3d::NumberFormat nf{sec.processor};
  auto word = [&](int w) { return nf.u16(data + 2 * (w - 1)); };  // 1-based header words
  auto fword = [&](int w) { return nf.f32(data + 2 * (w - 1)); };

  Take t;
  t.source = name;
  t.format = Format::kC3D;
  auto x = std::make_shared<C3DExtra>();
  x->processor = sec.processor;
  x->groups = std::move(sec.groups);
  for (auto& w : sec.warnings) t.warnings.push_back(w);
  for (auto& w : sec.notes) t.warnings.push_back(w);
  auto warn = [&](const std::string& w) { t.warnings.push_back(w); };

  // ---- header ----
  const size_t h_points = word(2);
  const size_t h_analog_total = word(3);
  const long h_first = word(4);
  const long h_last = word(5);
  x->max_interpolation_gap = word(6);
  const float h_scale = fword(7);
  const size_t h_data_start = word(9);
  const size_t h_analog_spf = word(10);
  const float h_rate = fword(11);

  // ---- storage ----
  const C3DParameter* scale_par = x->param("POINT", "SCALE");
  float p_scale = 0;
  bool have_p_scale = false;
  if (scale_par && scale_par->type != -1 && !scale_par->data.empty()) {
    p_scale = scale_par->as_floats()[0];
    have_p_scale = true;
  }
  x->float_storage = h_scale < 0;
  if (have_p_scale && (p_scale < 0) != (h_scale < 0))
    warn("header scale " + num(h_scale) + " and POINT:SCALE " + num(p_scale) +
         " disagree on the storage type (the header's is used)");
  double scale = std::fabs(static_cast<double>(h_scale));
  if (have_p_scale && std::fabs(p_scale) != std::fabs(h_scale)) {
    warn("header scale " + num(h_scale) + " differs from POINT:SCALE " + num(p_scale) +
         (x->float_storage ? "" : " (the header's is used)"));
  }
  if (!std::isfinite(scale) || scale == 0) {
    double alt = have_p_scale ? std::fabs(static_cast<double>(p_scale)) : 0;
    if (std::isfinite(alt) && alt > 0) {
      scale = alt;
    } else {
      if (!x->float_storage) warn("scale factor is " + num(h_scale) + "; using 1");
      scale = 1.0;
    }
  }
  x->point_scale = scale;
  const size_t elem = x->float_storage ? 4 : 2;

  // ---- data start ----
  size_t data_start = h_data_start;
  long p_start = count_param(*x, "POINT", "DATA_START");
  if (data_start == 0) {
    if (p_start <= 0)
      fail(ErrorCode::kCorrupt, name, "header and POINT:DATA_START give no data block");
    warn("header data start is 0; using POINT:DATA_START = " + std::to_string(p_start));
    data_start = static_cast<size_t>(p_start);
  } else if (p_start >= 0 && static_cast<size_t>(p_start) != data_start) {
    warn("header says the data starts at block " + std::to_string(data_start) +
         ", POINT:DATA_START says " + std::to_string(p_start) + " (the header's is used)");
  }
  const size_t data_offset = (data_start - 1) * kBlock;
  const size_t data_bytes = data_offset < size ? size - data_offset : 0;

  // ---- frames ----
  int64_t first = h_first;
  size_t frames = h_last >= h_first ? static_cast<size_t>(h_last - h_first + 1) : 0;
  long p_frames = count_param(*x, "POINT", "FRAMES");
  long tr_start = trial_field(*x, "ACTUAL_START_FIELD");
  long tr_end = trial_field(*x, "ACTUAL_END_FIELD");
  bool have_trial = tr_start >= 0 && tr_end >= tr_start;
  long tr_frames = have_trial ? tr_end - tr_start + 1 : -1;
  bool header_limited = h_last == 65535 || tr_frames > 65535 || p_frames > 65535;
  if (header_limited && (have_trial || p_frames > 0)) {
    size_t f = have_trial ? static_cast<size_t>(tr_frames) : static_cast<size_t>(p_frames);
    if (f != frames)
      warn("header says " + std::to_string(frames) + " frames, which 16 bits cannot exceed; " +
           (have_trial ? "TRIAL:ACTUAL_*_FIELD" : "POINT:FRAMES") + " says " + std::to_string(f) +
           " (used)");
    frames = f;
    if (have_trial) first = tr_start;
  } else if (p_frames >= 0 && static_cast<size_t>(p_frames) != frames) {
    warn("header says " + std::to_string(frames) + " frames, POINT:FRAMES says " +
         std::to_string(p_frames) + " (the header's count is used)");
  }

  // ---- layout: points and analog values per frame ----
  // The header's counts, unless POINT:USED / ANALOG:USED give a layout that fills the data
  // section exactly where the header's does not fit or leaves more unexplained bytes (some
  // writers put the channel count in header word 3 instead of channels x samples).
  size_t spf = h_analog_spf;
  long p_used = count_param(*x, "POINT", "USED");
  long a_used = count_param(*x, "ANALOG", "USED");
  if (h_analog_total > 0 && spf == 0) {
    spf = 1;
    if (a_used > 0 && h_analog_total % static_cast<size_t>(a_used) == 0)
      spf = h_analog_total / static_cast<size_t>(a_used);
    warn("header gives 0 analog samples per frame for " + std::to_string(h_analog_total) +
         " analog values per frame; using " + std::to_string(spf));
  }
  struct Layout {
    size_t points, analog_total;
  };
  std::vector<Layout> cands = {{h_points, h_analog_total}};
  std::vector<size_t> point_opts = {h_points}, analog_opts = {h_analog_total};
  if (p_used >= 0 && static_cast<size_t>(p_used) != h_points) point_opts.push_back(p_used);
  if (a_used >= 0 && spf > 0 && static_cast<size_t>(a_used) * spf != h_analog_total)
    analog_opts.push_back(static_cast<size_t>(a_used) * spf);
  for (size_t pp : point_opts)
    for (size_t aa : analog_opts)
      if (pp != h_points || aa != h_analog_total) cands.push_back({pp, aa});
  auto slack = [&](const Layout& l) -> long double {  // < 0: does not fit
    long double need = static_cast<long double>(frames) * (l.points * 4 + l.analog_total) * elem;
    return static_cast<long double>(data_bytes) - need;
  };
  auto tight = [&](const Layout& l) {  // fills the data section up to block padding
    long double sl = slack(l);
    return sl >= 0 &&
           sl < static_cast<long double>(kBlock + (l.points * 4 + l.analog_total) * elem);
  };
  Layout lay = cands[0];
  if (frames > 0 && !tight(lay))
    for (size_t i = 1; i < cands.size(); ++i)
      if (tight(cands[i])) {
        lay = cands[i];
        break;
      }
  const size_t points = lay.points;
  const size_t analog_total = lay.analog_total;
  if (p_used >= 0 && static_cast<size_t>(p_used) != h_points)
    warn("header says " + std::to_string(h_points) + " points, POINT:USED says " +
         std::to_string(p_used) + " (" + (points == h_points ? "the header's" : "POINT:USED's") +
         " count fits the data and is used)");
  if (analog_total != h_analog_total)
    warn("header says " + std::to_string(h_analog_total) +
         " analog values per frame, ANALOG:USED " + std::to_string(a_used) + " x " +
         std::to_string(spf) + " samples per frame fits the data and is used");
  size_t channels = 0;
  if (analog_total == 0) {
    spf = 0;
  } else {
    channels = analog_total / spf;
    if (analog_total % spf != 0)
      warn("the " + std::to_string(analog_total) +
           " analog values per frame are not a multiple of " + std::to_string(spf) +
           " samples per frame; the remainder is skipped");
    if (a_used >= 0 && static_cast<size_t>(a_used) != channels && analog_total == h_analog_total)
      warn("header gives " + std::to_string(channels) + " analog channels, ANALOG:USED says " +
           std::to_string(a_used) + " (the header's count is used)");
  }

  const size_t per_frame = (points * 4 + analog_total) * elem;
  if (per_frame == 0 && frames > 0) {
    // No bytes per frame: nothing bounds the count (TRIAL fields can claim 4 billion frames of
    // nothing, which every later stage would loop over). Such frames carry no data.
    warn("header says " + std::to_string(frames) +
         " frames of no points and no analog values; read as 0 frames");
    frames = 0;
  }
  if (per_frame > 0) {
    size_t avail = data_bytes / per_frame;
    if (frames > avail) {
      warn("header says " + std::to_string(frames) + " frames, file holds " +
           std::to_string(avail));
      frames = avail;
    }
  } else if (frames > 0) {
    // Frames of nothing: the count is unverifiable, and a lying one would make every consumer
    // loop over billions of empty frames.
    warn("header says " + std::to_string(frames) +
         " frames of no points and no analog channels; read as 0 frames");
    frames = 0;
  }

  // ---- data layout ----
  t.frames = frames;
  t.points = points;
  t.first_frame = first;
  t.analog.channels = static_cast<int>(channels);
  t.analog.samples_per_frame = static_cast<int>(spf);
  bool analog_unsigned = false;
  if (const C3DParameter* fmt = x->param("ANALOG", "FORMAT"))
    if (fmt->type == -1) analog_unsigned = upper(trim(fmt->as_string())) == "UNSIGNED";
  out->nf = nf;
  out->data_offset = data_offset;
  out->per_frame = per_frame;
  out->frames = frames;
  out->points = points;
  out->analog_values = spf * channels;
  out->float_storage = x->float_storage;
  out->analog_unsigned = analog_unsigned;
  out->scale = scale;
  out->warning_at = t.warnings.size();

  // ---- labels, rate, units ----
  t.labels = c3d::string_list(*x, "POINT", "LABELS");
  if (t.labels.size() < points && x->group("POINT"))
    warn("POINT:LABELS has " + std::to_string(t.labels.size()) + " labels for " +
         std::to_string(points) + " points");
  t.labels.resize(points);
  t.descriptions = c3d::string_list(*x, "POINT", "DESCRIPTIONS");
  if (!t.descriptions.empty()) t.descriptions.resize(points);
  t.analog.labels = c3d::string_list(*x, "ANALOG", "LABELS");
  t.analog.labels.resize(channels);

  double p_rate = c3d::number_param(*x, "POINT", "RATE", 0);
  t.rate = std::isfinite(p_rate) && p_rate > 0 ? p_rate : static_cast<double>(h_rate);
  if (!std::isfinite(t.rate) || t.rate < 0) t.rate = 0;
  if (p_rate > 0 && std::isfinite(h_rate) && std::fabs(p_rate - h_rate) > 1e-3 * p_rate)
    warn("header rate " + num(h_rate) + " Hz differs from POINT:RATE " + num(p_rate) +
         " Hz (POINT:RATE is used)");
  double a_rate = c3d::number_param(*x, "ANALOG", "RATE", 0);
  t.analog.rate = channels == 0 ? (std::isfinite(a_rate) && a_rate > 0 ? a_rate : 0)
                                : (std::isfinite(a_rate) && a_rate > 0 ? a_rate : t.rate * spf);
  if (const C3DParameter* u = x->param("POINT", "UNITS"))
    if (u->type == -1) t.units = trim(u->as_string());

  // ---- header events ----
  x->header_events_label_range = word(150) == 12345;
  size_t nev = word(151);
  if (nev > 18) {
    warn("header says " + std::to_string(nev) + " events, it holds at most 18");
    nev = 18;
  }
  for (size_t i = 0; i < nev; ++i) {
    C3DHeaderEvent e;
    e.time = fword(153 + 2 * static_cast<int>(i));
    e.display = data[376 + i] != 0;
    e.label = trim(std::string(reinterpret_cast<const char*>(data + 396 + 4 * i), 4));
    x->header_events.push_back(e);
  }

  t.c3d = std::move(x);
  return t;
}

void decode_frames(const DataLayout& lay, const uint8_t* bytes, size_t count, double* xyz,
                   uint8_t* valid_out, float* residual, uint8_t* camera, double* analog,
                   size_t* wide_word4) {
  const NumberFormat& nf = lay.nf;
  const size_t points = lay.points, elem = lay.float_storage ? 4 : 2;
  const double scale = lay.scale;
  for (size_t f = 0; f < count; ++f) {
    const uint8_t* fp = bytes + f * lay.per_frame;
    for (size_t p = 0; p < points; ++p) {
      const uint8_t* q = fp + p * 4 * elem;
      double c[3];
      bool valid;
      uint32_t word4 = 0;
      if (lay.float_storage) {
        for (int a = 0; a < 3; ++a) c[a] = nf.f32(q + 4 * a);
        // The float holds the int16 4th word: 32768..65535 are negative int16 values (Qualisys
        // and Vicon write 65535 for -1). Larger values are no int16 at all: valid, residual 0.
        float w = nf.f32(q + 12);
        valid = w >= 0 && !(w >= 32768.0f && w <= 65535.0f);  // NaN is not >= 0
        if (valid && w < 32768.0f) word4 = static_cast<uint32_t>(w);
        if (valid && w > 65535.0f) ++*wide_word4;
      } else {
        for (int a = 0; a < 3; ++a) c[a] = nf.i16(q + 2 * a) * scale;
        int16_t w = nf.i16(q + 6);
        valid = w >= 0;
        if (valid) word4 = static_cast<uint32_t>(w);
      }
      if (valid) {
        bool finite = std::isfinite(c[0]) && std::isfinite(c[1]) && std::isfinite(c[2]);
        bool zero = c[0] == 0 && c[1] == 0 && c[2] == 0;
        valid = finite && !zero;
      }
      const size_t i = f * points + p;
      double* dst = xyz + 3 * i;
      valid_out[i] = valid ? 1 : 0;
      residual[i] = valid ? static_cast<float>((word4 & 0xff) * scale) : -1.0f;
      camera[i] = valid ? static_cast<uint8_t>((word4 >> 8) & 0xff) : 0;
      for (int a = 0; a < 3; ++a) dst[a] = valid ? c[a] : 0.0;
    }
    const uint8_t* ap = fp + points * 4 * elem;
    double* av = analog + f * lay.analog_values;
    for (size_t k = 0; k < lay.analog_values; ++k) {
      const uint8_t* q = ap + k * elem;
      if (lay.float_storage)
        av[k] = nf.f32(q);
      else
        av[k] =
            lay.analog_unsigned ? static_cast<double>(nf.u16(q)) : static_cast<double>(nf.i16(q));
    }
  }
}

std::string wide_word4_warning(size_t n) {
  return std::to_string(n) +
         " samples have a 4th word beyond 16 bits; read as valid with "
         "residual 0 and no camera mask";
}

}  // namespace c3d

Take read_c3d(const std::string& path) {
  std::vector<uint8_t> bytes = read_file(path);
  return read_c3d_bytes(bytes.data(), bytes.size(), path);
}

Take read_c3d_bytes(const uint8_t* data, size_t size, const std::string& name) {
  c3d::DataLayout lay;
  Take t = c3d::read_header(data, size, size, name, &lay);
  const size_t frames = t.frames, points = t.points;
  t.resize(frames, points);
  C3DExtra& x = *t.c3d;
  x.residual.assign(frames * points, -1.0f);
  x.camera_mask.assign(frames * points, 0);
  t.analog.values.assign(frames * lay.analog_values, 0.0);
  size_t wide_word4 = 0;
  c3d::decode_frames(lay, data + lay.data_offset, frames, t.xyz.data(), t.valid.data(),
                     x.residual.data(), x.camera_mask.data(), t.analog.values.data(), &wide_word4);
  if (wide_word4)
    t.warnings.insert(t.warnings.begin() + static_cast<long>(lay.warning_at),
                      c3d::wide_word4_warning(wide_word4));
  return t;
}

}  // namespace capz

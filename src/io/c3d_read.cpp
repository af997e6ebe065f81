// capz — C3D reader.
// Decoder library (capz_decode): builds without PCL and without the transform encoders.
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
#include <type_traits>

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

namespace {

// The header block's fields (1-based 16-bit words, docs/C3D.md) in the file's number form.
struct HeaderFields {
  size_t points = 0;         // word 2
  size_t analog_total = 0;   // word 3: analog values per frame
  long first = 0, last = 0;  // words 4, 5
  float scale = 0;           // words 7-8
  size_t data_start = 0;     // word 9
  size_t analog_spf = 0;     // word 10
  float rate = 0;            // words 11-12
};

// Throws unless the first bytes can be a C3D header pointing at a parameter block.
void check_header_block(const uint8_t* data, size_t avail, size_t size, const std::string& name) {
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
}

// Storage type and |scale| from the header's scale and POINT:SCALE (the header's wins).
void read_storage(const HeaderFields& h, C3DExtra* x, std::vector<std::string>* warnings) {
  auto warn = [&](const std::string& w) { warnings->push_back(w); };
  const C3DParameter* scale_par = x->param("POINT", "SCALE");
  float p_scale = 0;
  bool have_p_scale = false;
  if (scale_par && scale_par->type != -1 && !scale_par->data.empty()) {
    p_scale = scale_par->as_floats()[0];
    have_p_scale = true;
  }
  x->float_storage = h.scale < 0;
  if (have_p_scale && (p_scale < 0) != (h.scale < 0))
    warn("header scale " + num(h.scale) + " and POINT:SCALE " + num(p_scale) +
         " disagree on the storage type (the header's is used)");
  double scale = std::fabs(static_cast<double>(h.scale));
  if (have_p_scale && std::fabs(p_scale) != std::fabs(h.scale)) {
    warn("header scale " + num(h.scale) + " differs from POINT:SCALE " + num(p_scale) +
         (x->float_storage ? "" : " (the header's is used)"));
  }
  if (!std::isfinite(scale) || scale == 0) {
    double alt = have_p_scale ? std::fabs(static_cast<double>(p_scale)) : 0;
    if (std::isfinite(alt) && alt > 0) {
      scale = alt;
    } else {
      if (!x->float_storage) warn("scale factor is " + num(h.scale) + "; using 1");
      scale = 1.0;
    }
  }
  x->point_scale = scale;
}

// The first data block: the header's, or POINT:DATA_START when the header gives 0.
size_t data_start_block(const HeaderFields& h, const C3DExtra& x, const std::string& name,
                        std::vector<std::string>* warnings) {
  size_t data_start = h.data_start;
  long p_start = count_param(x, "POINT", "DATA_START");
  if (data_start == 0) {
    if (p_start <= 0)
      fail(ErrorCode::kCorrupt, name, "header and POINT:DATA_START give no data block");
    warnings->push_back("header data start is 0; using POINT:DATA_START = " +
                        std::to_string(p_start));
    data_start = static_cast<size_t>(p_start);
  } else if (p_start >= 0 && static_cast<size_t>(p_start) != data_start) {
    warnings->push_back("header says the data starts at block " + std::to_string(data_start) +
                        ", POINT:DATA_START says " + std::to_string(p_start) +
                        " (the header's is used)");
  }
  return data_start;
}

// Frames the header and parameters claim (before checking them against the bytes present), and
// the first frame's number.
size_t claimed_frames(const HeaderFields& h, const C3DExtra& x, long* first,
                      std::vector<std::string>* warnings) {
  *first = h.first;
  size_t frames = h.last >= h.first ? static_cast<size_t>(h.last - h.first + 1) : 0;
  long p_frames = count_param(x, "POINT", "FRAMES");
  long tr_start = trial_field(x, "ACTUAL_START_FIELD");
  long tr_end = trial_field(x, "ACTUAL_END_FIELD");
  bool have_trial = tr_start >= 0 && tr_end >= tr_start;
  long tr_frames = have_trial ? tr_end - tr_start + 1 : -1;
  bool header_limited = h.last == 65535 || tr_frames > 65535 || p_frames > 65535;
  if (header_limited && (have_trial || p_frames > 0)) {
    size_t f = have_trial ? static_cast<size_t>(tr_frames) : static_cast<size_t>(p_frames);
    if (f != frames)
      warnings->push_back("header says " + std::to_string(frames) +
                          " frames, which 16 bits cannot exceed; " +
                          (have_trial ? "TRIAL:ACTUAL_*_FIELD" : "POINT:FRAMES") + " says " +
                          std::to_string(f) + " (used)");
    frames = f;
    if (have_trial) *first = tr_start;
  } else if (p_frames >= 0 && static_cast<size_t>(p_frames) != frames) {
    warnings->push_back("header says " + std::to_string(frames) + " frames, POINT:FRAMES says " +
                        std::to_string(p_frames) + " (the header's count is used)");
  }
  return frames;
}

struct FrameLayout {
  size_t points = 0, analog_total = 0, spf = 0, channels = 0;
};

// Analog samples per frame: the header's, or for a header that gives 0 with analog values,
// ANALOG:USED's division of them (1 when it does not divide them), with a warning.
size_t analog_samples_per_frame(const HeaderFields& h, long a_used,
                                std::vector<std::string>* warnings) {
  size_t spf = h.analog_spf;
  if (h.analog_total > 0 && spf == 0) {
    spf = 1;
    if (a_used > 0 && h.analog_total % static_cast<size_t>(a_used) == 0)
      spf = h.analog_total / static_cast<size_t>(a_used);
    warnings->push_back("header gives 0 analog samples per frame for " +
                        std::to_string(h.analog_total) + " analog values per frame; using " +
                        std::to_string(spf));
  }
  return spf;
}

// The points and analog values per frame (points and analog_total only) of the first candidate
// that fills the `data_bytes` of the data section up to block padding: the header's counts
// first, then those with POINT:USED and ANALOG:USED x spf in their place; the header's when none
// fits.
FrameLayout fitting_layout(const HeaderFields& h, long p_used, long a_used, size_t spf,
                           size_t frames, size_t elem, size_t data_bytes) {
  struct Layout {
    size_t points, analog_total;
  };
  std::vector<Layout> cands = {{h.points, h.analog_total}};
  std::vector<size_t> point_opts = {h.points}, analog_opts = {h.analog_total};
  if (p_used >= 0 && static_cast<size_t>(p_used) != h.points) point_opts.push_back(p_used);
  if (a_used >= 0 && spf > 0 && static_cast<size_t>(a_used) * spf != h.analog_total)
    analog_opts.push_back(static_cast<size_t>(a_used) * spf);
  for (size_t pp : point_opts)
    for (size_t aa : analog_opts)
      if (pp != h.points || aa != h.analog_total) cands.push_back({pp, aa});
  auto tight = [&](const Layout& l) {  // fills the data section up to block padding
    const size_t frame_bytes = (l.points * 4 + l.analog_total) * elem;
    long double sl = static_cast<long double>(data_bytes) -
                     static_cast<long double>(frames) * static_cast<long double>(frame_bytes);
    return sl >= 0 && sl < static_cast<long double>(kBlock + frame_bytes);
  };
  Layout lay = cands[0];
  if (frames > 0 && !tight(lay))
    for (size_t i = 1; i < cands.size(); ++i)
      if (tight(cands[i])) {
        lay = cands[i];
        break;
      }
  FrameLayout out;
  out.points = lay.points;
  out.analog_total = lay.analog_total;
  return out;
}

// Points and analog values per frame: the header's counts, unless POINT:USED / ANALOG:USED
// give a layout that fills the `data_bytes` of the data section exactly where the header's does
// not fit or leaves more unexplained bytes (some writers put the channel count in header word 3
// instead of channels x samples).
FrameLayout choose_layout(const HeaderFields& h, const C3DExtra& x, size_t frames, size_t elem,
                          size_t data_bytes, std::vector<std::string>* warnings) {
  auto warn = [&](const std::string& w) { warnings->push_back(w); };
  long p_used = count_param(x, "POINT", "USED");
  long a_used = count_param(x, "ANALOG", "USED");
  const size_t spf = analog_samples_per_frame(h, a_used, warnings);
  FrameLayout out = fitting_layout(h, p_used, a_used, spf, frames, elem, data_bytes);
  if (p_used >= 0 && static_cast<size_t>(p_used) != h.points)
    warn("header says " + std::to_string(h.points) + " points, POINT:USED says " +
         std::to_string(p_used) + " (" +
         (out.points == h.points ? "the header's" : "POINT:USED's") +
         " count fits the data and is used)");
  if (out.analog_total != h.analog_total)
    warn("header says " + std::to_string(h.analog_total) +
         " analog values per frame, ANALOG:USED " + std::to_string(a_used) + " x " +
         std::to_string(spf) + " samples per frame fits the data and is used");
  if (out.analog_total == 0) return out;
  out.spf = spf;
  out.channels = out.analog_total / spf;
  if (out.analog_total % spf != 0)
    warn("the " + std::to_string(out.analog_total) +
         " analog values per frame are not a multiple of " + std::to_string(spf) +
         " samples per frame; the remainder is skipped");
  if (a_used >= 0 && static_cast<size_t>(a_used) != out.channels &&
      out.analog_total == h.analog_total)
    warn("header gives " + std::to_string(out.channels) + " analog channels, ANALOG:USED says " +
         std::to_string(a_used) + " (the header's count is used)");
  return out;
}

// The ROTATION group's layout into lay->rot_* and r's segments, ratio, rate and labels (arrays
// left empty). No rotations (segments 0) without the group, with USED 0, or when the group does
// not say where the data is (a warning then).
void read_rotation_layout(const C3DExtra& x, double point_rate, DataLayout* lay, Rotations* r,
                          std::vector<std::string>* warnings) {
  const long used = count_param(x, "ROTATION", "USED");
  if (used <= 0) return;
  const long start = count_param(x, "ROTATION", "DATA_START");
  if (start < 2) {
    warnings->push_back("ROTATION:USED says " + std::to_string(used) +
                        " segments but ROTATION:DATA_START gives no data block (" +
                        std::to_string(start) + "); the rotations are not read");
    return;
  }
  long ratio = count_param(x, "ROTATION", "RATIO");
  const double rate = number_param(x, "ROTATION", "RATE", 0);
  const double rate_ratio = point_rate > 0 ? rate / point_rate : 0;
  if (ratio <= 0 && rate_ratio >= 0.5 && rate_ratio < 65535.5)
    ratio = std::lround(rate_ratio);  // ezc3d's fallback without RATIO
  if (ratio <= 0) {
    warnings->push_back("ROTATION:RATIO and RATE give no samples per frame; 1 is used");
    ratio = 1;
  }
  if (used > 65535 || ratio > 65535) {  // float parameters can claim billions
    warnings->push_back("ROTATION:USED " + std::to_string(used) + " x RATIO " +
                        std::to_string(ratio) +
                        " is beyond what a C3D holds (65535 each); "
                        "the rotations are not read");
    return;
  }
  r->segments = static_cast<int>(used);
  r->samples_per_frame = static_cast<int>(ratio);
  r->rate = std::isfinite(rate) && rate > 0 ? rate : point_rate * static_cast<double>(ratio);
  r->labels = string_list(x, "ROTATION", "LABELS");
  r->labels.resize(static_cast<size_t>(used));
  lay->rot_offset = (static_cast<size_t>(start) - 1) * kBlock;
  lay->rot_samples_per_frame = static_cast<size_t>(ratio);
  lay->rot_segments = static_cast<size_t>(used);
  lay->rot_per_frame = lay->rot_samples_per_frame * lay->rot_segments * kRotationBytes;
}

// The frame count checked against the bytes there are: the point / analog section holds
// `data_bytes`, the rotation section runs to the end of a file of `size` bytes.
size_t frames_present(size_t frames, size_t per_frame, size_t data_bytes, size_t size,
                      DataLayout* lay, Rotations* rot, std::vector<std::string>* warnings) {
  auto warn = [&](const std::string& w) { warnings->push_back(w); };
  if (per_frame > 0 && frames > data_bytes / per_frame) {
    warn("header says " + std::to_string(frames) + " frames, file holds " +
         std::to_string(data_bytes / per_frame));
    frames = data_bytes / per_frame;
  }
  if (lay->rot_per_frame > 0) {
    const size_t rot_frames =
        lay->rot_offset < size ? (size - lay->rot_offset) / lay->rot_per_frame : 0;
    if (rot_frames == 0 && per_frame > 0 && frames > 0) {
      warn("ROTATION:DATA_START points past the file's end; the " + std::to_string(rot->segments) +
           " rotation segments are not read");
      *rot = Rotations();
      lay->rot_per_frame = lay->rot_segments = lay->rot_samples_per_frame = 0;
    } else if (frames > rot_frames) {
      warn("header says " + std::to_string(frames) + " frames, the rotation section holds " +
           std::to_string(rot_frames));
      frames = rot_frames;
    }
  } else if (per_frame == 0 && frames > 0) {
    // Frames of nothing: the count is unverifiable (TRIAL fields can claim 4 billion frames of
    // nothing, which every later stage would loop over). Such frames carry no data.
    warn("header says " + std::to_string(frames) +
         " frames of no points and no analog values; read as 0 frames");
    frames = 0;
  }
  return frames;
}

// POINT / ANALOG labels, rates and units into t (points and channels already set).
void read_labels_rates_units(const C3DExtra& x, float h_rate, Take* t,
                             std::vector<std::string>* warnings) {
  auto warn = [&](const std::string& w) { warnings->push_back(w); };
  const size_t points = t->points, channels = static_cast<size_t>(t->analog.channels);
  t->labels = string_list(x, "POINT", "LABELS");
  if (t->labels.size() < points && x.group("POINT"))
    warn("POINT:LABELS has " + std::to_string(t->labels.size()) + " labels for " +
         std::to_string(points) + " points");
  t->labels.resize(points);
  t->descriptions = string_list(x, "POINT", "DESCRIPTIONS");
  if (!t->descriptions.empty()) t->descriptions.resize(points);
  t->analog.labels = string_list(x, "ANALOG", "LABELS");
  t->analog.labels.resize(channels);

  double p_rate = number_param(x, "POINT", "RATE", 0);
  t->rate = std::isfinite(p_rate) && p_rate > 0 ? p_rate : static_cast<double>(h_rate);
  if (!std::isfinite(t->rate) || t->rate < 0) t->rate = 0;
  if (p_rate > 0 && std::isfinite(h_rate) && std::fabs(p_rate - h_rate) > 1e-3 * p_rate)
    warn("header rate " + num(h_rate) + " Hz differs from POINT:RATE " + num(p_rate) +
         " Hz (POINT:RATE is used)");
  double a_rate = number_param(x, "ANALOG", "RATE", 0);
  const bool a_ok = std::isfinite(a_rate) && a_rate > 0;
  t->analog.rate = a_ok ? a_rate : channels == 0 ? 0 : t->rate * t->analog.samples_per_frame;
  std::string units_fault;
  t->units = point_units(x, &units_fault);
  if (!units_fault.empty()) warn(units_fault);
}

// The header's events (words 150..198, bytes 376.. and 396..).
void read_header_events(const uint8_t* data, const NumberFormat& nf, C3DExtra* x,
                        std::vector<std::string>* warnings) {
  auto word = [&](int w) { return nf.u16(data + 2 * (w - 1)); };
  x->header_events_label_range = word(150) == 12345;
  size_t nev = word(151);
  if (nev > 18) {
    warnings->push_back("header says " + std::to_string(nev) + " events, it holds at most 18");
    nev = 18;
  }
  for (size_t i = 0; i < nev; ++i) {
    C3DHeaderEvent e;
    e.time = nf.f32(data + 2 * (153 + 2 * static_cast<int>(i) - 1));
    e.display = data[376 + i] != 0;
    e.label = trim(std::string(reinterpret_cast<const char*>(data + 396 + 4 * i), 4));
    x->header_events.push_back(e);
  }
}

// The header block's fields (1-based 16-bit words 2 to 12; word 6, the interpolation gap, into
// x).
HeaderFields read_header_words(const uint8_t* data, const NumberFormat& nf, C3DExtra* x) {
  auto word = [&](int w) { return nf.u16(data + 2 * (w - 1)); };  // 1-based header words
  auto fword = [&](int w) { return nf.f32(data + 2 * (w - 1)); };
  HeaderFields h;
  h.points = word(2);
  h.analog_total = word(3);
  h.first = word(4);
  h.last = word(5);
  x->max_interpolation_gap = word(6);
  h.scale = fword(7);
  h.data_start = word(9);
  h.analog_spf = word(10);
  h.rate = fword(11);
  return h;
}

// The point / analog section's layout into out: frames of per_frame bytes from data_offset, as
// fl lays them out; warning_at, where a warning about the frames belongs in the take's list.
void set_frame_layout(const NumberFormat& nf, const C3DExtra& x, const FrameLayout& fl,
                      size_t data_offset, size_t per_frame, size_t frames, size_t warning_at,
                      DataLayout* out) {
  bool analog_unsigned = false;
  if (const C3DParameter* fmt = x.param("ANALOG", "FORMAT"))
    if (fmt->type == -1) analog_unsigned = upper(trim(fmt->as_string())) == "UNSIGNED";
  out->nf = nf;
  out->data_offset = data_offset;
  out->per_frame = per_frame;
  out->frames = frames;
  out->points = fl.points;
  out->analog_values = fl.spf * fl.channels;
  out->float_storage = x.float_storage;
  out->analog_unsigned = analog_unsigned;
  out->scale = x.point_scale;
  out->warning_at = warning_at;
}

}  // namespace

Take read_header(const uint8_t* data, size_t avail, size_t size, const std::string& name,
                 DataLayout* out) {
  check_header_block(data, avail, size, name);
  const size_t param_offset = (static_cast<size_t>(data[0]) - 1) * kBlock;
  const size_t limit = parameter_limit(data, size);
  ParameterSection sec = parse_parameter_section(data, avail, param_offset, limit, name);
  const NumberFormat nf{sec.processor};

  Take t;
  t.source = name;
  t.format = Format::kC3D;
  auto x = std::make_shared<C3DExtra>();
  x->processor = sec.processor;
  x->groups = std::move(sec.groups);
  for (auto& w : sec.warnings) t.warnings.push_back(w);
  for (auto& w : sec.notes) t.warnings.push_back(w);
  std::vector<std::string>* warnings = &t.warnings;
  const HeaderFields h = read_header_words(data, nf, x.get());

  read_storage(h, x.get(), warnings);
  const size_t elem = x->float_storage ? 4 : 2;
  const size_t data_offset = (data_start_block(h, *x, name, warnings) - 1) * kBlock;
  long first = 0;
  size_t frames = claimed_frames(h, *x, &first, warnings);

  // Point rate before the rotation layout (a ROTATION group without RATIO needs it).
  const double p_rate = number_param(*x, "POINT", "RATE", 0);
  const double point_rate = std::isfinite(p_rate) && p_rate > 0 ? p_rate : h.rate;
  read_rotation_layout(*x, point_rate, out, &t.rotations, warnings);
  // The point / analog section ends where a rotation section after it starts.
  size_t data_end = size;
  if (out->rot_per_frame > 0 && out->rot_offset > data_offset)
    data_end = std::min(size, out->rot_offset);
  const size_t data_bytes = data_offset < data_end ? data_end - data_offset : 0;
  const FrameLayout fl = choose_layout(h, *x, frames, elem, data_bytes, warnings);
  const size_t per_frame = (fl.points * 4 + fl.analog_total) * elem;
  frames = frames_present(frames, per_frame, data_bytes, size, out, &t.rotations, warnings);

  t.frames = frames;
  t.points = fl.points;
  t.first_frame = first;
  t.analog.channels = static_cast<int>(fl.channels);
  t.analog.samples_per_frame = static_cast<int>(fl.spf);
  set_frame_layout(nf, *x, fl, data_offset, per_frame, frames, t.warnings.size(), out);

  read_labels_rates_units(*x, h.rate, &t, warnings);
  read_header_events(data, nf, x.get(), warnings);
  t.c3d = std::move(x);
  return t;
}

namespace {

// Decodes `count` frames (decode_frames) for one processor type and storage, both fixed at
// compile time: the number reads then carry no test per value (this loop reads every frame of a
// take twice when it is compressed: once for the scan, once to code it).
template <class Proc, class FloatStorage>
void decode_frames_as(const DataLayout& lay, const uint8_t* bytes, size_t count, double* xyz,
                      uint8_t* valid_out, float* residual, uint8_t* camera, double* analog,
                      size_t* wide_word4) {
  const size_t points = lay.points;
  const double scale = lay.scale;
  NumberFormat nf;
  nf.processor = Proc::value;
  constexpr bool float_storage = FloatStorage::value;
  constexpr size_t elem = float_storage ? 4 : 2;
  for (size_t f = 0; f < count; ++f) {
    const uint8_t* fp = bytes + f * lay.per_frame;
    for (size_t p = 0; p < points; ++p) {
      const uint8_t* q = fp + p * 4 * elem;
      double c[3];
      bool valid;
      uint32_t word4 = 0;
      if (float_storage) {
        for (int a = 0; a < 3; ++a) c[a] = nf.f32(q + 4 * a);
        // The float holds the int16 4th word: 32768..65535 are negative int16 values
        // (Qualisys and Vicon write 65535 for -1). Larger values are no int16 at all: valid,
        // residual 0.
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
      if (float_storage)
        av[k] = nf.f32(q);
      else
        av[k] =
            lay.analog_unsigned ? static_cast<double>(nf.u16(q)) : static_cast<double>(nf.i16(q));
    }
  }
}

}  // namespace

void decode_frames(const DataLayout& lay, const uint8_t* bytes, size_t count, double* xyz,
                   uint8_t* valid_out, float* residual, uint8_t* camera, double* analog,
                   size_t* wide_word4) {
  auto with_storage = [&](auto proc) {
    using Proc = decltype(proc);
    if (lay.float_storage)
      decode_frames_as<Proc, std::true_type>(lay, bytes, count, xyz, valid_out, residual, camera,
                                             analog, wide_word4);
    else
      decode_frames_as<Proc, std::false_type>(lay, bytes, count, xyz, valid_out, residual, camera,
                                              analog, wide_word4);
  };
  if (lay.nf.processor == kDec)
    with_storage(std::integral_constant<int, kDec>());
  else if (lay.nf.processor == kMips)
    with_storage(std::integral_constant<int, kMips>());
  else
    with_storage(std::integral_constant<int, kIntel>());
}

void decode_c3d_rotations(const DataLayout& lay, const uint8_t* bytes, size_t count,
                          float* matrices, float* reliability) {
  const NumberFormat& nf = lay.nf;
  for (size_t i = 0; i < count; ++i, bytes += kRotationBytes) {
    for (size_t k = 0; k < 16; ++k) matrices[i * 16 + k] = nf.f32(bytes + 4 * k);
    reliability[i] = nf.f32(bytes + 64);
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
  const size_t rotations = frames * lay.rot_samples_per_frame * lay.rot_segments;
  t.rotations.matrices.resize(rotations * 16);
  t.rotations.reliability.resize(rotations);
  c3d::decode_c3d_rotations(lay, data + lay.rot_offset, rotations, t.rotations.matrices.data(),
                            t.rotations.reliability.data());
  return t;
}

}  // namespace capz

// META's encoder (docs/FORMAT.md 5): the take's metadata written by the block functions that
// mirror meta.cpp's readers, then coded as they are, by the byte model or by LZMA2 (after a
// preset dictionary), whichever is smallest.
#include <cmath>
#include <cstring>

#include "capz/error.h"
#include "capz/tool/file.h"
#include "coding/bytes.h"
#include "coding/c3d_params.h"
#include "coding/entropy.h"
#include "coding/lzma_block.h"
#include "coding/meta.h"
#include "coding/meta_shared.h"
#include "coding/ply_types.h"

namespace capz {
namespace {

using meta::derive_labels;
using meta::wrap_add64;
using meta::wrap_sub64;

void put_strings(ByteWriter* w, const std::vector<std::string>& v) {
  w->varint(v.size());
  for (const auto& s : v) w->str(s);
}

// True when the lists derive_labels gives (meta_shared.h) are exactly the given ones.
bool labels_from_parameters(const C3DExtra& c, size_t points, int channels,
                            const std::vector<std::string>& labels,
                            const std::vector<std::string>& descriptions,
                            const std::vector<std::string>& analog_labels) {
  std::vector<std::string> l, d, a;
  derive_labels(c, points, channels, &l, &d, &a);
  return l == labels && d == descriptions && a == analog_labels;
}

// FORMAT.md 5.3's C3D block.
void put_c3d_block(const C3DExtra& c, bool has_sample_words, ByteWriter* out) {
  ByteWriter& w = *out;
  w.u8(static_cast<uint8_t>(c.processor));
  w.u8(c.float_storage ? 1 : 0);
  w.f64(c.point_scale);
  w.varint(static_cast<uint64_t>(std::max(0, c.max_interpolation_gap)));
  w.u8(c.header_events_label_range ? 1 : 0);
  w.varint(c.header_events.size());
  for (const auto& e : c.header_events) {
    w.f32(e.time);
    w.u8(e.display ? 1 : 0);
    w.str(e.label);
  }
  w.u8(has_sample_words ? 1 : 0);
  std::vector<uint8_t> params = encode_c3d_parameters(c);
  w.varint(params.size());
  w.bytes(params);
}

// The TRC block's Time column: regular (t0 + i * dt exactly), on a decimal grid, or listed.
void put_trc_times(const std::vector<double>& times, size_t frames, ByteWriter* out) {
  ByteWriter& w = *out;
  if (times.size() != frames) {
    w.u8(0);
  } else {
    bool regular = frames >= 1;
    double t0 = frames ? times[0] : 0, dt = frames > 1 ? times[1] - times[0] : 0;
    for (size_t i = 0; regular && i < frames; ++i)
      regular = (t0 + static_cast<double>(i) * dt) == times[i];
    int decimals = -1;
    for (int k = 0; !regular && decimals < 0 && k <= 9; ++k) {
      const double d = std::pow(10.0, k);
      bool ok = true;
      for (size_t i = 0; ok && i < frames; ++i) {
        const double v = times[i] * d;
        ok = std::fabs(v) < 2e9 && std::round(v) / d == times[i];
      }
      if (ok) decimals = k;
    }
    if (regular) {
      w.u8(1);
      w.f64(t0);
      w.f64(dt);
    } else if (decimals >= 0) {
      const double d = std::pow(10.0, decimals);
      std::vector<int32_t> deltas(frames);
      int32_t prev = 0;
      for (size_t i = 0; i < frames; ++i) {
        const int32_t k = static_cast<int32_t>(std::round(times[i] * d));
        deltas[i] = k - prev;
        prev = k;
      }
      w.u8(3);
      w.u8(static_cast<uint8_t>(decimals));
      std::vector<uint8_t> block = encode_ints(deltas);
      w.varint(block.size());
      w.bytes(block);
    } else {
      w.u8(2);
      for (double v : times) w.f64(v);
    }
  }
}

// The TRC block's Frame# column: consecutive from the first, or listed as differences.
void put_trc_frame_numbers(const std::vector<int64_t>& numbers, size_t frames, ByteWriter* out) {
  ByteWriter& w = *out;
  if (numbers.size() != frames) {
    w.u8(0);
  } else {
    bool regular = frames >= 1;
    for (size_t i = 1; regular && i < frames; ++i)
      regular = numbers[i] == wrap_add64(numbers[0], static_cast<int64_t>(i));
    if (regular) {
      w.u8(1);
      w.svarint(numbers[0]);
    } else {
      w.u8(2);
      int64_t prev = 0;
      for (int64_t v : numbers) {
        w.svarint(wrap_sub64(v, prev));
        prev = v;
      }
    }
  }
}

// FORMAT.md 5.4's TRC block.
void put_trc_block(const TRCExtra& x, size_t frames, ByteWriter* out) {
  ByteWriter& w = *out;
  w.str(x.path_file_type_line);
  w.f64(x.camera_rate);
  w.f64(x.orig_data_rate);
  w.svarint(x.orig_data_start_frame);
  w.svarint(x.orig_num_frames);
  w.svarint(x.decimals);
  put_trc_times(x.times, frames, out);
  put_trc_frame_numbers(x.frame_numbers, frames, out);
}

// FORMAT.md 5.5: the PCD layout (fields, WIDTH x HEIGHT, VIEWPOINT).
void put_pcd_layout(const PCDExtra& x, size_t points, ByteWriter* out) {
  ByteWriter& w = *out;
  w.str(x.version);
  w.varint(x.width ? x.width : points);
  w.varint(x.width ? x.height : 1);
  w.u8(x.viewpoint.size() == 7 ? 1 : 0);
  if (x.viewpoint.size() == 7)
    for (double v : x.viewpoint) w.f64(v);
  w.varint(x.fields.size());
  for (const PCDField& f : x.fields) {
    w.str(f.name);
    w.u8(static_cast<uint8_t>(f.type));
    w.u8(static_cast<uint8_t>(f.size));
    w.varint(static_cast<uint64_t>(f.count));
  }
  size_t bounded = 0;
  for (double b : x.field_bounds) bounded += b > 0;
  w.varint(bounded);
  for (size_t i = 0; i < x.field_bounds.size() && i < x.fields.size(); ++i)
    if (x.field_bounds[i] > 0) {
      w.varint(i);
      w.f64(x.field_bounds[i]);
    }
}

// FORMAT.md 5.5's PCD block, then (layout) its PCD layout.
void put_pcd_block(const PCDExtra& x, size_t frames, size_t points, bool layout, ByteWriter* out) {
  out->str(x.encoding);
  put_strings(out, x.frame_names.size() == frames ? x.frame_names : std::vector<std::string>());
  if (layout) put_pcd_layout(x, points, out);
}

// "Scans (format 1.1)": the PLY block of a frame-file source, after the PCD block whose layout
// (`fields`) it names the types of. A field's type name is the one the source spelled for a
// property of that name, type and size, else the classic name.
void put_ply_block(const PLYExtra& x, const std::vector<PCDField>& fields, ByteWriter* out) {
  ByteWriter& w = *out;
  uint8_t enc = 1;
  for (uint8_t i = 0; i < 3; ++i)
    if (x.encoding == meta::kPlyEncodings[i]) enc = i;
  w.u8(enc);
  w.str(x.version);
  for (const PCDField& f : fields) w.str(spelled_ply_type(x.fields, x.type_names, f));
  put_strings(&w, x.comments);
  put_strings(&w, x.obj_info);
}

// FORMAT.md 5.7: the bounded analog channels.
void put_analog_bounds(const Analog& a, ByteWriter* out) {
  ByteWriter& w = *out;
  size_t nb = 0;
  for (size_t c = 0; c < a.bounds.size(); ++c) nb += a.bounds[c] > 0;
  w.varint(nb);
  size_t next = 0;
  for (size_t c = 0; c < a.bounds.size(); ++c)
    if (a.bounds[c] > 0) {
      w.varint(c - next);
      next = c + 1;
      w.f64(a.bounds[c]);
      w.f64(c < a.factors.size() ? a.factors[c] : 1.0);
    }
}

std::vector<uint8_t> encode_meta_fields(const Take& t, bool has_sample_words) {
  ByteWriter w;
  const std::string src = without_trailing_slashes(t.source);  // its last name, a folder's too
  size_t slash = src.find_last_of('/');
  w.str(slash == std::string::npos ? src : src.substr(slash + 1));
  w.str(t.units);
  w.f64(t.rate);
  w.svarint(t.first_frame);
  // FORMAT.md 5.3: labels the C3D parameters already hold are not written twice.
  const bool derived = t.c3d && labels_from_parameters(*t.c3d, t.points, t.analog.channels,
                                                       t.labels, t.descriptions, t.analog.labels);
  static const std::vector<std::string> kNone;
  if (!t.ragged() && t.labels.empty() && is_frame_files(t.format)) {
    // FORMAT.md 5.2: frame files' points have no labels; their list is N empty strings.
    w.varint(t.points);
    for (size_t p = 0; p < t.points; ++p) w.varint(0);  // an empty string
  } else {
    put_strings(&w, derived ? kNone : t.labels);
  }
  put_strings(&w, derived ? kNone : t.descriptions);
  w.f64(t.analog.rate);
  put_strings(&w, derived ? kNone : t.analog.labels);
  // FORMAT.md 5.5: a PCD layout (fields, WIDTH x HEIGHT, VIEWPOINT) follows the PCD block.
  const bool layout = t.pcd && !t.pcd->fields.empty();
  // "Scans (format 1.1)": a PLY source's header facts follow its PCD block (its point layout).
  const bool ply = t.format == Format::kPLYFolder && t.ply && layout;
  uint8_t extras = static_cast<uint8_t>((t.c3d ? 1 : 0) | (t.trc ? 2 : 0) | (t.pcd ? 4 : 0) |
                                        (derived ? 8 : 0) | (layout ? 16 : 0) | (ply ? 32 : 0));
  w.u8(extras);
  if (t.c3d) put_c3d_block(*t.c3d, has_sample_words, &w);
  if (t.trc) put_trc_block(*t.trc, t.frames, &w);
  if (t.pcd) put_pcd_block(*t.pcd, t.frames, t.points, layout, &w);
  if (ply) put_ply_block(*t.ply, t.pcd->fields, &w);
  if (t.rotations.segments > 0) {  // FORMAT.md 5.6 (HEAD says rotations)
    w.f64(t.rotations.rate);
    put_strings(&w, t.rotations.labels);
  }
  if (t.analog.lossy()) put_analog_bounds(t.analog, &w);  // FORMAT.md 5.7, appended
  return std::move(w.buffer());
}
}  // namespace

std::vector<uint8_t> encode_meta_raw(const Take& t, bool has_sample_words) {
  ByteWriter w;
  w.u8(0);
  w.bytes(encode_meta_fields(t, has_sample_words));
  return std::move(w.buffer());
}

std::vector<uint8_t> encode_meta(const Take& t, bool has_sample_words, bool dictionary) {
  return code_meta_fields(encode_meta_fields(t, has_sample_words), dictionary);
}

std::vector<uint8_t> code_meta_fields(const std::vector<uint8_t>& fields, bool dictionary) {
  // The smallest of codings 0 (as they are), 1 (byte model), 2 (LZMA2) and, when offered, 3
  // (LZMA2 after dictionary 1); ties: the lowest.
  ByteWriter w;
  w.u8(0);
  w.bytes(fields);
  for (uint8_t coding = 1; coding <= (dictionary ? 3 : 2); ++coding) {
    const std::vector<uint8_t> coded =
        coding == 1   ? encode_bytes(fields.data(), fields.size())
        : coding == 2 ? lzma2_encode(fields.data(), fields.size())
                      : lzma2_encode(fields.data(), fields.size(), meta_dictionary(1));
    ByteWriter c;
    c.u8(coding);
    if (coding == 3) c.u8(1);  // dictionary 1
    c.varint(fields.size());
    c.bytes(coded);
    if (c.buffer().size() < w.buffer().size()) w = std::move(c);
  }
  return std::move(w.buffer());
}

}  // namespace capz

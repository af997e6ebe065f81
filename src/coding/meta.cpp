// META (docs/FORMAT.md 5): everything of the Take that the other chunks do
// not hold, as fields written and read by mirrored block functions, then coded as they are, by a
// byte model or by LZMA2 (after a preset dictionary from 8.0 on). Decoder library (capz_decode).
#include "coding/meta.h"

#include <cmath>
#include <cstring>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/c3d_params.h"
#include "coding/entropy.h"
#include "coding/lzma_block.h"
#include "coding/ply_types.h"

namespace capz {
namespace {

void put_strings(ByteWriter* w, const std::vector<std::string>& v) {
  w->varint(v.size());
  for (const auto& s : v) w->str(s);
}
std::vector<std::string> get_strings(ByteReader* r, size_t expect, const char* what) {
  uint64_t n = r->count(1, what);
  if (n != 0 && n != expect)
    throw Error(ErrorCode::kCorrupt, r->what() + ": " + what + " = " + std::to_string(n) +
                                         ", expected 0 or " + std::to_string(expect));
  std::vector<std::string> v(static_cast<size_t>(n));
  for (auto& s : v) s = r->str();
  return v;
}

// A list of any length (each string at least its length byte).
std::vector<std::string> get_any_strings(ByteReader* r, const char* what) {
  std::vector<std::string> v(static_cast<size_t>(r->count(1, what)));
  for (auto& s : v) s = r->str();
  return v;
}

// Frame numbers are coded with wrapping int64 arithmetic (FORMAT.md 5.4): every int64
// round-trips, and no input makes the sums overflow (signed overflow is undefined).
int64_t wrap_add64(int64_t a, int64_t b) {
  return static_cast<int64_t>(static_cast<uint64_t>(a) + static_cast<uint64_t>(b));
}
int64_t wrap_sub64(int64_t a, int64_t b) {
  return static_cast<int64_t>(static_cast<uint64_t>(a) - static_cast<uint64_t>(b));
}

}  // namespace

namespace {
// The lists the C3D reader derives from the parameters (FORMAT.md 5.3, "Labels from the
// parameters"; c3d_read.cpp read_labels_rates_units): cut or padded to the points (descriptions:
// when there are any) and to the channels.
void derive_labels(const C3DExtra& c, size_t points, int channels, std::vector<std::string>* l,
                   std::vector<std::string>* d, std::vector<std::string>* a) {
  *l = c3d::string_list(c, "POINT", "LABELS");
  l->resize(points);
  *d = c3d::string_list(c, "POINT", "DESCRIPTIONS");
  if (!d->empty()) d->resize(points);
  *a = c3d::string_list(c, "ANALOG", "LABELS");
  a->resize(static_cast<size_t>(std::max(0, channels)));
}

// True when those lists are exactly the given ones.
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

const char* const kPlyEncodings[] = {"ascii", "binary_little_endian", "binary_big_endian"};

// "Scans (format 1.1)": the PLY block of a frame-file source, after the PCD block whose layout
// (`fields`) it names the types of. A field's type name is the one the source spelled for a
// property of that name, type and size, else the classic name.
void put_ply_block(const PLYExtra& x, const std::vector<PCDField>& fields, ByteWriter* out) {
  ByteWriter& w = *out;
  uint8_t enc = 1;
  for (uint8_t i = 0; i < 3; ++i)
    if (x.encoding == kPlyEncodings[i]) enc = i;
  w.u8(enc);
  w.str(x.version);
  for (const PCDField& f : fields) {
    const char* name = ply_type_name(f.type, f.size);
    std::string spelled = name ? name : "";
    for (size_t i = 0; i < x.fields.size() && i < x.type_names.size(); ++i)
      if (x.fields[i].name == f.name && x.fields[i].type == f.type && x.fields[i].size == f.size)
        spelled = x.type_names[i];
    w.str(spelled);
  }
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
  std::string src = t.source;
  while (!src.empty() && src.back() == '/') src.pop_back();
  size_t slash = src.find_last_of('/');
  w.str(slash == std::string::npos ? src : src.substr(slash + 1));
  w.str(t.units);
  w.f64(t.rate);
  w.svarint(t.first_frame);
  // FORMAT.md 5.3: labels the C3D parameters already hold are not written twice.
  const bool derived = t.c3d && labels_from_parameters(*t.c3d, t.points, t.analog.channels,
                                                       t.labels, t.descriptions, t.analog.labels);
  static const std::vector<std::string> kNone;
  put_strings(&w, derived ? kNone : t.labels);
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

std::vector<uint8_t> encode_meta(const Take& t, bool has_sample_words, bool dictionary) {
  std::vector<uint8_t> fields = encode_meta_fields(t, has_sample_words);
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

namespace {
// FORMAT.md 5.5: the PCD layout; sets the take's attribute layouts (no data).
void get_pcd_layout(ByteReader* r, const std::string& what, Take* t, PCDExtra* p) {
  p->version = r->str();
  const uint64_t width = r->varint(), height = r->varint();
  if (width > (uint64_t{1} << 40) || height > (uint64_t{1} << 40) || width * height != t->points)
    fail(ErrorCode::kCorrupt, what,
         "PCD layout " + std::to_string(width) + " x " + std::to_string(height) + " is not the " +
             std::to_string(t->points) + " points");
  p->width = static_cast<size_t>(width);
  p->height = static_cast<size_t>(height);
  const uint8_t vf = r->u8();
  if (vf > 1) fail(ErrorCode::kCorrupt, what, "bad PCD viewpoint flag");
  p->viewpoint.clear();
  if (vf == 1)
    for (int i = 0; i < 7; ++i) p->viewpoint.push_back(r->f64());
  const uint64_t nf = r->count(4, "PCD field count");
  if (nf < 3 || nf > 1024)
    fail(ErrorCode::kCorrupt, what, "PCD layout with " + std::to_string(nf) + " fields");
  uint64_t step = 0;
  int xyz[3] = {0, 0, 0};
  t->attributes.clear();
  for (uint64_t i = 0; i < nf; ++i) {
    PCDField f;
    f.name = r->str();
    f.type = static_cast<char>(r->u8());
    f.size = r->u8();
    const uint64_t count = r->varint();
    if (!valid_field_form(f.type, f.size, count))
      fail(ErrorCode::kCorrupt, what, "PCD field '" + f.name + "' has a bad type, size or count");
    f.count = static_cast<int>(count);
    step += count * static_cast<uint64_t>(f.size);
    if (step > (1u << 20)) fail(ErrorCode::kCorrupt, what, "PCD points larger than 2^20 bytes");
    const int axis = f.name == "x" ? 0 : f.name == "y" ? 1 : f.name == "z" ? 2 : -1;
    if (axis >= 0) {
      if (++xyz[axis] > 1 || f.type != 'F' || f.count != 1)
        fail(ErrorCode::kCorrupt, what, "PCD field " + f.name + " twice or not one float");
    } else {
      t->attributes.push_back(attribute_of(f));
    }
    p->fields.push_back(std::move(f));
  }
  if (xyz[0] != 1 || xyz[1] != 1 || xyz[2] != 1)
    fail(ErrorCode::kCorrupt, what, "PCD layout without x, y and z");
  const uint64_t bounded = r->count(9, "bounded field count");
  if (bounded > nf) fail(ErrorCode::kCorrupt, what, "more bounded fields than fields");
  p->field_bounds.clear();
  if (bounded > 0) p->field_bounds.assign(static_cast<size_t>(nf), 0.0);
  uint64_t next = 0;
  for (uint64_t k = 0; k < bounded; ++k) {
    const uint64_t i = r->varint();
    const double b = r->f64();
    const PCDField& f = i < nf ? p->fields[static_cast<size_t>(i)] : p->fields[0];
    if (i >= nf || i < next || !(b > 0) || !std::isfinite(b) || f.type != 'F' || f.name == "x" ||
        f.name == "y" || f.name == "z")
      fail(ErrorCode::kCorrupt, what, "bad bound of a PCD field");
    p->field_bounds[static_cast<size_t>(i)] = b;
    next = i + 1;
  }
}
}  // namespace

std::vector<uint8_t> decode_meta_fields(const Chunk& c, const std::string& name) {
  const std::string what = chunk_what(name, c);
  ByteReader outer(c.payload, c.size, what);
  const uint8_t coding = outer.u8();
  std::vector<uint8_t> fields;
  if (coding == 1) {
    const uint64_t n = outer.varint();
    if (n > kMaxSymbolsPerByte / 2 * outer.remaining())
      fail(ErrorCode::kCorrupt, what, "metadata size " + std::to_string(n) + " is implausible");
    fields =
        decode_bytes(c.payload + outer.offset(), outer.remaining(), static_cast<size_t>(n), what);
  } else if (coding == 0) {
    fields.assign(c.payload + 1, c.payload + c.size);
  } else if (coding == 2 || coding == 3) {  // FORMAT.md 5.1, 8.1
    LzmaPreset preset;
    if (coding == 3) {
      const uint8_t number = outer.u8();
      preset = meta_dictionary(number);
      if (!preset.size)
        fail(ErrorCode::kCorrupt, what, "unknown metadata dictionary " + std::to_string(number));
    }
    const uint64_t n = outer.varint();
    if (n == 0 || n > (uint64_t{1} << 26))
      fail(ErrorCode::kCorrupt, what, "metadata size " + std::to_string(n) + " is implausible");
    fields = lzma2_decode(c.payload + outer.offset(), outer.remaining(), static_cast<size_t>(n),
                          what, preset);
  } else {
    fail(ErrorCode::kCorrupt, what, "unknown metadata coding " + std::to_string(coding));
  }
  return fields;
}

namespace {
// FORMAT.md 5.3's C3D block: sets *has_sample_words.
std::shared_ptr<C3DExtra> get_c3d_block(ByteReader* in, const std::string& what,
                                        bool* has_sample_words) {
  ByteReader& r = *in;
  auto c3d = std::make_shared<C3DExtra>();
  c3d->processor = r.u8();
  c3d->float_storage = r.u8() != 0;
  c3d->point_scale = r.f64();
  c3d->max_interpolation_gap = static_cast<int>(std::min<uint64_t>(r.varint(), 1u << 30));
  c3d->header_events_label_range = r.u8() != 0;
  uint64_t ne = r.count(6, "header event count");
  c3d->header_events.resize(static_cast<size_t>(ne));
  for (auto& e : c3d->header_events) {
    e.time = r.f32();
    e.display = r.u8() != 0;
    e.label = r.str();
  }
  *has_sample_words = r.u8() != 0;
  uint64_t np = r.count(1, "parameter section length");
  const uint8_t* pb = r.bytes(static_cast<size_t>(np));
  try {
    decode_c3d_parameters(pb, static_cast<size_t>(np), what + " C3D parameters", c3d.get());
  } catch (const Error& e) {
    throw Error(ErrorCode::kCorrupt, e.what());
  }
  return c3d;
}

// The TRC block's Time column (put_trc_times).
std::vector<double> get_trc_times(ByteReader* in, const std::string& what, size_t frames) {
  ByteReader& r = *in;
  std::vector<double> times;
  uint8_t kt = r.u8();
  if (kt == 1) {
    double t0 = r.f64(), dt = r.f64();
    times.resize(frames);
    for (size_t i = 0; i < frames; ++i) times[i] = t0 + static_cast<double>(i) * dt;
  } else if (kt == 2) {
    if (frames > r.remaining() / 8) fail(ErrorCode::kCorrupt, what, "truncated Time column");
    times.resize(frames);
    for (auto& v : times) v = r.f64();
  } else if (kt == 3) {
    const uint8_t k = r.u8();
    if (k > 9) fail(ErrorCode::kCorrupt, what, "Time column with more than 9 decimals");
    const double d = std::pow(10.0, k);
    uint64_t n = r.count(1, "Time column block length");
    const uint8_t* b = r.bytes(static_cast<size_t>(n));
    std::vector<int32_t> deltas =
        decode_ints(b, static_cast<size_t>(n), frames, what + " Time column");
    times.resize(frames);
    int32_t prev = 0;
    for (size_t i = 0; i < frames; ++i) {
      prev = static_cast<int32_t>(static_cast<uint32_t>(prev) + static_cast<uint32_t>(deltas[i]));
      times[i] = static_cast<double>(prev) / d;
    }
  } else if (kt != 0) {
    fail(ErrorCode::kCorrupt, what, "unknown Time column kind");
  }
  return times;
}

// The TRC block's Frame# column (put_trc_frame_numbers).
std::vector<int64_t> get_trc_frame_numbers(ByteReader* in, const std::string& what, size_t frames) {
  ByteReader& r = *in;
  std::vector<int64_t> numbers;
  uint8_t kf = r.u8();
  if (kf == 1) {
    const int64_t n0 = r.svarint();
    numbers.resize(frames);
    for (size_t i = 0; i < frames; ++i) numbers[i] = wrap_add64(n0, static_cast<int64_t>(i));
  } else if (kf == 2) {
    if (frames > r.remaining()) fail(ErrorCode::kCorrupt, what, "truncated Frame# column");
    numbers.resize(frames);
    int64_t prev = 0;
    for (auto& v : numbers) v = prev = wrap_add64(prev, r.svarint());
  } else if (kf != 0) {
    fail(ErrorCode::kCorrupt, what, "unknown Frame# column kind");
  }
  return numbers;
}

// FORMAT.md 5.4's TRC block.
std::shared_ptr<TRCExtra> get_trc_block(ByteReader* in, const std::string& what, size_t frames) {
  ByteReader& r = *in;
  auto x = std::make_shared<TRCExtra>();
  x->path_file_type_line = r.str();
  x->camera_rate = r.f64();
  x->orig_data_rate = r.f64();
  x->orig_data_start_frame = r.svarint();
  x->orig_num_frames = r.svarint();
  x->decimals = static_cast<int>(r.svarint());
  x->times = get_trc_times(in, what, frames);
  x->frame_numbers = get_trc_frame_numbers(in, what, frames);
  return x;
}

// "Scans (format 1.1)": the PLY block, into a PLYExtra whose fields are the PCD layout's.
std::shared_ptr<PLYExtra> get_ply_block(ByteReader* in, const std::string& what,
                                        const PCDExtra& layout) {
  ByteReader& r = *in;
  auto x = std::make_shared<PLYExtra>();
  const uint8_t enc = r.u8();
  if (enc > 2) fail(ErrorCode::kCorrupt, what, "unknown PLY encoding " + std::to_string(enc));
  x->encoding = kPlyEncodings[enc];
  x->version = r.str();
  x->frame_names = layout.frame_names;
  x->fields = layout.fields;
  for (const PCDField& f : layout.fields) {
    x->type_names.push_back(r.str());
    const PlyType* t = find_ply_type(x->type_names.back());
    if (!t || t->type != f.type || t->size != f.size || f.count != 1)
      fail(ErrorCode::kCorrupt, what,
           "PLY property " + f.name + " of type '" + x->type_names.back() +
               "' does not match its field");
  }
  x->comments = get_any_strings(&r, "PLY comment count");
  x->obj_info = get_any_strings(&r, "PLY obj_info count");
  return x;
}

// "Scans (format 1.1)": a frame-file source's extras from its PCD block (the point layout) and
// PLY block. Throws kCorrupt for a layout its format cannot have.
void set_frame_file_extras(const std::string& what, std::shared_ptr<PLYExtra> ply, Take* t) {
  const PCDExtra* p = t->pcd.get();
  if (!p || p->fields.empty())
    fail(ErrorCode::kCorrupt, what, "frame-file source without a PCD layout");
  if (p->encoding != "binary")
    fail(ErrorCode::kCorrupt, what, "frame-file source with PCD encoding '" + p->encoding + "'");
  if (t->format == Format::kPLYFolder) {
    if (!ply) fail(ErrorCode::kCorrupt, what, "PLY source without a PLY block");
    t->ply = std::move(ply);
    return;
  }
  const std::vector<std::string> names = {"x", "y", "z", "intensity"};
  bool ok = p->fields.size() == 3 || p->fields.size() == 4;
  for (size_t i = 0; ok && i < p->fields.size(); ++i)
    ok = p->fields[i].name == names[i] && p->fields[i].type == 'F' && p->fields[i].size == 4 &&
         p->fields[i].count == 1;
  if (!ok) fail(ErrorCode::kCorrupt, what, ".bin source whose fields are not x y z intensity");
  t->bin = std::make_shared<BinExtra>();
  t->bin->frame_names = p->frame_names;
}

// FORMAT.md 5.7: the bounded analog channels.
void get_analog_bounds(ByteReader* in, const std::string& what, Analog* a) {
  ByteReader& r = *in;
  const size_t C = static_cast<size_t>(std::max(0, a->channels));
  const uint64_t nb = r.varint();
  if (nb == 0 || nb > C) fail(ErrorCode::kCorrupt, what, "bad count of bounded analog channels");
  a->bounds.assign(C, 0.0);
  a->factors.assign(C, 1.0);
  uint64_t next = 0;
  for (uint64_t i = 0; i < nb; ++i) {
    const uint64_t d = r.varint();
    if (d >= C || next + d >= C)
      fail(ErrorCode::kCorrupt, what, "a bounded analog channel outside the channels");
    const size_t ch = static_cast<size_t>(next + d);
    next = ch + 1;
    const double b = r.f64(), f = r.f64();
    if (!(b > 0) || !std::isfinite(b) || !(f > 0) || !std::isfinite(f))
      fail(ErrorCode::kCorrupt, what, "a bad analog channel bound or factor");
    a->bounds[ch] = b;
    a->factors[ch] = f;
  }
}
}  // namespace

void decode_meta(const Chunk& c, const std::string& name, Take* t, bool* has_sample_words) {
  const std::string what = chunk_what(name, c);
  const std::vector<uint8_t> fields = decode_meta_fields(c, name);
  ByteReader r(fields.data(), fields.size(), what);
  t->source = r.str();
  t->units = r.str();
  t->rate = r.f64();
  t->first_frame = r.svarint();
  t->labels = get_strings(&r, t->points, "label count");
  t->descriptions = get_strings(&r, t->points, "description count");
  t->analog.rate = r.f64();
  t->analog.labels = get_strings(&r, static_cast<size_t>(t->analog.channels), "analog label count");
  uint8_t extras = r.u8();
  *has_sample_words = false;
  if (extras & 1) {
    t->c3d = get_c3d_block(&r, what, has_sample_words);
    if (extras & 8) {  // FORMAT.md 5.1: the lists are the parameters'
      if (!t->labels.empty() || !t->descriptions.empty() || !t->analog.labels.empty())
        fail(ErrorCode::kCorrupt, what, "labels both listed and taken from the parameters");
      derive_labels(*t->c3d, t->points, t->analog.channels, &t->labels, &t->descriptions,
                    &t->analog.labels);
    }
  } else if (extras & 8) {
    fail(ErrorCode::kCorrupt, what, "labels from parameters without a C3D block");
  }
  if (extras & 2) t->trc = get_trc_block(&r, what, t->frames);
  if (extras & 4) {
    auto p = std::make_shared<PCDExtra>();
    p->encoding = r.str();
    p->frame_names = get_strings(&r, t->frames, "frame name count");
    if (extras & 16) get_pcd_layout(&r, what, t, p.get());
    t->pcd = p;
  } else if (extras & 16) {
    fail(ErrorCode::kCorrupt, what, "PCD layout without a PCD block");
  }
  if (extras & ~63) fail(ErrorCode::kCorrupt, what, "unknown metadata blocks");
  std::shared_ptr<PLYExtra> ply;
  if (extras & 32) {  // "Scans (format 1.1)": the PLY block, of a PLY source only
    if (t->format != Format::kPLYFolder || !t->pcd)
      fail(ErrorCode::kCorrupt, what, "a PLY block in a stream whose source is not a PLY folder");
    ply = get_ply_block(&r, what, *t->pcd);
  }
  if (t->format == Format::kPLYFolder || t->format == Format::kBinFolder)
    set_frame_file_extras(what, std::move(ply), t);
  if (t->rotations.segments > 0) {  // FORMAT.md 5.6
    t->rotations.rate = r.f64();
    t->rotations.labels =
        get_strings(&r, static_cast<size_t>(t->rotations.segments), "rotation label count");
  }
  t->analog.bounds.clear();
  t->analog.factors.clear();
  if (t->analog.channels > 0 && r.remaining() > 0) {  // FORMAT.md 5.7: bounded analog channels
    get_analog_bounds(&r, what, &t->analog);
  }
  // Fields appended by later minor versions follow; they are skipped.
}

}  // namespace capz

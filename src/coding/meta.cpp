// META (docs/FORMAT.md 5): everything of the Take that the other chunks do
// not hold, as fields written and read by mirrored block functions, then coded as they are, by a
// byte model or by LZMA2 (after a preset dictionary). This is the decoder; the encoder, whose
// block functions these mirror, is meta_encode.cpp.
#include "coding/meta.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "capz/error.h"
#include "coding/bytes.h"
#include "coding/c3d_params.h"
#include "coding/entropy.h"
#include "coding/lzma_block.h"
#include "coding/meta_shared.h"
#include "coding/ply_types.h"

namespace capz {
namespace {

using meta::derive_labels;
using meta::wrap_add64;

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

// Whether a PCD layout of width x height fits the take: N = width x height (FORMAT.md 5.5), or,
// in a ragged stream, width 0 and height 1 or an organized shape of at most 2^40 points ("Ragged
// frames: HEAD and the window chunk").
bool layout_fits(uint64_t width, uint64_t height, size_t points, bool ragged) {
  const uint64_t most = uint64_t{1} << 40;
  if (width > most || height > most) return false;
  if (!ragged) return width * height == points;
  return width == 0 ? height == 1 : height >= 1 && width <= most / height;
}

// FORMAT.md 5.5: the PCD layout; sets the take's attribute layouts (no data).
void get_pcd_layout(ByteReader* r, const std::string& what, Take* t, PCDExtra* p, bool ragged) {
  p->version = r->str();
  const uint64_t width = r->varint(), height = r->varint();
  if (!layout_fits(width, height, t->points, ragged))
    fail(ErrorCode::kCorrupt, what,
         "PCD layout " + std::to_string(width) + " x " + std::to_string(height) + " is not the " +
             (ragged ? std::string("shape of a ragged stream's frames")
                     : std::to_string(t->points) + " points"));
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
  x->encoding = meta::kPlyEncodings[enc];
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
  // "Frame-file sources": float32 x y z, then the record's fields. HEAD's frame_format 6 (the
  // caller's t->bin, declared): a declared record, any fields; else the names' record (KITTI's for
  // names of two kinds) or none (the fields dropped).
  const bool declared = t->bin && t->bin->declared;
  bool ok = p->fields.size() >= 3;
  for (size_t i = 0; ok && i < p->fields.size(); ++i)
    ok =
        p->fields[i].count == 1 && (i >= 3 || (p->fields[i].name == std::string(1, "xyz"[i]) &&
                                               p->fields[i].type == 'F' && p->fields[i].size == 4));
  const std::vector<PCDField> names = bin_record_or_kitti(p->frame_names);
  const std::vector<PCDField> record(p->fields.begin() + 3, p->fields.end());
  if (ok && !declared && !record.empty()) ok = same_bin_records(record, names);
  if (!ok) fail(ErrorCode::kCorrupt, what, ".bin source whose fields are not those of its record");
  t->bin = std::make_shared<BinExtra>();
  t->bin->frame_names = p->frame_names;
  t->bin->declared = declared;
  if (declared) t->bin->record = record;
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

void decode_meta(const Chunk& c, const std::string& name, Take* t, bool* has_sample_words,
                 bool ragged) {
  const std::string what = chunk_what(name, c);
  const std::vector<uint8_t> fields = decode_meta_fields(c, name);
  ByteReader r(fields.data(), fields.size(), what);
  t->source = r.str();
  t->units = r.str();
  t->rate = r.f64();
  t->first_frame = r.svarint();
  t->labels = get_strings(&r, t->points, "label count");
  // FORMAT.md 5.2: the N empty labels of frame files are no labels (take.h).
  if (is_frame_files(t->format) && std::all_of(t->labels.begin(), t->labels.end(),
                                               [](const std::string& l) { return l.empty(); }))
    t->labels.clear();
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
    if (extras & 16) get_pcd_layout(&r, what, t, p.get(), ragged);
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

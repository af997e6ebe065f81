// PCD frame files (io/pcd_frame_writer.h).
#include "io/pcd_frame_writer.h"

#include <charconv>
#include <cmath>
#include <cstring>

#include "capz/error.h"
#include "coding/lzf.h"

namespace capz {

namespace {

bool is_packed_colour(const PCDField& f) {
  return f.type == 'F' && f.size == 4 && f.count == 1 && (f.name == "rgb" || f.name == "rgba");
}

template <typename T>
void append_float(T v, std::string* s) {
  if (std::isnan(v)) {
    *s += "nan";
  } else if (std::isinf(v)) {
    *s += v < 0 ? "-inf" : "inf";
  } else {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    s->append(buf, r.ptr);
  }
}

void append_value(const PCDField& f, bool colour, const uint8_t* p, std::string* s) {
  char buf[32];
  if (f.type == 'F' && !colour) {
    if (f.size == 4) {
      float v;
      std::memcpy(&v, p, 4);
      append_float(v, s);
    } else {
      double v;
      std::memcpy(&v, p, 8);
      append_float(v, s);
    }
    return;
  }
  uint64_t u = 0;
  for (int i = 0; i < f.size; ++i) u |= static_cast<uint64_t>(p[i]) << (8 * i);
  std::to_chars_result r{};
  if (f.type == 'I') {
    const int shift = 64 - 8 * f.size;
    const int64_t v = static_cast<int64_t>(u << shift) >> shift;  // sign-extended
    r = std::to_chars(buf, buf + sizeof buf, v);
  } else {
    r = std::to_chars(buf, buf + sizeof buf, u);
  }
  s->append(buf, r.ptr);
}

}  // namespace

void append_value_text(const PCDField& f, const uint8_t* p, std::string* s) {
  append_value(f, false, p, s);
}

namespace {

std::string header(const PcdFrameLayout& l, size_t n) {
  std::string h = "# .PCD v" + l.version + " - Point Cloud Data file format\nVERSION " + l.version;
  std::string fields = "\nFIELDS", sizes = "\nSIZE", types = "\nTYPE", counts = "\nCOUNT";
  const bool ascii = l.encoding == "ascii";
  for (const PCDField& f : l.fields) {
    fields += " " + f.name;
    sizes += " " + std::to_string(f.size);
    types += " ";
    types += ascii && is_packed_colour(f) ? 'U' : f.type;
    counts += " " + std::to_string(f.count);
  }
  h += fields + sizes + types + counts;
  h += "\nWIDTH " + std::to_string(l.width) + "\nHEIGHT " + std::to_string(l.height);
  h += "\nVIEWPOINT";
  static const double kDefault[7] = {0, 0, 0, 1, 0, 0, 0};
  for (int i = 0; i < 7; ++i) {
    h += " ";
    append_float(l.viewpoint.size() == 7 ? l.viewpoint[static_cast<size_t>(i)] : kDefault[i], &h);
  }
  h += "\nPOINTS " + std::to_string(n) + "\nDATA " + l.encoding + "\n";
  return h;
}

// The layout as written: without padding fields ("_") unless the body is binary.
PcdFrameLayout written_layout(const PcdFrameLayout& layout) {
  PcdFrameLayout l = layout;
  if (l.encoding != "binary") {
    l.fields.clear();
    for (const PCDField& f : layout.fields)
      if (f.name != "_") l.fields.push_back(f);
  }
  return l;
}

void store_le32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
void put_le32(std::vector<uint8_t>* b, uint32_t v) {
  for (int i = 0; i < 4; ++i) b->push_back(static_cast<uint8_t>(v >> (8 * i)));
}

// Appends a binary_compressed body (the two sizes, then LZF) of the field-major bytes fm.
void append_compressed(const std::vector<uint8_t>& fm, LzfVariant lzf, std::vector<uint8_t>* out) {
  if (fm.size() > 0xFFFFFFFFu)
    fail(ErrorCode::kUsage, "", "a PCD frame above 4 GiB cannot be binary_compressed");
  if (lzf == LzfVariant::kCapz) {  // compressed in place, after the two sizes
    const size_t at = out->size() + 8;
    out->resize(at + lzf_bound(fm.size()));
    const size_t c = lzf_compress_into(fm.data(), fm.size(), out->data() + at);
    store_le32(out->data() + at - 8, static_cast<uint32_t>(c));
    store_le32(out->data() + at - 4, static_cast<uint32_t>(fm.size()));
    out->resize(at + c);
  } else {
    const std::vector<uint8_t> c = lzf_compress(fm.data(), fm.size(), lzf);
    put_le32(out, static_cast<uint32_t>(c.size()));
    put_le32(out, static_cast<uint32_t>(fm.size()));
    out->insert(out->end(), c.begin(), c.end());
  }
}

// A point's bytes under `fields`.
size_t point_bytes(const std::vector<PCDField>& fields) {
  size_t step = 0;
  for (const PCDField& f : fields)
    step += static_cast<size_t>(f.size) * static_cast<size_t>(f.count);
  return step;
}

// n points of `layout` without its padding fields ("_"), point by point, into *packed.
void drop_padding(const PcdFrameLayout& layout, const uint8_t* all_points, size_t n,
                  std::vector<uint8_t>* packed) {
  const size_t all_step = point_bytes(layout.fields);
  std::vector<std::pair<size_t, size_t>> keep;  // (offset, bytes) of the kept fields
  size_t off = 0;
  for (const PCDField& f : layout.fields) {
    const size_t fs = static_cast<size_t>(f.size) * static_cast<size_t>(f.count);
    if (f.name != "_") keep.emplace_back(off, fs);
    off += fs;
  }
  for (size_t p = 0; p < n; ++p)
    for (const auto& k : keep)
      packed->insert(packed->end(), all_points + p * all_step + k.first,
                     all_points + p * all_step + k.first + k.second);
}

// A binary_compressed body: the n points (of `step` bytes) field-major in *fm, compressed.
void append_field_major(const PcdFrameLayout& l, const uint8_t* points, size_t n, size_t step,
                        LzfVariant lzf, std::vector<uint8_t>* fm, std::vector<uint8_t>* out) {
  fm->resize(n * step);  // each byte written below
  uint8_t* d = fm->data();
  size_t off = 0;
  for (const PCDField& f : l.fields) {
    const size_t fs = static_cast<size_t>(f.size) * static_cast<size_t>(f.count);
    const uint8_t* s = n > 0 ? points + off : points;  // no points: may be null
    if (fs == 4)                                       // fixed sizes: a copy the compiler inlines
      for (size_t p = 0; p < n; ++p, d += 4) std::memcpy(d, s + p * step, 4);
    else if (fs == 8)
      for (size_t p = 0; p < n; ++p, d += 8) std::memcpy(d, s + p * step, 8);
    else
      for (size_t p = 0; p < n; ++p, d += fs) std::memcpy(d, s + p * step, fs);
    off += fs;
  }
  append_compressed(*fm, lzf, out);
}

// An ascii body: a line a point, its values separated by spaces.
void append_ascii(const PcdFrameLayout& l, const uint8_t* points, size_t n, size_t step,
                  std::vector<uint8_t>* out) {
  std::string body;
  for (size_t p = 0; p < n; ++p) {
    const uint8_t* q = points + p * step;
    bool first = true;
    for (const PCDField& f : l.fields) {
      const bool colour = is_packed_colour(f);
      for (int k = 0; k < f.count; ++k) {
        if (!first) body += ' ';
        first = false;
        append_value(f, colour, q, &body);
        q += f.size;
      }
    }
    body += '\n';
  }
  out->insert(out->end(), body.begin(), body.end());
}

}  // namespace

std::vector<uint8_t> pcd_frame_bytes(const PcdFrameLayout& layout, const uint8_t* all_points,
                                     LzfVariant lzf, std::vector<uint8_t>* scratch) {
  const size_t n = layout.width * layout.height;
  // Padding fields ("_") exist only in binary bodies: PCL's ASCII and compressed readers skip
  // them, so those encodings leave them out, as PCL's writers do.
  const PcdFrameLayout l = written_layout(layout);
  std::vector<uint8_t> packed;
  const uint8_t* points = all_points;
  if (l.fields.size() != layout.fields.size()) {
    drop_padding(layout, all_points, n, &packed);
    points = packed.data();
  }
  const size_t step = point_bytes(l.fields);
  const std::string h = header(l, n);
  std::vector<uint8_t> out(h.begin(), h.end());
  if (l.encoding == "binary") {
    out.insert(out.end(), points, points + n * step);
  } else if (l.encoding == "binary_compressed") {
    std::vector<uint8_t> own;
    append_field_major(l, points, n, step, lzf, scratch ? scratch : &own, &out);
  } else if (l.encoding == "ascii") {
    append_ascii(l, points, n, step, &out);
  } else {
    fail(ErrorCode::kInvalidParameter, "", "unknown PCD encoding '" + l.encoding + "'");
  }
  return out;
}

std::string pcd_frame_header(const PcdFrameLayout& layout) {
  return header(written_layout(layout), layout.width * layout.height);
}

bool coordinates_are_floats(size_t n, const double* xyz, const uint8_t* valid) {
  for (size_t i = 0; i < n; ++i)
    for (int a = 0; a < 3 && valid[i]; ++a)
      if (static_cast<double>(static_cast<float>(xyz[i * 3 + a])) != xyz[i * 3 + a]) return false;
  return true;
}

PcdFramePlan pcd_frame_plan(const Take& take, const std::string& enc,
                            std::optional<bool> xyz_float) {
  const size_t N = take.points, total = take.total_points();
  // The fields: the source's layout when it matches the take (x y z and its attributes, in
  // order), else x y z then the attributes.
  std::vector<PCDField> fields;
  if (take.pcd && !take.pcd->fields.empty()) {
    fields = take.pcd->fields;
    size_t k = 0;
    bool ok = true;
    for (const PCDField& fd : fields) {
      if (fd.name == "x" || fd.name == "y" || fd.name == "z") continue;
      ok = ok && k < take.attributes.size() && take.attributes[k].name == fd.name &&
           take.attributes[k].type == fd.type && take.attributes[k].size == fd.size &&
           take.attributes[k].count == fd.count;
      ++k;
    }
    if (!ok || k != take.attributes.size()) fields.clear();
  }
  int xyz_size = 0;  // 4 or 8 when the layout says
  for (const PCDField& fd : fields)
    if (fd.name == "x") xyz_size = fd.size;
  if (fields.empty()) {
    for (const char* axis : {"x", "y", "z"}) {
      PCDField fd;
      fd.name = axis;
      fields.push_back(fd);
    }
    for (const PointAttribute& a : take.attributes)
      fields.push_back(PCDField{a.name, a.type, a.size, a.count});
  }
  PcdFramePlan plan;
  // Coordinates: float32 when the source's were (or every coordinate is exactly a float), else
  // float64 so no precision is lost.
  plan.as_float = xyz_size == 4;
  if (xyz_size == 0) {
    plan.xyz_from_data = true;
    const bool arrays = take.valid.size() == total && take.xyz.size() == total * 3;
    plan.as_float =
        xyz_float ? *xyz_float
                  : !arrays || coordinates_are_floats(total, take.xyz.data(), take.valid.data());
  }
  PcdFrameLayout& layout = plan.layout;
  layout.encoding = enc;
  if (take.pcd && !take.pcd->version.empty()) layout.version = take.pcd->version;
  for (PCDField f : fields) {
    const int axis = f.name == "x" ? 0 : f.name == "y" ? 1 : f.name == "z" ? 2 : -1;
    if (axis >= 0) {
      plan.axis_offset[axis] = plan.step;
      f.type = 'F';
      f.size = plan.as_float ? 4 : 8;
      f.count = 1;
    } else {
      plan.attr_offset.push_back(plan.step);
    }
    plan.step += static_cast<size_t>(f.size) * static_cast<size_t>(f.count);
    layout.fields.push_back(f);
  }
  const PCDExtra* px = take.pcd.get();
  const bool organized = px && px->width > 0 && px->height > 1 && px->width * px->height == N;
  layout.width = organized ? px->width : N;
  layout.height = organized ? px->height : 1;
  if (px && px->viewpoint.size() == 7) layout.viewpoint = px->viewpoint;
  return plan;
}

void pcd_frame_points(const PcdFramePlan& plan, size_t n, const double* xyz, const uint8_t* valid,
                      const std::vector<const uint8_t*>& attrs, std::vector<uint8_t>* out) {
  const size_t step = plan.step;
  out->resize(step * n);
  const double nan = std::nan("");
  std::vector<size_t> bpp(attrs.size());
  size_t k = 0;
  for (const PCDField& f : plan.layout.fields)
    if (f.name != "x" && f.name != "y" && f.name != "z" && k < bpp.size())
      bpp[k++] = static_cast<size_t>(f.size) * static_cast<size_t>(f.count);
  for (size_t p = 0; p < n; ++p) {
    const bool ok = valid[p] != 0;
    const double* v = xyz + p * 3;
    uint8_t* dst = out->data() + p * step;
    for (int a = 0; a < 3; ++a) {
      const double x = ok ? v[a] : nan;
      if (plan.as_float) {
        const float fx = static_cast<float>(x);
        std::memcpy(dst + plan.axis_offset[a], &fx, 4);
      } else {
        std::memcpy(dst + plan.axis_offset[a], &x, 8);
      }
    }
    for (size_t a = 0; a < attrs.size(); ++a)
      std::memcpy(dst + plan.attr_offset[a], attrs[a] + p * bpp[a], bpp[a]);
  }
}

std::vector<uint8_t> pcd_frame_file(const PcdFramePlan& plan, size_t n, const double* xyz,
                                    const uint8_t* valid, const std::vector<const uint8_t*>& attrs,
                                    std::vector<uint8_t>* points, std::vector<uint8_t>* body) {
  const PcdFrameLayout& layout = plan.layout;
  size_t fields = 0;  // fields other than x y z: one a take attribute each
  for (const PCDField& f : layout.fields) fields += f.name != "x" && f.name != "y" && f.name != "z";
  if (layout.encoding != "binary_compressed" || n != layout.width * layout.height ||
      fields != attrs.size()) {
    pcd_frame_points(plan, n, xyz, valid, attrs, points);
    return pcd_frame_bytes(layout, points->data(), LzfVariant::kCapz, body);
  }
  // The field-major body from the arrays: a coordinate's plane as pcd_frame_points converts it
  // (NaN at gaps), an attribute's plane its bytes as they are (padding fields left out).
  const PcdFrameLayout l = written_layout(layout);
  size_t step = 0;
  for (const PCDField& f : l.fields)
    step += static_cast<size_t>(f.size) * static_cast<size_t>(f.count);
  body->resize(n * step);
  uint8_t* d = body->data();
  const double nan = std::nan("");
  size_t k = 0;
  for (const PCDField& f : layout.fields) {
    const int axis = f.name == "x" ? 0 : f.name == "y" ? 1 : f.name == "z" ? 2 : -1;
    if (axis < 0) {
      const size_t bpp = static_cast<size_t>(f.size) * static_cast<size_t>(f.count);
      const uint8_t* a = attrs[k++];
      if (f.name == "_") continue;
      if (n > 0) std::memcpy(d, a, n * bpp);
      d += n * bpp;
    } else if (plan.as_float) {
      for (size_t p = 0; p < n; ++p, d += 4) {
        const float x = static_cast<float>(valid[p] ? xyz[3 * p + axis] : nan);
        std::memcpy(d, &x, 4);
      }
    } else {
      for (size_t p = 0; p < n; ++p, d += 8) {
        const double x = valid[p] ? xyz[3 * p + axis] : nan;
        std::memcpy(d, &x, 8);
      }
    }
  }
  const std::string h = header(l, n);
  std::vector<uint8_t> out(h.begin(), h.end());
  append_compressed(*body, LzfVariant::kCapz, &out);
  return out;
}

}  // namespace capz

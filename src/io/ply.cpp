// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// PLY frames (io/ply.h): header, ASCII and binary bodies, and the writer.
#include "io/ply.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>

#include "capz/error.h"
#include "coding/ply_types.h"
#include "io/pcd_frame_writer.h"
#include "io/text_number.h"

namespace capz {

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> w;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    size_t e = i;
    while (e < line.size() && line[e] != ' ' && line[e] != '\t' && line[e] != '\r') ++e;
    if (e > i) w.push_back(line.substr(i, e - i));
    i = e;
  }
  return w;
}

// The text after the first word of a comment or obj_info line.
std::string rest_of(const std::string& line, size_t key) {
  std::string r = line.substr(std::min(line.size(), key + 1));
  while (!r.empty() && r.back() == '\r') r.pop_back();
  return r;
}

bool parse_count(const std::string& s, size_t* out) {
  uint64_t v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size() || v > (uint64_t{1} << 40)) return false;
  *out = static_cast<size_t>(v);
  return true;
}

// Little-endian bytes of one value: `big` swaps from the file's big-endian order.
void copy_value(const uint8_t* in, int size, bool big, uint8_t* out) {
  for (int k = 0; k < size; ++k) out[k] = big ? in[size - 1 - k] : in[k];
}

double value_of(const uint8_t* le, char type, int size) {
  if (type == 'F' && size == 4) {
    float f;
    std::memcpy(&f, le, 4);
    return f;
  }
  if (type == 'F') {
    double d;
    std::memcpy(&d, le, 8);
    return d;
  }
  return std::nan("");  // x y z are floats (checked by the header)
}

// One ASCII token as the little-endian bytes of its field. False when it is not a number of
// that type.
bool parse_token(const std::string& tok, const PCDField& f, uint8_t* out) {
  if (f.type == 'F') {
    double d;
    if (!parse_double(tok, &d)) return false;
    if (f.size == 4) {
      const float v = static_cast<float>(d);
      std::memcpy(out, &v, 4);
    } else {
      std::memcpy(out, &d, 8);
    }
    return true;
  }
  uint64_t u = 0;
  if (f.type == 'U') {
    const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), u);
    if (r.ec != std::errc() || r.ptr != tok.data() + tok.size()) return false;
    if (f.size < 8 && u >> (8 * f.size)) return false;
  } else {
    int64_t v = 0;
    const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    if (r.ec != std::errc() || r.ptr != tok.data() + tok.size()) return false;
    const int64_t lim = int64_t{1} << (8 * f.size - 1);
    if (f.size < 8 && (v < -lim || v >= lim)) return false;
    u = static_cast<uint64_t>(v);
  }
  for (int k = 0; k < f.size; ++k) out[k] = static_cast<uint8_t>(u >> (8 * k));
  return true;
}

// Reads the element lines of a header into *h; `line` is the current "element" line.
struct ElementReader {
  PlyHeader* h;
  const std::string& name;
  std::string current;  // the element being read
  size_t count = 0;
  bool seen_vertex = false;

  void element(const std::vector<std::string>& w) {
    size_t n = 0;
    if (w.size() != 3 || !parse_count(w[2], &n))
      fail(ErrorCode::kCorrupt, name, "PLY header: bad element line");
    current = w[1];
    count = n;
    if (current == "vertex") {
      if (seen_vertex) fail(ErrorCode::kCorrupt, name, "PLY header: two vertex elements");
      seen_vertex = true;
      h->vertices = n;
    } else if (n > 0) {
      fail(ErrorCode::kNotOurFormat, name,  // a valid PLY, of a kind capz does not read
           "PLY element '" + current + "' (" + std::to_string(n) +
               ") is not supported: capz reads point clouds (the vertex element), not meshes");
    }
  }
  void property(const std::vector<std::string>& w) {
    if (current.empty()) fail(ErrorCode::kCorrupt, name, "PLY header: property before element");
    if (current != "vertex") return;  // of an empty element
    if (w.size() >= 2 && w[1] == "list")
      fail(ErrorCode::kCorrupt, name, "PLY vertex list properties are not supported");
    if (w.size() != 3) fail(ErrorCode::kCorrupt, name, "PLY header: bad property line");
    const PlyType* t = find_ply_type(w[1]);
    if (!t) fail(ErrorCode::kCorrupt, name, "PLY header: unknown property type '" + w[1] + "'");
    for (const PCDField& f : h->fields)
      if (f.name == w[2]) fail(ErrorCode::kCorrupt, name, "PLY property " + w[2] + " twice");
    h->fields.push_back(PCDField{w[2], t->type, t->size, 1});
    h->type_names.push_back(w[1]);
    h->step += static_cast<size_t>(t->size);
  }
};

}  // namespace

PlyHeader parse_ply_header(const std::vector<uint8_t>& bytes, const std::string& name) {
  PlyHeader h;
  size_t pos = 0;
  const size_t n = bytes.size();
  auto next_line = [&]() {
    size_t e = pos;
    while (e < n && bytes[e] != '\n') ++e;
    if (e >= n) fail(ErrorCode::kCorrupt, name, "PLY header has no end_header line");
    std::string line(reinterpret_cast<const char*>(bytes.data()) + pos, e - pos);
    pos = e + 1;
    return line;
  };
  if (n < 4 || std::memcmp(bytes.data(), "ply", 3) != 0 || (bytes[3] != '\n' && bytes[3] != '\r'))
    fail(ErrorCode::kNotOurFormat, name, "not a PLY file (no 'ply' line)");
  next_line();
  ElementReader er{&h, name, std::string()};
  for (;;) {
    if (pos > (size_t{1} << 20)) fail(ErrorCode::kCorrupt, name, "PLY header longer than 1 MiB");
    const std::string line = next_line();
    const std::vector<std::string> w = split(line);
    if (w.empty()) continue;
    const std::string& k = w[0];
    if (k == "format") {
      if (w.size() != 3 ||
          (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian"))
        fail(ErrorCode::kCorrupt, name, "PLY header: bad format line");
      h.encoding = w[1];
      h.version = w[2];
    } else if (k == "comment") {
      h.comments.push_back(rest_of(line, line.find("comment") + 7));
    } else if (k == "obj_info") {
      h.obj_info.push_back(rest_of(line, line.find("obj_info") + 8));
    } else if (k == "element") {
      er.element(w);
    } else if (k == "property") {
      er.property(w);
    } else if (k == "end_header") {
      break;
    } else {
      fail(ErrorCode::kCorrupt, name, "PLY header: unknown line '" + k + "'");
    }
  }
  h.body = pos;
  if (h.encoding.empty()) fail(ErrorCode::kCorrupt, name, "PLY header has no format line");
  if (!er.seen_vertex) fail(ErrorCode::kCorrupt, name, "PLY file has no vertex element");
  for (const char* axis : {"x", "y", "z"}) {
    bool found = false;
    for (const PCDField& f : h.fields)
      if (f.name == axis) {
        found = true;
        if (f.type != 'F')
          fail(ErrorCode::kCorrupt, name,
               std::string("PLY coordinate ") + axis + " is not float or double");
      }
    if (!found) fail(ErrorCode::kCorrupt, name, std::string("PLY vertex has no '") + axis + "'");
  }
  return h;
}

void check_ply_body_fits(const PlyHeader& h, uint64_t file_size, const std::string& name) {
  const uint64_t body = file_size < h.body ? 0 : file_size - h.body;
  const uint64_t N = h.vertices;
  if (h.encoding != "ascii" && body / h.step < N)
    fail(ErrorCode::kCorrupt, name,
         "PLY body truncated mid-vertex: " + std::to_string(body) + " bytes, " + std::to_string(N) +
             " vertices need " + std::to_string(N * h.step));
  // An ASCII value takes at least one character and one separator.
  if (h.encoding == "ascii" && N > (body + 1) / (2 * h.fields.size()))
    fail(ErrorCode::kCorrupt, name,
         "PLY ASCII body too short for " + std::to_string(N) + " vertices (truncated)");
}

void read_ply_frame(const std::vector<uint8_t>& bytes, const PlyHeader& h, const std::string& name,
                    FrameData* out) {
  const size_t N = h.vertices, F = h.fields.size();
  const bool ascii = h.encoding == "ascii", big = h.encoding == "binary_big_endian";
  check_ply_body_fits(h, bytes.size(), name);
  out->points = N;
  out->xyz.assign(N * 3, 0.0);
  out->valid.assign(N, 0);
  std::vector<int> slot(F, -1);  // attribute index per field, or -1 - axis
  out->attrs.clear();
  for (size_t i = 0; i < F; ++i) {
    const std::string& fn = h.fields[i].name;
    if (fn == "x" || fn == "y" || fn == "z") {
      slot[i] = -1 - (fn[0] - 'x');
    } else {
      slot[i] = static_cast<int>(out->attrs.size());
      out->attrs.emplace_back(N * static_cast<size_t>(h.fields[i].size));
    }
  }
  size_t pos = h.body;
  uint8_t le[8];
  std::vector<std::string> tok;
  for (size_t p = 0; p < N; ++p) {
    if (ascii) {
      size_t e = pos;
      while (e < bytes.size() && bytes[e] != '\n') ++e;
      tok = split(std::string(reinterpret_cast<const char*>(bytes.data()) + pos, e - pos));
      pos = e + 1;
      if (tok.empty() && e < bytes.size()) {  // a blank line
        --p;
        continue;
      }
      if (tok.size() != F)
        fail(ErrorCode::kCorrupt, name,
             "PLY vertex " + std::to_string(p) + " has " + std::to_string(tok.size()) +
                 " values, the header declares " + std::to_string(F));
    }
    double v[3] = {0, 0, 0};
    for (size_t i = 0; i < F; ++i) {
      const PCDField& f = h.fields[i];
      if (ascii) {
        if (!parse_token(tok[i], f, le))
          fail(ErrorCode::kCorrupt, name,
               "PLY vertex " + std::to_string(p) + ": '" + tok[i] + "' is not a " +
                   ply_type_name(f.type, f.size));
      } else {
        copy_value(bytes.data() + pos, f.size, big, le);
        pos += static_cast<size_t>(f.size);
      }
      if (slot[i] < 0)
        v[-1 - slot[i]] = value_of(le, f.type, f.size);
      else
        std::memcpy(
            out->attrs[static_cast<size_t>(slot[i])].data() + p * static_cast<size_t>(f.size), le,
            static_cast<size_t>(f.size));
    }
    if (std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2])) {
      std::copy(v, v + 3, out->xyz.data() + 3 * p);
      out->valid[p] = 1;
    }
  }
}

PlyPlan ply_plan(const Take& take, const std::string& encoding, std::optional<bool> xyz_float) {
  PlyPlan plan;
  PlyHeader& h = plan.header;
  h.encoding = !encoding.empty()                         ? encoding
               : take.ply && !take.ply->encoding.empty() ? take.ply->encoding
                                                         : "binary_little_endian";
  if (take.ply) {
    h.version = take.ply->version;
    h.comments = take.ply->comments;
    h.obj_info = take.ply->obj_info;
  }
  // The source's layout when it matches the take (x y z and its attributes, in order).
  if (take.ply && !take.ply->fields.empty()) {
    size_t k = 0;
    bool ok = take.ply->type_names.size() == take.ply->fields.size();
    for (const PCDField& f : take.ply->fields) {
      const int axis = f.name == "x" ? 0 : f.name == "y" ? 1 : f.name == "z" ? 2 : -1;
      if (axis >= 0) {
        plan.attribute.push_back(-1 - axis);
        continue;
      }
      ok = ok && k < take.attributes.size() && take.attributes[k].name == f.name &&
           take.attributes[k].type == f.type && take.attributes[k].size == f.size &&
           take.attributes[k].count == 1;
      plan.attribute.push_back(static_cast<int>(k++));
    }
    if (ok && k == take.attributes.size()) {
      h.fields = take.ply->fields;
      h.type_names = take.ply->type_names;
      return plan;
    }
    plan.attribute.clear();
  }
  plan.xyz_from_data = true;
  const size_t n = std::min(take.valid.size(), take.xyz.size() / 3);
  const bool as_float =
      xyz_float ? *xyz_float : coordinates_are_floats(n, take.xyz.data(), take.valid.data());
  for (int a = 0; a < 3; ++a) {
    h.fields.push_back(
        PCDField{std::string(1, static_cast<char>('x' + a)), 'F', as_float ? 4 : 8, 1});
    plan.attribute.push_back(-1 - a);
  }
  for (size_t k = 0; k < take.attributes.size(); ++k) {
    const PointAttribute& at = take.attributes[k];
    if (at.count != 1 || at.name == "_" || !ply_type_name(at.type, at.size)) continue;
    h.fields.push_back(PCDField{at.name, at.type, at.size, 1});
    plan.attribute.push_back(static_cast<int>(k));
  }
  for (const PCDField& f : h.fields) h.type_names.push_back(ply_type_name(f.type, f.size));
  return plan;
}

std::vector<uint8_t> ply_frame_bytes(const PlyPlan& plan, size_t n, const double* xyz,
                                     const uint8_t* valid,
                                     const std::vector<const uint8_t*>& attr_bytes) {
  const PlyHeader& h = plan.header;
  std::string text = "ply\nformat " + h.encoding + " " + h.version + "\n";
  for (const std::string& c : h.comments) text += "comment " + c + "\n";
  for (const std::string& c : h.obj_info) text += "obj_info " + c + "\n";
  text += "element vertex " + std::to_string(n) + "\n";
  for (size_t i = 0; i < h.fields.size(); ++i)
    text += "property " + h.type_names[i] + " " + h.fields[i].name + "\n";
  text += "end_header\n";
  const bool ascii = h.encoding == "ascii", big = h.encoding == "binary_big_endian";
  std::vector<uint8_t> out(text.begin(), text.end());
  std::string line;
  uint8_t le[8], be[8];
  for (size_t p = 0; p < n; ++p) {
    line.clear();
    for (size_t i = 0; i < h.fields.size(); ++i) {
      const PCDField& f = h.fields[i];
      const int a = plan.attribute[i];
      if (a < 0) {  // a coordinate, NaN at a gap
        const double v = valid[p] ? xyz[p * 3 + static_cast<size_t>(-1 - a)]
                                  : std::numeric_limits<double>::quiet_NaN();
        if (f.size == 4) {
          const float fv = static_cast<float>(v);
          std::memcpy(le, &fv, 4);
        } else {
          std::memcpy(le, &v, 8);
        }
      } else {
        std::memcpy(le, attr_bytes[static_cast<size_t>(a)] + p * static_cast<size_t>(f.size),
                    static_cast<size_t>(f.size));
      }
      if (ascii) {
        if (i) line += ' ';
        append_value_text(f, le, &line);
      } else {
        copy_value(le, f.size, big, be);
        out.insert(out.end(), be, be + f.size);
      }
    }
    if (ascii) {
      line += '\n';
      out.insert(out.end(), line.begin(), line.end());
    }
  }
  return out;
}

}  // namespace capz

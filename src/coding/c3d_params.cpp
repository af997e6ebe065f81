// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// capz — the C3D parameter section: number forms, parsing, encoding, and typed helpers.
#include "coding/c3d_params.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <map>

#include "capz/error.h"

namespace capz {
namespace c3d {

// ---- numbers --------------------------------------------------------------------------------

// VAX F: the 32 bits are two little-endian 16-bit words, the first holding sign (bit 15),
// exponent (bits 14..7, bias 128) and the top 7 fraction bits; value = 0.1f x 2^(e-128), i.e.
// the IEEE reading of the same bits (1.f x 2^(e-127)) divided by 4.
float dec_to_float(const uint8_t* p) {
  uint32_t hi = static_cast<uint32_t>(p[0] | (p[1] << 8));
  uint32_t lo = static_cast<uint32_t>(p[2] | (p[3] << 8));
  uint32_t bits = (hi << 16) | lo;
  uint32_t e = (bits >> 23) & 0xff;
  if (e == 0) return 0.0f;
  float out;
  if (e > 2) {
    bits -= 2u << 23;  // exact: the exponent drops by 2
    std::memcpy(&out, &bits, 4);
    return out;
  }
  // e = 1 or 2: an IEEE denormal, rounded.
  double mant = static_cast<double>((bits & 0x7fffff) | 0x800000);
  double v = std::ldexp(mant, static_cast<int>(e) - 128 - 24);
  out = static_cast<float>(v);
  return (bits >> 31) ? -out : out;
}

void float_to_dec(float v, uint8_t* out) {
  uint32_t bits = 0;
  if (std::isnan(v) || std::isinf(v)) {
    bits = 0x7fffffffu | (std::signbit(v) ? 0x80000000u : 0u);
  } else if (v != 0.0f) {
    int ex = 0;
    double fr = std::frexp(std::fabs(static_cast<double>(v)), &ex);  // fr in [0.5, 1)
    int e = ex + 128;
    if (e >= 1) {
      if (e > 255) {
        bits = 0x7fffffffu;
      } else {
        uint32_t mant = static_cast<uint32_t>(std::ldexp(fr, 24));  // exact: float has 24 bits
        bits = (static_cast<uint32_t>(e) << 23) | (mant & 0x7fffff);
      }
      if (v < 0) bits |= 0x80000000u;
    }
  }
  uint16_t hi = static_cast<uint16_t>(bits >> 16), lo = static_cast<uint16_t>(bits & 0xffff);
  out[0] = static_cast<uint8_t>(hi & 0xff);
  out[1] = static_cast<uint8_t>(hi >> 8);
  out[2] = static_cast<uint8_t>(lo & 0xff);
  out[3] = static_cast<uint8_t>(lo >> 8);
}

// ---- parsing --------------------------------------------------------------------------------

namespace {

std::string printable(const std::string& s) {
  std::string out;
  for (char c : s) out += (std::isprint(static_cast<unsigned char>(c)) ? c : '?');
  return out;
}

// A parameter entry read, waiting to be attached to its group once all groups are known.
struct Pending {
  int group_id;
  size_t order;  // index among all entries, to resolve "most recent group with this id"
  C3DParameter p;
};

// Reads a parameter's type, dimensions and data (normalized to little-endian) starting at *q,
// advancing *q past them; false with *what set when the entry is malformed or cut off.
bool read_parameter_value(const uint8_t* data, size_t size, const NumberFormat& nf, size_t* q,
                          C3DParameter* p, std::string* what) {
  if (size - *q < 2) {
    *what = "cut off before its type";
    return false;
  }
  p->type = static_cast<int8_t>(data[*q]);
  size_t ndims = data[*q + 1];
  *q += 2;
  if (p->type != -1 && p->type != 1 && p->type != 2 && p->type != 4) {
    *what = "has type " + std::to_string(p->type) + " (expected -1, 1, 2 or 4)";
    return false;
  }
  if (ndims > 7) {
    *what = "has " + std::to_string(ndims) + " dimensions (at most 7)";
    return false;
  }
  if (size - *q < ndims) {
    *what = "dimensions cut off by the end of the file";
    return false;
  }
  uint64_t bytes = static_cast<uint64_t>(p->type < 0 ? -p->type : p->type);
  for (size_t d = 0; d < ndims; ++d) {
    p->dims.push_back(data[*q + d]);
    bytes *= data[*q + d];  // at most 4 * 255^7 < 2^59: no overflow
  }
  *q += ndims;
  if (bytes > size - *q) {
    *what = "needs " + std::to_string(bytes) + " data bytes but the file has " +
            std::to_string(size - *q) + " left";
    return false;
  }
  size_t n = static_cast<size_t>(bytes);
  p->data.resize(n);
  if (p->type == 2) {
    for (size_t i = 0; i < n; i += 2) put_u16le(nf.u16(data + *q + i), &p->data[i]);
  } else if (p->type == 4) {
    for (size_t i = 0; i < n; i += 4) put_f32le(nf.f32(data + *q + i), &p->data[i]);
  } else if (n > 0) {
    std::memcpy(p->data.data(), data + *q, n);
  }
  *q += n;
  return true;
}

// The start of the entry after one whose offset word `off` sits at offpos and whose own bytes end
// at q (entry names it in messages). The offset is what C3D readers follow, and some writers rely
// on it: e.g. char parameters written without their description byte, the offset skipping it.
// An offset pointing backwards, into the entry's own name, or past `limit` is wrong: a
// byte-swapped offset (seen in MIPS files) is tried (noted), then the entry's own end (warned).
size_t next_entry(int off, size_t offpos, size_t q, size_t limit, const std::string& entry,
                  ParameterSection* s) {
  auto fits = [&](long o) {
    size_t n = offpos + static_cast<size_t>(o);
    return o >= 2 && n <= limit;
  };
  if (fits(off)) return offpos + static_cast<size_t>(off > 0 ? off : 0);
  long swapped = static_cast<int16_t>(((off & 0xff) << 8) | ((off >> 8) & 0xff));
  if (fits(swapped) && offpos + static_cast<size_t>(swapped) >= q) {
    s->notes.push_back(entry + " has a byte-swapped offset " + std::to_string(off) + "; used as " +
                       std::to_string(swapped));
    return offpos + static_cast<size_t>(swapped);
  }
  s->warnings.push_back(entry + " has offset " + std::to_string(off) +
                        " to the next entry; continuing after the entry's own end");
  return q;
}

// Attaches each parameter to the most recent group with its id before it, else the first group
// with the id after it, else an implicit group per id; notes shared and missing group ids.
void attach_parameters(std::vector<Pending>& params,
                       const std::vector<std::pair<size_t, size_t>>& group_order,
                       ParameterSection* s) {
  std::map<int, std::vector<std::pair<size_t, size_t>>> by_id;  // id -> (entry, group index)
  for (const auto& go : group_order) by_id[s->groups[go.second].id].push_back(go);
  for (const auto& ids : by_id)
    if (ids.second.size() > 1)
      s->notes.push_back("group id " + std::to_string(ids.first) + " is used by " +
                         std::to_string(ids.second.size()) + " groups (" +
                         printable(s->groups[ids.second[0].second].name) + ")");
  std::map<int, size_t> implicit;  // group id -> index of its implicit group
  for (auto& pp : params) {
    auto it = by_id.find(pp.group_id);
    if (it == by_id.end()) {
      auto ig = implicit.find(pp.group_id);
      if (ig == implicit.end()) {
        C3DGroup g;
        g.id = pp.group_id;
        g.implicit = true;
        ig = implicit.emplace(pp.group_id, s->groups.size()).first;
        s->groups.push_back(std::move(g));
      }
      s->groups[ig->second].params.push_back(std::move(pp.p));
      continue;
    }
    const auto& list = it->second;
    size_t target = list.front().second;
    for (const auto& e : list)
      if (e.first < pp.order) target = e.second;
    s->groups[target].params.push_back(std::move(pp.p));
  }
  for (const auto& ig : implicit)
    s->notes.push_back(std::to_string(s->groups[ig.second].params.size()) +
                       " parameter(s) name group id " + std::to_string(ig.first) +
                       ", which has no group entry (kept in an unnamed group)");
}

// The entries read so far: parameters waiting for their groups, and the order of the groups.
struct Entries {
  std::vector<Pending> params;
  std::vector<std::pair<size_t, size_t>> group_order;  // (entry index, group index)
  size_t count = 0;                                    // entries read
};

// How messages name the entry starting at byte p.
std::string entry_at(size_t p) {
  return "parameter entry at byte " + std::to_string(p);
}

// Reads a description (a length byte, then the bytes) at *q into *out, advancing *q; false with
// *what set when it is cut off.
bool read_description(const uint8_t* data, size_t size, size_t* q, std::string* out,
                      std::string* what) {
  if (*q >= size) {
    *what = "cut off before its description";
    return false;
  }
  size_t dlen = data[(*q)++];
  if (size - *q < dlen) {
    *what = "description cut off by the end of the file";
    return false;
  }
  out->assign(reinterpret_cast<const char*>(data + *q), dlen);
  *q += dlen;
  return true;
}

// Reads the rest of a group (gid < 0) or parameter entry named ename from *q, advancing *q, into
// s->groups or e->params; false with *what set when the entry is malformed or cut off.
bool read_entry_body(const uint8_t* data, size_t size, const NumberFormat& nf, int8_t nlen,
                     int8_t gid, const std::string& ename, size_t* q, Entries* e,
                     ParameterSection* s, std::string* what) {
  if (gid < 0) {
    C3DGroup g;
    g.id = -gid;
    g.name = ename;
    g.locked = nlen < 0;
    if (!read_description(data, size, q, &g.description, what)) return false;
    e->group_order.emplace_back(e->count, s->groups.size());
    s->groups.push_back(std::move(g));
    return true;
  }
  C3DParameter p;
  p.name = ename;
  p.locked = nlen < 0;
  if (!read_parameter_value(data, size, nf, q, &p, what) ||
      !read_description(data, size, q, &p.description, what))
    return false;
  e->params.push_back({gid, e->count, std::move(p)});
  return true;
}

// Reads the entry at *pos (below limit, with its first two bytes in the file) and moves *pos to
// the next entry; false when the section ends here: a terminator, the last entry, or a malformed
// entry (warned, ignoring the rest of the section).
bool read_entry(const uint8_t* data, size_t size, size_t limit, const NumberFormat& nf, size_t* pos,
                Entries* e, ParameterSection* s) {
  const size_t at = *pos;
  int8_t nlen = static_cast<int8_t>(data[at]);
  int8_t gid = static_cast<int8_t>(data[at + 1]);
  if (nlen == 0) return false;                    // terminator
  if (gid == 0 || gid == -128 || nlen == -128) {  // ids and name lengths are 1..127
    s->warnings.push_back(entry_at(at) + " has " +
                          (nlen == -128 ? "name length -128" : "group id " + std::to_string(gid)) +
                          "; ignoring the rest of the section");
    return false;
  }
  size_t len = static_cast<size_t>(nlen < 0 ? -nlen : nlen);
  size_t q = at + 2;
  if (size - q < len + 2) {
    s->warnings.push_back(entry_at(at) + " is cut off by the end of the file");
    return false;
  }
  std::string ename(reinterpret_cast<const char*>(data + q), len);
  q += len;
  size_t offpos = q;
  int off = nf.i16(data + q);
  q += 2;
  std::string what;
  if (!read_entry_body(data, size, nf, nlen, gid, ename, &q, e, s, &what)) {
    s->warnings.push_back(entry_at(at) + " (" + printable(ename) + ") " + what +
                          "; ignoring the rest of the section");
    return false;
  }
  ++e->count;
  if (off == 0) return false;  // the last entry
  const size_t next =
      next_entry(off, offpos, q, limit, entry_at(at) + " (" + printable(ename) + ")", s);
  if (next < q) {
    // The entry claims to end before its description does: the description is not there.
    if (!s->groups.empty() && gid < 0) s->groups.back().description.clear();
    if (!e->params.empty() && gid > 0) e->params.back().p.description.clear();
  }
  *pos = next;
  return true;
}

// The section's header (4 bytes at offset): its declared block count and processor type.
ParameterSection read_section_header(const uint8_t* data, size_t size, size_t offset,
                                     const std::string& name) {
  if (offset > size || size - offset < 4)
    fail(ErrorCode::kCorrupt, name,
         "parameter section at byte " + std::to_string(offset) +
             " lies beyond the end of the file (" + std::to_string(size) + " bytes)");
  ParameterSection s;
  s.declared_blocks = data[offset + 2];
  s.processor = data[offset + 3];
  if (s.processor < kIntel || s.processor > kMips)
    fail(ErrorCode::kUnsupportedVersion, name,
         "unknown processor type " + std::to_string(s.processor) +
             " in the parameter section at byte " + std::to_string(offset) +
             " (expected 84 Intel, 85 DEC or 86 MIPS)");
  return s;
}

}  // namespace

ParameterSection parse_parameter_section(const uint8_t* data, size_t size, size_t offset,
                                         size_t limit, const std::string& name) {
  ParameterSection s = read_section_header(data, size, offset, name);
  NumberFormat nf{s.processor};
  Entries e;
  size_t pos = offset + 4;
  // Many writers understate the block count (byte 2), so entries are bounded by `limit` only.
  limit = std::min(limit, size);
  while (true) {
    if (pos >= limit || size - pos < 2) {
      s.warnings.push_back(
          limit < size ? "parameter section runs into the data section without a terminator"
                       : std::string("parameter section runs to the end of the file without a "
                                     "terminator"));
      break;
    }
    if (!read_entry(data, size, limit, nf, &pos, &e, &s)) break;
  }
  attach_parameters(e.params, e.group_order, &s);
  return s;
}

// ---- encoding -------------------------------------------------------------------------------

namespace {

void put_name(std::vector<uint8_t>& out, const std::string& name, bool locked, int id,
              const char* kind) {
  // The length is stored as int8, negated when locked: a locked name may have 128 bytes.
  if (name.empty() || name.size() > (locked ? 128u : 127u))
    fail(ErrorCode::kUsage, "",
         std::string("C3D ") + kind + " name '" + name + "' must be 1..127 bytes long");
  // A group is stored with -id (the reader accepts id byte 0x80, i.e. group 128); a parameter
  // with its group's positive id.
  if (id < -128 || id > 127 || id == 0)
    fail(ErrorCode::kUsage, "",
         std::string("C3D ") + kind + " " + name + " has group id " + std::to_string(id) +
             " (must be 1..127, or 128 for a group)");
  int n = static_cast<int>(name.size());
  out.push_back(static_cast<uint8_t>(static_cast<int8_t>(locked ? -n : n)));
  out.push_back(static_cast<uint8_t>(static_cast<int8_t>(id)));
  out.insert(out.end(), name.begin(), name.end());
}

void put_desc(std::vector<uint8_t>& out, const std::string& d, const std::string& who) {
  if (d.size() > 255)
    fail(ErrorCode::kUsage, "", "C3D description of " + who + " is longer than 255 bytes");
  out.push_back(static_cast<uint8_t>(d.size()));
  out.insert(out.end(), d.begin(), d.end());
}

void put_offset(std::vector<uint8_t>& out, size_t at, size_t value) {
  if (value > 32767) fail(ErrorCode::kUsage, "", "C3D parameter entry longer than 32767 bytes");
  put_u16le(static_cast<uint16_t>(value), &out[at]);
}

}  // namespace

std::vector<uint8_t> encode_parameter_section(const std::vector<C3DGroup>& groups) {
  std::vector<uint8_t> out = {1, 0x50, 0, static_cast<uint8_t>(kIntel)};
  size_t last_offset_at = 0;
  for (const auto& g : groups) {
    if (!g.implicit) {
      put_name(out, g.name, g.locked, -g.id, "group");
      last_offset_at = out.size();
      out.resize(out.size() + 2);
      put_desc(out, g.description, g.name);
      put_offset(out, last_offset_at, out.size() - last_offset_at);
    }
    for (const auto& p : g.params) {
      std::string who = g.name + ":" + p.name;
      put_name(out, p.name, p.locked, g.id, "parameter");
      last_offset_at = out.size();
      out.resize(out.size() + 2);
      if (p.type != -1 && p.type != 1 && p.type != 2 && p.type != 4)
        fail(ErrorCode::kUsage, "", "C3D parameter " + who + " has type " + std::to_string(p.type));
      if (p.dims.size() > 7)
        fail(ErrorCode::kUsage, "", "C3D parameter " + who + " has more than 7 dimensions");
      out.push_back(static_cast<uint8_t>(p.type));
      out.push_back(static_cast<uint8_t>(p.dims.size()));
      size_t expect = static_cast<size_t>(p.type < 0 ? -p.type : p.type);
      for (int d : p.dims) {
        if (d < 0 || d > 255)
          fail(
              ErrorCode::kUsage, "",
              "C3D parameter " + who + " has dimension " + std::to_string(d) + " (must be 0..255)");
        out.push_back(static_cast<uint8_t>(d));
        expect *= static_cast<size_t>(d);
      }
      if (p.data.size() != expect)
        fail(ErrorCode::kUsage, "",
             "C3D parameter " + who + " holds " + std::to_string(p.data.size()) +
                 " bytes, its dimensions say " + std::to_string(expect));
      out.insert(out.end(), p.data.begin(), p.data.end());  // host form is Intel form
      put_desc(out, p.description, who);
      put_offset(out, last_offset_at, out.size() - last_offset_at);
    }
  }
  // The last entry says "last" with a zero offset; a zero name length follows as terminator.
  if (last_offset_at) put_u16le(0, &out[last_offset_at]);
  out.push_back(0);
  out.push_back(0);
  size_t blocks = (out.size() + kBlock - 1) / kBlock;
  if (blocks > 255)
    fail(ErrorCode::kUsage, "",
         "C3D parameter section needs " + std::to_string(blocks) + " blocks (at most 255)");
  out.resize(blocks * kBlock, 0);
  out[2] = static_cast<uint8_t>(blocks);
  return out;
}

// ---- helpers --------------------------------------------------------------------------------

static std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

static std::string trimmed(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\0')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\0')) --e;
  return s.substr(b, e - b);
}

namespace {

// base, base2, base3, ... of a group while `take` accepts the parameter (and appends its values).
template <typename Take>
void continued(const C3DExtra& extra, const std::string& group, const std::string& base,
               Take&& take) {
  const C3DGroup* g = extra.group(group);
  if (!g) return;
  for (int k = 1;; ++k) {
    const C3DParameter* p = g->find(k == 1 ? base : base + std::to_string(k));
    if (!p || !take(*p)) break;
  }
}

}  // namespace

std::vector<std::string> string_list(const C3DExtra& extra, const std::string& group,
                                     const std::string& base) {
  std::vector<std::string> out;
  continued(extra, group, base, [&](const C3DParameter& p) {
    if (p.type != -1) return false;
    const std::vector<std::string> v = p.as_strings();
    out.insert(out.end(), v.begin(), v.end());
    return true;
  });
  return out;
}

std::vector<float> float_list(const C3DExtra& extra, const std::string& group,
                              const std::string& base) {
  std::vector<float> out;
  continued(extra, group, base, [&](const C3DParameter& p) {
    if (p.type == -1) return false;
    const std::vector<float> v = p.as_floats();
    out.insert(out.end(), v.begin(), v.end());
    return true;
  });
  return out;
}

namespace {

// The entries of a units parameter: a 2-D array's strings, or a 1-D one's blank-separated words
// (writers pad one unit per point into a single string too), trimmed, empty ones skipped.
std::vector<std::string> unit_entries(const C3DParameter& p) {
  std::vector<std::string> out;
  for (const std::string& s : p.as_strings()) {
    std::string word;
    for (char c : s + ' ') {
      if (c != ' ' && c != '\0' && c != '\t') {
        word.push_back(c);
      } else if (!word.empty()) {
        out.push_back(word);
        word.clear();
      }
    }
  }
  return out;
}

bool same_unit(const std::string& a, const std::string& b) {
  const double fa = units_to_metres(a), fb = units_to_metres(b);
  return fa != 0 || fb != 0 ? fa == fb : lower(a) == lower(b);
}

}  // namespace

std::string point_units(const C3DExtra& extra, std::string* disagreement) {
  if (disagreement) disagreement->clear();
  const C3DParameter* p = extra.param("POINT", "UNITS");
  if (!p || p->type != -1) return "";
  const std::vector<std::string> entries = unit_entries(*p);
  if (entries.empty()) return "";
  std::vector<std::string> distinct;
  for (const std::string& e : entries)
    if (std::none_of(distinct.begin(), distinct.end(),
                     [&](const std::string& d) { return same_unit(d, e); }))
      distinct.push_back(e);
  if (distinct.size() == 1) return entries[0];
  std::string joined, quoted;
  for (const std::string& d : distinct) {
    joined += (joined.empty() ? "" : ", ") + d;
    quoted += (quoted.empty() ? "'" : ", '") + d + "'";
  }
  if (disagreement)
    *disagreement = "POINT:UNITS names different units (" + quoted +
                    "); capz does not know which the coordinates are in (give --units)";
  return joined;
}

double number_param(const C3DExtra& extra, const std::string& group, const std::string& name,
                    double fallback) {
  const C3DParameter* p = extra.param(group, name);
  if (!p || p->type == -1 || p->data.empty()) return fallback;
  auto v = p->as_floats();
  return v.empty() ? fallback : static_cast<double>(v[0]);
}

bool has_param(const C3DExtra& extra, const std::string& group, const std::string& name) {
  return extra.param(group, name) != nullptr;
}

C3DGroup* find_group(std::vector<C3DGroup>& groups, const std::string& name) {
  std::string key = lower(trimmed(name));
  for (auto& g : groups)
    if (lower(trimmed(g.name)) == key) return &g;
  return nullptr;
}

C3DParameter* find_param(C3DGroup& group, const std::string& name) {
  std::string key = lower(trimmed(name));
  for (auto& p : group.params)
    if (lower(trimmed(p.name)) == key) return &p;
  return nullptr;
}

C3DGroup& ensure_group(std::vector<C3DGroup>& groups, const std::string& name,
                       const std::string& description) {
  if (C3DGroup* g = find_group(groups, name)) return *g;
  int id = 1;
  for (const auto& g : groups) id = std::max(id, g.id + 1);
  if (id > 127) {  // ids used up at the top: take the smallest free one
    for (id = 1; id <= 127; ++id) {
      bool used = false;
      for (const auto& g : groups) used = used || g.id == id;
      if (!used) break;
    }
  }
  C3DGroup g;
  g.id = id;
  g.name = name;
  g.description = description;
  groups.push_back(std::move(g));
  return groups.back();
}

C3DParameter& ensure_param(C3DGroup& group, const std::string& name,
                           const std::string& description) {
  if (C3DParameter* p = find_param(group, name)) return *p;
  C3DParameter p;
  p.name = name;
  p.description = description;
  p.type = 2;
  group.params.push_back(std::move(p));
  return group.params.back();
}

void set_int16(C3DParameter& p, int value) {
  // A byte parameter (some writers store DATA_START or USED as one byte) stays a byte while the
  // value fits one, read unsigned as the reader does.
  if (p.type == 1 && p.data.size() == 1 && value >= 0 && value <= 255) {
    p.data[0] = static_cast<uint8_t>(value);
    return;
  }
  uint8_t b[2];
  put_u16le(static_cast<uint16_t>(value), b);
  if (p.type == 2 && p.data.size() == 2) {
    p.data.assign(b, b + 2);  // keeps dims ({} or {1})
    return;
  }
  p.type = 2;
  p.dims.clear();
  p.data.assign(b, b + 2);
}

void set_int16_array(C3DParameter& p, const std::vector<int>& values) {
  // A byte array stays bytes while every value fits one (as set_int16 keeps a byte).
  if (p.type == 1 &&
      std::all_of(values.begin(), values.end(), [](int v) { return v >= 0 && v <= 255; })) {
    if (!(p.dims.size() == 1 && static_cast<size_t>(p.dims[0]) == values.size()))
      p.dims = {static_cast<int>(values.size())};
    p.data.assign(values.begin(), values.end());
    return;
  }
  std::vector<uint8_t> d(values.size() * 2);
  for (size_t i = 0; i < values.size(); ++i) put_u16le(static_cast<uint16_t>(values[i]), &d[2 * i]);
  if (p.type == 2 && p.data == d) return;
  p.type = 2;
  if (!(p.dims.size() == 1 && static_cast<size_t>(p.dims[0]) == values.size()))
    p.dims = {static_cast<int>(values.size())};
  p.data = d;
}

void set_float(C3DParameter& p, float value) {
  uint8_t b[4];
  put_f32le(value, b);
  if (p.type == 4 && p.data.size() == 4) {
    p.data.assign(b, b + 4);
    return;
  }
  p.type = 4;
  p.dims.clear();
  p.data.assign(b, b + 4);
}

void set_string(C3DParameter& p, const std::string& s) {
  if (p.type == -1 && p.dims.size() <= 1 && p.as_string() == trimmed(s) &&
      trimmed(s).size() == s.size())
    return;
  p.type = -1;
  p.dims = {static_cast<int>(s.size())};
  p.data.assign(s.begin(), s.end());
}

void set_strings(C3DParameter& p, const std::vector<std::string>& v, size_t min_len) {
  if (p.type == -1 && p.dims.size() == 2 && p.as_strings() == v) return;
  size_t len = std::max<size_t>(min_len, 1);
  for (const auto& s : v) len = std::max(len, s.size());
  if (len > 255) len = 255;  // C3D dimensions are bytes; longer strings are cut
  p.type = -1;
  p.dims = {static_cast<int>(len), static_cast<int>(v.size())};
  p.data.assign(len * v.size(), ' ');
  for (size_t i = 0; i < v.size(); ++i)
    std::memcpy(&p.data[i * len], v[i].data(), std::min(len, v[i].size()));
}

void set_string_list(C3DGroup& group, const std::string& base, const std::vector<std::string>& v,
                     const std::string& description, size_t per_param) {
  size_t chunks = std::max<size_t>(1, (v.size() + per_param - 1) / per_param);
  for (size_t k = 0; k < chunks; ++k) {
    std::string pname = k == 0 ? base : base + std::to_string(k + 1);
    C3DParameter& p = ensure_param(group, pname, description);
    size_t min_len = (p.type == -1 && !p.dims.empty()) ? static_cast<size_t>(p.dims[0]) : 1;
    size_t b = k * per_param, e = std::min(v.size(), b + per_param);
    set_strings(p,
                std::vector<std::string>(v.begin() + static_cast<std::ptrdiff_t>(b),
                                         v.begin() + static_cast<std::ptrdiff_t>(e)),
                min_len);
  }
  // Drop continuations beyond what is needed (base{chunks+1}, ...).
  std::string key_base = lower(base);
  auto& ps = group.params;
  ps.erase(
      std::remove_if(ps.begin(), ps.end(),
                     [&](const C3DParameter& p) {
                       std::string n = lower(trimmed(p.name));
                       if (n.size() <= key_base.size() || n.compare(0, key_base.size(), key_base))
                         return false;
                       std::string rest = n.substr(key_base.size());
                       if (rest.empty() || !std::all_of(rest.begin(), rest.end(), ::isdigit))
                         return false;
                       long k = std::strtol(rest.c_str(), nullptr, 10);
                       return k >= 2 && static_cast<size_t>(k) > chunks;
                     }),
      ps.end());
}

}  // namespace c3d

// ---- the container's entry points (coding/c3d_params.h)
// -----------------------------------------------------------------------------

std::vector<uint8_t> encode_c3d_parameters(const C3DExtra& extra) {
  return c3d::encode_parameter_section(extra.groups);
}

void decode_c3d_parameters(const uint8_t* data, size_t size, const std::string& name,
                           C3DExtra* extra) {
  c3d::ParameterSection s = c3d::parse_parameter_section(data, size, 0, size, name);
  if (!s.warnings.empty()) fail(ErrorCode::kCorrupt, name, s.warnings.front());
  extra->groups = std::move(s.groups);
}

}  // namespace capz

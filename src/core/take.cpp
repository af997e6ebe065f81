// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "capz/take.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstring>

#include "capz/error.h"

namespace capz {

const char* format_name(Format f) {
  switch (f) {
    case Format::kC3D:
      return "c3d";
    case Format::kTRC:
      return "trc";
    case Format::kPCDFolder:
      return "pcd-folder";
    case Format::kBinFolder:
      return "bin-folder";
    case Format::kPLYFolder:
      return "ply-folder";
    case Format::kUnknown:
      break;
  }
  return "unknown";
}

bool nuscenes_bin_name(const std::string& name) {
  static const std::string kNuScenes = ".pcd.bin";
  return name.size() > kNuScenes.size() &&
         name.compare(name.size() - kNuScenes.size(), kNuScenes.size(), kNuScenes) == 0;
}

std::vector<PCDField> bin_record_fields(const std::vector<std::string>& frame_names) {
  const auto nuscenes =
      static_cast<size_t>(std::count_if(frame_names.begin(), frame_names.end(), nuscenes_bin_name));
  if (nuscenes == 0) return {{"intensity", 'F', 4, 1}};
  if (nuscenes == frame_names.size()) return {{"intensity", 'F', 4, 1}, {"ring", 'F', 4, 1}};
  return {};
}

std::vector<PCDField> bin_record_or_kitti(const std::vector<std::string>& frame_names) {
  std::vector<PCDField> r = bin_record_fields(frame_names);
  return r.empty() ? bin_record_fields({}) : r;
}

bool same_bin_records(const std::vector<PCDField>& a, const std::vector<PCDField>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(),
                    [](const PCDField& x, const PCDField& y) {
                      return x.name == y.name && x.type == y.type && x.size == y.size;
                    });
}

bool bin_record_float32(const std::vector<PCDField>& record) {
  return std::all_of(record.begin(), record.end(),
                     [](const PCDField& f) { return f.type == 'F' && f.size == 4; });
}

std::string bin_record_text(const std::vector<PCDField>& record) {
  std::string s = "x y z";
  for (const PCDField& f : record) {
    s += " " + f.name;
    if (f.type != 'F' || f.size != 4) s += ":" + std::string(1, f.type) + std::to_string(f.size);
  }
  return s;
}

std::vector<PCDField> parse_bin_record(const std::string& text, const std::string& what) {
  std::vector<std::string> words;
  std::string w;
  for (char c : text + " ") {
    if (c == ' ' || c == ',' || c == '\t') {
      if (!w.empty()) words.push_back(w);
      w.clear();
    } else {
      w += c;
    }
  }
  const auto bad = [&](const std::string& why) {
    fail(ErrorCode::kUsage, what,
         "--bin-fields '" + text + "': " + why +
             " (give x y z first, then the fields, each NAME or NAME:TYPE, TYPE one of F4 F8 U1 "
             "U2 U4 U8 I1 I2 I4 I8; F4 when none)");
  };
  std::vector<PCDField> record;
  for (size_t i = 0; i < words.size(); ++i) {
    const size_t colon = words[i].find(':');
    PCDField f;
    f.name = words[i].substr(0, colon);
    if (colon != std::string::npos) {
      const std::string t = words[i].substr(colon + 1);
      const bool form = t.size() == 2 && std::isdigit(static_cast<unsigned char>(t[1]));
      f.type = form ? static_cast<char>(std::toupper(static_cast<unsigned char>(t[0]))) : '?';
      f.size = form ? t[1] - '0' : 0;
      if (!valid_field_form(f.type, f.size, 1)) bad("unknown type '" + t + "'");
    }
    if (f.name.empty()) bad("a field without a name");
    if (i < 3) {
      if (f.name != std::string(1, static_cast<char>('x' + i)) || f.type != 'F' || f.size != 4)
        bad("the record starts with x y z, each float32");
      continue;
    }
    for (const PCDField& g : record)
      if (g.name == f.name && f.name != "_") bad("two fields named '" + f.name + "'");
    if (f.name == "x" || f.name == "y" || f.name == "z") bad("two fields named '" + f.name + "'");
    record.push_back(f);
  }
  if (words.size() < 3) bad("the record starts with x y z, each float32");
  return record;
}

std::vector<PCDField> bin_record_of(const Take& take) {
  if (take.bin && take.bin->declared) return take.bin->record;
  return bin_record_or_kitti(take.bin ? take.bin->frame_names : std::vector<std::string>());
}

bool is_frame_files(Format f) {
  return f == Format::kPCDFolder || f == Format::kPLYFolder || f == Format::kBinFolder;
}

static std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

static std::string trim(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && (std::isspace(static_cast<unsigned char>(s[b])) || s[b] == '\0')) ++b;
  while (e > b && (std::isspace(static_cast<unsigned char>(s[e - 1])) || s[e - 1] == '\0')) --e;
  return s.substr(b, e - b);
}

size_t C3DParameter::element_count() const {
  size_t n = 1;
  for (int d : dims) n *= static_cast<size_t>(d < 0 ? 0 : d);
  return n;
}

std::string C3DParameter::as_string() const {
  if (type != -1) fail(ErrorCode::kCorrupt, "", "parameter " + name + " is not a char array");
  std::string s(data.begin(), data.end());
  size_t e = s.size();
  while (e > 0 && (s[e - 1] == ' ' || s[e - 1] == '\0')) --e;
  return s.substr(0, e);
}

const char* C3DParameter::type_name() const {
  return type == -1 ? "char" : type == 1 ? "byte" : type == 2 ? "int16" : "float";
}

std::string C3DGroup::key() const {
  return name.empty() ? "#" + std::to_string(id) : name;
}

std::vector<std::string> C3DParameter::as_strings() const {
  if (type != -1) fail(ErrorCode::kCorrupt, "", "parameter " + name + " is not a char array");
  std::vector<std::string> out;
  if (dims.empty()) {
    out.push_back(as_string());
    return out;
  }
  size_t len = static_cast<size_t>(std::max(dims[0], 0));
  size_t count = len == 0 ? 0 : data.size() / len;
  for (size_t i = 0; i < count; ++i) {
    std::string s(data.begin() + i * len, data.begin() + (i + 1) * len);
    size_t e = s.size();
    while (e > 0 && (s[e - 1] == ' ' || s[e - 1] == '\0')) --e;
    out.push_back(s.substr(0, e));
  }
  return out;
}

std::vector<int> C3DParameter::as_ints() const {
  std::vector<int> out;
  if (type == 1) {
    for (uint8_t b : data) out.push_back(b);
  } else if (type == 2) {
    for (size_t i = 0; i + 1 < data.size(); i += 2)
      out.push_back(static_cast<int16_t>(static_cast<uint16_t>(data[i] | (data[i + 1] << 8))));
  } else {
    fail(ErrorCode::kCorrupt, "", "parameter " + name + " is not an integer array");
  }
  return out;
}

std::vector<float> C3DParameter::as_floats() const {
  std::vector<float> out;
  if (type == 4) {
    for (size_t i = 0; i + 3 < data.size(); i += 4) {
      uint32_t u = static_cast<uint32_t>(data[i]) | (static_cast<uint32_t>(data[i + 1]) << 8) |
                   (static_cast<uint32_t>(data[i + 2]) << 16) |
                   (static_cast<uint32_t>(data[i + 3]) << 24);
      float f;
      std::memcpy(&f, &u, 4);
      out.push_back(f);
    }
  } else if (type == 1 || type == 2) {
    for (int v : as_ints()) out.push_back(static_cast<float>(v));
  } else {
    fail(ErrorCode::kCorrupt, "", "parameter " + name + " is not numeric");
  }
  return out;
}

const C3DParameter* C3DGroup::find(const std::string& n) const {
  std::string key = lower(trim(n));
  for (const auto& p : params)
    if (lower(trim(p.name)) == key) return &p;
  return nullptr;
}

const C3DGroup* C3DExtra::group(const std::string& n) const {
  std::string key = lower(trim(n));
  for (const auto& g : groups)
    if (lower(trim(g.name)) == key) return &g;
  return nullptr;
}

const C3DParameter* C3DExtra::param(const std::string& g, const std::string& n) const {
  const C3DGroup* grp = group(g);
  return grp ? grp->find(n) : nullptr;
}

void Take::resize(size_t f, size_t p) {
  frames = f;
  points = p;
  frame_offsets.clear();
  xyz.assign(f * p * 3, 0.0);
  valid.assign(f * p, 0);
}

void Take::resize_ragged(const std::vector<size_t>& counts) {
  frames = counts.size();
  points = 0;
  labels.clear();
  descriptions.clear();
  frame_offsets = offsets_of_counts(counts);
  xyz.assign(frame_offsets.back() * 3, 0.0);
  valid.assign(frame_offsets.back(), 0);
}

bool same_frame_counts(const Take& a, const Take& b) {
  if (a.frames != b.frames) return false;
  if (a.ragged() == b.ragged())
    return a.ragged() ? a.frame_offsets == b.frame_offsets : a.points == b.points;
  const Take& fixed = a.ragged() ? b : a;
  const std::vector<size_t>& offsets = a.ragged() ? a.frame_offsets : b.frame_offsets;
  if (offsets.size() != fixed.frames + 1) return false;
  for (size_t f = 0; f <= fixed.frames; ++f)
    if (offsets[f] != f * fixed.points) return false;
  return true;
}

std::string Take::shape_fault() const {
  if (ragged()) {
    if (frame_offsets.size() != frames + 1)
      return "frame offsets (" + std::to_string(frame_offsets.size()) + ") are not frames + 1 (" +
             std::to_string(frames + 1) + ")";
    if (frame_offsets[0] != 0) return "the first frame offset is not 0";
    for (size_t f = 0; f < frames; ++f)
      if (frame_offsets[f + 1] < frame_offsets[f])
        return "frame offsets decrease at frame " + std::to_string(f);
    if (points != 0) return "a ragged take with a point count per frame";
    if (!labels.empty()) return "a ragged take with point labels";
  } else if (points != 0 && frames > SIZE_MAX / 3 / points) {
    return "frames x points overflows";
  }
  const size_t n = total_points();
  if (xyz.size() / 3 != n || xyz.size() % 3 != 0 || valid.size() != n)
    return "positions or validity do not hold " + std::to_string(n) + " points";
  for (const PointAttribute& a : attributes)
    if (a.size < 1 || a.count < 1 || a.data.size() / a.bytes_per_point() != n ||
        a.data.size() % a.bytes_per_point() != 0)
      return "point field '" + a.name + "' does not hold " + std::to_string(n) + " points";
  return std::string();
}

std::string point_field_fault(const Take& take) {
  const std::vector<PointAttribute>& fields = take.attributes;
  for (size_t i = 0; i < fields.size(); ++i) {
    const std::string& name = fields[i].name;
    if (name.empty()) return "a point field without a name";
    if (name == "x" || name == "y" || name == "z")
      return "a point field named '" + name + "' (the positions' name)";
    for (const char c : name)
      if (static_cast<unsigned char>(c) <= ' ' || c == 0x7F)
        return "point field '" + name + "': a blank or control character in its name";
    for (size_t j = 0; j < i; ++j)
      if (fields[j].name == name && name != "_") return "two point fields named '" + name + "'";
  }
  return std::string();
}

void refuse_ragged(const Take& take, const std::string& consumer, const std::string& file) {
  if (take.ragged())
    fail(ErrorCode::kInvalidParameter, file.empty() ? take.source : file,
         "ragged takes (frames of different point counts) are not supported by " + consumer +
             " yet");
}

std::string units_text(const Take& take) {
  if (!take.units_assumed || take.units.empty()) return take.units;
  const char* what = take.format == Format::kPLYFolder   ? "PLY"
                     : take.format == Format::kBinFolder ? ".bin"
                                                         : "PCD";
  return take.units + " (assumed: " + what + " frames carry no units; --units overrides)";
}

std::vector<size_t> frame_point_counts(const Take& take) {
  std::vector<size_t> c(take.frames);
  for (size_t f = 0; f < take.frames; ++f) c[f] = take.frame_points(f);
  return c;
}

std::vector<size_t> offsets_of_counts(const std::vector<size_t>& counts) {
  std::vector<size_t> o(counts.size() + 1, 0);
  for (size_t f = 0; f < counts.size(); ++f) o[f + 1] = o[f] + counts[f];
  return o;
}

size_t Take::gap_samples() const {
  return static_cast<size_t>(std::count(valid.begin(), valid.end(), uint8_t{0}));
}

namespace {

struct UnitName {
  const char* name;
  double metres;
};
// Abbreviations, matched whole.
const UnitName kUnitAbbreviations[] = {
    {"mm", 0.001}, {"cm", 0.01},        {"dm", 0.1},    {"m", 1.0},     {"km", 1000.0},
    {"um", 1e-6},  {"\xc2\xb5m", 1e-6}, {"in", 0.0254}, {"ft", 0.3048}, {"yd", 0.9144},
};
// Names spelled out, matched whole or cut short (C3D writers truncate char parameters: "mete"),
// both spellings, singular or plural.
const UnitName kUnitNames[] = {
    {"millimetres", 0.001}, {"millimeters", 0.001}, {"centimetres", 0.01}, {"centimeters", 0.01},
    {"decimetres", 0.1},    {"decimeters", 0.1},    {"metres", 1.0},       {"meters", 1.0},
    {"kilometres", 1000.0}, {"kilometers", 1000.0}, {"micrometres", 1e-6}, {"micrometers", 1e-6},
    {"microns", 1e-6},      {"inches", 0.0254},     {"feet", 0.3048},      {"foot", 0.3048},
    {"yards", 0.9144},
};
// A cut-short name must keep this many letters ("met" could be a typo for anything).
constexpr size_t kMinUnitPrefix = 4;

}  // namespace

double units_to_metres(const std::string& units) {
  const std::string u = lower(trim(units));
  if (u.empty()) return 0.0;
  for (const UnitName& a : kUnitAbbreviations)
    if (u == a.name) return a.metres;
  // Whole names and their singulars ("metre", "inch") are prefixes of the plurals too.
  double found = 0;
  for (const UnitName& n : kUnitNames) {
    const std::string name = n.name;
    const bool whole = u == name || u + "s" == name || u + "es" == name;
    const bool prefix = u.size() >= kMinUnitPrefix && name.compare(0, u.size(), u) == 0;
    if (!whole && !prefix) continue;
    if (found != 0 && found != n.metres) return 0.0;  // a prefix of two different units
    found = n.metres;
  }
  return found;
}

std::string field_names(const Take& take) {
  std::string s;
  for (const PointAttribute& a : take.attributes) s += (s.empty() ? "" : ", ") + a.name;
  return s;
}

}  // namespace capz

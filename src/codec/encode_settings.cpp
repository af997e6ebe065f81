// What CompressOptions settle on a source's header before encoding (encode_settings.h).
#include "codec/encode_settings.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "capz/error.h"
#include "coding/attributes.h"
#include "coding/ply_types.h"

namespace capz {

// The per-field bounds of opts.attr_error on the header's PCD layout (field_bounds).
void set_field_bounds(Take& e, const CompressOptions& opts) {
  if (opts.attr_error.empty()) return;
  if (e.attributes.empty() || !e.pcd)
    fail(ErrorCode::kInvalidParameter, e.source,
         "--attr-error: the take has no point fields to bound");
  auto x = std::make_shared<PCDExtra>(*e.pcd);
  x->field_bounds.assign(x->fields.size(), 0.0);
  for (const auto& kv : opts.attr_error) {
    if (!(kv.second > 0) || !std::isfinite(kv.second))
      fail(ErrorCode::kInvalidParameter, e.source,
           "--attr-error " + kv.first + ": the bound must be a positive number");
    bool any = false;
    for (size_t i = 0; i < x->fields.size(); ++i) {
      const PCDField& f = x->fields[i];
      const bool exact = f.name == kv.first;
      if (!(exact || f.name.rfind(kv.first + "_", 0) == 0) || f.name == "x" || f.name == "y" ||
          f.name == "z")
        continue;
      // NAME_* stands for its float fields (CloudCompare's scalar_Intensity beside its
      // scalar_Classification, uchar): its integer fields stay lossless, as they always are.
      if (f.type != 'F' && !exact) continue;
      if (f.type != 'F')
        fail(ErrorCode::kInvalidParameter, e.source,
             "--attr-error " + kv.first + ": field " + f.name +
                 " holds integers, which are always lossless");
      x->field_bounds[i] = kv.second;
      any = true;
    }
    if (!any)
      fail(ErrorCode::kInvalidParameter, e.source,
           "--attr-error names no float field '" + kv.first + "' (fields: " + field_names(e) + ")");
  }
  e.pcd = x;
}

void set_field_bounds(FrameSource& source, const CompressOptions& opts) {
  set_field_bounds(source.edit_header(), opts);
}

// The per-channel bounds of opts.analog_max_error (FORMAT.md 5.7) on the header's analog
// channels: a key names a channel's label or its unit; a label's bound wins over its unit's.
// Returns the keys that name no channel.
std::vector<std::string> set_analog_bounds(FrameSource& source, const CompressOptions& opts) {
  std::vector<std::string> unmatched;
  if (opts.analog_max_error.empty()) return unmatched;
  Take& e = source.edit_header();
  for (const auto& kv : opts.analog_max_error)
    if (!(kv.second > 0) || !std::isfinite(kv.second))
      fail(ErrorCode::kInvalidParameter, e.source,
           "--analog-max-error " + kv.first + ": the bound must be a positive number");
  if (opts.lossless)
    fail(ErrorCode::kInvalidParameter, e.source,
         "--lossless keeps every analog sample: it cannot be given with --analog-max-error");
  const size_t C = static_cast<size_t>(std::max(0, e.analog.channels));
  const std::vector<AnalogPhysics> phys = analog_physics(e);
  std::vector<double> bounds(C, 0.0), factors(C, 1.0);
  std::map<std::string, bool> used;
  auto trim = [](const std::string& s) {
    const size_t a = s.find_first_not_of(" \t");
    return a == std::string::npos ? std::string() : s.substr(a, s.find_last_not_of(" \t") - a + 1);
  };
  for (size_t c = 0; c < C; ++c) {
    const std::string label = c < e.analog.labels.size() ? trim(e.analog.labels[c]) : "";
    const std::string unit = canonical_analog_unit(phys[c].unit);
    auto hit = opts.analog_max_error.end();
    if (!label.empty()) hit = opts.analog_max_error.find(label);
    for (auto it = opts.analog_max_error.begin();
         hit == opts.analog_max_error.end() && !unit.empty() && it != opts.analog_max_error.end();
         ++it)
      if (canonical_analog_unit(it->first) == unit) hit = it;
    if (hit == opts.analog_max_error.end()) continue;
    used[hit->first] = true;
    if (!(phys[c].factor > 0) || !std::isfinite(phys[c].factor)) continue;  // cannot be bounded
    bounds[c] = hit->second;
    factors[c] = phys[c].factor;
  }
  for (const auto& kv : opts.analog_max_error)
    if (!used.count(kv.first)) unmatched.push_back(kv.first);
  e.analog.bounds.clear();
  e.analog.factors.clear();
  for (double b : bounds)
    if (b > 0) {
      e.analog.bounds = bounds;
      e.analog.factors = factors;
      break;
    }
  return unmatched;
}

namespace {

// The fields of a frame-file source's layout: a PLY's vertex properties, a .bin's float32 x y z and
// record (bin_record_of), those the take's attributes still are (--drop-fields: x y z); else
// x y z as float64 (float32 for .bin) then the attributes. Empty when an attribute cannot be the
// format's (COUNT above 1 or an 8-byte integer in a PLY; a .bin field not of its record).
std::vector<PCDField> frame_file_fields(const Take& t) {
  std::vector<PCDField> source, fields;
  if (t.ply) source = t.ply->fields;
  const std::vector<PCDField> record = bin_record_of(t);
  if (t.format == Format::kBinFolder) {
    for (const char* axis : {"x", "y", "z"}) source.push_back({axis, 'F', 4, 1});
    source.insert(source.end(), record.begin(), record.end());
  }
  // The source's x y z and those of its fields the take still has, in the source's order.
  size_t k = 0, axes = 0;
  for (const PCDField& f : source) {
    const PointAttribute* a = k < t.attributes.size() ? &t.attributes[k] : nullptr;
    if (f.name == "x" || f.name == "y" || f.name == "z") {
      ++axes;
      fields.push_back(f);
    } else if (a && a->name == f.name && a->type == f.type && a->size == f.size &&
               a->count == f.count) {
      fields.push_back(f);
      ++k;
    }
  }
  if (axes == 3 && k == t.attributes.size()) return fields;
  fields.clear();
  for (const char* axis : {"x", "y", "z"}) fields.push_back(PCDField{axis, 'F', 8, 1});
  for (const PointAttribute& a : t.attributes) {
    const auto in_record = [&](const PCDField& f) {
      return f.name == a.name && f.type == a.type && f.size == a.size;
    };
    if (a.count != 1 || !ply_type_name(a.type, a.size) ||
        (t.format == Format::kBinFolder &&
         std::find_if(record.begin(), record.end(), in_record) == record.end()))
      return {};
    fields.push_back(PCDField{a.name, a.type, a.size, a.count});
  }
  if (t.format == Format::kBinFolder) fields[0].size = fields[1].size = fields[2].size = 4;
  return fields;
}

}  // namespace

void settle_frame_layout(Take* t, bool drop_fields) {
  if ((t->format != Format::kPLYFolder && t->format != Format::kBinFolder) || t->pcd) return;
  if (t->format == Format::kBinFolder && t->bin && !t->bin->declared &&
      bin_record_fields(t->bin->frame_names).empty())
    fail(ErrorCode::kInvalidParameter, t->source,
         "the .bin frame names are of two kinds (some *.pcd.bin, nuScenes', some not, KITTI's): "
         "no one record holds the frames");
  auto x = std::make_shared<PCDExtra>();
  x->encoding = "binary";
  x->fields = frame_file_fields(*t);
  if (x->fields.empty() && drop_fields) {  // the source's x y z alone
    Take bare;
    bare.format = t->format;
    bare.ply = t->ply;
    x->fields = frame_file_fields(bare);
  }
  if (x->fields.empty())
    fail(ErrorCode::kInvalidParameter, t->source,
         std::string("the point fields (") + field_names(*t) + ") cannot be written back as " +
             (t->format == Format::kPLYFolder
                  ? "PLY properties (one value a point each)"
                  : ".bin frames (" + bin_record_text(bin_record_of(*t)) + ")") +
             ": give --drop-fields to leave them out");
  if (const std::vector<std::string>* names = t->ply   ? &t->ply->frame_names
                                              : t->bin ? &t->bin->frame_names
                                                       : nullptr)
    x->frame_names = *names;
  t->pcd = x;
}

// A take with point fields needs a PCD layout in META (FORMAT.md 5.5): one read from a PCD
// folder has it; for any other (built in memory) it is x y z as float64 then the fields, one
// row. With opts.drop_fields the fields are left out instead.
void settle_fields(Take& e, const CompressOptions& opts) {
  if (e.format == Format::kPLYFolder || e.format == Format::kBinFolder) {
    if (opts.drop_fields) e.attributes.clear();
    settle_frame_layout(&e, opts.drop_fields);
  }
  const Take& h = e;
  if (h.attributes.empty()) return;
  if (opts.drop_fields) {
    e.attributes.clear();
    if (e.pcd) {
      auto x = std::make_shared<PCDExtra>(*e.pcd);
      x->fields = std::vector<PCDField>();
      for (const PCDField& f : e.pcd->fields)
        if (f.name == "x" || f.name == "y" || f.name == "z") x->fields.push_back(f);
      e.pcd = x;
    }
    return;
  }
  bool match = h.pcd && !h.pcd->fields.empty();
  if (match) {
    const std::vector<AttrSpec> specs = attribute_specs(h.pcd->fields);
    match = specs.size() == h.attributes.size();
    for (size_t i = 0; match && i < specs.size(); ++i)
      match = specs[i].name == h.attributes[i].name && specs[i].type == h.attributes[i].type &&
              specs[i].size == h.attributes[i].size && specs[i].count == h.attributes[i].count;
  }
  for (const PointAttribute& a : h.attributes)
    if (a.count < 1 || !valid_field_form(a.type, a.size, static_cast<uint64_t>(a.count)) ||
        a.name.empty() || a.name == "x" || a.name == "y" || a.name == "z")
      fail(ErrorCode::kInvalidParameter, h.source,
           "point field '" + a.name + "' has a bad name, type, size or count");
  if (match) return;
  auto x = h.pcd ? std::make_shared<PCDExtra>(*h.pcd) : std::make_shared<PCDExtra>();
  x->fields.clear();
  for (const char* axis : {"x", "y", "z"}) x->fields.push_back(PCDField{axis, 'F', 8, 1});
  for (const PointAttribute& a : h.attributes)
    x->fields.push_back(PCDField{a.name, a.type, a.size, a.count});
  if (x->width * x->height != h.points) {
    x->width = h.points;
    x->height = 1;
  }
  e.pcd = x;
}

void settle_fields(FrameSource& source, const CompressOptions& opts) {
  settle_fields(source.edit_header(), opts);
}

}  // namespace capz

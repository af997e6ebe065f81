// capz._capz: capz.open's file, a .capz read for random access (py_common.h).
#include <pybind11/stl.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "capz/codec.h"
#include "capz/metrics.h"
#include "capz/tool/file.h"
#include "capz/tool/original.h"
#include "py_common.h"

namespace capz_py {

namespace {

// The windows per float32 split exponent, keyed by the exponent as text, as the CLI.
py::dict split_windows_dict(const capz::StreamInfo& si) {
  py::dict splits;
  for (const auto& kv : si.float32_split_windows)
    splits[py::str(std::to_string(kv.first))] = kv.second;
  return splits;
}

// The lossy analog channels (FORMAT.md 5.7) with their labels, units and bounds, as the CLI.
py::list analog_bounds_list(const capz::StreamInfo& si) {
  py::list bounds;
  for (size_t c = 0; c < si.analog_bounds.size(); ++c)
    if (si.analog_bounds[c] > 0) {
      py::dict b;
      b["channel"] = c;
      b["label"] = text(c < si.analog_labels.size() ? si.analog_labels[c] : std::string());
      b["unit"] = text(c < si.analog_units.size() ? si.analog_units[c] : std::string());
      b["bound"] = si.analog_bounds[c];
      bounds.append(b);
    }
  return bounds;
}

// The rotation segments' counts, rate and labels.
py::dict rotations_dict(const capz::StreamInfo& si) {
  py::dict rot;
  rot["segments"] = si.rotation_segments;
  rot["samples"] = si.rotation_segments > 0
                       ? si.frames * static_cast<size_t>(si.rotation_samples_per_frame)
                       : size_t{0};
  rot["rate"] = si.rotation_rate;
  rot["samples_per_frame"] = si.rotation_samples_per_frame;
  rot["labels"] = texts(si.rotation_labels);
  return rot;
}

// Adds a PCD sequence's layout, fields and their bounds to d.
void add_pcd_layout(const capz::StreamInfo& si, py::dict* d) {
  (*d)["width"] = si.pcd_width;
  (*d)["height"] = si.pcd_height;
  py::list fields;
  for (const capz::PCDField& f : si.pcd_fields) {
    py::dict x;
    x["name"] = text(f.name);
    x["type"] = std::string(1, f.type);
    x["size"] = f.size;
    x["count"] = f.count;
    fields.append(x);
  }
  (*d)["fields"] = fields;
  py::dict bounds_of;
  for (size_t i = 0; i < si.pcd_field_bounds.size() && i < si.pcd_fields.size(); ++i)
    if (si.pcd_field_bounds[i] > 0) bounds_of[text(si.pcd_fields[i].name)] = si.pcd_field_bounds[i];
  (*d)["field_bounds"] = bounds_of;
}

// The original file's size and hash from the HASH chunk, or None when it has none.
py::object original_dict(const std::string& path) {
  const capz::OriginalInfo orig = capz::original_info(path);
  if (!orig.hashed) return py::none();
  py::dict o;
  o["bytes"] = orig.size;
  o["xxh3_128"] = orig.hash_hex;
  o["byte_exact"] = orig.exact;
  return o;
}

// The bytes of each chunk, keyed by the chunk's name.
py::dict chunk_bytes_dict(const capz::StreamInfo& si) {
  py::dict chunks;
  for (const auto& kv : si.chunk_bytes) chunks[py::str(kv.first)] = kv.second;
  return chunks;
}

// The same members as `capz info --json` on a .capz (apps/capz/cmd_info_capz.cpp).
py::dict info_dict(const std::string& path, const std::vector<uint8_t>& bytes) {
  const capz::StreamInfo si = capz::describe(bytes.data(), bytes.size(), path);
  py::dict d;
  d["file"] = path;
  d["format"] = "capz";
  d["version"] = std::to_string(si.major) + "." + std::to_string(si.minor);
  d["bytes"] = bytes.size();
  d["source_format"] = capz::format_name(si.source_format);
  d["source_name"] = text(si.source_name);
  d["frames"] = si.frames;
  d["points"] = si.points;
  d["rate"] = si.rate;
  d["units"] = text(si.units);
  d["mode"] = si.mode;
  if (!si.float32_split_windows.empty()) d["float32_split_windows"] = split_windows_dict(si);
  d["codec"] = si.codec;
  d["lossless"] = si.lossless;
  d["grid_step"] = si.step;
  d["max_error"] = si.max_error;
  if (si.transform_output) d["kg_target"] = si.kg_target;
  if (si.ragged || si.points_reordered)
    d["point_order"] = si.points_reordered ? "reordered" : "kept";
  d["window_frames"] = si.window_frames;
  d["windows"] = si.windows;
  d["analog_channels"] = si.analog_channels;
  d["analog_samples_per_frame"] = si.analog_samples_per_frame;
  d["analog_bounds"] = analog_bounds_list(si);
  d["rotations"] = rotations_dict(si);
  if (!si.pcd_fields.empty()) add_pcd_layout(si, &d);
  if (si.source_format == capz::Format::kC3D) {  // the EVENT group, from META
    const capz::Take h = capz::decompress_frames(bytes.data(), bytes.size(), 0, 0, path);
    d["events"] = h.c3d ? events_list(capz::c3d_events(*h.c3d)) : py::list();
  }
  d["original"] = original_dict(path);                       // HASH: the original file
  d["bpvf"] = capz::bpvf(bytes.size(), 1, si.total_points);  // as capz info: over every point
  d["chunk_bytes"] = chunk_bytes_dict(si);
  return d;
}

// A .capz opened for random access: the file's bytes in memory, frames decoded on demand.
class CapzFile {
 public:
  CapzFile(const std::string& path, uint64_t memory_limit) : path_(path) {
    opts_.memory_limit = memory_limit;
    py::gil_scoped_release nogil;
    bytes_ = capz::read_file(path);
    info_ = capz::describe(bytes_.data(), bytes_.size(), path);
  }
  TakePtr read_frames(size_t first, std::optional<size_t> count) const {
    const size_t n = count ? *count : info_.frames;
    capz::Take t;
    {
      py::gil_scoped_release nogil;
      t = capz::decompress_frames(bytes_.data(), bytes_.size(), first, n, path_, opts_);
    }
    return adopt(std::move(t));
  }
  py::dict info() const { return info_dict(path_, bytes_); }
  size_t frames() const { return info_.frames; }
  size_t points() const { return info_.points; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::vector<uint8_t> bytes_;
  capz::StreamInfo info_;
  capz::DecompressOptions opts_;
};

}  // namespace

// capz.open's file: random access to a .capz.
void bind_capz_file(py::module_& m) {
  py::class_<CapzFile>(m, "CapzFile")
      .def(py::init<const std::string&, uint64_t>())
      .def("read_frames", &CapzFile::read_frames)
      .def_property_readonly("info", &CapzFile::info)
      .def_property_readonly("frames", &CapzFile::frames)
      .def_property_readonly("points", &CapzFile::points)
      .def_property_readonly("path", &CapzFile::path);
}

}  // namespace capz_py

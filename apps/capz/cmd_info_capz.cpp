// `capz info X.capz`: the stream header, metadata and chunk sizes of an archive.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "capz/codec.h"
#include "capz/tool/original.h"
#include "compress_common.h"

namespace capz_cli {

namespace {

// Rotation samples per point frame (0 without rotations).
size_t rotations_per_frame(const capz::StreamInfo& si) {
  return si.rotation_segments > 0 ? static_cast<size_t>(si.rotation_samples_per_frame) : 0;
}

// The analog line: channels, samples per frame, and the lossy ones grouped by bound and unit, in
// channel order (FORMAT.md 5.7).
std::string analog_text(const capz::StreamInfo& si) {
  std::vector<std::pair<std::string, std::vector<std::string>>> groups;
  size_t lossy = 0;
  for (size_t c = 0; c < si.analog_bounds.size(); ++c) {
    if (!(si.analog_bounds[c] > 0)) continue;
    ++lossy;
    const std::string unit = c < si.analog_units.size() ? si.analog_units[c] : "";
    const std::string key = num(si.analog_bounds[c]) + (unit.empty() ? "" : " " + unit);
    const std::string label = c < si.analog_labels.size() && !si.analog_labels[c].empty()
                                  ? si.analog_labels[c]
                                  : "#" + std::to_string(c);
    auto g =
        std::find_if(groups.begin(), groups.end(), [&](const auto& x) { return x.first == key; });
    if (g == groups.end()) groups.push_back({key, {}}), g = groups.end() - 1;
    g->second.push_back(label);
  }
  std::string v = std::to_string(si.analog_channels) + " channels x " +
                  std::to_string(si.analog_samples_per_frame) + " samples per frame";
  if (lossy == 0) {
    v += ", lossless";
  } else {
    v += ", " + std::to_string(si.analog_channels - static_cast<int>(lossy)) + " lossless";
    for (const auto& g : groups) {
      std::string names;
      for (const std::string& n : g.second) names += (names.empty() ? "" : ", ") + n;
      v += "; within " + g.first + ": " + names;
    }
  }
  return v;
}

// info --json: how the archive codes its positions (mode, codec, grid, order, windows).
void json_coding(Json* j, const capz::StreamInfo& si) {
  j->member("mode", si.mode);
  // Windows per float32 split exponent (capz::kPlainFloat32WindowsKey: none, kRawWindowsKey: raw).
  if (!si.float32_split_windows.empty()) {
    j->key("float32_split_windows");
    j->begin_object();
    for (const auto& kv : si.float32_split_windows)
      j->member(std::to_string(kv.first), static_cast<uint64_t>(kv.second));
    j->end_object();
  }
  j->member("codec", si.codec);
  j->member("lossless", si.lossless);
  j->member("grid_step", si.step);
  j->member("max_error", si.max_error);
  if (si.transform_output) j->member("kg_target", si.kg_target);
  if (si.ragged || si.points_reordered)  // a one-frame stream's order, if the encoder chose it
    j->member("point_order", si.points_reordered ? "reordered" : "kept");
  j->member("window_frames", static_cast<uint64_t>(si.window_frames));
  j->member("windows", static_cast<uint64_t>(si.windows));
}

// info --json: the analog channels and their bounds (FORMAT.md 5.7; the others lossless).
void json_analog(Json* j, const capz::StreamInfo& si) {
  j->member("analog_channels", si.analog_channels);
  j->member("analog_samples_per_frame", si.analog_samples_per_frame);
  j->key("analog_bounds");  // the lossy channels (FORMAT.md 5.7); the others are lossless
  j->begin_array();
  for (size_t c = 0; c < si.analog_bounds.size(); ++c)
    if (si.analog_bounds[c] > 0) {
      j->begin_object();
      j->member("channel", static_cast<uint64_t>(c));
      j->member("label", c < si.analog_labels.size() ? si.analog_labels[c] : std::string());
      j->member("unit", c < si.analog_units.size() ? si.analog_units[c] : std::string());
      j->member("bound", si.analog_bounds[c]);
      j->end_object();
    }
  j->end_array();
}

// info --json: the rotation segments.
void json_rotations(Json* j, const capz::StreamInfo& si) {
  j->key("rotations");
  j->begin_object();
  j->member("segments", si.rotation_segments);
  j->member("samples", static_cast<uint64_t>(si.frames * rotations_per_frame(si)));
  j->member("rate", si.rotation_rate);
  j->member("samples_per_frame", si.rotation_samples_per_frame);
  j->member_strings("labels", si.rotation_labels);
  j->end_object();
}

// info --json: a PCD source's shape, fields and the fields' bounds.
void json_pcd(Json* j, const capz::StreamInfo& si) {
  if (!si.pcd_fields.empty()) {
    j->member("width", static_cast<uint64_t>(si.pcd_width));
    j->member("height", static_cast<uint64_t>(si.pcd_height));
    pcd_fields_json(j, si.pcd_fields);
    j->key("field_bounds");
    j->begin_object();
    for (size_t i = 0; i < si.pcd_field_bounds.size() && i < si.pcd_fields.size(); ++i)
      if (si.pcd_field_bounds[i] > 0) j->member(si.pcd_fields[i].name, si.pcd_field_bounds[i]);
    j->end_object();
  }
}

// info --json: the original file (HASH, FORMAT.md 6), null when the archive records none.
void json_original(Json* j, const std::string& path) {
  const capz::OriginalInfo orig = capz::original_info(path);
  j->key("original");
  if (orig.hashed) {
    j->begin_object();
    j->member("bytes", orig.size);
    j->member("xxh3_128", orig.hash_hex);
    j->member("byte_exact", orig.exact);
    j->end_object();
  } else {
    j->null();
  }
}

void print_json(const std::string& path, size_t size, const capz::StreamInfo& si, double bp,
                const std::vector<capz::C3DEvent>* events) {
  Json j;
  j.begin_object();
  j.member("file", path);
  j.member("format", "capz");
  j.member("version", std::to_string(si.major) + "." + std::to_string(si.minor));
  j.member("bytes", static_cast<uint64_t>(size));
  j.member("source_format", capz::format_name(si.source_format));
  j.member("source_name", si.source_name);
  j.member("frames", static_cast<uint64_t>(si.frames));
  j.member("points", static_cast<uint64_t>(si.points));
  j.member("rate", si.rate);
  j.member("units", si.units);
  json_coding(&j, si);
  json_analog(&j, si);
  json_rotations(&j, si);
  if (events) events_json(&j, *events);
  json_pcd(&j, si);
  json_original(&j, path);
  j.member("bpvf", bp);
  j.key("chunk_bytes");
  j.begin_object();
  for (const auto& kv : si.chunk_bytes) j.member(kv.first, static_cast<uint64_t>(kv.second));
  j.end_object();
  j.end_object();
  std::printf("%s\n", j.str().c_str());
}

void print_text(const std::string& path, size_t size, const capz::StreamInfo& si, double bp,
                const std::vector<capz::C3DEvent>* events) {
  bool assumed = false;
  const std::string units = archive_units(si.source_format, si.units, &assumed);
  const std::string u = units.empty() ? "" : " " + units;
  capz::Take shown;  // for capz::units_text's note on assumed units
  shown.format = si.source_format;
  shown.units = units;
  shown.units_assumed = assumed;
  auto line = [](const char* k, const std::string& v) {
    std::printf("  %-12s %s\n", k, printable(v).c_str());
  };
  std::printf("%s\n", path.c_str());
  line("format:", "capz " + std::to_string(si.major) + "." + std::to_string(si.minor) + ", " +
                      human_size(size) + ", " + num(bp) + " bpvf");
  line("source:", std::string(capz::format_name(si.source_format)) +
                      (si.source_name.empty() ? "" : " " + si.source_name));
  line("take:", shape_text(si.frames, si.points, si.ragged, si.total_points) +
                    (si.rate > 0 ? ", " + num(si.rate) + " Hz" : "") +
                    (units.empty() ? ", units unknown" : ", " + capz::units_text(shown)));
  line("coding:",
       positions_text(si.mode, si.float32_split_windows, u) +
           (si.lossless           ? ", lossless"
            : si.transform_output ? ", KG target " + num(si.kg_target) + "%, no bound"
                                  : ", bound " + num(si.max_error) + u + " per coordinate") +
           (si.step > 0 ? ", grid step " + num(si.step, 6) + u : "") + ", codec " + si.codec);
  // Frames of their own size (or one frame, reordered): the encoder may reorder their points
  if (si.ragged || si.points_reordered)
    line("point order:", si.points_reordered ? "reordered (--point-order any)" : "kept");
  // Each window holds up to window_frames frames (the last may hold fewer: a take of 5 frames
  // in windows of 9 is 1 window of 5).
  line("windows:", std::to_string(si.windows) + " of up to " + std::to_string(si.window_frames) +
                       " frames each");
  const capz::OriginalInfo orig = capz::original_info(path);
  if (orig.hashed)
    line("original:", std::to_string(orig.size) + " bytes, xxh3-128 " + orig.hash_hex +
                          (orig.exact ? ", rebuilt byte for byte (checksum checked)"
                                      : ", not rebuilt byte for byte"));
  if (si.analog_channels > 0) line("analog:", analog_text(si));
  if (si.rotation_segments > 0)
    line("rotations:", std::to_string(si.rotation_segments) + " segments x " +
                           std::to_string(si.frames * rotations_per_frame(si)) + " samples at " +
                           num(si.rotation_rate) + " Hz (" +
                           std::to_string(si.rotation_samples_per_frame) + " per frame), lossless");
  if (events) line("events:", events_text(*events));
  if (!si.pcd_fields.empty()) {
    std::string v = pcd_fields_text(si.pcd_fields);
    std::string bounded;
    for (size_t i = 0; i < si.pcd_field_bounds.size() && i < si.pcd_fields.size(); ++i)
      if (si.pcd_field_bounds[i] > 0)
        bounded += (bounded.empty() ? "" : ", ") + si.pcd_fields[i].name + " within " +
                   num(si.pcd_field_bounds[i]);
    if (!bounded.empty()) line("bounded:", bounded);
    line("fields:",
         v + (si.pcd_fields.size() > 3 && bounded.empty() ? " (all but x y z lossless)" : ""));
    line("layout:", si.pcd_height > 1 ? "organized " + std::to_string(si.pcd_width) + " x " +
                                            std::to_string(si.pcd_height)
                                      : std::string("unorganized"));
  }
  std::string chunks;
  for (const auto& kv : si.chunk_bytes)
    chunks += (chunks.empty() ? "" : ", ") + kv.first + " " + human_size(kv.second);
  line("chunks:", chunks);
}
}  // namespace

int info_capz(const std::string& path, bool json) {
  std::vector<uint8_t> bytes = capz::read_file(path);
  capz::StreamInfo si = capz::describe(bytes.data(), bytes.size(), path);
  const double bp = si.ragged ? capz::bpvf(bytes.size(), 1, si.total_points)
                              : capz::bpvf(bytes.size(), si.frames, si.points);
  // A C3D take's EVENT group, from META (no frame decoded).
  std::vector<capz::C3DEvent> events;
  const bool c3d = si.source_format == capz::Format::kC3D;
  if (c3d) {
    const capz::Take h = capz::decompress_frames(bytes.data(), bytes.size(), 0, 0, path);
    if (h.c3d) events = capz::c3d_events(*h.c3d);
  }
  if (json)
    print_json(path, bytes.size(), si, bp, c3d ? &events : nullptr);
  else
    print_text(path, bytes.size(), si, bp, c3d ? &events : nullptr);
  return 0;
}

}  // namespace capz_cli

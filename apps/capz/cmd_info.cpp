// capz info FILE [--json]: describes a .c3d, a .trc or a folder of PCD frames (format and
// variant, shape, rate, units, gaps, labels, analog channels, every inconsistency the reader
// found). .capz archives are handled by the hook below.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/io.h"
#include "capz/stream.h"
#include "cli_util.h"
#include "commands.h"
#include "compress_common.h"

namespace capz_cli {

namespace {

const size_t kLabelsShown = 8;  // labels listed without -v

// A .bin source's frame fields: float32 x y z then its record's (text and --json).
std::vector<capz::PCDField> bin_fields(const capz::Take& t) {
  std::vector<capz::PCDField> fields;
  for (const char* axis : {"x", "y", "z"}) fields.push_back({axis, 'F', 4, 1});
  for (const capz::PCDField& f : capz::bin_record_of(t)) fields.push_back(f);
  return fields;
}

// True for a file that starts with the .capz magic or is named *.capz.
bool looks_like_capz(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  std::ifstream in(path, std::ios::binary);
  char head[5] = {};
  in.read(head, 5);  // the .capz magic starts 0x89 "capz" (docs/FORMAT.md)
  if (in.gcount() == 5 && static_cast<unsigned char>(head[0]) == 0x89 &&
      std::memcmp(head + 1, "capz", 4) == 0)
    return true;
  std::string ext = std::filesystem::path(path).extension().string();
  return ext == ".capz" || ext == ".CAPZ";
}

const char* processor_name(int p) {
  switch (p) {
    case 84:
      return "Intel";
    case 85:
      return "DEC";
    case 86:
      return "MIPS";
  }
  return "unknown processor";
}

struct Summary {
  size_t samples = 0, gaps = 0, points_with_gaps = 0;
  double duration = 0;                                       // seconds, 0 when the rate is unknown
  size_t min_points = 0, median_points = 0, max_points = 0;  // per frame (ragged takes)
};

// One pass over the frames, a block at a time (a C3D is read by frame ranges, so memory stays
// bounded by the block).
Summary summarise(capz::FrameSource& src) {
  const capz::Take& t = src.header();
  Summary s;
  s.samples = t.total_points();
  if (t.ragged() && t.frames > 0) {
    std::vector<size_t> c = capz::frame_point_counts(t);
    std::sort(c.begin(), c.end());
    s.min_points = c.front();
    s.median_points = c[c.size() / 2];
    s.max_points = c.back();
  }
  std::vector<uint8_t> has_gap(t.points, 0);
  capz::FrameBlock b;
  const size_t B = src.preferred_block();
  for (size_t f0 = 0; f0 < t.frames; f0 += B) {
    src.read(f0, std::min(B, t.frames - f0), &b);
    for (size_t i = 0; i < b.total_points(); ++i)
      if (!b.valid[i]) {
        ++s.gaps;
        if (!b.ragged()) has_gap[i % t.points] = 1;
      }
  }
  for (uint8_t g : has_gap) s.points_with_gaps += g;
  if (t.rate > 0) s.duration = static_cast<double>(t.frames) / t.rate;
  return s;
}

// One line describing the format variant.
std::string variant_text(const capz::Take& t) {
  if (t.c3d) {
    const auto& c = *t.c3d;
    std::string s = std::string(processor_name(c.processor)) + " (" + std::to_string(c.processor) +
                    "), " + (c.float_storage ? "float" : "int16") + " storage";
    s += ", scale " + number(c.point_scale);
    if (!t.units.empty()) s += " " + t.units;
    return s;
  }
  if (t.trc) {
    std::string s = "OpenSim/Motion Analysis TRC";
    if (t.trc->decimals >= 0) s += ", " + std::to_string(t.trc->decimals) + " decimals";
    return s;
  }
  if (t.ply) {
    std::string s = t.ply->encoding + " PLY frames";
    if (!t.ply->frame_names.empty())
      s += " " + t.ply->frame_names.front() + " .. " + t.ply->frame_names.back();
    return s;
  }
  if (t.bin) {
    const std::vector<capz::PCDField> record = capz::bin_record_of(t);
    const std::string text = capz::bin_record_text(record);
    std::string s = t.bin->declared      ? ".bin frames (" + text + ", given by --bin-fields)"
                    : record.size() == 2 ? "nuScenes .bin frames (float32 " + text + ")"
                                         : "KITTI .bin frames (float32 " + text + ")";
    if (!t.bin->frame_names.empty())
      s += " " + t.bin->frame_names.front() + " .. " + t.bin->frame_names.back();
    return s;
  }
  if (t.pcd) {
    std::string s = t.pcd->encoding + " PCD frames";
    if (!t.pcd->frame_names.empty())
      s += " " + t.pcd->frame_names.front() + " .. " + t.pcd->frame_names.back();
    if (t.pcd->height > 1)
      s += ", organized " + std::to_string(t.pcd->width) + " x " + std::to_string(t.pcd->height);
    else
      s += ", unorganized";
    return s;
  }
  return "";
}

// One "key: value" line of the text description, the value made printable.
void line(const char* k, const std::string& v) {
  std::printf("%-10s %s\n", k, printable(v).c_str());
}

// The labels line: the first kLabelsShown labels (all with -v), or none.
std::string labels_text(const capz::Take& t) {
  size_t named = 0;
  for (const auto& l : t.labels) named += !l.empty();
  if (named == 0) return "none";
  const size_t shown = g_verbosity >= 2 ? t.labels.size() : std::min(kLabelsShown, t.labels.size());
  std::string v;
  for (size_t i = 0; i < shown; ++i) {
    if (i) v += ", ";
    v += t.labels[i].empty() ? "(unnamed)" : t.labels[i];
  }
  if (shown < t.labels.size())
    v += ", ... (" + std::to_string(t.labels.size() - shown) + " more; -v lists all)";
  return v;
}

// The analog line: channels, rate, samples per frame and units counted (what
// --analog-max-error's keys name besides labels), or none; with -v a line per channel: its label,
// unit and physical value per stored unit.
void print_analog(const capz::Take& t) {
  if (t.analog.channels > 0) {
    const std::vector<capz::AnalogPhysics> phys = capz::analog_physics(t);
    std::vector<std::pair<std::string, int>> units;
    for (const capz::AnalogPhysics& p : phys) {
      if (p.unit.empty()) continue;
      auto u = std::find_if(units.begin(), units.end(),
                            [&](const auto& x) { return x.first == p.unit; });
      if (u == units.end())
        units.push_back({p.unit, 1});
      else
        ++u->second;
    }
    std::string us;
    for (const auto& u : units)
      us += (us.empty() ? "; units " : ", ") + u.first + " (" + std::to_string(u.second) + ")";
    line("analog:", std::to_string(t.analog.channels) + " channels at " + number(t.analog.rate) +
                        " Hz (" + std::to_string(t.analog.samples_per_frame) + " per frame)" + us);
    if (g_verbosity >= 2)
      for (size_t c = 0; c < phys.size(); ++c)
        std::printf("  - %s: %s, %s per stored unit\n",
                    printable(c < t.analog.labels.size() && !t.analog.labels[c].empty()
                                  ? t.analog.labels[c]
                                  : "#" + std::to_string(c))
                        .c_str(),
                    phys[c].unit.empty() ? "no unit" : printable(phys[c].unit).c_str(),
                    number(phys[c].factor).c_str());
  } else {
    line("analog:", "none");
  }
}

void print_text(const std::string& path, const capz::Take& t, const Summary& s) {
  line("file:", path + " (" + human_size(path_size(path)) + ")");
  line("format:", std::string(capz::format_name(t.format)) + ": " + variant_text(t));
  if (t.ragged())
    line("points:", std::to_string(t.total_points()) + " in all, " + std::to_string(s.min_points) +
                        " .. " + std::to_string(s.max_points) + " a frame (median " +
                        std::to_string(s.median_points) + ")");
  else
    line("points:", std::to_string(t.points));
  line("frames:",
       std::to_string(t.frames) + " (first frame " + std::to_string(t.first_frame) + ")");
  line("rate:", t.rate > 0 ? number(t.rate) + " Hz" : std::string("unknown"));
  line("duration:",
       t.rate > 0 ? number(std::round(s.duration * 1000) / 1000) + " s" : std::string("unknown"));
  line("units:", t.units.empty() ? std::string("unknown") : capz::units_text(t));
  line("gaps:", s.samples == 0
                    ? std::string("none (no samples)")
                    : percent(static_cast<double>(s.gaps) / static_cast<double>(s.samples)) +
                          " of samples (" + std::to_string(s.gaps) + " of " +
                          std::to_string(s.samples) + ")" +
                          (t.ragged() ? std::string()
                                      : ", " + std::to_string(s.points_with_gaps) + " of " +
                                            std::to_string(t.points) + " points have gaps"));
  line("labels:", labels_text(t));
  if (t.file_fields() && !t.file_fields()->empty()) {
    // Every field of the frames, x y z included: NAME TYPE SIZE[xCOUNT].
    line("fields:", pcd_fields_text(*t.file_fields()));
  } else if (t.bin) {
    line("fields:", pcd_fields_text(bin_fields(t)));
  }
  print_analog(t);
  const capz::Rotations& r = t.rotations;
  if (r.segments > 0)
    line("rotations:", std::to_string(r.segments) + " segments x " +
                           std::to_string(r.samples(t.frames)) + " samples at " + number(r.rate) +
                           " Hz (" + std::to_string(r.samples_per_frame) + " per frame)");
  else if (t.c3d)
    line("rotations:", "none");
  if (t.c3d) line("events:", events_text(capz::c3d_events(*t.c3d)));
  if (t.c3d && g_verbosity >= 2) {
    size_t params = 0;
    for (const auto& g : t.c3d->groups) params += g.params.size();
    line("c3d:", std::to_string(t.c3d->groups.size()) + " parameter groups, " +
                     std::to_string(params) + " parameters, " +
                     std::to_string(t.c3d->header_events.size()) + " header events");
  }
  if (t.warnings.empty()) {
    line("warnings:", "none");
  } else {
    line("warnings:", std::to_string(t.warnings.size()));
    for (const auto& w : t.warnings) std::printf("  - %s\n", w.c_str());
  }
}

// info --json: what the source's format says of it (C3D, TRC, PCD, PLY, .bin).
void json_variant(Json* j, const capz::Take& t) {
  j->key("variant");
  j->begin_object();
  if (t.c3d) {
    j->member("processor", processor_name(t.c3d->processor));
    j->member("processor_type", t.c3d->processor);
    j->member("storage", t.c3d->float_storage ? "float" : "int16");
    j->member("scale", t.c3d->point_scale);
  } else if (t.trc) {
    j->member("path_file_type", t.trc->path_file_type_line);
    j->member("decimals", t.trc->decimals);
  } else if (t.pcd) {
    j->member("encoding", t.pcd->encoding);
    j->member_strings("frame_files", t.pcd->frame_names);
    j->member("organized", t.pcd->height > 1);
    j->member("width", static_cast<uint64_t>(t.pcd->width ? t.pcd->width : t.points));
    j->member("height", static_cast<uint64_t>(t.pcd->width ? t.pcd->height : 1));
    pcd_fields_json(j, t.pcd->fields);
  } else if (t.ply) {
    j->member("encoding", t.ply->encoding);
    j->member_strings("frame_files", t.ply->frame_names);
    pcd_fields_json(j, t.ply->fields);
  } else if (t.bin) {
    j->member_strings("frame_files", t.bin->frame_names);
    pcd_fields_json(j, bin_fields(t));
  }
  j->end_object();
}

// info --json: points and frames, with a ragged take's points per frame, and the rate.
void json_counts(Json* j, const capz::Take& t, const Summary& s) {
  j->member("points", static_cast<uint64_t>(t.points));
  j->member("ragged", t.ragged());
  j->member("total_points", static_cast<uint64_t>(t.total_points()));
  if (t.ragged()) {
    j->key("points_per_frame");
    j->begin_object();
    j->member("min", static_cast<uint64_t>(s.min_points));
    j->member("median", static_cast<uint64_t>(s.median_points));
    j->member("max", static_cast<uint64_t>(s.max_points));
    j->end_object();
  }
  j->member("frames", static_cast<uint64_t>(t.frames));
  j->member("first_frame", t.first_frame);
  j->key("rate");
  if (t.rate > 0)
    j->value(t.rate);
  else
    j->null();
  j->key("duration_s");
  if (t.rate > 0)
    j->value(s.duration);
  else
    j->null();
}

// info --json: the units, the samples and their gaps, the labels.
void json_samples(Json* j, const capz::Take& t, const Summary& s) {
  j->member("units", t.units);
  j->member("units_assumed", t.units_assumed);
  j->member("samples", static_cast<uint64_t>(s.samples));
  j->member("gap_samples", static_cast<uint64_t>(s.gaps));
  j->member("gap_share",
            s.samples ? static_cast<double>(s.gaps) / static_cast<double>(s.samples) : 0.0);
  j->member("points_with_gaps", static_cast<uint64_t>(s.points_with_gaps));
  j->member_strings("labels", t.labels);
}

// info --json: the analog channels and the rotation segments.
void json_channels(Json* j, const capz::Take& t) {
  j->key("analog");
  j->begin_object();
  j->member("channels", t.analog.channels);
  j->member("rate", t.analog.rate);
  j->member("samples_per_frame", t.analog.samples_per_frame);
  j->member_strings("labels", t.analog.labels);
  j->end_object();
  j->key("rotations");
  j->begin_object();
  j->member("segments", t.rotations.segments);
  j->member("samples", static_cast<uint64_t>(t.rotations.samples(t.frames)));
  j->member("rate", t.rotations.rate);
  j->member("samples_per_frame", t.rotations.samples_per_frame);
  j->member_strings("labels", t.rotations.labels);
  j->end_object();
}

void print_json(const std::string& path, const capz::Take& t, const Summary& s) {
  Json j;
  j.begin_object();
  j.member("file", path);
  j.member("bytes", static_cast<uint64_t>(path_size(path)));
  j.member("format", capz::format_name(t.format));
  json_variant(&j, t);
  json_counts(&j, t, s);
  json_samples(&j, t, s);
  json_channels(&j, t);
  if (t.c3d) events_json(&j, capz::c3d_events(*t.c3d));
  j.member_strings("warnings", t.warnings);
  j.end_object();
  std::printf("%s\n", j.str().c_str());
}

}  // namespace

int cmd_info(const Args& args) {
  po::options_description opts("info options");
  opts.add_options()("json", "print one JSON object instead of text (all labels included)")(
      "parameters",
      "print the C3D parameter section and header events instead (of a .c3d, or of the C3D "
      "a .capz holds; the first 8 values of each, all with -v or --json)");
  add_bin_fields_option(&opts);
  po::variables_map vm;
  std::string path;
  if (!parse_single_input(
          args, "capz info FILE [--json] [--parameters] [-v]",
          "Describes FILE (a .c3d, a .trc, a .pcd / .ply / .bin frame or a folder of them):\n"
          "format and variant, points (a ragged take: in all and per frame), frames, rate,\n"
          "duration, units, gaps, fields, labels (the first 8; all with -v),\n"
          "analog channels and every inconsistency the reader found.",
          opts, "FILE", &vm, &path))
    return 0;

  if (vm.count("parameters"))
    return info_parameters(path, vm.count("json") > 0, looks_like_capz(path));
  if (looks_like_capz(path)) return info_capz(path, vm.count("json") > 0);

  std::unique_ptr<capz::FrameSource> src = capz::open_frames(path, read_options(vm));
  const Summary s = summarise(*src);
  capz::Take& t = src->edit_header();
  for (const std::string& w : src->frame_warnings()) t.warnings.push_back(w);
  if (vm.count("json"))
    print_json(path, t, s);
  else
    print_text(path, t, s);
  return 0;
}

}  // namespace capz_cli

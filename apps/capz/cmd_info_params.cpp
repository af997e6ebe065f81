// capz info FILE --parameters: the C3D parameter section and header events of a .c3d, or of the
// C3D a .capz archive holds (read from its META, no window decoded); a TRC's header lines.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "capz/error.h"
#include "capz/stream.h"
#include "cli_util.h"
#include "commands.h"
#include "compress_common.h"

namespace capz_cli {

namespace {

const size_t kValuesShown = 8;  // elements listed without -v

// A char parameter's strings (trailing blanks and NULs removed): one for at most one dimension,
// else dims[0] characters each.
std::vector<std::string> char_values(const capz::C3DParameter& p) {
  return p.dims.size() <= 1 ? std::vector<std::string>{p.as_string()} : p.as_strings();
}

// A numeric parameter's elements in file order (byte unsigned, int16, float).
std::vector<double> numbers(const capz::C3DParameter& p) {
  std::vector<double> v;
  if (p.type == 4)
    for (float f : p.as_floats()) v.push_back(std::isfinite(f) ? shortest_float32(f) : f);
  else
    for (int i : p.as_ints()) v.push_back(static_cast<double>(i));
  return v;
}

std::string dims_text(const std::vector<int>& dims) {
  std::string s;
  for (size_t i = 0; i < dims.size(); ++i) s += (i ? "x" : "[") + std::to_string(dims[i]);
  return dims.empty() ? s : s + "]";
}

// The groups by name, in the order names first appear: a file may hold one name twice (some
// Vicon files write PROCESSING twice), and the parameters of both are listed under it.
struct NamedGroup {
  std::string name, description;
  std::vector<const capz::C3DParameter*> params;
};
std::vector<NamedGroup> named_groups(const capz::C3DExtra& c) {
  std::vector<NamedGroup> out;
  for (const capz::C3DGroup& g : c.groups) {
    const std::string name = g.key();
    auto it =
        std::find_if(out.begin(), out.end(), [&](const NamedGroup& n) { return n.name == name; });
    if (it == out.end()) it = out.insert(out.end(), NamedGroup{name, g.description, {}});
    if (it->description.empty()) it->description = g.description;
    for (const capz::C3DParameter& p : g.params) it->params.push_back(&p);
  }
  return out;
}

void print_text(const capz::C3DExtra& c) {
  const bool all = g_verbosity >= 2;
  for (const NamedGroup& g : named_groups(c)) {
    std::printf("%s%s\n", printable(g.name).c_str(),
                g.description.empty() ? "" : ("  (" + printable(g.description) + ")").c_str());
    for (const capz::C3DParameter* pp : g.params) {
      const capz::C3DParameter& p = *pp;
      std::string v;
      size_t count = 0;
      if (p.type == -1) {
        const std::vector<std::string> s = char_values(p);
        count = s.size();
        for (size_t i = 0; i < s.size() && (all || i < kValuesShown); ++i)
          v += (i ? ", \"" : "\"") + printable(s[i]) + "\"";
      } else {
        const std::vector<double> n = numbers(p);
        count = n.size();
        for (size_t i = 0; i < n.size() && (all || i < kValuesShown); ++i)
          v += (i ? " " : "") + number(n[i]);
      }
      if (!all && count > kValuesShown)
        v += " ... (" + std::to_string(count - kValuesShown) + " more; -v lists all)";
      std::printf("  %s:%s %s%s = %s\n", printable(g.name).c_str(), printable(p.name).c_str(),
                  p.type_name(), dims_text(p.dims).c_str(), v.c_str());
    }
  }
  for (const capz::C3DHeaderEvent& e : c.header_events)
    std::printf("header event: %s at %s s%s\n", printable(e.label).c_str(),
                number(static_cast<double>(e.time)).c_str(), e.display ? "" : " (hidden)");
}

void print_json(const std::string& path, const capz::C3DExtra& c) {
  Json j;
  j.begin_object();
  j.member("file", path);
  j.key("parameters");
  j.begin_object();
  for (const NamedGroup& g : named_groups(c)) {
    j.key(g.name);
    j.begin_object();
    for (const capz::C3DParameter* pp : g.params) {
      const capz::C3DParameter& p = *pp;
      j.key(p.name);
      j.begin_object();
      j.member("type", p.type_name());
      j.key("dims");
      j.begin_array();
      for (int d : p.dims) j.value(d);
      j.end_array();
      j.key("value");
      if (p.type == -1) {
        const std::vector<std::string> s = char_values(p);
        if (p.dims.size() <= 1) {
          j.value(s[0]);
        } else {
          j.begin_array();
          for (const std::string& x : s) j.value(x);
          j.end_array();
        }
      } else {
        const std::vector<double> n = numbers(p);
        if (p.dims.empty() && n.size() == 1) {
          j.value(n[0]);
        } else {
          j.begin_array();
          for (double x : n) j.value(x);
          j.end_array();
        }
      }
      j.member("description", p.description);
      j.member("locked", p.locked);
      j.end_object();
    }
    j.end_object();
  }
  j.end_object();
  j.key("header_events");
  j.begin_array();
  for (const capz::C3DHeaderEvent& e : c.header_events) {
    j.begin_object();
    j.member("label", e.label);
    j.member("time", static_cast<double>(e.time));
    j.member("display", e.display);
    j.end_object();
  }
  j.end_array();
  j.end_object();
  std::printf("%s\n", j.str().c_str());
}

// A TRC's header lines as the take holds them: the PathFileType line's fields after its key, then
// the eight fields of lines 2 and 3; a field the file did not give (a rate of 0) is "".
std::vector<std::pair<std::string, std::string>> trc_header(const capz::Take& t) {
  const capz::TRCExtra& x = *t.trc;
  auto given = [](double v) { return v > 0 ? number(v) : std::string(); };
  std::string type = x.path_file_type_line;
  // Tab-separated, or comma-separated (pyomeca, spreadsheets: no tab, and a comma right after
  // the key or at the end of the line; docs/FORMAT.md 14.5).
  const bool comma =
      type.find('\t') == std::string::npos &&
      ((type.size() > 12 && type[12] == ',') || (!type.empty() && type.back() == ','));
  const char sep = comma ? ',' : '\t';
  const size_t at = type.find(sep);
  type = at == std::string::npos ? std::string() : type.substr(at + 1);
  type.erase(type.find_last_not_of(" \t\r,") + 1);  // writers pad the line with tabs or commas
  std::replace(type.begin(), type.end(), sep, ' ');
  return {{"PathFileType", type},
          {"DataRate", given(t.rate)},
          {"CameraRate", given(x.camera_rate)},
          {"NumFrames", std::to_string(t.frames)},
          {"NumMarkers", std::to_string(t.points)},
          {"Units", t.units},
          {"OrigDataRate", given(x.orig_data_rate)},
          {"OrigDataStartFrame", std::to_string(x.orig_data_start_frame)},
          {"OrigNumFrames", x.orig_num_frames > 0 ? std::to_string(x.orig_num_frames) : ""}};
}

void print_trc(const std::string& path, const capz::Take& t, bool json) {
  const auto fields = trc_header(t);
  if (!json) {
    std::printf("TRC header\n");
    for (const auto& f : fields)
      std::printf("  %-19s %s\n", f.first.c_str(),
                  f.second.empty() ? "(not given)" : printable(f.second).c_str());
    return;
  }
  Json j;
  j.begin_object();
  j.member("file", path);
  j.key("trc_header");
  j.begin_object();
  for (const auto& f : fields) {  // numbers as numbers, a field not given as null
    j.key(f.first);
    if (f.first == "PathFileType" || f.first == "Units")
      j.value(f.second);
    else if (f.second.empty())
      j.null();
    else
      j.value(std::strtod(f.second.c_str(), nullptr));
  }
  j.end_object();
  j.end_object();
  std::printf("%s\n", j.str().c_str());
}

}  // namespace

int info_parameters(const std::string& path, bool json, bool archive) {
  std::unique_ptr<capz::FrameSource> src =
      archive ? capz::open_capz_frames(path) : capz::open_frames(path);
  const capz::Take& t = src->header();
  if (!t.c3d && t.trc) {
    print_trc(path, t, json);
    return 0;
  }
  if (!t.c3d)
    capz::fail(capz::ErrorCode::kInvalidParameter, path,
               "--parameters: a PCD take has no parameter section (C3D's) or header (TRC's)");
  if (json)
    print_json(path, *t.c3d);
  else
    print_text(*t.c3d);
  return 0;
}

}  // namespace capz_cli

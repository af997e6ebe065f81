#include "interop/ezc3d_compare.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>

namespace capz_interop {

namespace {

const char* const kNames[kDiffClasses] = {"shape",     "header", "params",    "points",    "gaps",
                                          "residuals", "analog", "rotations", "capz error"};

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

std::string at(size_t f, size_t p) {
  return "frame " + std::to_string(f) + " point " + std::to_string(p);
}

void compare_header(const EzTake& a, const EzTake& b, Diffs* d) {
  for (size_t i = 0; i < a.header.size() && i < b.header.size(); ++i)
    if (!same_bits(a.header[i].second, b.header[i].second))
      d->add(kHeader, a.header[i].first + " " + std::to_string(a.header[i].second) + " -> " +
                          std::to_string(b.header[i].second));
  if (a.events != b.events) d->add(kHeader, "header events");
}

std::string param_change(const EzParam& a, const EzParam& b) {
  if (a.type != b.type) return "type " + std::to_string(a.type) + " -> " + std::to_string(b.type);
  if (a.dims != b.dims) return "dimensions";
  if (a.values != b.values) return "values";
  if (a.description != b.description) return "description";
  if (a.locked != b.locked) return "lock";
  return "";
}

// Groups and parameters are matched by name, in file order; a name may occur more than once
// (some files hold two PROCESSING groups), each occurrence is matched once.
void compare_params(const EzTake& a, const EzTake& b, Diffs* d) {
  std::multimap<std::string, const EzGroup*> groups;
  for (const EzGroup& g : b.groups) groups.emplace(g.name, &g);
  for (const EzGroup& g : a.groups) {
    auto it = groups.lower_bound(g.name);
    if (it != groups.end() && it->first != g.name) it = groups.end();
    if (it == groups.end()) {
      d->add(kParams, "group '" + g.name + "' missing");
      continue;
    }
    if (it->second->description != g.description || it->second->locked != g.locked)
      d->add(kParams, "group '" + g.name + "' description or lock");
    groups.erase(it);
  }
  for (const auto& g : groups) d->add(kParams, "group '" + g.first + "' added");
  std::multimap<std::string, const EzParam*> params;
  for (const EzParam& p : b.params) params.emplace(p.group + ":" + p.name, &p);
  for (const EzParam& p : a.params) {
    const std::string key = p.group + ":" + p.name;
    auto it = params.lower_bound(key);
    if (it != params.end() && it->first != key) it = params.end();
    if (it == params.end()) {
      d->add(kParams, key + " missing");
      continue;
    }
    const std::string change = param_change(p, *it->second);
    if (!change.empty()) d->add(kParams, key + " " + change);
    params.erase(it);
  }
  for (const auto& p : params) d->add(kParams, p.first + " added");
}

// "(x, y, z; r residual)" of sample i.
std::string xyzr(const EzTake& t, size_t i) {
  char s[96];
  std::snprintf(s, sizeof s, "(%g, %g, %g; r %g)", t.xyz[3 * i], t.xyz[3 * i + 1], t.xyz[3 * i + 2],
                t.residual[i]);
  return s;
}

// One float32 step at x's magnitude: the room the writer's float rounding takes.
double float_step(double x) {
  const float f = static_cast<float>(std::fabs(x));
  return std::isfinite(f) ? double(std::nextafter(f, INFINITY)) - double(f) : 0.0;
}

void compare_points(const EzTake& a, const EzTake& b, double bound, Diffs* d) {
  const size_t n = a.frames * a.points;
  for (size_t i = 0; i < n; ++i) {
    const size_t f = i / a.points, p = i % a.points;
    const bool gap_a = a.residual[i] < 0, gap_b = b.residual[i] < 0;
    if (gap_a != gap_b) {
      const EzTake& v = gap_a ? b : a;  // the read where it is valid
      d->add(kGaps, at(f, p) + (gap_a ? " gap -> valid " : " valid ") + xyzr(v, i) +
                        (gap_a ? "" : " -> gap"));
      continue;
    }
    if (gap_a) continue;
    if (!same_bits(a.residual[i], b.residual[i]) || a.camera[i] != b.camera[i])
      d->add(kResiduals, at(f, p) + " residual " + std::to_string(a.residual[i]) + " -> " +
                             std::to_string(b.residual[i]));
    for (int k = 0; k < 3; ++k) {
      const double x = a.xyz[3 * i + k], y = b.xyz[3 * i + k];
      if (bound == 0
              ? same_bits(x, y)
              : std::fabs(x - y) <= bound + float_step(x) || (std::isnan(x) && std::isnan(y))) {
        if (!std::isnan(x)) d->max_point_error = std::max(d->max_point_error, std::fabs(x - y));
        continue;
      }
      d->max_point_error = std::isnan(x - y) ? NAN : std::max(d->max_point_error, std::fabs(x - y));
      d->add(kPoints, at(f, p) + " " + std::to_string(x) + " -> " + std::to_string(y));
    }
  }
}

}  // namespace

const char* diff_name(int bit) {
  return bit >= 0 && bit < kDiffClasses ? kNames[bit] : "?";
}

std::string diff_names(unsigned set) {
  std::string s;
  for (int k = 0; k < kDiffClasses; ++k)
    if (set & (1u << k)) s += (s.empty() ? "" : "+") + std::string(kNames[k]);
  return s.empty() ? "none" : s;
}

void Diffs::add(DiffClass c, const std::string& what) {
  int k = 0;
  while ((1u << k) != c) ++k;
  found |= c;
  if (count[k]++ < 3) examples[k] += (examples[k].empty() ? "" : ", ") + what;
}

std::string Diffs::describe() const {
  std::string s;
  for (int k = 0; k < kDiffClasses; ++k)
    if (count[k])
      s += std::string(s.empty() ? "" : "; ") + kNames[k] + ": " + std::to_string(count[k]) + " (" +
           examples[k] + (count[k] > 3 ? ", ..." : "") + ")";
  return s;
}

Diffs compare(const EzTake& want, const EzTake& got, double bound) {
  Diffs d;
  compare_header(want, got, &d);
  compare_params(want, got, &d);
  if (want.frames != got.frames || want.points != got.points || want.channels != got.channels ||
      want.subframes != got.subframes) {
    d.add(kShape, std::to_string(want.frames) + "x" + std::to_string(want.points) + " points, " +
                      std::to_string(want.channels) + "x" + std::to_string(want.subframes) +
                      " analog -> " + std::to_string(got.frames) + "x" +
                      std::to_string(got.points) + ", " + std::to_string(got.channels) + "x" +
                      std::to_string(got.subframes));
    return d;
  }
  compare_points(want, got, bound, &d);
  for (size_t i = 0; i < want.analog.size(); ++i)
    if (!same_bits(want.analog[i], got.analog[i]))
      d.add(kAnalog, "value " + std::to_string(i) + " " + std::to_string(want.analog[i]) + " -> " +
                         std::to_string(got.analog[i]));
  if (want.rotations.size() != got.rotations.size())
    d.add(kRotations, std::to_string(want.rotations.size() / 17) + " matrices -> " +
                          std::to_string(got.rotations.size() / 17));
  else
    for (size_t i = 0; i < want.rotations.size(); ++i)
      if (!same_bits(want.rotations[i], got.rotations[i]))
        d.add(kRotations, "value " + std::to_string(i));
  return d;
}

}  // namespace capz_interop

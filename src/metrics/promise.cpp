// The rule for "the stream keeps its promise" (include/capz/verify.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "capz/tool/verify.h"
#include "coding/c3d_params.h"
#include "coding/quantiser.h"
#include "metrics/point_match.h"

namespace capz {

namespace {

// Equal values, or both NaN (a NaN's payload bits are not part of what a take promises).
bool same_value(double a, double b) {
  return a == b || (std::isnan(a) && std::isnan(b));
}
bool same_values(const double* a, const double* b, size_t n) {
  for (size_t i = 0; i < n; ++i)
    if (!same_value(a[i], b[i])) return false;
  return true;
}

std::string text(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

// The C3D extras of the header a .capz keeps: "" when `a` and `b` agree, else what differs.
std::string c3d_difference(const C3DExtra& a, const C3DExtra& b) {
  if (encode_c3d_parameters(a) != encode_c3d_parameters(b))
    return "the C3D parameter section differs";
  if (a.max_interpolation_gap != b.max_interpolation_gap || a.processor != b.processor ||
      a.float_storage != b.float_storage || a.point_scale != b.point_scale ||
      a.header_events_label_range != b.header_events_label_range)
    return "the C3D header fields differ";
  if (a.header_events.size() != b.header_events.size()) return "the C3D header events differ";
  for (size_t i = 0; i < a.header_events.size(); ++i) {
    const C3DHeaderEvent &x = a.header_events[i], &y = b.header_events[i];
    if (x.time != y.time || x.display != y.display || x.label != y.label)
      return "C3D header event " + std::to_string(i) + " differs";
  }
  return "";
}

// The format extras (C3D, TRC, PCD) of the header: "" when they agree.
std::string extras_difference(const Take& a, const Take& b) {
  if (a.c3d) {
    if (!b.c3d) return "the C3D extras are missing";
    std::string d = c3d_difference(*a.c3d, *b.c3d);
    if (!d.empty()) return d;
  }
  if (a.trc) {
    if (!b.trc) return "the TRC extras are missing";
    if (a.trc->times.size() != b.trc->times.size() ||
        !same_values(a.trc->times.data(), b.trc->times.data(), a.trc->times.size()) ||
        a.trc->frame_numbers != b.trc->frame_numbers)
      return "the TRC time or frame columns differ";
  }
  if (a.pcd) {
    if (!b.pcd) return "the PCD extras are missing";
    if (a.pcd->frame_names != b.pcd->frame_names) return "the PCD frame names differ";
  }
  if (a.ply && (!b.ply || a.ply->frame_names != b.ply->frame_names))
    return "the PLY frame names differ";
  if (a.bin && (!b.bin || a.bin->frame_names != b.bin->frame_names))
    return "the .bin frame names differ";
  return "";
}

// FORMAT.md "Points reordered": each decoded point's partner among the original's
// (metrics/point_match.h), or false with the breach in *why.
bool pair_reordered(const PointsView& original, const PointsView& decoded, const Promise& p,
                    std::vector<size_t>* partner, std::string* why) {
  std::vector<bool> exact;
  for (size_t i = 0; i < original.fields.size(); ++i)
    exact.push_back(i >= p.attribute_bounds.size() || p.attribute_bounds[i] <= 0);
  const double bound = p.kind == Promise::Kind::kBound ? p.max_error : 0;
  return match_reordered(original, decoded, bound, exact, partner, why);
}

std::string header_difference(const Take& a, const Take& b) {
  if (!same_frame_counts(a, b)) {
    if (a.ragged() || b.ragged())
      return a.frames != b.frames ? "decodes to " + std::to_string(b.frames) +
                                        " frames instead of " + std::to_string(a.frames)
                                  : "the frames' point counts differ";
    return "decodes to " + std::to_string(b.frames) + " frames x " + std::to_string(b.points) +
           " points instead of " + std::to_string(a.frames) + " x " + std::to_string(a.points);
  }
  // Units a reader assumed (PCD, PLY, .bin: metres) are not stored: they match none.
  const bool same_units = a.units == b.units || (a.units_assumed && b.units.empty()) ||
                          (b.units_assumed && a.units.empty());
  if (!same_value(a.rate, b.rate) || !same_units || a.first_frame != b.first_frame)
    return "the rate, units or first frame differ";
  if (a.labels != b.labels || a.descriptions != b.descriptions)
    return "the point labels or descriptions differ";
  const Analog &p = a.analog, &q = b.analog;
  if (p.channels != q.channels || p.samples_per_frame != q.samples_per_frame ||
      !same_value(p.rate, q.rate) || p.labels != q.labels)
    return "the analog channel layout differs";
  const Rotations &r = a.rotations, &o = b.rotations;
  if (r.segments != o.segments || r.per_frame() != o.per_frame() || !same_value(r.rate, o.rate) ||
      r.labels != o.labels)
    return "the rotation layout, rate or labels differ";
  return extras_difference(a, b);
}

}  // namespace

// The per-frame arrays of frames [first, first + frames): a block, or a whole take.
struct PromiseCheck::Frames {
  size_t first = 0, frames = 0, points = 0;
  const std::vector<size_t>* offsets = nullptr;  // a ragged block or take: its frame offsets
  const double* xyz = nullptr;
  const uint8_t* valid = nullptr;
  const std::vector<float>* residual = nullptr;  // null: none
  const std::vector<uint8_t>* camera_mask = nullptr;
  const double* analog = nullptr;
  size_t analog_values = 0;
  const std::vector<float>* rotation_matrices = nullptr;
  const std::vector<float>* rotation_reliability = nullptr;
  std::vector<const std::vector<uint8_t>*> attributes;  // per point field, its bytes

  explicit Frames(const FrameBlock& b)
      : first(b.first),
        frames(b.frames),
        points(b.points),
        offsets(b.ragged() ? &b.frame_offsets : nullptr),
        xyz(b.xyz.data()),
        valid(b.valid.data()),
        residual(&b.residual),
        camera_mask(&b.camera_mask),
        analog(b.analog.data()),
        analog_values(b.analog.size()),
        rotation_matrices(&b.rotation_matrices),
        rotation_reliability(&b.rotation_reliability) {
    for (const auto& a : b.attributes) attributes.push_back(&a);
  }
  explicit Frames(const Take& t)
      : frames(t.frames),
        points(t.points),
        offsets(t.ragged() ? &t.frame_offsets : nullptr),
        xyz(t.xyz.data()),
        valid(t.valid.data()),
        analog(t.analog.values.data()),
        analog_values(t.analog.values.size()),
        rotation_matrices(&t.rotations.matrices),
        rotation_reliability(&t.rotations.reliability) {
    if (t.c3d) residual = &t.c3d->residual, camera_mask = &t.c3d->camera_mask;
    for (const auto& a : t.attributes) attributes.push_back(&a.data);
  }
  // These frames with the original's points at their partners' places in `decoded`
  // (pair_reordered), taken from *m, and decoded's shape: the original as the decoder ordered it.
  struct Moved {
    std::vector<double> xyz;
    std::vector<uint8_t> valid;
    std::vector<std::vector<uint8_t>> fields;
  };
  void move_to(const PointsView& original, const std::vector<size_t>& partner,
               const Frames& decoded, Moved* m) {
    move_to_partners(original, partner, &m->xyz, &m->valid, &m->fields);
    points = decoded.points;
    offsets = decoded.offsets;
    xyz = m->xyz.data();
    valid = m->valid.data();
    for (size_t a = 0; a < attributes.size() && a < m->fields.size(); ++a)
      attributes[a] = &m->fields[a];
  }
  size_t total() const { return offsets ? offsets->back() : frames * points; }
  bool same_shape(const Frames& o) const {
    if (frames != o.frames || points != o.points || (offsets == nullptr) != (o.offsets == nullptr))
      return false;
    return !offsets || *offsets == *o.offsets;
  }
  // "frame F, point P" of sample i.
  std::string where(size_t i) const {
    size_t f = 0, p = i;
    if (offsets) {
      f = static_cast<size_t>(std::upper_bound(offsets->begin(), offsets->end(), i) -
                              offsets->begin()) -
          1;
      p = i - (*offsets)[f];
    } else if (points > 0) {
      f = i / points, p = i % points;
    }
    return "frame " + std::to_string(first + f) + ", point " + std::to_string(p);
  }
  // The point fields of both agree byte for byte, or, for a field with a bound (Promise), its
  // float values within the bound and its non-finite values bit for bit.
  bool same_attributes(const Frames& o, const Promise& p) const {
    if (attributes.size() != o.attributes.size()) return false;
    for (size_t i = 0; i < attributes.size(); ++i) {
      const std::vector<uint8_t>& a = *attributes[i];
      const std::vector<uint8_t>& b = *o.attributes[i];
      const double bound = i < p.attribute_bounds.size() ? p.attribute_bounds[i] : 0;
      const size_t fs =
          i < p.attribute_float_size.size() ? static_cast<size_t>(p.attribute_float_size[i]) : 0;
      if (bound <= 0 || (fs != 4 && fs != 8) || a.size() != b.size()) {
        if (a != b) return false;
        continue;
      }
      for (size_t k = 0; k + fs <= a.size(); k += fs) {
        double x, y;
        if (fs == 4) {
          float fx, fy;
          std::memcpy(&fx, &a[k], 4);
          std::memcpy(&fy, &b[k], 4);
          x = fx, y = fy;
        } else {
          std::memcpy(&x, &a[k], 8);
          std::memcpy(&y, &b[k], 8);
        }
        if (!std::isfinite(x) || !std::isfinite(y)) {
          if (std::memcmp(&a[k], &b[k], fs) != 0) return false;
        } else if (!(std::fabs(x - y) <= bound)) {
          return false;
        }
      }
    }
    return true;
  }
  // The C3D 4th words of both takes agree (absent counts as empty).
  bool same_words(const Frames& o) const {
    static const std::vector<float> no_residual;
    static const std::vector<uint8_t> no_mask;
    return (residual ? *residual : no_residual) == (o.residual ? *o.residual : no_residual) &&
           (camera_mask ? *camera_mask : no_mask) == (o.camera_mask ? *o.camera_mask : no_mask);
  }
  // The rotation samples of both agree bit for bit (NaN payloads and -0.0 included).
  bool same_rotations(const Frames& o) const {
    return same_float_bits(*rotation_matrices, *o.rotation_matrices) &&
           same_float_bits(*rotation_reliability, *o.rotation_reliability);
  }
  static bool same_float_bits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() &&
           (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
  }
};

Promise promise_of(const StreamInfo& info) {
  Promise p;
  if (info.lossless) {
    p.kind = Promise::Kind::kLossless;
  } else if (info.transform_output) {
    p.kind = Promise::Kind::kKgTarget;
    p.kg_target = info.kg_target;
  } else {
    p.kind = Promise::Kind::kBound;
    p.max_error = info.max_error;
  }
  p.points_reordered = info.points_reordered;
  p.analog_bounds = info.analog_bounds;
  p.analog_factors = info.analog_factors;
  for (size_t i = 0; i < info.pcd_fields.size(); ++i) {
    const PCDField& f = info.pcd_fields[i];
    if (f.name == "x" || f.name == "y" || f.name == "z") continue;
    const double b = i < info.pcd_field_bounds.size() ? info.pcd_field_bounds[i] : 0;
    p.attribute_bounds.push_back(b);
    p.attribute_float_size.push_back(f.type == 'F' ? f.size : 0);
  }
  return p;
}

bool PromiseCheck::breach(const std::string& what) {
  if (why_.empty()) why_ = what;
  return false;
}

bool PromiseCheck::header(const Take& original, const Take& decoded) {
  const std::string what = header_difference(original, decoded);
  return what.empty() ? holds() : breach(what);
}

// Every valid sample of the original (a): its coordinates as the promise says. One loop per
// kind (fixed at compile time) with one branch per sample (its three tests combined).
bool PromiseCheck::positions(const Frames& a, const Frames& b) {
  using K = Promise::Kind;
  const K kind = promise_.kind;
  const double bound = promise_.max_error;
  const size_t n = a.total();
  size_t bad = n, axis = 0;  // the first sample that breaks the promise, and its coordinate
  auto find = [&](auto kind_c) {
    constexpr K k = decltype(kind_c)::value;
    auto ok = [bound](double x, double y) {
      return k == K::kKgTarget   ? std::isfinite(y)
             : k == K::kLossless ? same_bits(x, y)
                                 : std::fabs(x - y) <= bound;
    };
    for (size_t i = 0; i < n; ++i) {
      if (!a.valid[i]) continue;
      const double *x = a.xyz + i * 3, *y = b.xyz + i * 3;
      if (ok(x[0], y[0]) && ok(x[1], y[1]) && ok(x[2], y[2])) continue;
      bad = i;
      axis = ok(x[0], y[0]) ? ok(x[1], y[1]) ? 2 : 1 : 0;
      return;
    }
  };
  if (kind == K::kKgTarget)
    find(std::integral_constant<K, K::kKgTarget>());
  else if (kind == K::kLossless)
    find(std::integral_constant<K, K::kLossless>());
  else
    find(std::integral_constant<K, K::kBound>());
  if (bad == n) return true;
  const double x = a.xyz[bad * 3 + axis], y = b.xyz[bad * 3 + axis];
  return breach("coordinate " + text(x, 17) + " at " + a.where(bad) + " comes back as " +
                text(y, 17) +
                (kind == K::kLossless   ? " (lossless)"
                 : kind == K::kKgTarget ? " (not finite)"
                                        : " (bound " + text(promise_.max_error, 6) + ")"));
}

// Mask, positions, 4th words and analog values of one stretch of frames.
bool PromiseCheck::check(const Frames& a, const Frames& b) {
  if (!a.same_shape(b))
    return breach((a.offsets ? "frame or point count" : "frame count") +
                  std::string(" differs at frame ") + std::to_string(a.first));
  if (measure_) {
    if (a.offsets)
      acc_.add_ragged(a.frames, a.offsets->data(), a.xyz, b.xyz, a.valid);
    else
      acc_.add(a.frames, a.points, a.xyz, b.xyz, a.valid);
  }
  size_t n = 0, at = 0;
  for (size_t i = 0; i < a.total(); ++i)
    if ((a.valid[i] != 0) != (b.valid[i] != 0) && n++ == 0) at = i;
  mask_mismatches_ += n;
  if (n) return breach(std::to_string(n) + " samples' gap mask differs, first at " + a.where(at));
  if (!positions(a, b)) return false;
  if (!a.same_words(b)) return breach("the C3D residual/camera words differ");
  if (a.analog_values != b.analog_values) return breach("the analog values differ");
  if (!analog(a, b)) return false;
  if (!a.same_rotations(b)) return breach("the rotation samples differ");
  if (!a.same_attributes(b, promise_))
    return breach("the point fields (" + std::to_string(a.attributes.size()) + ") differ");
  return holds();
}

// The analog samples: equal, or for a lossy channel (FORMAT.md 5.7) within its bound in
// physical units, non-finite samples bit for bit.
bool PromiseCheck::analog(const Frames& a, const Frames& b) {
  const size_t C = promise_.analog_bounds.size();
  if (C == 0)
    return same_values(a.analog, b.analog, a.analog_values) ? holds()
                                                            : breach("the analog values differ");
  for (size_t i = 0; i < a.analog_values; ++i) {
    const size_t c = i % C;
    const double bound = promise_.analog_bounds[c];
    const double f = c < promise_.analog_factors.size() ? promise_.analog_factors[c] : 1.0;
    const double x = a.analog[i], y = b.analog[i];
    bool ok;
    if (bound > 0 && std::isfinite(x)) {
      const double err = std::fabs(y - x) * f;
      ok = std::isfinite(y) && err <= bound;
      if (ok) analog_bound_use_ = std::max(analog_bound_use_, err / bound);
    } else {
      ok = same_value(x, y);
    }
    if (!ok)
      return breach("analog channel " + std::to_string(c) + " sample " + text(x, 17) +
                    " comes back as " + text(y, 17) +
                    (bound > 0 ? " (bound " + text(bound, 6) + ")" : ""));
  }
  return holds();
}

bool PromiseCheck::frames(const FrameBlock& original, const FrameBlock& decoded) {
  if (!promise_.points_reordered) return check(Frames(original), Frames(decoded));
  // FORMAT.md "Points reordered": the block's frames compared as sets.
  const PointsView o = points_of(original), d = points_of(decoded);
  if (!same_counts(o, d))
    return check(Frames(original), Frames(decoded));  // the shape check names it
  std::vector<size_t> partner;
  std::string why;
  if (!pair_reordered(o, d, promise_, &partner, &why)) return breach(why);
  Frames a(original), b(decoded);  // a fixed source's frames compared as the ragged ones they are
  Frames::Moved moved;
  a.move_to(o, partner, b, &moved);
  return check(a, b);
}

bool PromiseCheck::finish() {
  if (promise_.kind != Promise::Kind::kKgTarget) return holds();
  const double kg = acc_.finish().kg_error;
  // The encoder met the target on its own measure; 1e-9 relative absorbs summation order.
  if (!(kg <= promise_.kg_target * (1 + 1e-9)))
    return breach("KG error " + text(kg, 6) + "% over its target " + text(promise_.kg_target, 6) +
                  "%");
  return holds();
}

ErrorStats PromiseCheck::error() const {
  ErrorStats s = acc_.finish();
  s.mask_mismatches = mask_mismatches_;
  return s;
}

PromiseResult check_promise(const Take& original, const Take& decoded, const Promise& promise) {
  PromiseCheck c(promise);
  PromiseResult r;
  c.header(original, decoded);
  // The frames are measured even when the metadata differs, so the caller can report both. A
  // fixed original of a ragged take's shape (same_frame_counts) is compared as that take.
  if (same_frame_counts(original, decoded)) {
    const bool whole = original.xyz.size() == original.total_points() * 3 &&
                       original.valid.size() == original.total_points() &&
                       decoded.xyz.size() == original.xyz.size() &&
                       decoded.valid.size() == original.valid.size();
    if (!whole) return {false, "the takes' frame arrays do not match their shapes", c.error()};
    PromiseCheck::Frames a(original), b(decoded);
    a.points = b.points;
    a.offsets = b.offsets;
    PromiseCheck::Frames::Moved moved;
    if (promise.points_reordered) {
      std::vector<size_t> partner;
      std::string why;
      const PointsView o = points_of(original);
      if (!pair_reordered(o, points_of(decoded), promise, &partner, &why))
        return {false, why, c.error()};
      a.move_to(o, partner, b, &moved);
    }
    c.check(a, b);
    c.finish();
  }
  r.holds = c.holds();
  r.why = c.why();
  r.error = c.error();
  r.analog_bound_use = c.analog_bound_use();
  return r;
}

}  // namespace capz

// The scan encoder's laser table, inferred from the points (docs/FORMAT.md "Scans (format
// 1.1)"): rings, then per ring the cone (slope, z offset) and azimuth offset, and one azimuth
// step. Encoder side only: the decoder reads the table, so nothing here needs to repeat bit for
// bit on another build.
#include "coding/scan_table.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

namespace capz {
namespace scan {

namespace {

constexpr double kTwoPi = 6.283185307179586;

// Whether every integer of p is below kMaxSphericalCoord in magnitude: |v| < M, M = 2^29, is
// v + (M - 1) in [0, 2 (M - 1)], as an unsigned sum (a negative one wraps above), without a
// branch per integer (this test runs several times a point in the fits).
bool small_enough(const int32_t* p) {
  constexpr uint32_t kBias = static_cast<uint32_t>(kMaxSphericalCoord) - 1;
  const uint32_t a = static_cast<uint32_t>(p[0]) + kBias, b = static_cast<uint32_t>(p[1]) + kBias,
                 c = static_cast<uint32_t>(p[2]) + kBias;
  return std::max(a, std::max(b, c)) <= 2 * kBias;
}

double wrap_pi(double d) {
  while (d > kTwoPi / 2) d -= kTwoPi;
  while (d <= -kTwoPi / 2) d += kTwoPi;
  return d;
}

// atan(k / 8) for k = 0 .. 8: the centres of quick_atan2's series.
struct AtanEighths {
  double v[9];
  AtanEighths() {
    for (int k = 0; k <= 8; ++k) v[k] = std::atan(k / 8.0);
  }
};

// std::atan2(y, x) for finite x y (the same signs and quadrants), within a few units in the last
// place, at about half its instructions (atan2 was 0.3 G of the 20-sweep pandar64 folder's
// encode, an azimuth a point): |y / x| or its inverse, t in [0, 1], is taken to the nearest
// c = k / 8, and atan t = atan c + atan u with u = (t - c) / (1 + t c), |u| < 1/16, whose odd
// series to u^15 is exact to about 2^-64.
double quick_atan2(double y, double x) {
  static const AtanEighths kAtan;
  const double ax = std::fabs(x), ay = std::fabs(y);
  if (!(ax > 0 || ay > 0)) return std::atan2(y, x);
  const bool steep = ay > ax;
  const double t = steep ? ax / ay : ay / ax;
  const int k = static_cast<int>(t * 8 + 0.5);
  const double c = k / 8.0, u = (t - c) / (1 + t * c), u2 = u * u;
  const double series =
      u * (1 + u2 * (-1.0 / 3 +
                     u2 * (1.0 / 5 +
                           u2 * (-1.0 / 7 +
                                 u2 * (1.0 / 9 + u2 * (-1.0 / 11 + u2 * (1.0 / 13 - u2 / 15)))))));
  double a = kAtan.v[k] + series;
  if (steep) a = kTwoPi / 4 - a;
  if (std::signbit(x)) a = kTwoPi / 2 - a;
  return std::signbit(y) ? -a : a;
}

// Point i's azimuth: from the source's coordinates when the hints have them (on a coarse grid a
// near point's azimuth is uncertain by more than the sensor's step), else from the integers.
double azimuth(const ScanGeometry& g, const ScanHints& h, size_t i) {
  if (h.xyz.size() == 3 * g.total()) {
    const double x = h.xyz[3 * i], y = h.xyz[3 * i + 1];
    if (std::isfinite(x) && std::isfinite(y)) return quick_atan2(y, x);
  }
  return quick_atan2(double(g.q[3 * i + 1]), double(g.q[3 * i]));
}

// Point i's x y z: the source's coordinates when the hints have them (finite), else the integers.
void coords(const ScanGeometry& g, const std::vector<float>& xyz, size_t i, double* v) {
  const int32_t* p = &g.q[3 * i];
  for (int a = 0; a < 3; ++a) v[a] = double(p[a]);
  if (xyz.size() != 3 * g.total()) return;
  const double f[3] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
  if (std::isfinite(f[0]) && std::isfinite(f[1]) && std::isfinite(f[2]))
    for (int a = 0; a < 3; ++a) v[a] = f[a];
}

// The cone slope of a point with coordinates v under the bow w (FORMAT.md "Scan geometry
// payload": a ring's slope at azimuth phi is s + w (1 - cos phi)): z / rho - w (1 - cos phi).
// NaN when rho is 0.
double bowed_slope(const double* v, double w) {
  const double r = planar_length(v[0], v[1]);
  if (!(r > 0)) return NAN;
  return v[2] / r - w * (1 - v[0] / r);
}

// How the slopes of points gather under the bow w: the sum of the squared counts of their bins
// of 0.0002. `pts` holds per point z / rho and 1 - cos phi; *bins all 0, left so (*touched:
// scratch). The sum grows by 2 c + 1 as a bin's count c grows by one: integers below 2^53, so the
// same double as summing c^2 over the bins, without a pass over all of them (find_bow calls this
// 43 times a window).
double gathering(const std::vector<double>& pts, double w, std::vector<uint32_t>* bins,
                 std::vector<size_t>* touched) {
  const double n = double(bins->size());
  uint64_t sum = 0;
  touched->clear();
  for (size_t i = 0; i + 1 < pts.size(); i += 2) {
    const double b = std::floor((pts[i] - w * pts[i + 1] + 1.6) / 0.0002);
    if (!(b >= 0 && b < n)) continue;
    uint32_t& c = (*bins)[size_t(b)];
    if (c == 0) touched->push_back(size_t(b));
    sum += 2 * uint64_t{c++} + 1;
  }
  for (size_t b : *touched) (*bins)[b] = 0;
  return double(sum);
}

// The cones' bow (FORMAT.md, informative): the w of -0.016 .. 0.016 in steps of 0.001, then
// within 0.001 of the best in steps of 0.00025, whose slopes of up to 4096 points gather most,
// kept when they gather at least 1.1 times as much as without a bow; else 0.
float find_bow(const ScanGeometry& g, const ScanHints& h) {
  const size_t n = g.total();
  const size_t stride = std::max<size_t>(1, n / 4096);
  std::vector<double> pts;
  for (size_t i = 0; i < n; i += stride) {
    if (!g.valid[i] || !small_enough(&g.q[3 * i])) continue;
    double v[3];
    coords(g, h.xyz, i, v);
    const double r = planar_length(v[0], v[1]);
    if (!(r > 0)) continue;
    pts.push_back(v[2] / r);
    pts.push_back(1 - v[0] / r);
  }
  if (pts.size() < 2 * 64) return 0;
  std::vector<uint32_t> bins(16000);
  std::vector<size_t> touched;
  const double flat = gathering(pts, 0, &bins, &touched);
  double best = 0, most = flat;
  for (int j = -16; j <= 16; ++j) {
    const double v = gathering(pts, 0.001 * j, &bins, &touched);
    if (v > most) most = v, best = 0.001 * j;
  }
  const double coarse = best;
  for (int j = -4; j <= 4; ++j) {
    const double w = coarse + 0.00025 * j;
    const double v = gathering(pts, w, &bins, &touched);
    if (v > most) most = v, best = w;
  }
  return most >= 1.1 * flat ? static_cast<float>(best) : 0.0f;
}

// Dense ring numbers 0..K-1 from the hint's values (sorted); K = 0 when there is no usable hint.
size_t dense_rings(const ScanGeometry& g, const ScanHints& h, std::vector<uint32_t>* ring) {
  ring->assign(g.total(), 0);
  if (h.ring.size() != g.total()) return 0;
  // The values seen, flagged in a table when they are small (ring fields are: laser numbers),
  // else collected in a map; then numbered in order.
  constexpr uint32_t kSmall = 1u << 16;
  std::vector<uint32_t> small;  // value -> 1 + its number (0: not seen)
  std::map<uint32_t, uint32_t> ids;
  for (size_t i = 0; i < g.total(); ++i) {
    if (!g.valid[i]) continue;
    const uint32_t v = h.ring[i];
    if (v < kSmall) {
      if (small.size() <= v) small.resize(std::max<size_t>(v + 1, 2 * small.size()), 0);
      small[v] = 1;
    } else {
      ids.emplace(v, 0);
    }
  }
  uint32_t n = 0;
  for (uint32_t& s : small)
    if (s) s = ++n;
  if (n + ids.size() == 0 || n + ids.size() > kMaxRings) return 0;
  for (auto& kv : ids) kv.second = n++;
  for (size_t i = 0; i < g.total(); ++i) {
    if (!g.valid[i]) continue;
    const uint32_t v = h.ring[i];
    (*ring)[i] = v < kSmall ? small[v] - 1 : ids[v];
  }
  return n;
}

// The number of the peak (of `peaks`, ascending) nearest elevation e.
uint32_t nearest_peak(const std::vector<double>& peaks, double e) {
  const auto it = std::lower_bound(peaks.begin(), peaks.end(), e);
  size_t k = size_t(it - peaks.begin());
  if (k == peaks.size() || (k > 0 && e - peaks[k - 1] < *it - e)) --k;
  return uint32_t(k);
}

// Rings from the points' elevations, for a source without a ring field: the peaks of the
// elevation histogram of all points (their elevations under the bow w: atan of bowed_slope),
// each point then given to the nearest peak. 0 when there are no points. (The farther half or
// quarter alone, where a laser's z offset moves the elevation least, found fewer rings:
// docs/lab/2026-11-28-scan-geometry.md.)
size_t elevation_rings(const ScanGeometry& g, const std::vector<float>& xyz, double w,
                       std::vector<uint32_t>* ring, std::vector<double>* found_peaks) {
  constexpr double kBin = 0.0002;  // radians (about 0.011 degrees)
  constexpr int kBins = static_cast<int>(3.2 / kBin);
  std::vector<double> el;
  std::vector<size_t> idx;
  el.reserve(g.total());
  idx.reserve(g.total());
  for (size_t i = 0; i < g.total(); ++i) {
    if (!g.valid[i] || !small_enough(&g.q[3 * i])) continue;
    double v[3];
    coords(g, xyz, i, v);
    const double t = bowed_slope(v, w);
    if (!std::isfinite(t)) continue;
    el.push_back(std::atan(t));
    idx.push_back(i);
  }
  if (el.empty()) return 0;
  std::vector<double> h(kBins, 0.0);
  auto bin = [&](double e) { return std::min(kBins - 1, std::max(0, int((e + 1.6) / kBin))); };
  for (double e : el) h[size_t(bin(e))] += 1;
  // Smoothed over 3 bins; a peak is the largest within 3 bins either side, at least 0.0008 of
  // the counted points and 8 (32 lost a third of the lasers of a 10198-point AT128 sweep).
  std::vector<double> s(kBins, 0.0);
  for (int b = 1; b + 1 < kBins; ++b)
    s[size_t(b)] = h[size_t(b - 1)] + 2 * h[size_t(b)] + h[size_t(b + 1)];
  double counted = 0;
  for (double v : h) counted += v;
  std::vector<double> peaks;
  for (int b = 3; b + 3 < kBins; ++b) {
    const double v = s[size_t(b)];
    if (v < 4 * 0.0002 * counted || v < 8) continue;
    bool top = true;
    for (int o = -3; o <= 3 && top; ++o)
      if (o != 0 && (s[size_t(b + o)] > v || (o < 0 && s[size_t(b + o)] == v))) top = false;
    if (top) peaks.push_back((b + 0.5) * kBin - 1.6);
  }
  if (peaks.empty() || peaks.size() > kMaxRings) return 0;
  ring->assign(g.total(), 0);
  for (size_t j = 0; j < el.size(); ++j) (*ring)[idx[j]] = nearest_peak(peaks, el[j]);
  if (found_peaks) *found_peaks = peaks;
  return peaks.size();
}

// The sums of a least squares fit z = z0 + slope * rho, over one ring's points in order.
struct ConeSums {
  double n = 0, sr = 0, sz = 0, srr = 0, srz = 0;
  void add(double rho, double z) { n += 1, sr += rho, sz += z, srr += rho * rho, srz += rho * z; }
};

// Least squares z = z0 + slope * rho over one ring's points.
void fit_cone(const ConeSums& c0, float* slope, float* z0) {
  const double n = c0.n, sr = c0.sr, sz = c0.sz, srr = c0.srr, srz = c0.srz;
  const double det = n * srr - sr * sr;
  double s = 0, c = n > 0 ? sz / n : 0;
  if (n >= 2 && det > 1e-9 * n * srr) {
    s = (n * srz - sr * sz) / det;
    c = (sz - s * sr) / n;
  } else if (sr > 0) {
    s = sz / sr, c = 0;
  }
  *slope = static_cast<float>(s);
  *z0 = static_cast<float>(c);
}

// The azimuth step: the median of the small azimuth changes between a ring's consecutive
// points, refined over the changes of a few steps.
double infer_step(const std::vector<std::vector<double>>& phi) {
  // The steps' sizes: one window-sized array (fewer pages touched), written in place (neither
  // zeroed first nor grown by push_back's call a step).
  size_t total = 0, neg = 0, n = 0;
  for (const auto& p : phi) total += p.size();
  const std::unique_ptr<double[]> steps(new double[total]);
  double* const a = steps.get();
  for (const auto& p : phi)
    for (size_t i = 1; i < p.size(); ++i) {
      const double e = wrap_pi(p[i] - p[i - 1]);
      if (std::fabs(e) > 1e-7 && std::fabs(e) < 0.1) a[n++] = std::fabs(e), neg += e < 0;
    }
  if (n == 0) return 0;
  std::nth_element(a, a + n / 2, a + n);
  const double s0 = a[n / 2];
  double num = 0, den = 0;
  for (size_t i = 0; i < n; ++i) {
    const double e = a[i];
    const double m = std::floor(e / s0 + 0.5);
    if (m >= 1 && m <= 8 && std::fabs(e - m * s0) < 0.25 * s0) num += e, den += m;
  }
  const double s = den > 0 ? num / den : s0;
  return 2 * neg > n ? -s : s;
}

// Whether the distances sit on whole multiples of q: nine in ten within 5 % of q of the nearest
// multiple (a median would take a step twice the sensor's, which half the points sit on).
bool on_steps(const std::vector<double>& dist, double q, std::vector<double>* scratch) {
  scratch->clear();
  for (double d : dist) {
    const double m = d / q;
    if (m >= 2147483647.0) return false;
    scratch->push_back(std::fabs(m - std::floor(m + 0.5)));
  }
  const auto p90 = scratch->begin() + static_cast<std::ptrdiff_t>(scratch->size() * 9 / 10);
  std::nth_element(scratch->begin(), p90, scratch->end());
  return *p90 < 0.05;
}

// The sensor's azimuth quantum (docs/FORMAT.md "units" bit 4, informative): 0.01 degree (the
// Velodyne and most Hesai drivers' azimuths, each ring's offset aside) when it is under half
// the step and nine in ten of up to 4096 of the rings' azimuths, less their ring's offset (the
// circular mean on the quantum), lie within 5 % of it of a multiple; else 0.
double azimuth_quantum(const RingFit& r) {
  const double q = 0.01 * kTwoPi / 360;
  size_t total = 0;
  for (const auto& p : r.phi) total += p.size();
  if (total == 0 || !(q < std::fabs(r.step) / 2)) return 0;
  const size_t stride = std::max<size_t>(1, total / 4096);
  size_t near = 0, seen = 0;
  for (const auto& p : r.phi) {
    double sc = 0, ss = 0;
    for (size_t i = 0; i < p.size(); i += stride)
      sc += std::cos(kTwoPi * p[i] / q), ss += std::sin(kTwoPi * p[i] / q);
    const double a0 = q * std::atan2(ss, sc) / kTwoPi;
    for (size_t i = 0; i < p.size(); i += stride, ++seen) {
      const double m = (p[i] - a0) / q;
      near += std::fabs(m - std::floor(m + 0.5)) < 0.05;
    }
  }
  return near >= seen - seen / 10 ? q : 0;
}

// Point i's distance from the sensor: the source's distance field, else from the origin (NaN
// when it has neither).
double distance(const ScanHints& h, size_t n, size_t i) {
  if (h.distance.size() == n) return h.distance[i];
  if (h.xyz.size() != 3 * n) return NAN;
  const double x = h.xyz[3 * i], y = h.xyz[3 * i + 1], z = h.xyz[3 * i + 2];
  return std::sqrt(x * x + y * y + z * z);
}

// The sensor's range step (FORMAT.md "range units", informative), in the units of h.xyz: the
// largest of 1, 2, 2.5, 4, 5 x 10^e that the distances of up to 16384 points sit on, at least
// one grid unit and at most an eighth of their median; 0 when none.
double range_step(const ScanGeometry& g, const ScanHints& h) {
  const size_t n = g.total();
  if (h.grid_per_unit <= 0 || h.xyz.size() != 3 * n) return 0;
  std::vector<double> dist;
  const size_t stride = std::max<size_t>(1, n / 16384);
  for (size_t i = 0; i < n; i += stride) {
    if (!g.valid[i]) continue;
    const double d = distance(h, n, i);
    if (std::isfinite(d) && d > 0) dist.push_back(d);
  }
  if (dist.size() < 64) return 0;
  // Steps of at most an eighth of the median distance (a step beyond the distances would fit
  // them all, as zero steps).
  std::vector<double> scratch = dist;
  const auto mid = scratch.begin() + static_cast<std::ptrdiff_t>(scratch.size() / 2);
  std::nth_element(scratch.begin(), mid, scratch.end());
  const double largest = *mid / 8;
  double best = 0;
  for (int e = -6; e <= 3; ++e)
    for (double m : {1.0, 2.0, 2.5, 4.0, 5.0}) {
      const double q = m * std::pow(10.0, e);
      if (q * h.grid_per_unit >= 0.999 && q <= largest && q > best && on_steps(dist, q, &scratch))
        best = q;
    }
  return best;
}

// The sensor's range step for distances from the origin that sit on the steps only less an
// offset of their own ring (a source without a distance field whose sensor measures its ranges
// from a centre off the axis: the Helios 16P's 35 mm), as range_step but with each ring's
// distances less *phase (per ring, in the units of h.xyz: the circular mean of the distances
// modulo the step). 0 (and *phase empty) when no step is found.
double ring_offset_step(const ScanGeometry& g, const ScanHints& h,
                        const std::vector<uint32_t>& ring, size_t rings,
                        std::vector<double>* phase) {
  phase->clear();
  const size_t n = g.total();
  if (h.grid_per_unit <= 0 || h.xyz.size() != 3 * n || !h.distance.empty() || rings == 0) return 0;
  std::vector<std::vector<double>> dist(rings);
  std::vector<double> all;
  const size_t stride = std::max<size_t>(1, n / 16384);
  for (size_t i = 0; i < n; i += stride) {
    if (!g.valid[i] || !small_enough(&g.q[3 * i])) continue;
    const double d = distance(h, n, i);
    if (std::isfinite(d) && d > 0) dist[ring[i]].push_back(d), all.push_back(d);
  }
  if (all.size() < 64) return 0;
  const auto mid = all.begin() + static_cast<std::ptrdiff_t>(all.size() / 2);
  std::nth_element(all.begin(), mid, all.end());
  const double largest = *mid / 8;
  std::vector<double> shifted, scratch, ph(rings);
  for (int e = 3; e >= -6; --e)
    for (double m : {5.0, 4.0, 2.5, 2.0, 1.0}) {
      const double q = m * std::pow(10.0, e);
      if (q * h.grid_per_unit < 0.999 || q > largest) continue;
      shifted.clear();
      for (size_t k = 0; k < rings; ++k) {
        double sc = 0, ss = 0;
        for (double d : dist[k]) sc += std::cos(kTwoPi * d / q), ss += std::sin(kTwoPi * d / q);
        ph[k] = dist[k].empty() ? 0 : q * std::atan2(ss, sc) / kTwoPi;
        for (double d : dist[k]) shifted.push_back(d - ph[k]);
      }
      if (on_steps(shifted, q, &scratch)) {
        *phase = ph;
        return q;
      }
    }
  return 0;
}

// Least-squares sums of a line y = u m + v.
struct LineSums {
  double n = 0, m = 0, y = 0, mm = 0, my = 0;
  void add(double mi, double yi) { n += 1, m += mi, y += yi, mm += mi * mi, my += mi * yi; }
  // The line, or through the origin (v = 0) without `offset` or when the step counts do not
  // spread.
  void fit(double fallback, bool offset, double* u, double* v) const {
    const double det = n * mm - m * m;
    if (offset && n >= 2 && det > 1e-9 * n * mm) {
      *u = (n * my - m * y) / det;
      *v = (y - *u * m) / n;
    } else {
      *u = mm > 0 ? my / mm : fallback;
      *v = 0;
    }
  }
};

// Per ring the grid units of one range step and the range's offset (least squares from the step
// counts to the horizontal ranges) and per point its range in steps; nothing when no step is
// found.
void fit_units(const ScanGeometry& g, const ScanHints& h, const std::vector<uint32_t>& ring,
               size_t rings, RingFit* r) {
  std::vector<double> phase;  // per ring, when only the rings' own offsets put them on steps
  double q = range_step(g, h);
  if (q == 0) q = ring_offset_step(g, h, ring, rings, &phase);
  if (q == 0) return;
  const double gpu = h.grid_per_unit;
  const size_t n = g.total();
  std::vector<LineSums> line(rings);
  for (size_t i = 0; i < n; ++i) {
    if (!g.valid[i] || !small_enough(&g.q[3 * i])) continue;
    const double d = distance(h, n, i) - (phase.empty() ? 0 : phase[ring[i]]);
    if (!std::isfinite(d)) continue;
    line[ring[i]].add(std::floor(d / q + 0.5),
                      planar_length(double(h.xyz[3 * i]), double(h.xyz[3 * i + 1])) * gpu);
  }
  r->unit.resize(rings);
  r->offset.resize(rings);
  // Offsets from a distance field, unless every ring's is under half a grid unit (the VLP-16's
  // distance field: then the lines through the origin, and no offsets stored).
  bool offsets = !h.distance.empty() || !phase.empty();
  for (size_t k = 0; k < rings && offsets; ++k)
    line[k].fit(q * gpu, true, &r->unit[k], &r->offset[k]);
  if (offsets &&
      std::all_of(r->offset.begin(), r->offset.end(), [](double v) { return std::fabs(v) < 0.5; }))
    offsets = false;
  for (size_t k = 0; k < rings; ++k) {
    line[k].fit(q * gpu, offsets, &r->unit[k], &r->offset[k]);
    if (!(r->unit[k] >= kMinUnit && r->unit[k] <= kMaxUnit) ||
        !(std::fabs(r->offset[k]) <= kMaxOffset)) {
      r->unit.clear();
      r->offset.clear();
      return;
    }
  }
  r->steps.assign(n, 0);
  for (size_t i = 0; i < n; ++i) {
    if (!g.valid[i] || !small_enough(&g.q[3 * i])) continue;
    const double rho = planar_length(double(h.xyz[3 * i]), double(h.xyz[3 * i + 1])) * gpu;
    r->steps[i] = round_clamp((rho - r->offset[ring[i]]) / r->unit[ring[i]]);
  }
}

// find_bow(g, h), from *found when it has it (then kept there).
float bow_of(const ScanGeometry& g, const ScanHints& h, FoundRings* found) {
  if (!found) return find_bow(g, h);
  if (!found->bow_known) found->bow = find_bow(g, h), found->bow_known = true;
  return found->bow;
}

// The rings fit_rings and placed_rings give the points (*ring; their number, 0 for none): the
// ring field's (with ring_field), else the elevations' under the bow; from *found when it has
// them (then kept there).
size_t rings_of(const ScanGeometry& g, const ScanHints& h, bool ring_field, FoundRings* found,
                std::vector<uint32_t>* ring) {
  size_t rings = 0;
  if (ring_field && !found) rings = dense_rings(g, h, ring);
  if (ring_field && found) {
    if (!found->field_known)
      found->field_rings = dense_rings(g, h, &found->field), found->field_known = true;
    rings = found->field_rings;
    if (rings > 0) *ring = found->field;
  }
  if (rings > 0) return rings;
  if (!found) return elevation_rings(g, h.xyz, find_bow(g, h), ring, nullptr);
  if (!found->elevations_known) {
    found->elevations = *ring;  // elevation_rings leaves it as it is when it finds none
    found->elevation_rings =
        elevation_rings(g, h.xyz, bow_of(g, h, found), &found->elevations, &found->peaks);
    found->elevations_known = true;
  }
  if (found->elevation_rings > 0) *ring = found->elevations;
  return found->elevation_rings;
}

}  // namespace

size_t placed_rings(const ScanGeometry& g, const ScanHints& hints, bool ring_field,
                    std::vector<uint32_t>* placed, FoundRings* found) {
  std::vector<uint32_t> ring;
  const size_t rings = rings_of(g, hints, ring_field, found, &ring);
  placed->assign(g.total(), 0);
  if (rings == 0) return 0;
  for (size_t i = 0; i < g.total(); ++i)
    if (g.valid[i] && small_enough(&g.q[3 * i])) (*placed)[i] = ring[i];
  return rings;
}

size_t peak_rings(const ScanGeometry& g, const ScanHints& hints, const std::vector<double>& peaks,
                  size_t stride, FoundRings* found, std::vector<uint32_t>* ring,
                  std::vector<uint8_t>* has) {
  ring->clear();
  has->clear();
  const double w = bow_of(g, hints, found);
  for (size_t i = 0; i < g.total(); i += stride) {
    double t = NAN;
    if (g.valid[i] && small_enough(&g.q[3 * i])) {
      double v[3];
      coords(g, hints.xyz, i, v);
      t = bowed_slope(v, w);
    }
    has->push_back(std::isfinite(t));
    ring->push_back(std::isfinite(t) ? nearest_peak(peaks, std::atan(t)) : 0);
  }
  return peaks.size();
}

RingFit fit_rings(const ScanGeometry& g, const ScanHints& hints, bool units, bool shares,
                  bool ring_field, FoundRings* found) {
  RingFit r;
  std::vector<uint32_t> ring;
  r.bow = bow_of(g, hints, found);
  const size_t rings = rings_of(g, hints, ring_field, found, &ring);
  r.polar.assign(g.total(), Polar{});
  if (rings == 0) return r;
  std::vector<size_t> size(rings, 0);
  for (size_t i = 0; i < g.total(); ++i)
    if (g.valid[i] && small_enough(&g.q[3 * i])) ++size[ring[i]];
  std::vector<ConeSums> cone(rings);
  r.phi.resize(rings);
  for (size_t k = 0; k < rings; ++k) r.phi[k].resize(size[k]);
  std::fill(size.begin(), size.end(), 0);  // now each ring's azimuths so far
  for (size_t i = 0; i < g.total(); ++i) {
    const int32_t* p = &g.q[3 * i];
    if (!g.valid[i] || !small_enough(p)) continue;
    const double x = p[0], y = p[1];
    const double h = planar_length(x, y);
    double bent = 0;  // the bow's part of z, 1 - cos phi from the finer coordinates
    if (r.bow != 0) {
      double v[3];
      coords(g, hints.xyz, i, v);
      const double rv = planar_length(v[0], v[1]);
      if (rv > 0) bent = double(r.bow) * h * (1 - v[0] / rv);
    }
    cone[ring[i]].add(h, p[2] - bent);
    r.phi[ring[i]][size[ring[i]]++] = azimuth(g, hints, i);
    r.polar[i].ring = ring[i];
    r.polar[i].range = round_clamp(h);
    r.reach = std::max(r.reach, h);
  }
  r.step = infer_step(r.phi);
  r.quantum = azimuth_quantum(r);
  if (shares) fit_shares(g, &r);
  r.slope.resize(rings), r.z0.resize(rings);
  for (size_t k = 0; k < rings; ++k) fit_cone(cone[k], &r.slope[k], &r.z0[k]);
  if (units) fit_units(g, hints, ring, rings, &r);
  return r;
}

double sorted_step(const RingFit& r) {
  std::vector<std::vector<double>> phi = r.phi;
  for (std::vector<double>& p : phi) std::sort(p.begin(), p.end());
  return std::fabs(infer_step(phi));
}

// The azimuths a ring's offset is the circular mean of: at least this many, evenly spaced in the
// ring's (all of a pandar64 sweep's 1,770, every 4th of a 9-sweep window's). All of them cost a
// sine and a cosine each per step tried: table_fit was 0.74 G of the 16.2 G instructions of the
// 20-sweep pandar64 folder's encode. 512 made robosense-helios16p 2.1 % larger at 1 mm with
// --point-order any; from 2048 up it was as with all (docs/lab/2026-11-30-encoder-speed-2.md).
constexpr size_t kOffsetSample = 4096;

Table table_fit(const RingFit& r, double step_divisor, bool units, const Table* twin) {
  Table t;
  const size_t rings = r.rings();
  if (rings == 0) return t;
  double step = step_divisor > 0 ? r.step / step_divisor : std::copysign(r.quantum, r.step);
  if (step == 0 || !std::isfinite(step)) return t;
  t.turn = step_divisor <= 0;
  if (t.turn) t.fire_turn = r.fire_turn, t.share = r.share, t.slots = r.slots, t.slot = r.slot;
  t.step = static_cast<float>(step);
  step = t.step;
  const double cols = std::floor(kTwoPi / std::fabs(step) + 0.5);
  t.columns = static_cast<uint32_t>(std::max(1.0, std::min(cols, double(kMaxMapCells / rings))));
  t.slope = r.slope;
  t.z0 = r.z0;
  t.bow = r.bow;
  units = units && !r.unit.empty();
  if (units) t.unit = r.unit, t.offset = r.offset;
  if (twin && twin->step == t.step && twin->rings() == rings) {  // the same offsets
    t.azimuth0 = twin->azimuth0;
    pack_table(&t, r.reach);
    return t;
  }
  t.azimuth0.resize(rings);
  for (size_t k = 0; k < rings; ++k) {
    double sc = 0, ss = 0;
    const std::vector<double>& phi = r.phi[k];
    const size_t stride = std::max<size_t>(1, phi.size() / kOffsetSample);
    for (size_t i = 0; i < phi.size(); i += stride) {
      double sn, cs;  // without libm's calls (a few units in the last place apart)
      det_sincos(kTwoPi * phi[i] / step, &sn, &cs);
      sc += cs, ss += sn;
    }
    t.azimuth0[k] = static_cast<float>(step * std::atan2(ss, sc) / kTwoPi);
  }
  pack_table(&t, r.reach);
  return t;
}

void place_points(const ScanGeometry& g, const RingFit& r, const Table& t, size_t n,
                  Placement* placed) {
  std::vector<Polar>* polar = &placed->polar;
  placed->fire.clear();
  if (t.rings() == 0) {
    polar->assign(n, Polar{});
    return;
  }
  polar->resize(n);  // each entry written once below
  const double step = t.step;
  const bool units = !t.unit.empty();  // table_fit's ranges in the sensor's steps
  // Each valid point's column: its azimuth is the next of its ring's (fit_rings kept them in
  // point order).
  std::vector<size_t> next(t.rings(), 0);
  for (size_t i = 0; i < n; ++i) {
    const int32_t* p = &g.q[3 * i];
    if (!g.valid[i] || !small_enough(p)) {
      (*polar)[i] = Polar{};
      continue;
    }
    Polar o = r.polar[i];
    o.column = round_clamp((r.phi[o.ring][next[o.ring]++] - t.azimuth0[o.ring]) / step);
    if (units) o.range = r.steps[i];
    (*polar)[i] = o;
  }
  if (t.slots) fire_points(g, t, n, placed);
}

Table table_for(const ScanGeometry& g, const RingFit& r, double step_divisor, bool units,
                Placement* placed) {
  const Table t = table_fit(r, step_divisor, units);
  place_points(g, r, t, g.total(), placed);
  return t;
}

bool spherical_ok(const ScanGeometry& g, size_t first, size_t n) {
  for (size_t i = first; i < first + n; ++i)
    if (g.valid[i] && !small_enough(&g.q[3 * i])) return false;
  return true;
}

}  // namespace scan
}  // namespace capz

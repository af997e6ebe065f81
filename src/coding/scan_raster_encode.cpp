// Raster frames, the encoding side (docs/FORMAT.md "Scans (format 1.1)": "Raster frames" and the
// encoder's note): finds whether a window is a raster's (its points' distances on a quantum,
// their directions repeating from frame to frame), infers the pixel table and codes the window.
#include <algorithm>
#include <cmath>

#include "coding/bytes.h"
#include "coding/quantiser.h"
#include "coding/scan_raster.h"

namespace capz {
namespace scan {
namespace raster {

namespace {

constexpr double kOnQuantum = 0.1;     // a distance within a tenth of a quantum is on it
constexpr double kQuantumShare = 0.8;  // of the points, for a quantum to be found
constexpr double kKeyScale = 32768.0;  // directions rounded to 2^-15
constexpr size_t kQuantumSample = 20000;
// Bits of the pixel vectors beyond the farthest range's: 2 puts a prediction within 1/8 of a
// grid step (robosense-e1 at 1 mm: 6.53 bits a point with 4, 6.11 with 2, 6.14 with 0).
constexpr int kExtraBits = 2;
// At a bound, points on their rays (fine shift > 0): 2 bits fewer than the farthest range's,
// the rays' error taken up by the choice of the range (robosense-e1, bytes at 5 mm / 1 cm / 2 cm
// with 2: 209,222 / 161,656 / 120,331; 0: 194,583 / 150,796 / 112,619; -2: 186,620 / 146,137 /
// 110,126; -3 at 1 cm 147,199, -4 155,586).
constexpr int kExtraBitsOnRays = -2;
// The fine shift of points on their rays (the trials of keep_smaller).
constexpr int kFineShift = 2;

// Direction keys to values: open addressing, linear probing (node-based maps cost a cache miss a
// point: a tenth of a pandar64 encode). Key 0 is no key (a point's key is never 0).
class KeyMap {
 public:
  explicit KeyMap(size_t n) {
    size_t cap = 16;
    while (cap < 2 * n) cap *= 2;
    keys_.assign(cap, 0);
    vals_.assign(cap, 0);
  }
  // The value slot of key k, inserted with v when absent (*inserted says which).
  uint32_t* get(uint64_t k, uint32_t v, bool* inserted) {
    const size_t mask = keys_.size() - 1;
    size_t i = static_cast<size_t>((k * 0x9e3779b97f4a7c15ull) >> 20) & mask;
    while (keys_[i] != 0 && keys_[i] != k) i = (i + 1) & mask;
    *inserted = keys_[i] == 0;
    if (*inserted) keys_[i] = k, vals_[i] = v;
    return &vals_[i];
  }
  const uint32_t* find(uint64_t k) const {
    const size_t mask = keys_.size() - 1;
    size_t i = static_cast<size_t>((k * 0x9e3779b97f4a7c15ull) >> 20) & mask;
    while (keys_[i] != 0 && keys_[i] != k) i = (i + 1) & mask;
    return keys_[i] == 0 ? nullptr : &vals_[i];
  }

 private:
  std::vector<uint64_t> keys_;
  std::vector<uint32_t> vals_;
};

// A point's direction rounded: the key of its pixel. Each coordinate over r (a distance, or a
// depth camera's depth: find_depth_axis keeps those below 3.9) takes 18 bits, offset by 2^17.
uint64_t direction_key(const float* xyz, double r) {
  uint64_t k = 0;
  for (int a = 0; a < 3; ++a) {
    const double u = r > 0 ? static_cast<double>(xyz[a]) / r : 0.0;
    k = (k << 18) |
        static_cast<uint64_t>(static_cast<int64_t>(round_half_away(u * kKeyScale)) + 131072);
  }
  return k;
}

// The largest quantum m 10^k (m in 5, 2.5, 2, 1; k in 0..-6) on which kQuantumShare of the
// (nonzero) distances lie, on up to kQuantumSample of them taken evenly; 0 for none.
double find_quantum(const std::vector<double>& dist) {
  std::vector<double> d;
  for (double v : dist)
    if (v > 0) d.push_back(v);
  if (d.empty()) return 0;
  const size_t stride = std::max<size_t>(1, d.size() / kQuantumSample);
  const double m[4] = {5, 2.5, 2, 1};
  double scale = 1;  // 10^-k
  for (int k = 0; k <= 6; ++k, scale *= 10) {
    for (double mm : m) {
      const double c = mm / scale;
      size_t on = 0, all = 0;
      for (size_t i = 0; i < d.size(); i += stride, ++all) {
        const double t = d[i] / c;
        on += std::fabs(t - std::nearbyint(t)) <= kOnQuantum;
      }
      if (static_cast<double>(on) >= kQuantumShare * static_cast<double>(all)) return c;
    }
  }
  return 0;
}

// The pixels of the window in table order: a merge of the frames' orders (each frame's new
// directions placed where it saw them). pixel[i] gets each valid point's pixel. False when the
// directions do not repeat (more pixels than 3/2 of the largest frame after two frames).
bool merge_pixels(const ScanGeometry& g, const std::vector<uint64_t>& keys,
                  std::vector<uint32_t>* pixel, size_t* count) {
  std::vector<uint64_t> order, next;
  KeyMap pos(0);
  size_t first = 0, largest = 0;
  for (size_t f = 0; f < g.counts.size(); ++f) {
    next.clear();
    KeyMap placed(g.counts[f]);  // this frame's new directions
    size_t mp = 0;
    bool fresh;
    for (size_t i = first; i < first + g.counts[f]; ++i) {
      if (!g.valid[i]) continue;
      const uint32_t* at = pos.find(keys[i]);
      if (at == nullptr) {
        placed.get(keys[i], 0, &fresh);
        if (fresh) next.push_back(keys[i]);
      } else if (*at >= mp) {
        next.insert(next.end(), order.begin() + static_cast<std::ptrdiff_t>(mp),
                    order.begin() + static_cast<std::ptrdiff_t>(*at) + 1);
        mp = *at + 1;
      }
    }
    next.insert(next.end(), order.begin() + static_cast<std::ptrdiff_t>(mp), order.end());
    order.swap(next);
    first += g.counts[f];
    largest = std::max<size_t>(largest, g.counts[f]);
    if (order.size() > (size_t{1} << 22) || (f >= 1 && 4 * order.size() > 5 * largest))
      return false;
    pos = KeyMap(order.size());
    for (size_t j = 0; j < order.size(); ++j) pos.get(order[j], static_cast<uint32_t>(j), &fresh);
  }
  pixel->assign(g.total(), 0);
  for (size_t i = 0; i < g.total(); ++i)
    if (g.valid[i]) (*pixel)[i] = *pos.find(keys[i]);
  *count = order.size();
  return true;
}

// A point's distance from the prediction at rho (the sum over the axes).
int64_t miss(const Pixels& px, size_t p, const int32_t* q, int32_t rho) {
  int64_t m = 0;
  for (int a = 0; a < 3; ++a) m += std::llabs(int64_t{q[a]} - predict(px, p, a, rho));
  return m;
}

// The pixel vectors: per pixel the sum of its points' source coordinates over the quantum c times
// the sum of their ranges (in quanta), rounded to 2^-e with e the bit length of the farthest
// range (grid units) plus `extra`, in 0..30.
template <class Range>
std::vector<int32_t> fit_vectors(const ScanGeometry& g, const ScanHints& hints,
                                 const std::vector<uint32_t>& pixel, const std::vector<Range>& rho,
                                 size_t count, double c, double delta, int extra, int* e) {
  std::vector<double> sum(3 * count, 0.0), rsum(count, 0.0);
  double far = 1;
  for (size_t i = 0; i < g.total(); ++i) {
    if (!g.valid[i]) continue;
    for (size_t a = 0; a < 3; ++a) sum[3 * pixel[i] + a] += hints.xyz[3 * i + a];
    rsum[pixel[i]] += rho[i];
    far = std::max(far, rho[i] * delta);
  }
  *e = std::clamp(static_cast<int>(std::ceil(std::log2(far))) + extra, 0, 30);
  const double scale = std::ldexp(1.0, *e);
  std::vector<int32_t> v(3 * count, 0);
  for (size_t p = 0; p < count; ++p)
    for (size_t a = 0; a < 3; ++a)
      if (rsum[p] > 0)
        v[3 * p + a] = static_cast<int32_t>(std::clamp<double>(
            std::nearbyint(sum[3 * p + a] / (c * rsum[p]) * scale), -2147483647.0, 2147483647.0));
  return v;
}

uint8_t validity(const ScanGeometry& g, size_t first, size_t n) {
  size_t v = 0;
  for (size_t i = first; i < first + n; ++i) v += g.valid[i] != 0;
  return v == n ? kAllValid : v == 0 ? kNoneValid : kSomeValid;
}

// A point's direction key from its source coordinates (0 for a gap).
uint64_t key_of(const ScanGeometry& g, const ScanHints& hints, size_t i, double* dist) {
  const float* x = &hints.xyz[3 * i];
  *dist = std::sqrt(static_cast<double>(x[0]) * x[0] + static_cast<double>(x[1]) * x[1] +
                    static_cast<double>(x[2]) * x[2]);
  return g.valid[i] && std::isfinite(*dist) ? direction_key(x, *dist) : 0;
}

// Whether most of the second frame's directions are the first frame's: the quick test that
// spares a spinning sensor's window the rest (a flash LiDAR's repeat; a spinning one's do not).
bool second_repeats(const ScanGeometry& g, const ScanHints& hints) {
  KeyMap first(g.counts[0]);
  double d;
  bool fresh;
  for (size_t i = 0; i < g.counts[0]; ++i)
    if (g.valid[i]) first.get(key_of(g, hints, i, &d), 0, &fresh);
  const size_t begin = g.counts[0], end = begin + g.counts[1];
  size_t valid = 0, missed = 0;
  for (size_t i = begin; i < end; ++i) valid += g.valid[i] != 0;
  // Repeats when 4 seen > 3 valid: no longer once 4 missed >= valid (a spinning sensor's window
  // stops after about a quarter of its second frame).
  for (size_t i = begin; i < end && 4 * missed < valid; ++i)
    if (g.valid[i]) missed += first.find(key_of(g, hints, i, &d)) == nullptr;
  return 4 * (valid - missed) > 3 * valid;
}

// What the encoder finds in a raster window: the pixels, the source distances, the quantum.
struct Found {
  std::vector<uint32_t> pixel;  // per point (valid ones)
  size_t count = 0;             // pixels
  std::vector<double> dist;     // per point, source units
  double quantum = 0;           // source units
  double step = 0;              // the grid step in source units
  int64_t largest = 0;          // the largest magnitude of an integer
  int axis = -1;                // a depth camera's: ranges along this axis (dist its |x_a|)
};

// A depth camera's window (a pinhole's pixels, depth on a quantum along its axis, no quantum in
// the distances): the first axis along which every valid point lies on one side, at most 3.9
// times as far as along the others (the direction keys' reach), with those magnitudes on a
// quantum. r->dist, quantum and axis set; false, r untouched, for none.
bool find_depth_axis(const ScanGeometry& g, const ScanHints& hints, Found* r) {
  const size_t total = g.total();
  for (int a = 0; a < 3; ++a) {
    std::vector<double> d(total, 0.0);
    int side = 0;
    bool ok = true;
    for (size_t i = 0; i < total && ok; ++i) {
      if (!g.valid[i]) continue;
      const float* x = &hints.xyz[3 * i];
      const int s = x[a] > 0 ? 1 : x[a] < 0 ? -1 : 0;
      d[i] = std::fabs(static_cast<double>(x[a]));
      ok = s != 0 && (side == 0 || s == side) && std::fabs(x[(a + 1) % 3]) < 3.9 * d[i] &&
           std::fabs(x[(a + 2) % 3]) < 3.9 * d[i];
      side = s;
    }
    const double c = ok && side != 0 ? find_quantum(d) : 0;
    if (c == 0) continue;
    r->dist.swap(d);
    r->quantum = c;
    r->axis = a;
    return true;
  }
  return false;
}

// How a window's raster frames code: ranges in quanta of `range` (source units); fine = 0: the
// integers given, exactly; else on the grid step times 2^-fine, chosen within the bound (FORMAT.md
// "Raster frames", fine shift).
struct Trial {
  double range = 0;
  int fine = 0;
};

// A bound's margin: 2^-22 of a coordinate's magnitude (the source as float32, the written float32).
constexpr double kMargin = 1.0 / 4194304.0;

// The encoding Io of code_frame.
class EncodeIo {
 public:
  EncodeIo(IntEncoder* enc, const ScanGeometry& g, const ScanHints& hints, const Found& r,
           const Pixels& px, const std::vector<int32_t>& rho, const Trial& t)
      : enc_(enc),
        g_(g),
        hints_(hints),
        r_(r),
        px_(px),
        rho_(rho),
        t_(t),
        unit_(std::ldexp(hints.step, -t.fine)) {}
  int32_t sym(int32_t actual, int32_t pred, int ctx) {
    scan::put_value(*enc_, zigzag(wrap_sub(actual, pred)), ctx);
    return actual;
  }
  int32_t sym_plain(int32_t actual, int32_t pred, int ctx) { return sym(actual, pred, ctx); }
  bool flag(bool actual, int ctx) {
    scan::put_value(*enc_, actual ? 1u : 0u, ctx);
    return actual;
  }
  bool actual_valid(size_t i) const { return g_.valid[i] != 0; }
  int32_t pixel_residual(size_t i, int64_t pix) const {
    return static_cast<int32_t>(static_cast<int64_t>(r_.pixel[i]) - pix - 1);
  }
  int64_t check_pixel(int64_t p, size_t) const { return p; }
  // Exactly: the range found. At a bound: of the ranges within the bound and a quantum of the
  // source's, the one whose predictions hold the bound on the most axes, then the nearest pred.
  int32_t rho(size_t i, int32_t pred) const {
    if (t_.fine == 0) return rho_[i];
    const int32_t span = static_cast<int32_t>(std::ceil(hints_.bound / t_.range)) + 1;
    int32_t best = rho_[i];
    int best_ok = -1;
    int64_t best_off = 0;
    for (int32_t c = std::max(0, rho_[i] - span); c <= rho_[i] + span; ++c) {
      int ok = 0;
      for (int a = 0; a < 3; ++a) ok += within(i, a, predict(px_, r_.pixel[i], a, c));
      const int64_t off = std::llabs(int64_t{c} - pred);
      if (ok > best_ok || (ok == best_ok && off < best_off)) best = c, best_ok = ok, best_off = off;
    }
    return best;
  }

  // Exactly: the integer given. At a bound: h where it holds the bound, else the source's
  // coordinate rounded to the fine grid.
  int32_t coord(size_t i, int a, int32_t h) const {
    if (t_.fine == 0) return g_.q[3 * i + static_cast<size_t>(a)];
    if (within(i, a, h)) return h;
    return round_clamp(static_cast<double>(hints_.xyz[3 * i + static_cast<size_t>(a)]) / unit_);
  }

 private:
  // Whether integer h of axis a decodes within the bound of point i's coordinate, as the decoder
  // gives it back and as a float32 writer stores it.
  bool within(size_t i, int a, int32_t h) const {
    const double x = hints_.xyz[3 * i + static_cast<size_t>(a)];
    const double y = std::ldexp(static_cast<double>(h) * hints_.step, -t_.fine);
    const double y32 = static_cast<float>(y);
    const double lim = hints_.bound - std::fabs(x) * kMargin;
    return std::fabs(y - x) <= lim && std::fabs(y32 - x) <= lim;
  }

  IntEncoder* enc_;
  const ScanGeometry& g_;
  const ScanHints& hints_;
  const Found& r_;
  const Pixels& px_;
  const std::vector<int32_t>& rho_;
  Trial t_;
  double unit_;  // source units of a fine integer
};

// Whether g is a raster window (FORMAT.md, the encoder's note), and what it is. *moving (when not
// null) set when its second frame did not repeat its first's directions.
bool find_raster(const ScanGeometry& g, const ScanHints& hints, Found* r, bool* moving) {
  const size_t total = g.total();
  if (g.counts.size() < 2 || hints.xyz.size() != 3 * total) return false;
  if (!second_repeats(g, hints)) {
    if (moving) *moving = true;
    return false;
  }
  r->dist.assign(total, 0.0);
  size_t valid = 0;
  for (size_t i = 0; i < total; ++i) {
    if (!g.valid[i]) continue;
    double d2 = 0;
    for (size_t a = 0; a < 3; ++a) {
      const double x = hints.xyz[3 * i + a];
      if (!std::isfinite(x) || std::llabs(g.q[3 * i + a]) >= kMaxSphericalCoord) return false;
      r->largest = std::max<int64_t>(r->largest, std::llabs(g.q[3 * i + a]));
      d2 += x * x;
    }
    r->dist[i] = std::sqrt(d2);
    ++valid;
  }
  r->quantum = find_quantum(r->dist);
  if (r->quantum == 0 && !find_depth_axis(g, hints, r)) return false;
  std::vector<uint64_t> keys(total, 0);
  for (size_t i = 0; i < total; ++i)
    if (g.valid[i]) keys[i] = direction_key(&hints.xyz[3 * i], r->dist[i]);
  if (!merge_pixels(g, keys, &r->pixel, &r->count) || 4 * r->count > 3 * valid) return false;
  double sxy = 0, syy = 0;  // distance against the integers' length, least squares
  for (size_t i = 0; i < total; ++i) {
    if (!g.valid[i]) continue;
    double r2 = 0;
    for (size_t a = 0; a < 3; ++a)
      if (r->axis < 0 || a == static_cast<size_t>(r->axis))
        r2 += static_cast<double>(g.q[3 * i + a]) * g.q[3 * i + a];
    sxy += r->dist[i] * std::sqrt(r2);
    syy += r2;
  }
  r->step = sxy / syy;
  return sxy > 0 && std::isfinite(r->step);
}

// Each valid point's range in quanta of c: its distance's, moved by one where that brings the
// prediction nearer.
std::vector<int32_t> ranges(const ScanGeometry& g, const Found& r, const Pixels& px, double c) {
  std::vector<int32_t> rho(g.total(), 0);
  for (size_t i = 0; i < g.total(); ++i) {
    if (!g.valid[i]) continue;
    rho[i] = static_cast<int32_t>(std::min(std::nearbyint(r.dist[i] / c), 1e9));
    if (px.v.empty()) continue;
    const int32_t* q = g.q.data() + 3 * i;
    int64_t best = miss(px, r.pixel[i], q, rho[i]);
    const int32_t r0 = rho[i];
    for (int32_t k : {r0 - 1, r0 + 1}) {
      const int64_t m = k >= 0 ? miss(px, r.pixel[i], q, k) : best;
      if (m < best) best = m, rho[i] = k;
    }
  }
  return rho;
}

// The pixel table into enc (FORMAT.md "Raster frames": second differences per axis).
void put_pixels(const std::vector<int32_t>& vint, size_t count, IntEncoder* enc) {
  int32_t prev[2][3] = {{0, 0, 0}, {0, 0, 0}};
  for (size_t p = 0; p < count; ++p)
    for (int a = 0; a < 3; ++a) {
      const int32_t v = vint[3 * p + static_cast<size_t>(a)];
      enc->put_signed(wrap_sub(v, wrap_sub(wrap_add(prev[0][a], prev[0][a]), prev[1][a])),
                      kCtxTable + a);
      prev[1][a] = prev[0][a];
      prev[0][a] = v;
    }
}

// The window coded as raster frames under trial t; *decoded (when not null) gets the integers
// the decoder gives back (x y z per point, 0 at gaps).
std::vector<uint8_t> code_raster(const ScanGeometry& g, const ScanHints& hints, const Found& r,
                                 const Trial& t, std::vector<int32_t>* decoded = nullptr) {
  Pixels px;
  std::vector<int32_t> rho;
  std::vector<int32_t> vint;
  int e = 0;
  const double c = t.range;
  if (t.fine == 0) {
    px.delta = c / r.step;
    rho = ranges(g, r, px, c);
    vint = fit_vectors(g, hints, r.pixel, rho, r.count, c, px.delta, kExtraBits, &e);
  } else {  // ranges from the source distances, the vectors fitted to them
    px.delta = c / std::ldexp(hints.step, -t.fine);
    rho.assign(g.total(), 0);
    std::vector<double> exact(g.total(), 0.0);
    for (size_t i = 0; i < g.total(); ++i) {
      exact[i] = r.dist[i] / c;
      rho[i] = static_cast<int32_t>(std::min(std::nearbyint(exact[i]), 1e9));
    }
    vint = fit_vectors(g, hints, r.pixel, exact, r.count, c, px.delta, kExtraBitsOnRays, &e);
  }
  px.v.resize(vint.size());
  const double unit = 1.0 / static_cast<double>(uint64_t{1} << e);
  for (size_t j = 0; j < vint.size(); ++j) px.v[j] = vint[j] * unit;
  if (t.fine == 0) rho = ranges(g, r, px, c);
  IntEncoder enc(kContexts);
  enc.add_bit_models();
  put_pixels(vint, r.count, &enc);
  EncodeIo io(&enc, g, hints, r, px, rho, t);
  State st(r.count);
  std::vector<uint8_t> flags(g.counts.size());
  std::vector<int32_t> q;
  std::vector<uint8_t> v;
  if (decoded) decoded->clear(), decoded->reserve(3 * g.total());
  size_t first = 0;
  for (size_t f = 0; f < g.counts.size(); ++f) {
    const size_t n = g.counts[f];
    flags[f] = static_cast<uint8_t>(validity(g, first, n) | kRaster);
    q.resize(3 * n);
    v.resize(n);
    code_frame(io, px, st, flags[f], first, n, q.data(), v.data());
    if (decoded) decoded->insert(decoded->end(), q.begin(), q.end());
    first += n;
  }
  std::vector<uint8_t> out;
  write_header(g, flags, Table{}, &out);
  ByteWriter w;
  w.varint(r.count);
  w.f64(px.delta);
  w.u8(static_cast<uint8_t>(e));
  w.u8(static_cast<uint8_t>(t.fine));
  out.insert(out.end(), w.buffer().begin(), w.buffer().end());
  const std::vector<uint8_t> body = enc.finish();
  out.insert(out.end(), body.begin(), body.end());
  return out;
}

}  // namespace

void keep_smaller(const ScanGeometry& g, const ScanHints& hints, std::vector<uint8_t>* best,
                  std::vector<int32_t>* fine_q, bool* moving) {
  if (fine_q) fine_q->clear();
  Found r;
  if (!find_raster(g, hints, &r, moving)) return;
  // Exactly, ranges in the sensor's quantum (coarser ones, 2 and 4 quanta, cost more on
  // robosense-e1 at 1 cm: 284,544 and 276,691 bytes against 248,758).
  std::vector<uint8_t> out = code_raster(g, hints, r, Trial{r.quantum, 0});
  if (out.size() < best->size()) best->swap(out);  // (fine shift 0: the integers given)
  if (!(hints.bound > 0 && hints.step > 0)) return;
  // At a bound, the points on their rays: fine shift 2, range steps of the whole quanta nearest
  // twice the bound and one less (robosense-e1, bytes with m quanta, k = 1 / 2 / 3 / 4: at 1 cm,
  // m = 4, 153,621 / 145,829 / 146,474 / 149,110, m = 3 and 5 larger; at 5 cm, m = 19, 84,511 /
  // 72,444 / 73,036 / 73,643, m = 20 larger; at 5 mm k = 2 with m = 2 186,312, m = 3 201,826;
  // at 1 mm k = 2, m = 1 241,713 beats k = 0's 256,994).
  if ((r.largest << kFineShift) >= kMaxSphericalCoord) return;
  const int m0 =
      static_cast<int>(std::min(1e6, std::max(1.0, std::nearbyint(2 * hints.bound / r.quantum))));
  std::vector<int32_t> q;
  for (int m = std::max(1, m0 - 1); m <= m0; ++m) {
    out = code_raster(g, hints, r, Trial{m * r.quantum, kFineShift}, fine_q ? &q : nullptr);
    if (out.size() >= best->size()) continue;
    best->swap(out);
    if (fine_q) fine_q->swap(q);
  }
}

}  // namespace raster
}  // namespace scan
}  // namespace capz

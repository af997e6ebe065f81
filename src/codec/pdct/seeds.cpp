#include "codec/pdct/seeds.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "codec/pdct/kdtree.h"

namespace capz {
namespace pdct {
namespace {

constexpr double kPi = 3.14159265358979323846;

double dist2(const double* a, const double* b) {
  const double d0 = a[0] - b[0], d1 = a[1] - b[1], d2 = a[2] - b[2];
  return d0 * d0 + d1 * d1 + d2 * d2;
}

}  // namespace

std::vector<uint32_t> farthest_point_seeds(const double* frame, size_t points,
                                           const uint8_t* candidate, const SeedParams& params) {
  std::vector<uint32_t> seeds;
  std::vector<uint32_t> cand;
  for (size_t i = 0; i < points; ++i)
    if (!candidate || candidate[i]) cand.push_back(static_cast<uint32_t>(i));
  if (cand.empty() || params.count == 0) return seeds;
  double c[3] = {0, 0, 0};
  for (uint32_t i : cand)
    for (int a = 0; a < 3; ++a) c[a] += frame[3 * i + a];
  for (int a = 0; a < 3; ++a) c[a] /= static_cast<double>(cand.size());
  uint32_t first = cand[0];
  double best = -1;
  for (uint32_t i : cand) {
    const double d = dist2(frame + 3 * i, c);
    if (d > best) {
      best = d;
      first = i;
    }
  }
  seeds.push_back(first);
  // nearest[j]: squared distance of cand[j] to the nearest seed so far.
  std::vector<double> nearest(cand.size(), std::numeric_limits<double>::infinity());
  while (seeds.size() < std::min(params.count, cand.size())) {
    const double* s = frame + 3 * static_cast<size_t>(seeds.back());
    size_t pick = 0;
    double far = -1;
    for (size_t j = 0; j < cand.size(); ++j) {
      nearest[j] = std::min(nearest[j], dist2(frame + 3 * static_cast<size_t>(cand[j]), s));
      if (nearest[j] > far) {
        far = nearest[j];
        pick = j;
      }
    }
    if (far <= 0) break;  // every remaining candidate coincides with a seed
    seeds.push_back(cand[pick]);
  }
  return seeds;
}

bool triangle_ok(const double* a, const double* b, const double* c, double min_edge_abs,
                 double min_angle_deg) {
  const double ab = std::sqrt(dist2(a, b)), bc = std::sqrt(dist2(b, c)),
               ca = std::sqrt(dist2(c, a));
  if (!(ab >= min_edge_abs && bc >= min_edge_abs && ca >= min_edge_abs)) return false;
  if (!(ab > 0 && bc > 0 && ca > 0)) return false;
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double w[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                       u[0] * v[1] - u[1] * v[0]};
  const double twice_area = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  const double min_sin = std::sin(min_angle_deg * kPi / 180.0);
  // sin of the angle at a, b, c
  const double sa = twice_area / (ab * ca), sb = twice_area / (ab * bc),
               sc = twice_area / (bc * ca);
  return std::min(sa, std::min(sb, sc)) >= min_sin;
}

double first_frame_diagonal(const PositionsView& in) {
  if (in.frames == 0 || in.points == 0) return 0;
  bool any_valid = false;
  for (size_t i = 0; i < in.points; ++i) any_valid = any_valid || in.valid[i];
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::numeric_limits<double>::infinity();
    hi[a] = -lo[a];
  }
  for (size_t i = 0; i < in.points; ++i) {
    if (any_valid && !in.valid[i]) continue;
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], in.xyz[3 * i + a]);
      hi[a] = std::max(hi[a], in.xyz[3 * i + a]);
    }
  }
  return std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                   (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

std::vector<Triangle> seed_triangles(const PositionsView& in, const std::vector<uint32_t>& seeds,
                                     const TriangleParams& params) {
  std::vector<Triangle> out;
  if (in.frames == 0 || in.points < 3) return out;
  const double min_edge_abs = params.min_edge * first_frame_diagonal(in);
  const auto knn = nearest_neighbours(in.xyz, in.points, nullptr, seeds, KnnParams{params.knn});
  const size_t F = in.frames, P = in.points;
  auto pos = [&](size_t f, uint32_t i) { return in.xyz + 3 * (f * P + i); };
  auto ok = [&](size_t f, uint32_t i) { return in.valid[f * P + i] != 0; };
  for (size_t s = 0; s < seeds.size(); ++s) {
    const uint32_t p1 = seeds[s];
    const auto& nb = knn[s];
    double best = std::numeric_limits<double>::infinity();
    Triangle pick;
    for (size_t i = 0; i < nb.size(); ++i) {
      for (size_t j = i + 1; j < nb.size(); ++j) {
        uint32_t a = nb[i], b = nb[j];
        if (dist2(pos(0, p1), pos(0, b)) > dist2(pos(0, p1), pos(0, a))) std::swap(a, b);
        bool good = true;
        double sum[3] = {0, 0, 0}, sum2[3] = {0, 0, 0};
        size_t measured = 0;
        for (size_t f = 0; f < F && good; ++f) {
          const double *x = pos(f, p1), *y = pos(f, a), *z = pos(f, b);
          good = triangle_ok(x, y, z, min_edge_abs, params.min_angle_deg);
          if (!good || !(ok(f, p1) && ok(f, a) && ok(f, b))) continue;
          const double e[3] = {std::sqrt(dist2(x, y)), std::sqrt(dist2(y, z)),
                               std::sqrt(dist2(z, x))};
          for (int k = 0; k < 3; ++k) {
            sum[k] += e[k];
            sum2[k] += e[k] * e[k];
          }
          ++measured;
        }
        if (!good) continue;
        double score =
            params.gap_penalty * static_cast<double>(F - measured) / static_cast<double>(F);
        if (measured > 0) {
          for (int k = 0; k < 3; ++k) {
            const double m = sum[k] / static_cast<double>(measured);
            const double var = std::max(0.0, sum2[k] / static_cast<double>(measured) - m * m);
            score += std::sqrt(var) / m;
          }
        } else {
          score += 3.0;  // never measured together: rigidity unknown
        }
        if (score < best) {
          best = score;
          pick = Triangle{p1, a, b};
        }
      }
    }
    if (best < std::numeric_limits<double>::infinity()) out.push_back(pick);
  }
  return out;
}

}  // namespace pdct
}  // namespace capz

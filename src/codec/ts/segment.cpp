#include "codec/ts/segment.h"

#include <algorithm>
#include <limits>
#include <random>
#include <string>

#include "capz/error.h"
#include "codec/ts/cluster.h"

namespace capz {
namespace ts {

namespace {

// Uniform in [0, 1) from 53 bits of the generator (no implementation-defined distribution).
double uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * (1.0 / 9007199254740992.0);
}

// Features: N x 3F, row i = point i's trajectory (rows 3i..3i+2 of `frames`) minus its mean.
Eigen::MatrixXd trajectory_features(const Eigen::MatrixXd& frames) {
  const Eigen::Index n = frames.rows() / 3, nf = frames.cols();
  Eigen::MatrixXd x(n, 3 * nf);
  for (Eigen::Index i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) {
      const auto row = frames.row(3 * i + a);
      const double mean = row.mean();
      for (Eigen::Index t = 0; t < nf; ++t) x(i, 3 * t + a) = row(t) - mean;
    }
  return x;
}

// k-means++ seeding of k centres among the rows of x; fewer when x has fewer distinct rows.
Eigen::MatrixXd seed_centres(const Eigen::MatrixXd& x, int k, uint64_t seed) {
  const Eigen::Index n = x.rows();
  std::mt19937_64 rng(seed);
  Eigen::MatrixXd mu(k, x.cols());
  std::vector<double> d2(static_cast<size_t>(n), std::numeric_limits<double>::infinity());
  Eigen::Index pick = static_cast<Eigen::Index>(rng() % static_cast<uint64_t>(n));
  for (int c = 0; c < k; ++c) {
    mu.row(c) = x.row(pick);
    double total = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      d2[i] = std::min(d2[i], (x.row(i) - mu.row(c)).squaredNorm());
      total += d2[i];
    }
    if (c + 1 == k) break;
    if (!(total > 0)) {  // fewer distinct trajectories than segments: stop seeding
      mu.conservativeResize(c + 1, Eigen::NoChange);
      break;
    }
    const double target = uniform01(rng) * total;
    double acc = 0;
    pick = n - 1;
    for (Eigen::Index i = 0; i < n; ++i) {
      acc += d2[i];
      if (acc > target && d2[i] > 0) {
        pick = i;
        break;
      }
    }
  }
  return mu;
}

// Lloyd iterations from centres mu (at least one, at most max_iterations); distances through
// ||x||^2 - 2 x.mu + ||mu||^2 (one matrix product). Labels into *lab; returns the last
// assignment's within-cluster sum of squares.
double lloyd(const Eigen::MatrixXd& x, Eigen::MatrixXd mu, int max_iterations,
             std::vector<int>* lab) {
  const Eigen::Index n = x.rows(), kc = mu.rows();
  const Eigen::VectorXd sq = x.rowwise().squaredNorm();
  lab->assign(static_cast<size_t>(n), -1);
  std::vector<Eigen::Index> count(static_cast<size_t>(kc));
  double wcss = 0;
  for (int it = 0; it < std::max(1, max_iterations); ++it) {
    const Eigen::MatrixXd dot = x * mu.transpose();  // n x kc
    const Eigen::VectorXd musq = mu.rowwise().squaredNorm();
    bool changed = false;
    wcss = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      int best = 0;
      double bd = std::numeric_limits<double>::infinity();
      for (Eigen::Index c = 0; c < kc; ++c) {
        if (it > 0 && count[c] == 0) continue;
        const double d = sq[i] - 2 * dot(i, c) + musq[c];
        if (d < bd) {
          bd = d;
          best = static_cast<int>(c);
        }
      }
      if (best != (*lab)[i]) changed = true;
      (*lab)[i] = best;
      wcss += std::max(0.0, bd);
    }
    if (!changed) break;
    mu.setZero();
    std::fill(count.begin(), count.end(), 0);
    for (Eigen::Index i = 0; i < n; ++i) {
      mu.row((*lab)[i]) += x.row(i);
      ++count[(*lab)[i]];
    }
    for (Eigen::Index c = 0; c < kc; ++c)
      if (count[c] > 0) mu.row(c) /= static_cast<double>(count[c]);
  }
  return wcss;
}

}  // namespace

Segmentation segment_points(const Eigen::MatrixXd& frames, const SegmentParams& params) {
  if (params.segments < 1 || params.segments > kMaxSegments)
    fail(ErrorCode::kInvalidParameter, "",
         "ts: segments must be 1.." + std::to_string(kMaxSegments));
  Segmentation out;
  const Eigen::Index n = frames.rows() / 3;
  if (n == 0) return out;
  const int k = static_cast<int>(std::min<Eigen::Index>(params.segments, n));
  out.label.assign(static_cast<size_t>(n), 0);
  out.segments = 1;
  if (k == 1) return out;

  const Eigen::MatrixXd x = trajectory_features(frames);
  const Eigen::MatrixXd mu = seed_centres(x, k, params.seed);
  std::vector<int> lab;
  out.wcss = lloyd(x, mu, params.max_iterations, &lab);
  // In point order; empty segments vanish.
  out.segments = renumber_by_first_appearance(lab, static_cast<int>(mu.rows()), &out.label);
  return out;
}

}  // namespace ts
}  // namespace capz

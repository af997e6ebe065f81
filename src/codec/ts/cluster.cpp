#include "codec/ts/cluster.h"

#include <algorithm>
#include <limits>
#include <random>

#include "capz/error.h"

namespace capz {
namespace ts {

namespace {

// One Lloyd run from a random partition. Returns WCSS; labels in *label.
double lloyd(const Eigen::MatrixXd& x, const Eigen::VectorXd& sqnorm, int k, std::mt19937_64& rng,
             int max_iter, std::vector<int>* label) {
  const Eigen::Index n = x.cols();
  std::vector<int>& lab = *label;
  lab.assign(static_cast<size_t>(n), 0);
  for (Eigen::Index j = 0; j < n; ++j) lab[j] = static_cast<int>(rng() % static_cast<uint64_t>(k));
  // Make every cluster non-empty at the start (random partition of few frames may miss one).
  for (int c = 0; c < k && c < n; ++c) {
    if (std::find(lab.begin(), lab.end(), c) == lab.end()) lab[static_cast<size_t>(c)] = c;
  }
  Eigen::MatrixXd mu(x.rows(), k);
  std::vector<int> count(static_cast<size_t>(k));
  double wcss = 0;
  for (int it = 0; it < max_iter; ++it) {
    mu.setZero();
    std::fill(count.begin(), count.end(), 0);
    for (Eigen::Index j = 0; j < n; ++j) {
      mu.col(lab[j]) += x.col(j);
      ++count[lab[j]];
    }
    // Distances through ||x||^2 - 2 x.mu + ||mu||^2 (one matrix product).
    for (int c = 0; c < k; ++c)
      if (count[c] > 0) mu.col(c) /= count[c];
    Eigen::MatrixXd dot = mu.transpose() * x;  // k x n
    Eigen::VectorXd musq = mu.colwise().squaredNorm().transpose();
    bool changed = false;
    wcss = 0;
    std::vector<double> best_d(static_cast<size_t>(n));
    for (Eigen::Index j = 0; j < n; ++j) {
      int best = lab[j];
      double bd = std::numeric_limits<double>::infinity();
      for (int c = 0; c < k; ++c) {
        if (count[c] == 0) continue;
        double d = sqnorm[j] - 2 * dot(c, j) + musq[c];
        if (d < bd) {
          bd = d;
          best = c;
        }
      }
      if (best != lab[j]) changed = true;
      lab[j] = best;
      best_d[j] = std::max(0.0, bd);
      wcss += best_d[j];
    }
    // An emptied cluster takes the frame farthest from its centre.
    std::fill(count.begin(), count.end(), 0);
    for (Eigen::Index j = 0; j < n; ++j) ++count[lab[j]];
    for (int c = 0; c < k; ++c) {
      if (count[c] > 0 || n <= c) continue;
      Eigen::Index far = 0;
      for (Eigen::Index j = 1; j < n; ++j)
        if (count[lab[j]] > 1 && best_d[j] > best_d[far]) far = j;
      if (count[lab[far]] <= 1) continue;
      --count[lab[far]];
      lab[far] = c;
      count[c] = 1;
      best_d[far] = 0;
      changed = true;
    }
    if (!changed) break;
  }
  return wcss;
}

}  // namespace

Clustering kmeans_frames(const Eigen::MatrixXd& frames, const ClusterParams& params) {
  const Eigen::Index n = frames.cols();
  if (params.k < 1) fail(ErrorCode::kInvalidParameter, "", "ts: number of clusters must be >= 1");
  Clustering out;
  if (n == 0) return out;
  const int k = static_cast<int>(std::min<Eigen::Index>(params.k, n));
  Eigen::VectorXd sqnorm = frames.colwise().squaredNorm().transpose();
  std::mt19937_64 rng(params.seed);
  std::vector<int> lab, best_lab;
  double best = std::numeric_limits<double>::infinity();
  const int runs = k == 1 ? 1 : std::max(1, params.restarts);
  for (int r = 0; r < runs; ++r) {
    double w = lloyd(frames, sqnorm, k, rng, std::max(1, params.max_iterations), &lab);
    if (w < best) {
      best = w;
      best_lab = lab;
    }
  }
  out.k = renumber_by_first_appearance(best_lab, k, &out.label);  // in time; empty ones dropped
  out.wcss = best;
  return out;
}

}  // namespace ts
}  // namespace capz

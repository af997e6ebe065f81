// pdct stage: seed points and their triangles (Amjoun & Strasser 2007, Sec. 4.1.1).
//
// Seeds are chosen by farthest-point selection on the first frame; each seed gets a "triangle"
// (the seed and two of its nearest neighbours, found with FLANN in kdtree.h) on which its
// cluster's local frame is built in every frame (lcf.h). Without connectivity there are no
// incident triangles, so the pair of neighbours is chosen:
//   - rejected if the triple is degenerate in ANY frame of the window (see TriangleParams),
//   - among the rest, the most rigid over the window: smallest sum over the three edges of
//     (standard deviation / mean) of the edge length over frames where all three are measured,
//     plus gap_penalty * (share of frames where any of the three is a gap). On mocap this picks
//     markers on one rigid segment.
// Encoder only: the chosen triangles are stored in the bitstream.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "codec/transform.h"

namespace capz {
namespace pdct {

struct SeedParams {
  size_t count = 10;  // seeds wanted; fewer if fewer candidates exist
};

// Farthest-point selection on one frame (points x 3 doubles), among points with candidate[i] != 0
// (null = all). The first seed is the candidate farthest from the candidates' centroid; each next
// one maximises the distance to the nearest seed chosen so far. Ties go to the lower index.
std::vector<uint32_t> farthest_point_seeds(const double* frame, size_t points,
                                           const uint8_t* candidate, const SeedParams& params);

struct TriangleParams {
  int knn = 12;  // neighbours of the seed examined (pairs among them are tried)
  // Near-coincident: rejected if, in any frame, an edge is shorter than min_edge * D, where D is
  // the diagonal of the first frame's bounding box.
  double min_edge = 1e-3;
  // Near-collinear: rejected if, in any frame, the smallest interior angle is below
  // min_angle_deg, tested as min over the vertices of 2 * area / (product of the two sides at
  // that vertex) = sin(angle) < sin(min_angle_deg) (an angle near 180 degrees forces two small
  // ones, so this covers it too).
  double min_angle_deg = 10;
  double gap_penalty = 1.0;  // added per unit share of frames with a gap in the triple
};

struct Triangle {
  uint32_t p1 = 0, p2 = 0, p3 = 0;  // p1 = the seed; edge (p1, p2) carries the frame's x axis
};

// The degeneracy test of one frame: a, b, c are 3 doubles each; min_edge_abs in position units.
bool triangle_ok(const double* a, const double* b, const double* c, double min_edge_abs,
                 double min_angle_deg);

// One triangle per seed that has an acceptable pair of neighbours (seeds without one are
// dropped); p2 is the neighbour farther from the seed in the first frame.
std::vector<Triangle> seed_triangles(const PositionsView& in, const std::vector<uint32_t>& seeds,
                                     const TriangleParams& params);

// Diagonal of the bounding box of frame 0 over points with valid != 0 (all points if none is
// valid); 0 for an empty window.
double first_frame_diagonal(const PositionsView& in);

}  // namespace pdct
}  // namespace capz

// Matching a source's points to a decoded take whose frames were reordered (compress
// --point-order any; docs/FORMAT.md "Points reordered"), so that the promise is checked point
// against point (capz/tool/verify.h).
#pragma once

#include <string>
#include <vector>

#include "capz/stream.h"
#include "capz/take.h"

namespace capz {

// The points of a take or a block of frames as the matching reads them, without a copy: frame
// f's points are [begin(f), begin(f + 1)) (`offsets`, frames + 1 of them, or `points` a frame),
// per point three coordinates and a gap flag, per point field its bytes (the points' values one
// after another, each of the same size).
struct PointsView {
  size_t frames = 0, points = 0;
  const std::vector<size_t>* offsets = nullptr;  // a ragged take or block: its frame offsets
  const double* xyz = nullptr;
  const uint8_t* valid = nullptr;
  std::vector<const std::vector<uint8_t>*> fields;
  size_t begin(size_t f) const { return offsets ? (*offsets)[f] : f * points; }
  size_t total() const { return begin(frames); }
};
PointsView points_of(const Take& t);
PointsView points_of(const FrameBlock& b);

// True when a and b have the same frames of the same point counts (one ragged, the other not,
// is no difference).
bool same_counts(const PointsView& a, const PointsView& b);

// A pairing of `original`'s points with `decoded`'s, views of the same frames and counts, frame
// by frame: each valid original point with a distinct valid decoded point within `bound` of it
// on each coordinate whose fields flagged in `exact_fields` are byte for byte its own (the
// nearest free one, else by moving earlier pairs along an augmenting path of bounded depth);
// gaps pair with gaps in order. *partner: per decoded point j, the original point paired with
// it. False, with *why naming the point, when a point finds no partner.
bool match_reordered(const PointsView& original, const PointsView& decoded, double bound,
                     const std::vector<bool>& exact_fields, std::vector<size_t>* partner,
                     std::string* why);

// The points of `v` at the places `partner` gives them (original point partner[j] at place j):
// *xyz, *valid and *fields (one per field of v; a field without a value for every point is
// copied as it is).
void move_to_partners(const PointsView& v, const std::vector<size_t>& partner,
                      std::vector<double>* xyz, std::vector<uint8_t>* valid,
                      std::vector<std::vector<uint8_t>>* fields);

}  // namespace capz

// Matching a source's points to a decoded take whose frames were reordered (compress
// --point-order any; docs/FORMAT.md "Points reordered"), so that the promise is checked point
// against point (capz/tool/verify.h).
#pragma once

#include <string>
#include <vector>

#include "capz/take.h"

namespace capz {

// `original` with each frame's points (and fields) moved to the places of their partners in
// `decoded`, a take of the same frames and counts: a pairing, frame by frame, of each valid
// original point with a distinct valid decoded point within `bound` of it on each coordinate
// whose fields flagged in `exact_fields` are byte for byte its own (the nearest free one, else
// by moving earlier pairs along an augmenting path of bounded depth); gaps pair with gaps in
// order. False, with *why naming the point, when a point finds no partner.
bool match_reordered(const Take& original, const Take& decoded, double bound,
                     const std::vector<bool>& exact_fields, Take* out, std::string* why);

}  // namespace capz

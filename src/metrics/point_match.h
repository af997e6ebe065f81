// Matching a source's points to a decoded take whose frames were reordered (compress
// --point-order any; docs/FORMAT.md "Points reordered"), so that the promise is checked point
// against point (capz/tool/verify.h).
#pragma once

#include <string>
#include <vector>

#include "capz/take.h"

namespace capz {

// `original` with each frame's points (and fields) moved to the places of their partners in
// `decoded`, a take of the same frames and counts: each valid decoded point takes the first
// valid original point of its frame, in original order, that lies within `bound` of it on each
// coordinate and whose fields flagged in `exact_fields` are byte for byte its own; gaps pair
// with gaps in order. False, with *why naming the point, when a point finds no partner (greedy
// pairing: points within the bound of several others with identical fields could, in principle,
// pair otherwise than the encoder's order; the promise is then checked on this pairing).
bool match_reordered(const Take& original, const Take& decoded, double bound,
                     const std::vector<bool>& exact_fields, Take* out, std::string* why);

}  // namespace capz

// Repeated analog frames (docs/FORMAT.md 11.3): a channel of a window names the point frames whose
// S samples are bit for bit the previous frame's; those rows are left out of the channel's coding
// (its *kept* rows) and copied back by the decoder. Only in 7.x streams.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "coding/bytes.h"

namespace capz {
namespace analog {

// The frames f in [1, frames) whose samples col[(f * S + j) * stride], j < S, equal frame
// f - 1's bit for bit (increasing). Empty when S is 0.
std::vector<uint32_t> repeated_frames(const double* col, size_t stride, size_t frames, size_t S);
// How many frames f in [1, frames) repeat frame f - 1 bit for bit and do not hold one bit pattern
// in all their S samples (the encoder's scan, FORMAT.md 11.3).
size_t count_varying_repeats(const double* col, size_t stride, size_t frames, size_t S);

// Increasing indices as runs (the gap list of FORMAT.md 11.6 and the repeat list of 11.3): the
// number of runs, then per run its start minus the previous run's end (0 at first) and its
// length - 1, varints.
void write_runs(const std::vector<uint32_t>& index, ByteWriter* w);
// Reads what write_runs wrote, indices below n; throws Error(kCorrupt) when the count is too
// large for the bytes left ("analog <list> runs") or a run passes n ("analog <list> run past
// the window's end"), `list` naming the list ("gap", "repeat").
std::vector<uint32_t> read_runs(ByteReader* in, uint64_t n, const char* list);
// Reads a repeat list of a window of `frames` point frames; throws Error(kCorrupt) when it is
// empty, too long for the bytes left, or names a frame outside [1, frames).
std::vector<uint32_t> read_repeats(ByteReader* in, size_t frames);

// The kept samples (the rows of the frames not in `repeats`), from col[0], col[stride], ...
std::vector<double> kept_samples(const double* col, size_t stride, size_t frames, size_t S,
                                 const std::vector<uint32_t>& repeats);
// Writes the channel's frames * S samples to col[0], col[stride], ... from its kept samples.
void expand_repeats(const double* kept, size_t frames, size_t S,
                    const std::vector<uint32_t>& repeats, double* col, size_t stride);

}  // namespace analog
}  // namespace capz

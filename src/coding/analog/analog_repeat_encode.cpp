// The encoder's side of repeated analog frames (docs/FORMAT.md 11.3): which frames repeat the
// previous one, the kept samples, and the run lists written (also of 11.4's and 11.5's
// exceptions); the decoder is analog_repeat.cpp.
#include <utility>
#include <vector>

#include "coding/analog/analog_repeat.h"
#include "coding/quantiser.h"

namespace capz {
namespace analog {

namespace {

// Whether frame f's S samples equal frame f - 1's bit for bit.
bool repeats_previous(const double* col, size_t stride, size_t f, size_t S) {
  const double* cur = col + f * S * stride;
  const double* prev = cur - S * stride;
  for (size_t j = 0; j < S; ++j)
    if (!same_bits(cur[j * stride], prev[j * stride])) return false;
  return true;
}

}  // namespace

std::vector<uint32_t> repeated_frames(const double* col, size_t stride, size_t frames, size_t S) {
  std::vector<uint32_t> out;
  if (S == 0) return out;
  for (size_t f = 1; f < frames; ++f)
    if (repeats_previous(col, stride, f, S)) out.push_back(static_cast<uint32_t>(f));
  return out;
}

size_t count_varying_repeats(const double* col, size_t stride, size_t frames, size_t S) {
  size_t k = 0;
  if (S < 2) return 0;
  for (size_t f = 1; f < frames; ++f) {
    if (!repeats_previous(col, stride, f, S)) continue;
    const double* cur = col + f * S * stride;
    for (size_t j = 1; j < S; ++j)
      if (!same_bits(cur[j * stride], cur[0])) {
        ++k;
        break;
      }
  }
  return k;
}

void write_runs(const std::vector<uint32_t>& index, ByteWriter* w) {
  std::vector<std::pair<uint32_t, uint32_t>> runs;  // start, length
  for (uint32_t f : index) {
    if (!runs.empty() && runs.back().first + runs.back().second == f)
      ++runs.back().second;
    else
      runs.push_back({f, 1});
  }
  w->varint(runs.size());
  uint32_t end = 0;
  for (const auto& run : runs) {
    w->varint(run.first - end);
    w->varint(run.second - 1);
    end = run.first + run.second;
  }
}

std::vector<double> kept_samples(const double* col, size_t stride, size_t frames, size_t S,
                                 const std::vector<uint32_t>& repeats) {
  std::vector<double> out;
  out.reserve((frames - repeats.size()) * S);
  size_t r = 0;
  for (size_t f = 0; f < frames; ++f) {
    if (r < repeats.size() && repeats[r] == f) {
      ++r;
      continue;
    }
    for (size_t j = 0; j < S; ++j) out.push_back(col[(f * S + j) * stride]);
  }
  return out;
}

}  // namespace analog
}  // namespace capz

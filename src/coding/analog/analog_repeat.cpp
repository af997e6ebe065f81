#include "coding/analog/analog_repeat.h"

#include <string>

#include "capz/error.h"
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

std::vector<uint32_t> read_runs(ByteReader* in, uint64_t n, const char* list) {
  const std::string runs_name = std::string("analog ") + list + " runs";
  const uint64_t runs = in->count(2, runs_name.c_str());
  std::vector<uint32_t> out;
  uint64_t end = 0;  // <= n
  for (uint64_t k = 0; k < runs; ++k) {
    const uint64_t skip = in->varint();
    if (skip >= n - end)
      throw Error(ErrorCode::kCorrupt,
                  in->what() + ": analog " + list + " run past the window's end");
    const uint64_t start = end + skip;
    const uint64_t len_minus_1 = in->varint();
    if (len_minus_1 >= n - start)
      throw Error(ErrorCode::kCorrupt,
                  in->what() + ": analog " + list + " run past the window's end");
    for (uint64_t i = start; i <= start + len_minus_1; ++i) out.push_back(static_cast<uint32_t>(i));
    end = start + len_minus_1 + 1;
  }
  return out;
}

std::vector<uint32_t> read_repeats(ByteReader* in, size_t frames) {
  std::vector<uint32_t> out = read_runs(in, frames, "repeat");
  if (out.empty()) throw Error(ErrorCode::kCorrupt, in->what() + ": empty analog repeat list");
  if (out.front() == 0)
    throw Error(ErrorCode::kCorrupt, in->what() + ": analog repeat of the window's first frame");
  return out;
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

void expand_repeats(const double* kept, size_t frames, size_t S,
                    const std::vector<uint32_t>& repeats, double* col, size_t stride) {
  size_t r = 0, k = 0;
  for (size_t f = 0; f < frames; ++f) {
    double* out = col + f * S * stride;
    const bool rep = r < repeats.size() && repeats[r] == f;
    if (rep) {
      ++r;
      const double* prev = out - S * stride;  // f >= 1 (read_repeats)
      for (size_t j = 0; j < S; ++j) out[j * stride] = prev[j * stride];
    } else {
      for (size_t j = 0; j < S; ++j) out[j * stride] = kept[k++];
    }
  }
}

}  // namespace analog
}  // namespace capz

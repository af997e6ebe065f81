#include "coding/analog/analog_repeat.h"

#include <string>

#include "capz/error.h"
#include "coding/quantiser.h"

namespace capz {
namespace analog {

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

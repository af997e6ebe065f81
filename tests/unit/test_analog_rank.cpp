// The rank candidate's table and ranks (the radix sort behind them, sort_unique in
// analog_repr.cpp) against std::sort and std::unique, on channels of many shapes: walks whose
// high digits repeat, random values, float32 and doubles, both signs, odd and even lengths,
// short ones (8-bit digits) and long ones (11-bit digits).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "coding/analog/analog_repr.h"

namespace capz {
namespace analog {
namespace {

void expect_rank_as_sorted(const std::vector<double>& x, const std::string& what) {
  std::vector<uint64_t> ord(x.size());
  for (size_t i = 0; i < x.size(); ++i) ord[i] = ordered_bits(bits_of(x[i]));
  std::vector<uint64_t> want = ord;
  std::sort(want.begin(), want.end());
  want.erase(std::unique(want.begin(), want.end()), want.end());
  const ChannelRepr* rank = nullptr;
  const std::vector<ChannelRepr> cands =
      candidate_representations(x.data(), 1, x.size(), ChannelHint());
  for (const ChannelRepr& c : cands)
    if (c.kind == Kind::kRank) rank = &c;
  ASSERT_NE(rank, nullptr) << what << ": no rank candidate";
  ASSERT_EQ(rank->table.size(), want.size()) << what;
  for (size_t k = 0; k < want.size(); ++k)
    ASSERT_EQ(ordered_bits(bits_of(rank->table[k])), want[k]) << what << ", entry " << k;
  ASSERT_EQ(rank->ints.size(), x.size()) << what;
  for (size_t i = 0; i < x.size(); ++i) {
    const size_t k =
        static_cast<size_t>(std::lower_bound(want.begin(), want.end(), ord[i]) - want.begin());
    ASSERT_EQ(rank->ints[i], static_cast<int32_t>(k)) << what << ", sample " << i;
  }
}

TEST(AnalogRank, GivenChannelsOfManyShapesWhenRankedThenAsSortAndUnique) {
  std::mt19937 rng(21);
  int shapes = 0;
  for (size_t n : {size_t{5}, size_t{600}, size_t{601}, size_t{2047}, size_t{2048}, size_t{9001},
                   size_t{20000}}) {
    for (int shape = 0; shape < 6; ++shape) {
      // A pool of at most n / 3 distinct non-integer values, drawn by a walk or at random.
      const size_t m = std::max<size_t>(2, n / 3);
      std::vector<double> pool(m);
      std::uniform_real_distribution<double> u(-1.0, 1.0);
      for (size_t k = 0; k < m; ++k) {
        double v = shape == 0   ? 0.001 * static_cast<double>(k) + 0.5e-3  // one sign, a walk
                   : shape == 1 ? u(rng)                                   // doubles
                   : shape == 2 ? static_cast<double>(static_cast<float>(u(rng)))  // float32
                   : shape == 3 ? std::ldexp(u(rng), static_cast<int>(k % 40) - 20)
                   : shape == 4 ? 1e6 + 0.25 + static_cast<double>(k)  // high digits shared
                                : -3.75 - 1e-7 * static_cast<double>(k);
        pool[k] = v;
      }
      std::vector<double> x(n);
      size_t at = 0;
      for (size_t i = 0; i < n; ++i) {
        // Walks through the pool (neighbours share their high digits) or jumps at random.
        const int r = static_cast<int>(rng() % 8);
        at = shape % 2 == 0 && r < 7 ? (at + m + static_cast<size_t>(r) % 3 - 1) % m : rng() % m;
        x[i] = pool[at];
      }
      x[0] = pool[0];
      x[n - 1] = pool[m - 1];
      expect_rank_as_sorted(x, "n " + std::to_string(n) + ", shape " + std::to_string(shape));
      ++shapes;
    }
  }
  EXPECT_EQ(shapes, 42);
}

}  // namespace
}  // namespace analog
}  // namespace capz

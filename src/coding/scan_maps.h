// The scan coder's ring x column maps (docs/FORMAT.md "Scans (format 1.1)"): the smoothed range
// each cell of the previous sweep held (a running mean of the cell's last ranges, in 1/16 of a
// grid step), and this sweep's as it is coded. Shared by the encoder and the
// decoder through scan::State.
//
// Memory: a map of the table's rings x columns cells (up to kMaxMapCells) has its set flags
// zero-filled by calloc (its ranges and counts are not filled: read only where set), and a
// sweep's set flags are cleared cell by cell from the list of the cells it wrote, not map-wide:
// a sweep costs time in proportion to its points, not to the table's cells.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <vector>

namespace capz {
namespace scan {

class SweepMaps {
 public:
  // Ready for a table of `cells` cells, nothing set in either map. Buffers are kept when they
  // are large enough (an encoder's maps serve each table it tries). Throws std::bad_alloc.
  void reset(size_t cells);
  // The previous sweep's smoothed range at cell i, in 1/16 steps (false: none there).
  bool prev(size_t i, int64_t* smooth) const {
    if (!prev_.set[i]) return false;
    *smooth = prev_.smooth[i];
    return true;
  }
  // Sets cell i of this sweep from its range and the previous sweep's cell j (i, or another
  // on a turning sensor's frame): the mean of up to kMeanOf ranges while each is within
  // kMeanReach steps of the mean, else the range.
  void set(size_t i, size_t j, int32_t range) {
    int64_t v = int64_t{range} * 16;
    uint8_t n = 1;
    if (prev_.set[j]) {
      const int64_t d = v - prev_.smooth[j];
      if (d <= kMeanReach * 16 && d >= -kMeanReach * 16) {
        n = static_cast<uint8_t>(std::min(prev_.count[j] + 1, kMeanOf));
        v = prev_.smooth[j] + d / n;  // rounded toward zero
      }
    }
    cur_.smooth[i] = v;
    cur_.count[i] = n;
    if (!cur_.set[i]) {
      cur_.set[i] = 1;
      cur_.succ[i] = 0;
      cur_.wrote.push_back(static_cast<uint32_t>(i));
    }
  }
  // The successor ring of the previous sweep's cell i (FORMAT.md "The previous sweep's
  // successors"; false: none), and this sweep's cell i's, set (cell i set in this sweep).
  bool prev_successor(size_t i, uint32_t* ring) const {
    if (!prev_.set[i] || prev_.succ[i] == 0) return false;
    *ring = prev_.succ[i] - 1u;
    return true;
  }
  void set_successor(size_t i, uint32_t ring) { cur_.succ[i] = static_cast<uint16_t>(ring + 1); }
  // This sweep's map becomes the previous one; the new sweep's is empty.
  void end_sweep();
  // Forgets what this sweep wrote.
  void clear_sweep() { cur_.clear(); }

 private:
  struct Free {
    void operator()(void* p) const { std::free(p); }
  };
  static constexpr int kMeanOf = 8, kMeanReach = 8;
  struct Map {
    std::unique_ptr<int64_t[], Free> smooth_buf;
    std::unique_ptr<uint8_t[], Free> set_buf, count_buf;
    std::unique_ptr<uint16_t[], Free> succ_buf;
    int64_t* smooth = nullptr;
    uint8_t* set = nullptr;
    uint8_t* count = nullptr;
    uint16_t* succ = nullptr;     // the successor ring + 1 (0: none), where set
    std::vector<uint32_t> wrote;  // the cells set, each once
    void clear() {
      for (uint32_t i : wrote) set[i] = 0;
      wrote.clear();
    }
  };
  Map prev_, cur_;
  size_t capacity_ = 0;
};

}  // namespace scan
}  // namespace capz

// The scan coder's ring x column maps (coding/scan_maps.h).
#include "coding/scan_maps.h"

#include <new>
#include <utility>

namespace capz {
namespace scan {

void SweepMaps::reset(size_t cells) {
  if (cells <= capacity_) {
    prev_.clear();
    cur_.clear();
    return;
  }
  for (Map* m : {&prev_, &cur_}) {
    m->smooth_buf.reset();
    m->set_buf.reset();
    m->count_buf.reset();
    m->succ_buf.reset();
    // Only the set flags start zeroed: a cell's smoothed range, count and successor are read
    // only when it is set, and written when it is set (zeroing them cost 4 % of a pandar64
    // sweep's encode).
    m->smooth_buf.reset(static_cast<int64_t*>(std::malloc(cells * sizeof(int64_t))));
    m->set_buf.reset(static_cast<uint8_t*>(std::calloc(cells, 1)));
    m->count_buf.reset(static_cast<uint8_t*>(std::malloc(cells)));
    m->succ_buf.reset(static_cast<uint16_t*>(std::malloc(cells * sizeof(uint16_t))));
    if (!m->smooth_buf || !m->set_buf || !m->count_buf || !m->succ_buf) throw std::bad_alloc();
    m->smooth = m->smooth_buf.get();
    m->set = m->set_buf.get();
    m->count = m->count_buf.get();
    m->succ = m->succ_buf.get();
    m->wrote.clear();
  }
  capacity_ = cells;
}

void SweepMaps::end_sweep() {
  std::swap(prev_, cur_);
  cur_.clear();
}

}  // namespace scan
}  // namespace capz

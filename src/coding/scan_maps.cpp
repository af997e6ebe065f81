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
    m->range_buf.reset();
    m->set_buf.reset();
    m->range_buf.reset(static_cast<int32_t*>(std::calloc(cells, sizeof(int32_t))));
    m->set_buf.reset(static_cast<uint8_t*>(std::calloc(cells, 1)));
    if (!m->range_buf || !m->set_buf) throw std::bad_alloc();
    m->range = m->range_buf.get();
    m->set = m->set_buf.get();
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

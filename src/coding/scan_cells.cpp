// Cells with counts, the decoding side (scan_cells.h).
#include "coding/scan_cells.h"

#include <algorithm>

namespace capz {
namespace scan {

void expand_cells(IntDecoder* counts, uint32_t copies, size_t n, int32_t* q, uint8_t* valid,
                  std::vector<uint32_t>* scratch) {
  const size_t m = n - copies;
  scratch->assign(m, 0);
  uint32_t left = copies;
  for (size_t i = 0; i < m; ++i) {
    if (!valid[i]) continue;
    const uint32_t c = counts->get(cell_context(q + 3 * i));
    if (c > left) counts->corrupt("a cell's count exceeds the frame's copies");
    (*scratch)[i] = c;
    left -= c;
  }
  if (left != 0) counts->corrupt("the cells' counts fall short of the frame's copies");
  // From the back: point i goes to i + (the counts of the points before it), never below i.
  size_t to = n;
  for (size_t i = m; i-- > 0;) {
    for (uint32_t k = 0; k <= (*scratch)[i]; ++k) {
      --to;
      std::copy_n(q + 3 * i, 3, q + 3 * to);
      valid[to] = valid[i];
    }
  }
}

}  // namespace scan
}  // namespace capz

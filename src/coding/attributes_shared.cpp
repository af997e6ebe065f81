// What ATTR's encoder and decoder share beyond attributes_lanes.h (docs/FORMAT.md 13): which
// fields of a PCD layout are attributes.
#include "coding/attributes.h"

namespace capz {

std::vector<AttrSpec> attribute_specs(const std::vector<PCDField>& fields) {
  std::vector<AttrSpec> out;
  for (const PCDField& f : fields)
    if (f.name != "x" && f.name != "y" && f.name != "z") out.push_back(f);
  return out;
}

}  // namespace capz

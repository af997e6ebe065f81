// What ATTR's encoder and decoder share beyond attributes_lanes.h (docs/FORMAT.md 13): which
// fields of a PCD layout are attributes, and predictor 12's range prediction (compiled without
// fused multiply-add, CMakeLists.txt, so every build computes the same).
#include <cmath>

#include "coding/attributes.h"
#include "coding/attributes_quantum.h"

namespace capz {

std::vector<AttrSpec> attribute_specs(const std::vector<PCDField>& fields) {
  std::vector<AttrSpec> out;
  for (const PCDField& f : fields)
    if (f.name != "x" && f.name != "y" && f.name != "z") out.push_back(f);
  return out;
}

namespace attr {

int32_t quantum_range_k(const double* xyz, double quantum, double offset) {
  const double r = std::sqrt((xyz[0] * xyz[0] + xyz[1] * xyz[1]) + xyz[2] * xyz[2]);
  const double t = (r - offset) / quantum;
  if (std::isnan(t)) return 0;
  if (t >= 2147483647.0) return INT32_MAX;
  if (t <= -2147483648.0) return INT32_MIN;
  return static_cast<int32_t>(std::floor(t + 0.5));
}

}  // namespace attr
}  // namespace capz

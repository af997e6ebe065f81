// Encoder library (capz): loads the PCL geometry module (codec/pcl_geom.h) on first use.
#include "codec/pcl_geom.h"

#include <string>

#include "core/modules.h"

namespace capz {
namespace geom {
namespace {

constexpr const char* kModuleName = "libcapz_pcl_geom.so";

}  // namespace

const Backend& backend(const std::string& what) {
  return module_backend<Backend>(kModuleName, CAPZ_MODULE_ENTRY_STR(CAPZ_GEOM_BACKEND_ENTRY), what,
                                 "needs");
}

}  // namespace geom
}  // namespace capz

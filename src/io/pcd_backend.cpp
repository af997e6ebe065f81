// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// Loads the PCL-backed PCD module (pcd_backend.h) on first use.
#include "io/pcd_backend.h"

#include <string>

#include "core/modules.h"

namespace capz {
namespace pcd {
namespace {

constexpr const char* kModuleName = "libcapz_pcl_io.so";

}  // namespace

const Backend& backend(const std::string& file) {
  return module_backend<Backend>(kModuleName, CAPZ_MODULE_ENTRY_STR(CAPZ_PCD_BACKEND_ENTRY), file,
                                 "PCD files need");
}

}  // namespace pcd
}  // namespace capz

// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// Loads the PCL-backed PCD module (pcd_backend.h) on first use.
#include "io/pcd_backend.h"

#include <mutex>
#include <string>

#include "capz/error.h"
#include "core/modules.h"

namespace capz {
namespace pcd {
namespace {

constexpr const char* kModuleName = "libcapz_pcl_io.so";

#define CAPZ_STR2(x) #x
#define CAPZ_STR(x) CAPZ_STR2(x)

}  // namespace

const Backend& backend(const std::string& file) {
  static std::once_flag once;
  static const Backend* loaded = nullptr;
  static std::string error;  // why it could not be loaded
  std::call_once(once, [] {
    loaded = open_backend<Backend>(kModuleName, CAPZ_STR(CAPZ_PCD_BACKEND_ENTRY), &error);
  });
  if (!loaded)
    fail(ErrorCode::kIo, file,
         std::string("PCD files need capz's PCL module ") + kModuleName +
             ", which could not be loaded: " + error);
  return *loaded;
}

}  // namespace pcd
}  // namespace capz

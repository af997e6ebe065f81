// Encoder library (capz): loads the PCL geometry module (codec/pcl_geom.h) on first use.
#include "codec/pcl_geom.h"

#include <mutex>
#include <string>

#include "capz/error.h"
#include "core/modules.h"

namespace capz {
namespace geom {
namespace {

constexpr const char* kModuleName = "libcapz_pcl_geom.so";

#define CAPZ_GEOM_STR2(x) #x
#define CAPZ_GEOM_STR(x) CAPZ_GEOM_STR2(x)

}  // namespace

const Backend& backend(const std::string& what) {
  static std::once_flag once;
  static const Backend* loaded = nullptr;
  static std::string error;  // why it could not be loaded
  std::call_once(once, [] {
    loaded = open_backend<Backend>(kModuleName, CAPZ_GEOM_STR(CAPZ_GEOM_BACKEND_ENTRY), &error);
  });
  if (!loaded)
    fail(ErrorCode::kIo, what,
         std::string("needs capz's PCL module ") + kModuleName +
             ", which could not be loaded: " + error);
  return *loaded;
}

}  // namespace geom
}  // namespace capz

#include "capz/version.h"

#define CAPZ_STR_(x) #x
#define CAPZ_STR(x) CAPZ_STR_(x)

namespace capz {

Version library_version() {
  return kVersion;
}

const char* version_string() {
  return CAPZ_STR(CAPZ_VERSION_MAJOR) "." CAPZ_STR(CAPZ_VERSION_MINOR) "." CAPZ_STR(
      CAPZ_VERSION_PATCH);
}

}  // namespace capz

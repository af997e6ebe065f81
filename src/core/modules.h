// capz's modules: shared objects that hold the calls into PCL, opened with dlopen the first time
// they are needed, so a process that never reads a PCD file through PCL or runs PCL's geometry
// does not load PCL at all (io/pcd_backend.h, codec/pcl_geom.h say why each exists).
#pragma once

#include <mutex>
#include <string>

#include "capz/error.h"

// A module entry point's name (a macro carrying the interface version) as a string.
#define CAPZ_MODULE_ENTRY_STR2(x) #x
#define CAPZ_MODULE_ENTRY_STR(x) CAPZ_MODULE_ENTRY_STR2(x)

namespace capz {

// The address of the C symbol `entry` in module `file` (e.g. "libcapz_pcl_io.so"), from the
// first folder that holds a copy dlopen opens, in this order: $CAPZ_MODULE_DIR (a program linked
// against a relocated install), beside the executable (a copied capz carries its modules along),
// the install's module folder relative to the executable (<prefix>/bin/capz finds
// <prefix>/<libdir>/capz) and where the library was configured to be installed, then the build
// tree the library was compiled in (tests and tools run from there). nullptr when none does,
// with *error saying why, folder by folder. The module stays loaded for the process's life.
void* open_module(const std::string& file, const std::string& entry, std::string* error);

// A module's backend, opened once (thread-safe) on the first call for that Backend type: the
// module `file`'s C function `entry` returns a static Backend. When it cannot be opened, every
// call throws Error(kIo) naming `what`: "<need> capz's PCL module <file>, which could not be
// loaded: <why>".
template <class Backend>
const Backend& module_backend(const char* file, const char* entry, const std::string& what,
                              const char* need) {
  static std::once_flag once;
  static const Backend* loaded = nullptr;
  static std::string error;  // why it could not be opened
  std::call_once(once, [&] {
    if (void* sym = open_module(file, entry, &error))
      loaded = reinterpret_cast<const Backend* (*)()>(sym)();
  });
  if (!loaded)
    fail(
        ErrorCode::kIo, what,
        std::string(need) + " capz's PCL module " + file + ", which could not be loaded: " + error);
  return *loaded;
}

}  // namespace capz

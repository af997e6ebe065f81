// capz's modules: shared objects that hold the calls into PCL, opened with dlopen the first time
// they are needed, so a process that never reads a PCD file through PCL or runs PCL's geometry
// does not load PCL at all (io/pcd_backend.h, codec/pcl_geom.h say why each exists).
#pragma once

#include <string>

namespace capz {

// The address of the C symbol `entry` in module `file` (e.g. "libcapz_pcl_io.so"), from the
// first folder that holds a copy dlopen opens, in this order: $CAPZ_MODULE_DIR (a program linked
// against a relocated install), beside the executable (a copied capz carries its modules along),
// the install's module folder relative to the executable (<prefix>/bin/capz finds
// <prefix>/<libdir>/capz) and where the library was configured to be installed, then the build
// tree the library was compiled in (tests and tools run from there). nullptr when none does,
// with *error saying why, folder by folder. The module stays loaded for the process's life.
void* open_module(const std::string& file, const std::string& entry, std::string* error);

// A module's backend: its entry point `entry` is a C function returning a static Backend.
// nullptr (and *error) when the module cannot be opened.
template <class Backend>
const Backend* open_backend(const std::string& file, const std::string& entry, std::string* error) {
  void* sym = open_module(file, entry, error);
  return sym ? reinterpret_cast<const Backend* (*)()>(sym)() : nullptr;
}

}  // namespace capz

// Decoder library (capz_decode): builds without PCL and without the transform encoders.
// Loads the PCL-backed PCD module (pcd_backend.h) on first use.
#include "io/pcd_backend.h"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <mutex>
#include <string>
#include <vector>

#include "capz/error.h"

#ifndef CAPZ_MODULE_DIR
#define CAPZ_MODULE_DIR ""
#endif
#ifndef CAPZ_MODULE_REL_DIR
#define CAPZ_MODULE_REL_DIR ""
#endif
#ifndef CAPZ_MODULE_INSTALL_DIR
#define CAPZ_MODULE_INSTALL_DIR ""
#endif

namespace capz {
namespace pcd {
namespace {

constexpr const char* kModuleName = "libcapz_pcl_io.so";

#define CAPZ_STR2(x) #x
#define CAPZ_STR(x) CAPZ_STR2(x)

// Directory of the running executable ("" if unknown).
std::string exe_dir() {
  std::string buf(4096, '\0');
  const ssize_t n = readlink("/proc/self/exe", &buf[0], buf.size());
  if (n <= 0 || static_cast<size_t>(n) >= buf.size()) return std::string();
  buf.resize(static_cast<size_t>(n));
  const size_t slash = buf.rfind('/');
  return slash == std::string::npos ? std::string() : buf.substr(0, slash);
}

struct Loaded {
  const Backend* backend = nullptr;
  std::string error;  // why it could not be loaded
};

// The folders to look in, in order: $CAPZ_MODULE_DIR (a program linked against a relocated
// install), beside the executable (a copied capz carries its module along), the install's module
// folder relative to the executable (<prefix>/bin/capz finds <prefix>/<libdir>/capz) and where
// the library was configured to be installed, then the build tree the library was compiled in
// (tests and tools run from there).
std::vector<std::string> module_dirs() {
  std::vector<std::string> dirs;
  auto add = [&dirs](const std::string& d) {
    if (!d.empty() && std::find(dirs.begin(), dirs.end(), d) == dirs.end()) dirs.push_back(d);
  };
  if (const char* env = std::getenv("CAPZ_MODULE_DIR")) add(env);
  const std::string own = exe_dir();
  add(own);
  const std::string rel = CAPZ_MODULE_REL_DIR;
  if (!own.empty() && !rel.empty()) add(own + "/" + rel);
  add(CAPZ_MODULE_INSTALL_DIR);
  add(CAPZ_MODULE_DIR);
  return dirs;
}

Loaded load() {
  Loaded l;
  const std::vector<std::string> dirs = module_dirs();
  for (const std::string& d : dirs) {
    const std::string path = d + "/" + kModuleName;
    if (access(path.c_str(), F_OK) != 0) {
      l.error += (l.error.empty() ? "" : "; ") + path + " does not exist";
      continue;
    }
    void* h = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!h) {
      const char* e = dlerror();
      l.error += (l.error.empty() ? "" : "; ") + std::string(e ? e : path + ": dlopen failed");
      continue;
    }
    void* sym = dlsym(h, CAPZ_STR(CAPZ_PCD_BACKEND_ENTRY));
    if (!sym) {
      l.error += (l.error.empty() ? "" : "; ") + path + " has no " +
                 CAPZ_STR(CAPZ_PCD_BACKEND_ENTRY) + " (built from other sources?)";
      dlclose(h);
      continue;
    }
    // The module stays loaded for the life of the process (its backend is a static object).
    l.backend = reinterpret_cast<BackendEntry>(sym)();
    l.error.clear();
    return l;
  }
  if (dirs.empty()) l.error = "no directory to look in";
  return l;
}

}  // namespace

const Backend& backend(const std::string& file) {
  static std::once_flag once;
  static Loaded loaded;
  std::call_once(once, [] { loaded = load(); });
  if (!loaded.backend)
    fail(ErrorCode::kIo, file,
         std::string("PCD files need capz's PCL module ") + kModuleName +
             ", which could not be "
             "loaded: " +
             loaded.error);
  return *loaded.backend;
}

}  // namespace pcd
}  // namespace capz

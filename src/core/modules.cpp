// capz's modules (core/modules.h).
#include "core/modules.h"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

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
namespace {

// Directory of the running executable ("" if unknown).
std::string exe_dir() {
  std::string buf(4096, '\0');
  const ssize_t n = readlink("/proc/self/exe", &buf[0], buf.size());
  if (n <= 0 || static_cast<size_t>(n) >= buf.size()) return std::string();
  buf.resize(static_cast<size_t>(n));
  const size_t slash = buf.rfind('/');
  return slash == std::string::npos ? std::string() : buf.substr(0, slash);
}

// The folders to look in, in open_module's order.
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

}  // namespace

void* open_module(const std::string& file, const std::string& entry, std::string* error) {
  error->clear();
  auto why = [error](const std::string& s) { *error += (error->empty() ? "" : "; ") + s; };
  const std::vector<std::string> dirs = module_dirs();
  for (const std::string& d : dirs) {
    const std::string path = d + "/" + file;
    if (access(path.c_str(), F_OK) != 0) {
      why(path + " does not exist");
      continue;
    }
    void* h = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!h) {
      const char* e = dlerror();
      why(e ? std::string(e) : path + ": dlopen failed");
      continue;
    }
    void* sym = dlsym(h, entry.c_str());
    if (!sym) {
      why(path + " has no " + entry + " (built from other sources?)");
      dlclose(h);
      continue;
    }
    error->clear();
    return sym;
  }
  if (dirs.empty()) why("no directory to look in");
  return nullptr;
}

}  // namespace capz

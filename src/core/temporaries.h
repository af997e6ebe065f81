// The temporaries of outputs not yet in place (AtomicFile's and AtomicDir's "<path>.tmp-XXXXXX",
// the folder an AtomicDir moves an old output to, the CLI's pipe folder): registered from their
// creation to their rename into place or their removal, so that remove_temporaries_on_signals()
// (capz/tool/file.h) removes what is registered when SIGINT, SIGTERM, SIGHUP, SIGQUIT or SIGPIPE
// ends the process.
// Each step runs under the registry's lock, which that removal takes too (and keeps until the
// process ends): it sees a temporary either registered or not made yet, never half.
#pragma once

#include <functional>
#include <string>

namespace capz::temporaries {

// Runs `make`, which creates a temporary and returns its path (or throws: nothing registered),
// and registers that path.
std::string create(const std::function<std::string()>& make);

// A fresh private folder made from `templ` (a path ending in XXXXXX, as mkdtemp(3) takes) and
// registered (create's); Error(kIo) naming `name` when it cannot be made.
std::string create_folder(const std::string& templ, const std::string& name);

// Runs `settle` (a rename of `path` into place), then unregisters `path` and registers what
// `settle` returns instead (a path still to remove: an old output moved aside), "" for none.
// When `settle` throws, `path` stays registered.
void settle(const std::string& path, const std::function<std::string()>& settle);

// Removes `path` (a file, or a folder with what it holds; an absent path is no error) and
// unregisters it.
void remove(const std::string& path);

}  // namespace capz::temporaries

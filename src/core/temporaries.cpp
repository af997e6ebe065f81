// Decoder library (capz_decode): builds without PCL and without the transform encoders.
#include "core/temporaries.h"

#include <pthread.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

#include "capz/error.h"
#include "capz/tool/file.h"

namespace fs = std::filesystem;

namespace capz {

namespace {

struct Registry {
  std::mutex lock;
  std::vector<std::string> paths;    // in registration order: a folder before what it holds
  std::vector<std::string> folders;  // create_output_folders', in creation order
};

// Never destroyed: a signal may come while the process exits, after static destructors ran.
Registry& registry() {
  static Registry* r = new Registry;
  return *r;
}

void drop(std::vector<std::string>* paths, const std::string& path) {
  const auto at = std::find(paths->begin(), paths->end(), path);
  if (at != paths->end()) paths->erase(at);
}

void remove_path(const std::string& path) {
  std::error_code ec;
  fs::remove_all(path, ec);
}

// The folders of `folders` that are empty, deepest first (rmdir(2) removes nothing else); all of
// them forgotten.
void remove_empty(std::vector<std::string>* folders) {
  for (auto p = folders->rbegin(); p != folders->rend(); ++p) ::rmdir(p->c_str());
  folders->clear();
}

// The signal thread: waits for one of `signals`, removes every registered temporary while holding
// the registry's lock (so no temporary is made or renamed into place meanwhile, nor after), then
// ends the process by that signal with its default action.
[[noreturn]] void wait_and_clean(sigset_t signals) {
  int sig = 0;
  while (sigwait(&signals, &sig) != 0) {
  }
  Registry& r = registry();
  r.lock.lock();  // kept: the process ends holding it
  for (auto p = r.paths.rbegin(); p != r.paths.rend(); ++p) remove_path(*p);
  remove_empty(&r.folders);
  std::signal(sig, SIG_DFL);
  sigset_t one;
  sigemptyset(&one);
  sigaddset(&one, sig);
  pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
  raise(sig);  // this thread's, unblocked now with the default action: the process ends
  _exit(128 + sig);
}

// The signal thread, which alone blocks SIGPIPE once remove_temporaries_on_signals() handles it.
pthread_t cleaner;

// SIGPIPE: a write to a pipe (or socket) nobody reads any more, raised in the writing thread,
// which sigwait() in another thread cannot take. It is handed to the signal thread, and the
// writing thread waits here for the process to end, so it goes on with nothing (no error message
// after its write fails, no output of the next step); no write of capz's happens under the
// registry's lock. The kernel sends it as from this process; one sent by another (kill -PIPE) may
// have stopped this thread anywhere, holding that lock even, so the thread goes on then.
// pthread_kill, getpid and pause are async-signal-safe.
extern "C" void on_broken_pipe(int, siginfo_t* info, void*) {
  pthread_kill(cleaner, SIGPIPE);
  if (info && info->si_pid == getpid())
    for (;;) pause();
}

// Whether `sig` is at its default action and not blocked in the calling thread (one ignored,
// blocked or handled by whoever started the process is left to it).
bool at_default(int sig, const sigset_t& blocked) {
  struct sigaction now {};
  return sigaction(sig, nullptr, &now) == 0 && now.sa_handler == SIG_DFL &&
         !sigismember(&blocked, sig);
}

}  // namespace

namespace temporaries {

std::string create(const std::function<std::string()>& make) {
  Registry& r = registry();
  std::lock_guard<std::mutex> hold(r.lock);
  std::string path = make();
  r.paths.push_back(path);
  return path;
}

std::string create_folder(const std::string& templ, const std::string& name) {
  return create([&] {
    std::vector<char> buf(templ.begin(), templ.end());
    buf.push_back('\0');
    if (!::mkdtemp(buf.data()))
      fail(ErrorCode::kIo, name,
           std::string("cannot create a temporary folder: ") + std::strerror(errno));
    return std::string(buf.data());
  });
}

void settle(const std::string& path, const std::function<std::string()>& settle) {
  Registry& r = registry();
  std::lock_guard<std::mutex> hold(r.lock);
  std::string instead = settle();
  drop(&r.paths, path);
  if (!instead.empty()) r.paths.push_back(std::move(instead));
}

void remove(const std::string& path) {
  Registry& r = registry();
  std::lock_guard<std::mutex> hold(r.lock);
  remove_path(path);
  drop(&r.paths, path);
}

}  // namespace temporaries

void remove_temporaries_on_signals() {
  static std::once_flag once;
  std::call_once(once, [] {
    // A signal ignored or blocked at start stays so (nohup's SIGHUP, SIGINT in a script's
    // background job, a parent's mask): only those that would end the process are waited for.
    sigset_t signals, blocked;
    sigemptyset(&signals);
    pthread_sigmask(SIG_BLOCK, nullptr, &blocked);
    for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT})
      if (at_default(sig, blocked)) sigaddset(&signals, sig);
    const bool pipe = at_default(SIGPIPE, blocked);
    if (pipe) sigaddset(&signals, SIGPIPE);
    if (sigisemptyset(&signals)) return;
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);  // the signal thread starts with them blocked
    std::thread waiter(wait_and_clean, signals);
    cleaner = waiter.native_handle();
    waiter.detach();
    if (!pipe) return;
    // Every other thread takes SIGPIPE in on_broken_pipe, which passes it to the signal thread.
    struct sigaction handed {};
    handed.sa_sigaction = on_broken_pipe;
    handed.sa_flags = SA_SIGINFO;
    sigemptyset(&handed.sa_mask);
    sigaction(SIGPIPE, &handed, nullptr);
    sigset_t one;
    sigemptyset(&one);
    sigaddset(&one, SIGPIPE);
    pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
  });
}

void create_output_folders(const std::string& path) {
  Registry& r = registry();
  std::lock_guard<std::mutex> hold(r.lock);
  fs::path made;
  for (const fs::path& part : fs::path(path)) {
    made /= part;
    std::error_code ec;
    if (fs::create_directory(made, ec))
      r.folders.push_back(made.string());
    else if (ec)
      fail(ErrorCode::kIo, made.string(), "cannot create: " + ec.message());
  }
}

void remove_empty_output_folders() {
  Registry& r = registry();
  std::lock_guard<std::mutex> hold(r.lock);
  remove_empty(&r.folders);
}

TemporaryFolder::TemporaryFolder(const std::string& templ)
    : path_(temporaries::create_folder(templ, templ)) {}

TemporaryFolder::~TemporaryFolder() {
  temporaries::remove(path_);
}

}  // namespace capz

// Replays fuzz inputs through a target's LLVMFuzzerTestOneInput without libFuzzer, so the
// committed corpus (seeds and every fixed crash) runs as an ordinary ctest test in any build.
//
//   capz_fuzz_replay_<target> <file or directory>...
//
// Directories are read non-recursively, files in name order. Each input is copied into a heap
// buffer of exactly its size so a sanitizer build catches any read past its end. A target
// signals a failure by aborting (or by an exception other than capz::Error escaping), which
// ends this process with a non-zero status naming the input. An input that runs longer than
// CAPZ_REPLAY_TIMEOUT seconds (default 30) is a hang: SIGALRM ends the process.
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  std::vector<std::string> inputs;
  for (int i = 1; i < argc; ++i) {
    std::error_code ec;
    if (fs::is_directory(argv[i], ec)) {
      std::vector<std::string> files;
      for (const auto& entry : fs::directory_iterator(argv[i]))
        if (entry.is_regular_file()) files.push_back(entry.path().string());
      std::sort(files.begin(), files.end());
      inputs.insert(inputs.end(), files.begin(), files.end());
    } else if (fs::is_regular_file(argv[i], ec)) {
      inputs.push_back(argv[i]);
    } else {
      std::fprintf(stderr, "replay: %s: no such file or directory\n", argv[i]);
      return 2;
    }
  }
  if (inputs.empty()) {
    std::fprintf(stderr,
                 "replay: no inputs (an empty corpus replays nothing and proves nothing)\n");
    return 2;
  }
  unsigned timeout = 30;
  if (const char* env = std::getenv("CAPZ_REPLAY_TIMEOUT"))
    timeout = static_cast<unsigned>(std::atoi(env));
  for (const std::string& path : inputs) {
    std::ifstream in(path, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in.eof() && in.fail()) {
      std::fprintf(stderr, "replay: cannot read %s\n", path.c_str());
      return 2;
    }
    std::fprintf(stderr, "replay: %s (%zu bytes)\n", path.c_str(), bytes.size());
    // Exact-size heap copy (new[] of 0 is valid and distinct from nullptr).
    std::unique_ptr<uint8_t[]> buf(new uint8_t[bytes.size()]);
    if (!bytes.empty()) std::memcpy(buf.get(), bytes.data(), bytes.size());
    alarm(timeout);
    LLVMFuzzerTestOneInput(buf.get(), bytes.size());
    alarm(0);
  }
  std::fprintf(stderr, "replay: %zu inputs, all passed\n", inputs.size());
  return 0;
}

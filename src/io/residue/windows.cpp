// The residue's window loop on the decoding side (windows.h); windows_encode.cpp is the
// encoder's.
#include "io/residue/windows.h"

#include "capz/error.h"

namespace capz {
namespace residue {

void rebuild_windows(const FileResidue& residue, FrameSource& frames, size_t block,
                     const std::function<void(const FrameBlock&, const std::vector<uint8_t>&,
                                              std::vector<uint8_t>*)>& rebuild,
                     const std::function<void(const uint8_t*, size_t)>& write,
                     const std::string& name) {
  const size_t F = frames.header().frames;
  if (block == 0 || (F + block - 1) / block != residue.windows.size())
    fail(ErrorCode::kCorrupt, name,
         "residue: " + std::to_string(residue.windows.size()) + " windows for " +
             std::to_string(F) + " frames in blocks of " + std::to_string(block));
  FrameBlock b;
  std::vector<uint8_t> bytes;
  for (size_t f = 0, w = 0; f < F; f += block, ++w) {
    frames.read(f, block, &b);
    bytes.clear();
    rebuild(b, residue.windows[w], &bytes);
    write(bytes.data(), bytes.size());
  }
}

}  // namespace residue
}  // namespace capz

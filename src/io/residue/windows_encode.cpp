// The residue's window loop on the encoding side (windows.h); windows.cpp is the decoder's.
#include "io/residue/windows.h"

namespace capz {
namespace residue {

void encode_windows(FrameSource& frames, size_t block,
                    const std::function<std::vector<uint8_t>(const FrameBlock&)>& encode,
                    FileResidue* r) {
  FrameBlock b;
  for (size_t f = 0; f < frames.header().frames; f += block) {
    frames.read(f, block, &b);
    r->windows.push_back(encode(b));
  }
}

}  // namespace residue
}  // namespace capz

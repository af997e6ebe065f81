// An in-memory take as a frame source that owns it (include/capz/stream.h's take_frames borrows
// one).
#pragma once

#include <memory>

#include "capz/stream.h"
#include "capz/take.h"

namespace capz {

// A ragged take as a source that owns it and hands its arrays over: a read of all its frames at
// once (a one-window encode's only read) moves x y z, the gaps and the fields into the block
// instead of copying them (the take's points held once, not twice). Any read after that throws
// Error(kInternal); reads of fewer frames copy, as take_frames' do.
std::unique_ptr<FrameSource> handing_take_frames(Take take);

}  // namespace capz

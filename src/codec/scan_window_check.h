// The scan encoder's self-check of its windows (scan_encoder.cpp): each window's chunks decoded
// by the one decoder and compared with the frames read, in place or beside the next window's
// coding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <future>
#include <memory>
#include <vector>

#include "capz/metrics.h"
#include "capz/stream.h"
#include "capz/take.h"
#include "codec/stream_reader.h"
#include "core/thread_pool.h"

namespace capz {

// Throws kInternal unless the decoded window d has the counts and gaps of the frames read (b)
// and every valid coordinate within the bound, also as the float32 a PCD writer stores
// (lossless: bit for bit).
void check_window(const Take& t, const FrameBlock& b, const FrameBlock& d, double bound,
                  bool exact);
// Throws kInternal unless the decoded window's fields are `fields`, byte for byte.
void check_fields(const Take& t, const std::vector<std::vector<uint8_t>>& fields,
                  const FrameBlock& d);

// The self-checks of one stream's windows, in window order: window w's chunks (the stream's
// bytes [base, base + size)) decoded, checked against the frames read and the fields the decoder
// must give back (check_window, check_fields), and the window's errors added to *acc. In place,
// check() returns when done and decoded() is the window decoded (the residue writer's). Beside
// (a worker thread), check() takes the block, a copy of the bytes and the fields, and returns at
// once: the check runs while the caller codes the next window; the next check() and finish()
// first wait for it and rethrow what it threw, so the errors and *acc are a serial run's.
class WindowChecks {
 public:
  WindowChecks(const Take& t, const StreamContext& ctx, double bound, bool exact, bool beside,
               ErrorAccumulator* acc);
  // Waits for a check in flight (what it threw is dropped: the caller is unwinding).
  ~WindowChecks();
  WindowChecks(const WindowChecks&) = delete;
  WindowChecks& operator=(const WindowChecks&) = delete;

  void check(size_t w, const uint8_t* bytes, size_t size, size_t base, FrameBlock* b,
             std::vector<std::vector<uint8_t>>* fields);
  // Waits for the last check and rethrows what it threw.
  void finish();
  bool beside() const { return pool_ != nullptr; }
  const FrameBlock& decoded() const { return d_; }
  // In place, frees the window decoded once its caller is done with it: kept, it would lie
  // beside the next window's coding (about 27 bytes a point of the window, 55 MB for 18
  // pandar64 sweeps), which the next check allocates again. Beside, the checks keep theirs.
  void release() {
    if (!pool_) d_ = FrameBlock();
  }

 private:
  void run(size_t w, const uint8_t* bytes, size_t size, size_t base, const FrameBlock& b,
           const std::vector<std::vector<uint8_t>>& fields);

  const Take& t_;
  const StreamContext& ctx_;
  double bound_;
  bool exact_;
  ErrorAccumulator* acc_;
  FrameBlock b_, d_;  // beside: the block in check; the window decoded (its memory reused)
  std::vector<uint8_t> bytes_;
  std::vector<std::vector<uint8_t>> fields_;
  std::future<void> done_;
  std::unique_ptr<ThreadPool> pool_;  // last: destroyed first, joining its worker
};

}  // namespace capz

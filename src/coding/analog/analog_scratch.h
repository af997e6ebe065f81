// Per-thread scratch buffers of the analog encoder: temporaries of a channel reused from
// channel to channel and window to window instead of allocated (and zeroed by std::vector)
// for each candidate. A buffer is not zeroed: its users write every entry they read. Each use
// has its own slot, so buffers live at the same time never alias; a slot's buffer only grows.
#pragma once

#include <cstddef>
#include <vector>

namespace capz {
namespace analog {

enum class Scratch {
  kLpcSamples,       // lpc_stage: the channel's samples as doubles after kMaxLpcOrder zeros
  kWithReference,    // plan_int_channel: the LPC residuals less the reference's prediction
  kPlainCascade,     // plan_int_channel: the cascade over the LPC residuals
  kRefCascade,       // plan_int_channel: the cascade over those with the reference
  kAutocorrelation,  // autocorrelation: the windowed samples, reversed, and zeros after
  kCrossTerms,       // choose_cross: 2 r1 + 1/2
  kRefitSteps,       // refine_fit: each sample's step count
  kRankKeys,         // sort_unique: the radix passes' two arrays
};

// A buffer of at least n values of T for `slot`, this thread's.
template <typename T, Scratch kSlot>
T* scratch(size_t n) {
  thread_local std::vector<T> buf;
  if (buf.size() < n) buf.resize(n + n / 4);
  return buf.data();
}

}  // namespace analog
}  // namespace capz

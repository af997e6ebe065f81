#include "coding/analog/analog_simd.h"

#include <atomic>

#include "coding/analog/analog_cascade.h"

namespace capz {
namespace analog {
namespace {

std::atomic<bool> g_allowed{true};

bool cpu_has_avx2() {
#if defined(__x86_64__) || defined(__i386__)
  static const bool has = [] {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return has;
#else
  return false;
#endif
}

}  // namespace

bool avx2_enabled() {
  return g_allowed.load(std::memory_order_relaxed) && cpu_has_avx2();
}

void allow_avx2(bool allowed) {
  g_allowed.store(allowed, std::memory_order_relaxed);
}

#if defined(__x86_64__) || defined(__i386__)
__attribute__((target("avx2"))) std::pair<uint64_t, uint64_t> sign_lms_run_avx2(const int32_t* in,
                                                                                size_t n,
                                                                                int32_t* out) {
  return sign_lms_kernel<4>(in, n, out);
}
#endif

}  // namespace analog
}  // namespace capz

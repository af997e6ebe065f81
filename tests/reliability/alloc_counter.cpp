// Replacement of the global allocation functions for the reliability tests (see alloc_counter.h).
// Every non-aligned form is replaced, so allocation and deallocation always pair through
// malloc/free (ASan would otherwise report a mismatch between our new and its delete).
#include "alloc_counter.h"

#include <malloc.h>

#include <atomic>
#include <cstdlib>
#include <new>

namespace {

std::atomic<bool> g_armed{false};
std::atomic<int64_t> g_current{0};
std::atomic<int64_t> g_peak{0};
std::atomic<size_t> g_largest{0};
std::atomic<size_t> g_refused{0};
size_t g_refuse_bytes = 0;

void raise_max(std::atomic<int64_t>* m, int64_t v) {
  int64_t old = m->load();
  while (v > old && !m->compare_exchange_weak(old, v)) {
  }
}
void raise_max(std::atomic<size_t>* m, size_t v) {
  size_t old = m->load();
  while (v > old && !m->compare_exchange_weak(old, v)) {
  }
}

void* counted_alloc(size_t n, bool nothrow) {
  if (g_armed.load(std::memory_order_relaxed)) {
    raise_max(&g_largest, n);
    if (n > g_refuse_bytes) {
      raise_max(&g_refused, n);
      if (nothrow) return nullptr;
      throw std::bad_alloc();
    }
  }
  void* p = std::malloc(n ? n : 1);
  if (!p) {
    if (nothrow) return nullptr;
    throw std::bad_alloc();
  }
  if (g_armed.load(std::memory_order_relaxed))
    raise_max(&g_peak, g_current += static_cast<int64_t>(malloc_usable_size(p)));
  return p;
}

void counted_free(void* p) noexcept {
  if (!p) return;
  if (g_armed.load(std::memory_order_relaxed))
    g_current -= static_cast<int64_t>(malloc_usable_size(p));
  std::free(p);
}

}  // namespace

void* operator new(size_t n) {
  return counted_alloc(n, false);
}
void* operator new[](size_t n) {
  return counted_alloc(n, false);
}
void* operator new(size_t n, const std::nothrow_t&) noexcept {
  return counted_alloc(n, true);
}
void* operator new[](size_t n, const std::nothrow_t&) noexcept {
  return counted_alloc(n, true);
}
void operator delete(void* p) noexcept {
  counted_free(p);
}
void operator delete[](void* p) noexcept {
  counted_free(p);
}
void operator delete(void* p, size_t) noexcept {
  counted_free(p);
}
void operator delete[](void* p, size_t) noexcept {
  counted_free(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  counted_free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
  counted_free(p);
}

namespace capz_test {

AllocScope::AllocScope(size_t refuse_bytes) {
  g_refuse_bytes = refuse_bytes;
  g_current = 0;
  g_peak = 0;
  g_largest = 0;
  g_refused = 0;
  g_armed = true;
}

AllocScope::~AllocScope() {
  g_armed = false;
}

AllocReport AllocScope::report() const {
  AllocReport r;
  r.peak_bytes = g_peak.load();
  r.largest_request = g_largest.load();
  r.refused_request = g_refused.load();
  return r;
}

}  // namespace capz_test

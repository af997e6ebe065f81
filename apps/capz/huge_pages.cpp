// The CLI's heap blocks of 2 MiB and more on transparent huge pages, where the kernel offers them
// on request (/sys/kernel/mm/transparent_hugepage/enabled "madvise", or "always", where this
// changes nothing).
//
// Why: coding a scan window touches about 170 bytes a point once (the frames read, the grid
// integers, the laser table's per-point arrays, the self-check's decoded window), and each first
// touch of a 4 KiB page is a page fault: about 40 thousand of them for 20 pandar64 sweeps, at
// about 9 us of CPU each on the benchmark machine (docs/lab/2026-11-29-scan-speed.md). A 2 MiB
// page takes one fault for 512 of those. Blocks are aligned to 2 MiB and sized to a multiple of
// it, so every page of the block can be a huge one (an unaligned block of a few MiB rarely holds
// a whole aligned 2 MiB extent: the first try, which advised unaligned blocks, kept most of the
// faults). The rounding costs at most 2 MiB of address space a block, not memory: pages never
// touched are never backed.
//
// Only the capz executable replaces operator new; the libraries (capz, capz_decode, the Python
// module) leave the allocator to their host.
#include <sys/mman.h>

#include <cstdlib>
#include <new>

namespace {

constexpr std::size_t kHugePage = std::size_t{2} << 20;

void* allocate(std::size_t n) noexcept {
  if (n < kHugePage) return std::malloc(n ? n : 1);
  const std::size_t rounded = (n + kHugePage - 1) / kHugePage * kHugePage;
  if (rounded < n) return nullptr;  // n within 2 MiB of SIZE_MAX
  void* p = nullptr;
  if (posix_memalign(&p, kHugePage, rounded) != 0) return nullptr;
  madvise(p, rounded, MADV_HUGEPAGE);  // advice only: refused, the block is ordinary memory
  return p;
}

void* allocate_or_throw(std::size_t n) {
  for (;;) {
    if (void* p = allocate(n)) return p;
    std::new_handler h = std::get_new_handler();
    if (!h) throw std::bad_alloc();
    h();
  }
}

}  // namespace

void* operator new(std::size_t n) {
  return allocate_or_throw(n);
}
void* operator new[](std::size_t n) {
  return allocate_or_throw(n);
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return allocate_or_throw(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return allocate_or_throw(n);
  } catch (...) {
    return nullptr;
  }
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}

// Counts the heap use of the code run inside an AllocScope (tests/reliability only: this
// executable replaces the global operator new/delete, see alloc_counter.cpp).
//
// While a scope is open, every operator new request is added to a running total (net of frees);
// the scope reports the peak of that total and the largest single request. A single request above
// `refuse_bytes` is not attempted: it throws std::bad_alloc and is recorded as refused, so a
// reader that trusts a hostile count fails the test instead of exhausting the machine. This works
// the same in a plain and an AddressSanitizer build (the replacement allocates with malloc, which
// ASan intercepts), unlike an RLIMIT_AS limit, which ASan's shadow memory makes unusable.
#pragma once

#include <cstddef>
#include <cstdint>

namespace capz_test {

struct AllocReport {
  int64_t peak_bytes = 0;      // highest net bytes allocated since the scope opened
  size_t largest_request = 0;  // the largest single request
  size_t refused_request = 0;  // the largest request refused (0 = none)
};

class AllocScope {
 public:
  explicit AllocScope(size_t refuse_bytes = size_t{256} << 20);
  ~AllocScope();
  AllocScope(const AllocScope&) = delete;
  AllocScope& operator=(const AllocScope&) = delete;
  AllocReport report() const;
};

}  // namespace capz_test

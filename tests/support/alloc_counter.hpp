// Counts global heap allocations, for the "a servo step never allocates" tests.
//
// Include in exactly ONE translation unit of a test program: it replaces the global operator
// new/delete of the whole program, plain and nothrow forms (they count and forward to
// malloc/free; the aligned forms are left to the library and stay consistent with themselves).
// Usage: const long before = test::heap_allocations(); step(...);
//        EXPECT_EQ(test::heap_allocations() - before, 0);
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

namespace inhap::test {

inline std::atomic<long> g_heap_allocations{0};

/// Allocations made so far by this program (all threads).
inline long heap_allocations() {
  return g_heap_allocations.load(std::memory_order_relaxed);
}

inline void* counted_malloc(std::size_t n) {
  g_heap_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}

}  // namespace inhap::test

void* operator new(std::size_t n) {
  return inhap::test::counted_malloc(n);
}
void* operator new[](std::size_t n) {
  return inhap::test::counted_malloc(n);
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

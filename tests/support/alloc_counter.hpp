// Counts global heap allocations, for the "a servo step never allocates" tests.
//
// Include in exactly ONE translation unit of a test program: it replaces every form of the
// global operator new/delete of the whole program (plain, array, nothrow, aligned); they count
// and forward to malloc/aligned_alloc/free. Replacing only some forms would pair the library's
// (or a sanitizer's) new with our free: ASan reports alloc-dealloc-mismatch.
// Usage: const long before = test::heap_allocations(); step(...);
//        EXPECT_EQ(test::heap_allocations() - before, 0);
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

// GCC flags free() on memory from operator new once these replacements are inlined; the pairing
// here is ours and correct.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif

namespace inhap::test {

inline std::atomic<long> g_heap_allocations{0};

/// Allocations made so far by this program (all threads).
inline long heap_allocations() {
  return g_heap_allocations.load(std::memory_order_relaxed);
}

inline void* counted_malloc(std::size_t n, std::size_t align = 0) noexcept {
  g_heap_allocations.fetch_add(1, std::memory_order_relaxed);
  if (n == 0) n = 1;
  if (align <= alignof(std::max_align_t)) return std::malloc(n);
  return std::aligned_alloc(align, (n + align - 1) / align * align);
}

inline void* counted_new(std::size_t n, std::size_t align = 0) {
  if (void* p = counted_malloc(n, align)) return p;
  throw std::bad_alloc();
}

}  // namespace inhap::test

// A second translation unit of the same test program defines INHAP_ALLOC_COUNTER_COUNT_ONLY
// before including this header: it gets the counter, the first one's replacements count.
#ifndef INHAP_ALLOC_COUNTER_COUNT_ONLY
void* operator new(std::size_t n) {
  return inhap::test::counted_new(n);
}
void* operator new[](std::size_t n) {
  return inhap::test::counted_new(n);
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  return inhap::test::counted_malloc(n);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  return inhap::test::counted_malloc(n);
}
void* operator new(std::size_t n, std::align_val_t a) {
  return inhap::test::counted_new(n, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t n, std::align_val_t a) {
  return inhap::test::counted_new(n, static_cast<std::size_t>(a));
}
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return inhap::test::counted_malloc(n, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return inhap::test::counted_malloc(n, static_cast<std::size_t>(a));
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
void operator delete(void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept {
  std::free(p);
}
#endif  // INHAP_ALLOC_COUNTER_COUNT_ONLY

// Storage of MeshIndex's large arrays: huge-page-friendly allocation. Units: bytes.
// See docs/spatial-queries.md ("Layout").
#include <algorithm>
#include <cstddef>
#include <limits>
#include <new>

#include "inhap/geometry/mesh_index.hpp"

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace inhap {

namespace detail {
namespace {
constexpr std::size_t kHugePage = std::size_t{2} << 20;
std::size_t index_alignment(std::size_t bytes, std::size_t min_align) {
  return std::max(bytes >= kHugePage / 2 ? kHugePage : std::size_t{64}, min_align);
}
}  // namespace

void* index_alloc(std::size_t bytes, std::size_t min_align) {
  const std::size_t align = index_alignment(bytes, min_align);
  if (bytes > (std::numeric_limits<std::size_t>::max() >> 2)) throw std::bad_alloc();
  const std::size_t size = (bytes + align - 1) / align * align;
  void* p = ::operator new(size, std::align_val_t(align));
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  if (align == kHugePage) madvise(p, size, MADV_HUGEPAGE);  // advice only: failure is harmless
#endif
  return p;
}

void index_free(void* p, std::size_t bytes, std::size_t min_align) noexcept {
  ::operator delete(p, std::align_val_t(index_alignment(bytes, min_align)));
}
}  // namespace detail

}  // namespace inhap

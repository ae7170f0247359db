// inhap studio: room for the static TLS on threads that ask for a small stack.
// glibc takes a thread's static TLS (64 KB in inhap: CGAL's Delaunay insertion keeps two 32 KB
// thread_local maps) out of the stack size the thread asked for, and civetweb's worker threads
// ask for 100 KB. src/studio/thread_stack.cpp defines pthread_attr_setstacksize for the whole
// program: a request below kSmallStack gets kStaticTlsRoom more; larger ones are unchanged.
// Sizes in bytes.
#pragma once

#include <cstddef>

namespace inhap::studio {

/// Requests below this are raised (bytes).
inline constexpr std::size_t kSmallStack = std::size_t{1} << 20;
/// What a small request is raised by (bytes): the static TLS and a margin as large again.
inline constexpr std::size_t kStaticTlsRoom = std::size_t{128} << 10;

/// The stack size pthread_attr_setstacksize passes on for a request of `asked` bytes.
std::size_t stack_size_granted(std::size_t asked);

}  // namespace inhap::studio

// Room for the static TLS on threads that ask for a small stack (civetweb's workers).
//
// glibc carves a thread's static TLS out of the stack size the thread asked for (glibc bug
// 11787, still so in Debian 12's 2.36). CGAL's Delaunay insertion has two `static thread_local`
// maps of 32 KB each (Triangulation_data_structure_3::_insert_in_small_hole), so every thread
// of a program that reconstructs shapes carries 64 KB of static TLS. civetweb's worker threads
// ask for 100 KB (USE_STACK_SIZE, fixed in Debian's build): 36 KB were left, enough for a plain
// build and not for AddressSanitizer, whose frames overflowed it in civetweb's own WebSocket
// handshake. This definition of pthread_attr_setstacksize, in the program itself, comes before
// the C library's in the dynamic linker's search order; it adds kStaticTlsRoom to every request
// below kSmallStack and passes the call on. Larger requests are passed on unchanged.
#include <dlfcn.h>
#include <pthread.h>

#include <cerrno>
#include <cstddef>

#include "inhap/studio/thread_stack.hpp"

namespace inhap::studio {

std::size_t stack_size_granted(std::size_t asked) {
  return asked < kSmallStack ? asked + kStaticTlsRoom : asked;
}

}  // namespace inhap::studio

extern "C" int pthread_attr_setstacksize(pthread_attr_t* attr, std::size_t size) noexcept {
  using Fn = int (*)(pthread_attr_t*, std::size_t);
  static const Fn next = reinterpret_cast<Fn>(dlsym(RTLD_NEXT, "pthread_attr_setstacksize"));
  if (!next) return ENOSYS;
  return next(attr, inhap::studio::stack_size_granted(size));
}

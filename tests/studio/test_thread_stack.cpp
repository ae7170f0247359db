// Room for the static TLS on small-stack threads (include/inhap/studio/thread_stack.hpp).
#include <gtest/gtest.h>
#include <pthread.h>

#include <cstddef>
#include <cstring>

#include "inhap/studio/thread_stack.hpp"

using namespace inhap::studio;

namespace {

constexpr std::size_t kCivetwebStack = 102400;  // civetweb's USE_STACK_SIZE in Debian's build

// 40 KB of static TLS of the test's own, so that, whether or not CGAL's 64 KB are linked in, a
// 100 KB stack without the room has at most 60 KB left (glibc takes the TLS out of it).
thread_local unsigned char t_tls[40 << 10];

// Uses `bytes` of its stack (every page written) and returns their sum.
__attribute__((noinline)) unsigned use_stack(std::size_t bytes) {
  volatile unsigned char* buf = static_cast<volatile unsigned char*>(__builtin_alloca(bytes));
  for (std::size_t i = 0; i < bytes; i += 512) buf[i] = static_cast<unsigned char>(i >> 9);
  unsigned sum = 0;
  for (std::size_t i = 0; i < bytes; i += 512) sum += buf[i];
  return sum;
}

void* eighty_kb(void* out) {
  volatile unsigned char* tls = t_tls;  // kept: the TLS must be there
  tls[sizeof t_tls - 1] = 1;
  *static_cast<unsigned*>(out) = use_stack(80 << 10) + tls[sizeof t_tls - 1] - 1;
  return nullptr;
}

}  // namespace

TEST(StudioThreadStack, SmallRequestsGetRoomForTheStaticTlsLargeOnesAreUnchanged) {
  EXPECT_EQ(stack_size_granted(kCivetwebStack), kCivetwebStack + kStaticTlsRoom);
  EXPECT_EQ(stack_size_granted(kSmallStack - 1), kSmallStack - 1 + kStaticTlsRoom);
  EXPECT_EQ(stack_size_granted(kSmallStack), kSmallStack);
  EXPECT_EQ(stack_size_granted(8u << 20), 8u << 20);
}

// A thread that asks for civetweb's 100 KB can use 80 KB of it although the program carries
// static TLS (this file's 40 KB, and CGAL's 64 KB when linked in). Without the room it has at
// most 60 KB and this test dies of a stack overflow.
TEST(StudioThreadStack, AThreadAskingForCivetwebsStackCanUseEightyKilobytes) {
  pthread_attr_t attr;
  ASSERT_EQ(pthread_attr_init(&attr), 0);
  ASSERT_EQ(pthread_attr_setstacksize(&attr, kCivetwebStack), 0);
  std::size_t got = 0;
  ASSERT_EQ(pthread_attr_getstacksize(&attr, &got), 0);
  EXPECT_EQ(got, stack_size_granted(kCivetwebStack));
  unsigned sum = 0;
  pthread_t t;
  ASSERT_EQ(pthread_create(&t, &attr, eighty_kb, &sum), 0);
  ASSERT_EQ(pthread_join(t, nullptr), 0);
  pthread_attr_destroy(&attr);
  unsigned want = 0;
  for (std::size_t i = 0; i < (80u << 10); i += 512) want += static_cast<unsigned char>(i >> 9);
  EXPECT_EQ(sum, want);
}

// Cooperative cancellation (cancel.hpp).
#include "inhap/core/cancel.hpp"

namespace inhap {

namespace {
thread_local const CancelFlag* t_flag = nullptr;
}

const CancelFlag* current_cancel() noexcept {
  return t_flag;
}

CancelScope::CancelScope(const CancelFlag* flag) noexcept : previous_(t_flag) {
  t_flag = flag;
}

CancelScope::~CancelScope() {
  t_flag = previous_;
}

}  // namespace inhap

#include "counting_new.hpp"

#include <sys/prctl.h>

#include <cstdlib>
#include <cstring>
#include <new>

namespace vigs::test {

bool on_thread_named(const char* name) noexcept {
  char current[16] = {};
  ::prctl(PR_GET_NAME, current, 0, 0, 0);
  return std::strcmp(current, name) == 0;
}

}  // namespace vigs::test

namespace {

void* counted_alloc(std::size_t n, void* caller) {
  vigs::test::on_operator_new(n, caller);
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}

}  // namespace

void* operator new(std::size_t n) {
  return counted_alloc(n, __builtin_return_address(0));
}
void* operator new[](std::size_t n) {
  return counted_alloc(n, __builtin_return_address(0));
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

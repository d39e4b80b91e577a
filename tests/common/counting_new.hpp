#pragma once
// Allocation counting for the no-allocation tests (drivers, tracker). Linking counting_new.cpp into
// a test binary replaces the global operator new / delete: every operator new first calls
// on_operator_new(bytes, caller), which that test defines, then takes the memory from malloc.
// Memory taken with malloc directly is not seen.
#include <cstddef>

namespace vigs::test {

/// Defined by the test binary; must not allocate. `caller` is the return address of the
/// operator new call.
void on_operator_new(std::size_t bytes, void* caller) noexcept;

/// True on the thread whose name (rt thread table, prctl PR_SET_NAME) is `name`; a syscall,
/// allocates nothing.
bool on_thread_named(const char* name) noexcept;

}  // namespace vigs::test

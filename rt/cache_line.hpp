// Cache-line size used to keep data written by different threads on different lines.
//
// A fixed 64 rather than std::hardware_destructive_interference_size: GCC and Clang disagree on
// whether that constant exists and what it is, and a layout that changes with the compiler (or
// with -march) is an ABI hazard between translation units. 64 bytes is the line size of every
// x86-64 and ARMv8 core VIGS targets.
#pragma once

#include <cstddef>

namespace vigs::rt {

inline constexpr std::size_t kCacheLineSize = 64;

}  // namespace vigs::rt

#pragma once
// Image rows in blocks for the per-pixel passes of the loss and SSIM: each block is an item of
// WorkerTeam::run_claimed (claimed by whichever member is free), or all run on the caller without
// a team. Results kept per block and reduced in block order do not depend on the team.
#include <algorithm>
#include <cstddef>

#include "rt/worker_team.hpp"

namespace vigs::mapping {

/// Blocks of block_rows rows that cover [0, rows).
[[nodiscard]] inline std::size_t row_block_count(int rows, int block_rows) {
  return static_cast<std::size_t>((rows + block_rows - 1) / block_rows);
}

/// fn(member, block, first row, end row) for every block of block_rows rows of [0, rows).
template <class Fn>
void for_row_blocks(rt::WorkerTeam* pool, int rows, int block_rows, Fn&& fn) {
  const auto body = [&](int member, std::size_t b) {
    const int r0 = static_cast<int>(b) * block_rows;
    fn(member, static_cast<int>(b), r0, std::min(rows, r0 + block_rows));
  };
  const std::size_t blocks = row_block_count(rows, block_rows);
  if (pool) {
    pool->run_claimed(blocks, body);
  } else {
    for (std::size_t b = 0; b < blocks; ++b) body(0, b);
  }
}

}  // namespace vigs::mapping

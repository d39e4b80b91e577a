#pragma once
// A results folder replaced whole. The new contents are written into a fresh temporary sibling
// (".NAME.tmp-XXXXXX" next to NAME) and swapped into place with one renameat2(RENAME_EXCHANGE)
// (or a plain rename when NAME does not exist yet), so a reader sees either the whole old
// folder or the whole new one: a reused folder never keeps an earlier run's files, and a kill
// at any moment never leaves a mix. The old contents are removed after the swap; a kill right
// then leaves them in the hidden sibling, never in NAME.
#include <filesystem>
#include <functional>
#include <string>

namespace vigs::io {

/// Builds folder `dir` by calling `fill(tmp)` on an empty temporary sibling folder, then puts
/// it in place of `dir`. An existing `dir` is replaced only if it is empty or holds
/// `marker_file` (i.e. it is an earlier output of the same kind), so a mistyped --out never
/// deletes an unrelated folder. Throws IoError naming the folder; on any failure (including
/// one thrown by `fill`) `dir` is left as it was and the temporary folder is removed.
void replace_dir_atomically(const std::string& dir, const std::string& marker_file,
                            const std::function<void(const std::filesystem::path& tmp)>& fill);

}  // namespace vigs::io

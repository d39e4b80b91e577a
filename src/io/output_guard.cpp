#include "io/output_guard.hpp"

#include <sys/stat.h>

#include <filesystem>

#include "io/io_error.hpp"

namespace vigs::io {
namespace {

struct FileId {
  dev_t dev = 0;
  ino_t ino = 0;
  bool operator==(const FileId&) const = default;
};

bool file_id(const std::string& path, FileId& id) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return false;
  id = {st.st_dev, st.st_ino};
  return true;
}

}  // namespace

void refuse_output_over_inputs(const std::string& output, const std::vector<std::string>& inputs) {
  FileId out;
  if (!file_id(output, out)) return;  // a new file cannot be an existing input
  for (const std::string& in : inputs) {
    FileId id;
    if (file_id(in, id) && id == out) {
      throw IoError(output + ": is the input file " + in +
                    " (same inode); refusing to overwrite an input");
    }
  }
}

void refuse_output_dir_over_inputs(const std::string& dir, const std::vector<std::string>& inputs) {
  FileId out;
  if (!file_id(dir, out)) return;
  for (const std::string& in : inputs) {
    std::error_code ec;
    // The input (links resolved) and each folder above it, compared by inode with the folder.
    std::filesystem::path p = std::filesystem::canonical(in, ec);
    if (ec) continue;
    for (bool first = true;; first = false) {
      FileId id;
      if (file_id(p.string(), id) && id == out) {
        throw IoError(dir + ": output folder " + (first ? "is" : "contains") + " the input " + in +
                      "; refusing to replace it");
      }
      if (!p.has_relative_path()) break;
      p = p.parent_path();
    }
  }
}

}  // namespace vigs::io

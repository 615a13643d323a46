// The one rule for output paths (docs/cli.md): missing parent directories are created for
// every output; "-" means stdout where an output is a single stream.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

namespace vlpground::cli {

/// Creates the directory `dir` and its parents; throws std::runtime_error naming it.
inline void create_directories_for(const std::filesystem::path& dir) {
  if (dir.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir)) {
    throw std::runtime_error("cannot create directory " + dir.string() + ": " +
                             (ec ? ec.message() : std::string("not a directory")));
  }
}

/// Creates the missing parent directories of the file `path`.
inline void create_parent_directories(const std::filesystem::path& path) {
  create_directories_for(path.parent_path());
}

}  // namespace vlpground::cli

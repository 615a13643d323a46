// Locating test data: the project's own pcaps/ and the shared captures in ../shared.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace vlpground::test {

/// `../shared/data/<sub>/<name>` if the shared folder is present, else nullopt (and the
/// caller skips with WARN). Honours the VLPGROUND_SHARED_DIR environment variable.
std::optional<std::filesystem::path> shared_file(const std::string& sub, const std::string& name);

/// `<source>/pcaps/<name>`.
std::filesystem::path project_pcap(const std::string& name);

/// A fresh empty temporary directory for one test, removed when the test program exits
/// (kept when the environment variable VLPGROUND_KEEP_TEST_FILES is set, for a post-mortem).
std::filesystem::path temp_dir(const std::string& tag);

}  // namespace vlpground::test

/// Skips the rest of the current test case with a visible message when `opt` is empty.
#define VLPGROUND_REQUIRE_SHARED(opt)                                            \
  do {                                                                           \
    if (!(opt)) {                                                                \
      WARN("skipped: ../shared test data not found (set VLPGROUND_SHARED_DIR)"); \
      return;                                                                    \
    }                                                                            \
  } while (false)

#include "test_data.hpp"

#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <mutex>
#include <system_error>
#include <vector>

namespace vlpground::test {

std::optional<std::filesystem::path> shared_file(const std::string& sub, const std::string& name) {
  const char* env = std::getenv("VLPGROUND_SHARED_DIR");
  const std::filesystem::path root = env ? env : VLPGROUND_SHARED_DIR;
  auto path = root / "data" / sub / name;
  if (!std::filesystem::exists(path)) return std::nullopt;
  return path;
}

std::filesystem::path project_pcap(const std::string& name) {
  return std::filesystem::path(VLPGROUND_SOURCE_DIR) / "pcaps" / name;
}

namespace {

/// The directories temp_dir made, removed when the test program exits (by the process that
/// made them, not by a forked child), unless VLPGROUND_KEEP_TEST_FILES is set.
class TempDirs {
 public:
  ~TempDirs() {
    if (::getpid() != owner_ || std::getenv("VLPGROUND_KEEP_TEST_FILES") != nullptr) return;
    for (const auto& dir : dirs_) {
      std::error_code ignored;
      std::filesystem::remove_all(dir, ignored);
    }
  }
  void add(const std::filesystem::path& dir) {
    const std::lock_guard<std::mutex> lock(mutex_);
    dirs_.push_back(dir);
  }

 private:
  const pid_t owner_ = ::getpid();
  std::mutex mutex_;
  std::vector<std::filesystem::path> dirs_;
};

}  // namespace

std::filesystem::path temp_dir(const std::string& tag) {
  static std::atomic<int> counter{0};
  static TempDirs made;
  auto dir =
      std::filesystem::temp_directory_path() /
      ("vlpground-" + tag + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  made.add(dir);
  return dir;
}

}  // namespace vlpground::test

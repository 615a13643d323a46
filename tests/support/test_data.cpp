#include "test_data.hpp"

#include <unistd.h>

#include <atomic>
#include <cstdlib>

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

std::filesystem::path temp_dir(const std::string& tag) {
  static std::atomic<int> counter{0};
  auto dir =
      std::filesystem::temp_directory_path() /
      ("vlpground-" + tag + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace vlpground::test

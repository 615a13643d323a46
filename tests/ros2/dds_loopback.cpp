#include "dds_loopback.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <string>

namespace vlpground::test {

namespace {

constexpr std::uint32_t kDomains = 200;  // ids 1..200

// A domain id that no other process on this machine holds: each process takes an exclusive
// lock on a file per domain (flock, held until the process ends), trying from a random id on.
// ctest runs the test cases as parallel processes; two on one domain receive each other's
// clouds on the same topic (a listener counted a frame of another test's replay).
std::uint32_t lock_free_domain() {
  std::random_device entropy;
  const std::uint32_t first =
      std::uniform_int_distribution<std::uint32_t>(0, kDomains - 1)(entropy);
  const std::filesystem::path dir = std::filesystem::temp_directory_path();
  for (std::uint32_t i = 0; i < kDomains; ++i) {
    const std::uint32_t domain = 1 + (first + i) % kDomains;
    const auto path = dir / ("vlpground-test-dds-domain-" + std::to_string(domain) + ".lock");
    const int fd = ::open(path.c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0666);
    if (fd < 0) continue;
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0) return domain;  // fd stays open: the lock holds
    ::close(fd);
  }
  throw std::runtime_error("no DDS domain in 1.." + std::to_string(kDomains) +
                           " is free: every lock file in " + dir.string() + " is held");
}

}  // namespace

std::uint32_t confine_dds_to_loopback() {
  static const std::uint32_t domain = [] {
    // Participant indices are probed on 127.0.0.1 only (MaxAutoParticipantIndex ports each).
    static const char* const kConfig =
        "<CycloneDDS><Domain Id=\"any\">"
        "<General><Interfaces><NetworkInterface address=\"127.0.0.1\"/></Interfaces>"
        "<AllowMulticast>false</AllowMulticast></General>"
        "<Discovery><ParticipantIndex>auto</ParticipantIndex>"
        "<MaxAutoParticipantIndex>20</MaxAutoParticipantIndex>"
        "<Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery>"
        "</Domain></CycloneDDS>";
    setenv("CYCLONEDDS_URI", kConfig, 1);
    return lock_free_domain();
  }();
  return domain;
}

}  // namespace vlpground::test

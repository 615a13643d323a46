#include "dds_loopback.hpp"

#include <cstdlib>
#include <random>

namespace vlpground::test {

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
    std::random_device entropy;
    return std::uniform_int_distribution<std::uint32_t>(1, 200)(entropy);
  }();
  return domain;
}

}  // namespace vlpground::test

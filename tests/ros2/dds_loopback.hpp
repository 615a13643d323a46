// Keeps the tests' DDS traffic on this machine: Cyclone DDS configured (CYCLONEDDS_URI, inherited
// by child processes) for the loopback interface only, no multicast, unicast discovery to
// 127.0.0.1, and a random domain id per test run.
#pragma once

#include <cstdint>

namespace vlpground::test {

/// Sets CYCLONEDDS_URI for this process and its children (before any DDS entity exists) and
/// returns a random domain id in [1, 200] for this run (the same on every call).
std::uint32_t confine_dds_to_loopback();

}  // namespace vlpground::test

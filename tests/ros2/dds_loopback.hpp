// Keeps the tests' DDS traffic on this machine: Cyclone DDS configured (CYCLONEDDS_URI, inherited
// by child processes) for the loopback interface only, no multicast, unicast discovery to
// 127.0.0.1, and a domain id per test process that no other process on this machine holds.
#pragma once

#include <cstdint>

namespace vlpground::test {

/// Sets CYCLONEDDS_URI for this process and its children (before any DDS entity exists) and
/// returns a domain id in [1, 200] that this process holds, by a lock file, until it ends (the
/// same on every call): test processes run in parallel never share one.
std::uint32_t confine_dds_to_loopback();

}  // namespace vlpground::test

// Global operator new counter of the baselines test binary.
#pragma once

namespace vlpground::test {
/// Number of global operator new / new[] calls so far in this process; -1 when not counted
/// (AddressSanitizer builds).
long allocation_count();
}  // namespace vlpground::test

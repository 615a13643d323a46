// `vlpground live --sensor NAME=IP[:PORT][@pose] ...`: several sensors in one process through
// a MultiPipeline; outputs per sensor (outputs_for_sensor), a summary per sensor plus the
// router's counters (datagrams from unknown addresses included).
#pragma once

#include <string>
#include <vector>

#include "commands/pipeline_runner.hpp"

namespace vlpground::cli {

/// `request.config.udp` gives the bind address, multicast group, default data port and the
/// position port; `specs` the sensors. Returns the process exit code; prints one-line errors.
int run_multi_pipeline(RunRequest request, const std::vector<std::string>& specs);

}  // namespace vlpground::cli

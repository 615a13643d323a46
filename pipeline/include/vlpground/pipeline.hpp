// Placeholder: the Pipeline API is designed by the pipeline work (issue 5).
#pragma once
#include "vlpground/detector/ground_detector.hpp"
#include "vlpground/driver/packet_source.hpp"
#include "vlpground/driver/rotation_assembler.hpp"

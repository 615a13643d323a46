// A vehicle-software stand-in: links the installed vlpground::pipeline and exercises the API.
#include <cstdio>
#include <vlpground/pipeline.hpp>

int main() {
  vlpground::DetectorConfig detector;
  detector.validate();
  vlpground::GroundDetector ground(detector);
  vlpground::Frame frame(64);
  vlpground::GroundResult result;
  result.reserve(frame.capacity());
  ground.detect(frame, result);
  std::printf("consumer: ok (%d columns)\n", frame.columns());
  return 0;
}

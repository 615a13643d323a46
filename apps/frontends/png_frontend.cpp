#include "frontends/png_frontend.hpp"

#include "writers/png_writer.hpp"

namespace vlpground::cli {
namespace {

class PngSink : public FrameSink {
 public:
  PngSink(const std::string& dir, const PipelineConfig& config)
      : writer_(dir, config.detector.fit_radius_m, config.sensor_name, config.detector.extrinsics) {}
  void write(const LabelledFrame& f) override {
    writer_.write(f.frame, f.ground, f.timings.detect_ms);
  }
  void finish() override { writer_.finish(); }  // the run's overview.png

 private:
  PngWriter writer_;
};

}  // namespace

void add_png_options(CLI::App& cmd, PngOptions& o) {
  cmd.add_option("--png", o.dir,
                 "one picture per frame, DIR/frame_NNNNNN.png: header (sensor, frame, time, ground "
                 "share), bird's-eye view (ground green, obstacles red) with legend and scale "
                 "bar, range image; DIR/overview.png plots the run")
      ->type_name("DIR")
      ->group("Outputs");
}

std::unique_ptr<FrameSink> make_png_sink(const PngOptions& o, const PipelineConfig& config) {
  if (o.dir.empty()) return nullptr;
  return std::make_unique<PngSink>(o.dir, config);
}

}  // namespace vlpground::cli

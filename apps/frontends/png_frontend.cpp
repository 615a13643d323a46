#include "frontends/png_frontend.hpp"

#include "writers/png_writer.hpp"

namespace vlpground::cli {
namespace {

class PngSink : public FrameSink {
 public:
  PngSink(const std::string& dir, double view_radius_m) : writer_(dir, view_radius_m) {}
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
                 "one picture per frame, DIR/frame_NNNNNN.png: bird's-eye view (ground green, "
                 "obstacles red) over the range image")
      ->type_name("DIR")
      ->group("Outputs");
}

std::unique_ptr<FrameSink> make_png_sink(const PngOptions& o, const PipelineConfig& config) {
  if (o.dir.empty()) return nullptr;
  return std::make_unique<PngSink>(o.dir, config.detector.fit_radius_m);
}

}  // namespace vlpground::cli

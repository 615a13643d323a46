#include "frontends/pcd_frontend.hpp"

#include "writers/pcd_writer.hpp"

namespace vlpground::cli {
namespace {

class PcdSink : public FrameSink {
 public:
  explicit PcdSink(const std::string& dir) : writer_(dir) {}
  void write(const LabelledFrame& f) override { writer_.write(f.frame, f.ground); }

 private:
  PcdWriter writer_;
};

}  // namespace

void add_pcd_options(CLI::App& cmd, PcdOptions& o) {
  cmd.add_option("--pcd", o.dir,
                 "one binary PCD per frame, DIR/frame_NNNNNN.pcd: x y z intensity ring time "
                 "label (label 1 = ground, 2 = obstacle)")
      ->type_name("DIR")
      ->group("Outputs");
}

std::unique_ptr<FrameSink> make_pcd_sink(const PcdOptions& o, const PipelineConfig& /*config*/) {
  if (o.dir.empty()) return nullptr;
  return std::make_unique<PcdSink>(o.dir);
}

}  // namespace vlpground::cli

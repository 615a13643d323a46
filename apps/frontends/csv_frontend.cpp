#include "frontends/csv_frontend.hpp"

#include "writers/csv_writer.hpp"

namespace vlpground::cli {
namespace {

class CsvSink : public FrameSink {
 public:
  explicit CsvSink(const std::string& path) : writer_(path) {}
  void write(const LabelledFrame& f) override { writer_.write(f.frame, f.ground); }
  void finish() override { writer_.close(); }

 private:
  CsvWriter writer_;
};

}  // namespace

void add_csv_options(CLI::App& cmd, CsvOptions& o) {
  cmd.add_option("--csv", o.path,
                 "one row per return: frame,laser_id,ring,return,timestamp_us,azimuth_deg,"
                 "distance_m,x,y,z,intensity,ground (ground 1 = ground, 0 = not); - = stdout")
      ->type_name("FILE")
      ->group("Outputs");
}

std::unique_ptr<FrameSink> make_csv_sink(const CsvOptions& o, const PipelineConfig& /*config*/) {
  if (o.path.empty()) return nullptr;
  return std::make_unique<CsvSink>(o.path);
}

}  // namespace vlpground::cli

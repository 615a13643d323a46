#include "frontends/mcap_frontend.hpp"

#include <string>
#include <vector>
#include <mutex>
#include <stdexcept>

#if VLPGROUND_HAVE_MCAP_RECORDER
#include "vlpground/viz/mcap_recorder.hpp"
#endif

namespace vlpground::cli {

void add_mcap_options(CLI::App& cmd, McapOptions& o) {
  CLI::Option* file =
      cmd.add_option("--mcap", o.path,
                     "record points, ground, range image and status (the Foxglove channels) "
                     "to an MCAP file that Foxglove opens; one chunk per frame, so a crash "
                     "keeps every frame written (docs/mcap.md)")
          ->type_name("FILE")
          ->group("Outputs");
  std::vector<std::string> names;
  for (const auto c : {mcap::Compression::zstd, mcap::Compression::lz4, mcap::Compression::none}) {
    names.emplace_back(mcap::to_string(c));
  }
  cmd.add_option_function<std::string>(
         "--mcap-compression",
         [&o](const std::string& name) { o.compression = *mcap::parse_compression(name); },
         "chunk compression of --mcap: zstd (smaller), lz4 (faster) or none")
      ->check(CLI::IsMember(names))
      ->default_str(std::string(mcap::to_string(o.compression)))
      ->needs(file)
      ->group("Outputs");
}

#if VLPGROUND_HAVE_MCAP_RECORDER
namespace {

// The runner names the option in front of write() and finish() errors (output_options.cpp).
class McapSink : public FrameSink {
 public:
  McapSink(const std::string& path, viz::McapRecorderConfig config)
      : recorder_(path, std::move(config)) {}
  void write(const LabelledFrame& f) override {
    rethrow_status_error();
    recorder_.record(f);
  }
  // From the runner's thread, which expects no exception here: the first error is kept and
  // reported by the next write() or finish().
  void on_stats(const PipelineStats& stats) override {
    try {
      recorder_.record_status(stats);
    } catch (const std::exception& e) {
      const std::lock_guard lock(error_mutex_);
      if (status_error_.empty()) status_error_ = e.what();
    }
  }
  // Acquisition thread: PPS and GPRMC state for the status channel.
  void on_position(const PositionPacket& packet) override { recorder_.note_position(packet); }
  void finish() override {
    rethrow_status_error();
    recorder_.close();
  }

 private:
  void rethrow_status_error() {
    const std::lock_guard lock(error_mutex_);
    if (!status_error_.empty()) throw std::runtime_error(status_error_);
  }

  viz::McapRecorder recorder_;
  std::mutex error_mutex_;
  std::string status_error_;
};

}  // namespace

std::unique_ptr<FrameSink> make_mcap_sink(const McapOptions& o, const PipelineConfig& config) {
  if (o.path.empty()) return nullptr;
  viz::McapRecorderConfig recorder;
  recorder.writer.compression = o.compression;
  recorder.encoder.extrinsics = config.detector.extrinsics;
  return std::make_unique<McapSink>(o.path, std::move(recorder));
}

#else

std::unique_ptr<FrameSink> make_mcap_sink(const McapOptions& o, const PipelineConfig& /*config*/) {
  if (o.path.empty()) return nullptr;
  throw std::runtime_error(
      "this vlpground was built without vlpground::viz (libprotobuf, protoc, nlohmann-json), "
      "which encodes the recorded channels");
}

#endif

}  // namespace vlpground::cli

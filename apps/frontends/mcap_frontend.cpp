#include "frontends/mcap_frontend.hpp"

#include <map>
#include <mutex>
#include <stdexcept>

#include "vlpground/viz/mcap_recorder.hpp"

namespace vlpground::cli {
namespace {

class McapSink : public FrameSink {
 public:
  McapSink(const std::string& path, viz::McapRecorderConfig config)
      : path_(path), recorder_(open(path, std::move(config))) {}
  void write(const LabelledFrame& f) override {
    guarded([&] { recorder_->record(f); });
  }
  // From the runner's thread, which does not expect errors here: the first one is kept and
  // reported by the next write() or finish().
  void on_stats(const PipelineStats& stats) override {
    try {
      recorder_->record_status(stats);
    } catch (const std::exception& e) {
      const std::lock_guard lock(error_mutex_);
      if (status_error_.empty()) status_error_ = e.what();
    }
  }
  void finish() override { guarded([&] { recorder_->close(); }); }

 private:
  static std::unique_ptr<viz::McapRecorder> open(const std::string& path,
                                                 viz::McapRecorderConfig config) {
    try {
      return std::make_unique<viz::McapRecorder>(path, std::move(config));
    } catch (const std::exception& e) {
      throw std::runtime_error("--mcap " + path + ": " + e.what());
    }
  }
  // One-line errors naming the option and the file (frame_sink.hpp).
  template <typename F>
  void guarded(F&& f) {
    {
      const std::lock_guard lock(error_mutex_);
      if (!status_error_.empty()) throw std::runtime_error("--mcap " + path_ + ": " + status_error_);
    }
    try {
      f();
    } catch (const std::exception& e) {
      throw std::runtime_error("--mcap " + path_ + ": " + e.what());
    }
  }

  std::string path_;
  std::unique_ptr<viz::McapRecorder> recorder_;
  std::mutex error_mutex_;
  std::string status_error_;
};

}  // namespace

void add_mcap_options(CLI::App& cmd, McapOptions& o) {
  CLI::Option* file = cmd.add_option("--mcap", o.path,
                 "record points, ground, range image and status (the Foxglove channels) to an "
                 "MCAP file that Foxglove opens; one chunk per frame, so a crash keeps every "
                 "frame written (docs/mcap.md)")
      ->type_name("FILE")
      ->group("Outputs");
  std::map<std::string, mcap::Compression> names;
  for (const auto c : {mcap::Compression::zstd, mcap::Compression::lz4, mcap::Compression::none}) {
    names.emplace(mcap::to_string(c), c);
  }
  cmd.add_option("--mcap-compression", o.compression, "chunk compression of --mcap")
      ->transform(CLI::CheckedTransformer(names))
      ->default_str(std::string(mcap::to_string(o.compression)))
      ->needs(file)
      ->group("Outputs");
}

std::unique_ptr<FrameSink> make_mcap_sink(const McapOptions& o, const PipelineConfig& config) {
  if (o.path.empty()) return nullptr;
  viz::McapRecorderConfig recorder;
  recorder.writer.compression = o.compression;
  recorder.encoder.extrinsics = config.detector.extrinsics;
  return std::make_unique<McapSink>(o.path, std::move(recorder));
}

}  // namespace vlpground::cli

#include "cli/report.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>

namespace vlpground::cli {
namespace {

double share(std::uint64_t part, std::uint64_t whole) {
  return whole == 0 ? 0.0 : static_cast<double>(part) / static_cast<double>(whole);
}

std::uint64_t count_returns(const Frame& f) {
  std::uint64_t n = 0;
  for (int l = 0; l < f.layers(); ++l) {
    for (int ring = 0; ring < kLasers; ++ring) {
      for (int c = 0; c < f.columns(); ++c) n += f.layer[l].valid[f.index(ring, c)];
    }
  }
  return n;
}

double frames_per_s(const PipelineStats& s) {
  return s.elapsed_s > 0 ? static_cast<double>(s.frames_delivered) / s.elapsed_s : 0.0;
}

double span_s(const PipelineStats& s, const SummaryContext& c) {
  return c.active_s >= 0 ? c.active_s : s.elapsed_s;
}

double frames_per_s(const PipelineStats& s, const SummaryContext& c) {
  const double span = span_s(s, c);
  return span > 0 ? static_cast<double>(s.frames_delivered) / span : 0.0;
}

// "p50 1.20 ms, p99 3.40 ms, max 4.00 ms (512 samples)", percentiles only with enough samples.
std::string describe_latency(const LatencyStats& l) {
  if (l.samples == 0) return "no samples";
  std::string text;
  char part[96];
  if (l.samples >= kMinSamplesP50) {
    std::snprintf(part, sizeof part, "p50 %.2f ms, ", l.p50_ms);
    text += part;
  }
  if (l.samples >= kMinSamplesP99) {
    std::snprintf(part, sizeof part, "p99 %.2f ms, ", l.p99_ms);
    text += part;
  }
  std::snprintf(part, sizeof part, "max %.2f ms, mean %.2f ms (%llu samples)", l.max_ms, l.mean_ms,
                static_cast<unsigned long long>(l.samples));
  return text + part;
}

// The live latency goal is judged only on enough samples.
std::string goal_verdict(const LatencyStats& l) {
  constexpr double kGoalMs = 10.0;
  if (l.samples < kMinSamplesP99) {
    return " (goal p99 < 10 ms: not judged, " + std::to_string(l.samples) + " samples < " +
           std::to_string(kMinSamplesP99) + ")";
  }
  return l.p99_ms < kGoalMs ? " (goal p99 < 10 ms: met)" : " (goal p99 < 10 ms: MISSED)";
}

}  // namespace

void print_frame_line(std::FILE* to, const LabelledFrame& f) {
  const std::uint64_t returns = count_returns(f.frame);
  std::fprintf(to, "%s%sframe %llu: %d columns, %llu returns, %.1f%% ground, %.1f ms detect%s\n",
               f.sensor_name.c_str(), f.sensor_name.empty() ? "" : " ",
               static_cast<unsigned long long>(f.frame.meta.sequence), f.frame.columns(),
               static_cast<unsigned long long>(returns),
               100.0 * share(f.ground.ground_returns, returns), f.timings.detect_ms,
               f.frame.meta.complete ? "" : " (partial rotation)");
  std::fflush(to);
}

void print_progress(std::FILE* to, const PipelineStats& s) {
  constexpr int kBar = 30;
  const double p = std::clamp(s.progress, 0.0, 1.0);
  const int filled = s.progress < 0 ? 0 : static_cast<int>(p * kBar);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.resize(kBar, s.progress < 0 ? '?' : '.');
  if (s.progress >= 0) {
    std::fprintf(to, "\r[%s] %5.1f%%  %llu frames  %.1f frames/s ", bar.c_str(), 100.0 * p,
                 static_cast<unsigned long long>(s.frames_delivered), frames_per_s(s));
  } else {
    std::fprintf(to, "\r%llu frames  %.1f frames/s  %llu dropped ",
                 static_cast<unsigned long long>(s.frames_delivered), frames_per_s(s),
                 static_cast<unsigned long long>(s.frames_dropped));
  }
  std::fflush(to);
}

void print_summary_table(std::FILE* to, const PipelineStats& s, const SummaryContext& c) {
  const auto& src = s.capture.source;
  const auto& dec = s.capture.decoder;
  const auto& as = s.capture.assembler;
  const auto u = [](std::uint64_t v) { return static_cast<unsigned long long>(v); };
  std::fprintf(to, "summary (%s)\n", c.command.c_str());
  std::fprintf(to, "  %-12s %s\n", "input", c.input.c_str());
  std::fprintf(to, "  %-12s %s\n", "method", c.method.c_str());
  std::fprintf(to, "  %-12s %llu delivered, %llu incomplete, %llu dropped, %llu callback errors\n",
               "frames", u(s.frames_delivered), u(s.incomplete_frames), u(s.frames_dropped),
               u(s.callback_exceptions));
  std::fprintf(to, "  %-12s %llu data, %llu position, %llu skipped, %llu lost, %llu malformed\n",
               "packets", u(src.data_packets), u(src.position_packets), u(src.skipped()),
               u(as.packets_lost),
               u(dec.wrong_size + dec.bad_flag + dec.bad_azimuth + dec.unknown_mode));
  if (s.live) std::fprintf(to, "  %-12s %llu\n", "kernel drops", u(src.kernel_drops));
  if (src.loop_wraps > 0) {
    std::fprintf(to,
                 "  %-12s %llu wrap%s, %llu packets skipped at the start of a pass to continue "
                 "the rotation\n",
                 "loop", u(src.loop_wraps), src.loop_wraps == 1 ? "" : "s", u(src.skipped_loop));
  }
  std::fprintf(to, "  %-12s %llu, %.1f%% ground\n", "returns", u(s.returns),
               100.0 * share(s.ground_returns, s.returns));
  std::fprintf(to, "  %-12s %s\n", "detect", describe_latency(s.detect).c_str());
  std::fprintf(to, "  %-12s %s%s\n", "latency", describe_latency(s.latency).c_str(),
               s.live ? goal_verdict(s.latency).c_str() : " (replay: includes queueing)");
  if (s.silence_frames > 0) {
    std::fprintf(to,
                 "  %-12s %llu frame%s ended by the silence timeout, latency up to %.2f ms "
                 "(not in the latency above)\n",
                 "", u(s.silence_frames), s.silence_frames == 1 ? "" : "s",
                 s.silence_latency_max_ms);
  }
  if (s.frames_delivered == 0) {
    std::fprintf(to, "  %-12s no frames\n", "throughput");
  } else {
    std::fprintf(to, "  %-12s %.1f frames/s over %.2f s%s\n", "throughput", frames_per_s(s, c),
                 span_s(s, c), c.active_s >= 0 ? " from the first packet" : "");
  }
  if (c.capture.has_position()) {
    std::fprintf(to, "  %-12s %s\n", "gps", c.capture.gps_line().c_str());
  }
  if (!c.capture.warnings().empty()) {
    std::fprintf(to, "  %-12s %zu (see log)\n", "warnings", c.capture.warnings().size());
  }
  std::fflush(to);
}

std::string summary_json(const PipelineStats& s, const SummaryContext& c) {
  const auto latency = [](const LatencyStats& l) {
    // Percentiles are null without enough samples (kMinSamplesP50, kMinSamplesP99).
    const auto value = [](double v, bool known) {
      return known ? nlohmann::json(v) : nlohmann::json();
    };
    return nlohmann::json{{"samples", l.samples},
                          {"p50_ms", value(l.p50_ms, l.samples >= kMinSamplesP50)},
                          {"p99_ms", value(l.p99_ms, l.samples >= kMinSamplesP99)},
                          {"max_ms", value(l.max_ms, l.samples > 0)},
                          {"mean_ms", value(l.mean_ms, l.samples > 0)}};
  };
  nlohmann::json frames = frames_json(s.frames_delivered, s.incomplete_frames);
  frames["assembled"] = s.frames_assembled;
  frames["dropped"] = s.frames_dropped;
  frames["callback_exceptions"] = s.callback_exceptions;
  nlohmann::json j = {
      {"command", c.command},
      {"input", c.input},
      {"method", c.method},
      {"live", s.live},
      {"frames", std::move(frames)},
      {"packets", packets_json(s.capture)},
      {"returns", s.returns},
      {"ground_returns", s.ground_returns},
      {"ground_share", share(s.ground_returns, s.returns)},
      {"timings", {{"detect", latency(s.detect)}, {"latency", latency(s.latency)}}},
      {"silence_frames",
       {{"count", s.silence_frames}, {"latency_max_ms", s.silence_latency_max_ms}}},
      {"elapsed_s", s.elapsed_s},
      {"active_s", span_s(s, c)},
      {"frames_per_s", frames_per_s(s, c)},
      {"loop",
       {{"wraps", s.capture.source.loop_wraps},
        {"skipped_packets", s.capture.source.skipped_loop}}},
  };
  c.capture.add_json_fields(j);
  return j.dump(2);
}

}  // namespace vlpground::cli

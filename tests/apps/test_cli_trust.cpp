// Issue 15, "a command line you can trust": right answers or a clear failure. End-to-end
// tests of the built `vlpground` executable, one TEST_CASE per item.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <nlohmann/json.hpp>

#include "child_process.hpp"
#include "cli_helpers.hpp"
#include "test_data.hpp"
#include "udp_sender.hpp"

using namespace vlpground;
using test::one_line;
using test::read_lines;
using test::run_cli;

namespace {

const std::string kCli = VLPGROUND_CLI;

bool is_one_json_document(const std::string& text) {
  try {
    const auto j = nlohmann::json::parse(text);  // throws on anything before or after it
    return j.is_object();
  } catch (const nlohmann::json::exception&) {
    return false;
  }
}

}  // namespace

TEST_CASE("15.3 an output that cannot be written fails the run after flushing the others") {
  const auto pcap = test::shared_file("sim", "urban_strongest.pcap");
  VLPGROUND_REQUIRE_SHARED(pcap);
  SECTION("--csv /dev/full") {
    const auto r = run_cli({kCli, "replay", pcap->string(), "--csv", "/dev/full"});
    CHECK(r.code == 1);
    CHECK(one_line(r.err));
    CHECK(r.err.find("--csv") != std::string::npos);
    CHECK(r.err.find("No space left") != std::string::npos);
  }
  SECTION("a PCD file that cannot be created mid-run") {
    const auto dir = test::temp_dir("cli_write_fail");
    std::filesystem::create_directories(dir / "pcd" / "frame_000002.pcd");  // in the way
    const auto csv = dir / "out.csv";
    const auto r = run_cli(
        {kCli, "replay", pcap->string(), "--pcd", (dir / "pcd").string(), "--csv", csv.string()});
    CHECK(r.code == 1);
    CHECK(one_line(r.err));
    CHECK(r.err.find("--pcd") != std::string::npos);
    CHECK(r.err.find("frame_000002.pcd") != std::string::npos);
    // The CSV holds every row of the frames delivered before the failure, flushed.
    const auto lines = read_lines(csv);
    REQUIRE(lines.size() > 1);
    CHECK(std::stoi(test::split(lines.back())[0]) >= 2);
    CHECK(std::filesystem::exists(dir / "pcd" / "frame_000001.pcd"));
  }
}

TEST_CASE("15.4 logs go to stderr, with --json stdout is exactly one JSON document") {
  const auto byte21 = test::shared_file("real", "vlp16_1200rpm_productbyte21.pcap");
  VLPGROUND_REQUIRE_SHARED(byte21);
  const auto warned = run_cli({kCli, "replay", byte21->string(), "--json"});
  CHECK(warned.code == 0);
  CHECK(is_one_json_document(warned.out));
  CHECK(warned.err.find("product byte 0x21") != std::string::npos);  // the warning, on stderr
  const auto sim = test::shared_file("sim", "urban_strongest.pcap");
  const auto info = run_cli({kCli, "replay", sim->string(), "--json", "--log-level", "debug"});
  CHECK(info.code == 0);
  CHECK(is_one_json_document(info.out));
  CHECK(!info.err.empty());
  const auto eval = run_cli({kCli, "info", byte21->string(), "--json"});
  CHECK(is_one_json_document(eval.out));
}

TEST_CASE("15.7 one rule for output paths") {
  const auto pcap = test::shared_file("sim", "urban_strongest.pcap");
  VLPGROUND_REQUIRE_SHARED(pcap);
  const auto dir = test::temp_dir("cli_paths");
  SECTION("missing directories are created for every output") {
    const auto r = run_cli({kCli, "replay", pcap->string(), "--frames", "1", "--csv",
                            (dir / "a" / "b" / "out.csv").string(), "--pcd",
                            (dir / "c" / "pcd").string(), "--png", (dir / "d" / "png").string()});
    CHECK(r.code == 0);
    CHECK(read_lines(dir / "a" / "b" / "out.csv").size() > 1);
    CHECK(!std::filesystem::is_empty(dir / "c" / "pcd"));
    CHECK(!std::filesystem::is_empty(dir / "d" / "png"));
  }
  SECTION("--csv - writes the CSV to stdout and the summary to stderr") {
    const auto r = run_cli({kCli, "replay", pcap->string(), "--frames", "2", "--csv", "-"});
    CHECK(r.code == 0);
    CHECK(r.out.rfind("frame,laser_id,ring,", 0) == 0);
    CHECK(r.out.find("summary") == std::string::npos);
    CHECK(r.err.find("summary (replay)") != std::string::npos);
    CHECK(!std::filesystem::exists("-"));
    const auto both = run_cli({kCli, "replay", pcap->string(), "--csv", "-", "--json"});
    CHECK(both.code == 2);
    CHECK(one_line(both.err));
  }
  SECTION("sim --out DIR writes inside an existing directory, and creates missing ones") {
    const auto r = run_cli({kCli, "sim", "flat", "--frames", "1", "--out", dir.string()});
    CHECK(r.code == 0);
    CHECK(std::filesystem::exists(dir / "flat.pcap"));
    CHECK(std::filesystem::exists(dir / "flat.labels"));
    CHECK(std::filesystem::exists(dir / "flat.json"));
    const auto nested = dir / "x" / "y" / "run1";
    CHECK(run_cli({kCli, "sim", "flat", "--frames", "1", "--out", nested.string()}).code == 0);
    CHECK(std::filesystem::exists(dir / "x" / "y" / "run1.pcap"));
  }
}

TEST_CASE("15.8 errors in the user's words, exit 2 for usage errors, 1 for runtime failures") {
  const auto pcap = test::shared_file("sim", "urban_strongest.pcap");
  VLPGROUND_REQUIRE_SHARED(pcap);
  const auto dir = test::temp_dir("cli_words");
  const auto expect = [](const std::vector<std::string>& args, int code, const std::string& text) {
    const auto r = run_cli(args);
    INFO(r.err);
    CHECK(r.code == code);
    CHECK(one_line(r.err));
    CHECK(r.err.find(text) != std::string::npos);
  };
  expect({kCli, "sim", "flat", "--frames", "0", "--out", (dir / "s").string()}, 2, "--frames");
  expect({kCli, "sim", "flat", "--height-m", "-3", "--out", (dir / "s").string()}, 2,
         "--height-m must be");
  expect({kCli, "replay", pcap->string(), "--frames", "-1"}, 2, "--frames: must be >= 0");
  expect({kCli, "replay", pcap->string(), "--calibration", dir.string()}, 1,
         "--calibration " + dir.string() + ": is a directory");
  expect({kCli, "eval", pcap->string(), "--labels", dir.string()}, 1,
         "--labels " + dir.string() + ": is a directory");
  expect({kCli, "replay", (dir / "missing.pcap").string()}, 1, "no such file");
  expect({kCli, "replay", pcap->string(), "--extrinsics", "1,2"}, 2, "--extrinsics");
  // The extrinsics as people type them, with spaces.
  const auto spaced = run_cli(
      {kCli, "replay", pcap->string(), "--frames", "1", "--extrinsics", "0, 0, 1.8, 0, 0, 0"});
  CHECK(spaced.code == 0);
  SECTION("a port in use is named by its role") {
    const int fd = socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    REQUIRE(bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
    socklen_t len = sizeof a;
    getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
    const std::string busy = std::to_string(ntohs(a.sin_port));
    const std::string open_port = std::to_string(test::free_port());
    expect({kCli, "live", "--bind", "127.0.0.1", "--port", open_port, "--position-port", busy}, 1,
           "position port " + busy + " on 127.0.0.1 is in use; use --position-port");
    expect({kCli, "live", "--bind", "127.0.0.1", "--port", busy, "--position-port", "0"}, 1,
           "data port " + busy + " on 127.0.0.1 is in use");
    close(fd);
  }
  // Both codes are documented in --help.
  CHECK(run_cli({kCli, "--help"}).out.find("2 usage error") != std::string::npos);
}

TEST_CASE("15.2 eval refuses labels that do not belong to the capture") {
  const auto hills = test::project_pcap("hills_demo.pcap");
  const auto expect_refused = [&](const std::filesystem::path& pcap, const std::string& labels,
                                  const std::string& text) {
    const auto r = run_cli({kCli, "eval", pcap.string(), "--labels", labels});
    INFO(r.err);
    CHECK(r.code == 1);
    CHECK(one_line(r.err));
    CHECK(r.err.find(text) != std::string::npos);
    CHECK(r.out.find("F1") == std::string::npos);
  };
  expect_refused(hills, test::project_pcap("urban_demo.labels").string(),
                 "labels cover 283 packets (108672 bytes), the capture has 135");
  expect_refused(hills, "/dev/null", "labels cover 0 packets");
  // The simulator's JSON beside the capture must describe it too.
  const auto dir = test::temp_dir("cli_labels");
  std::filesystem::copy_file(hills, dir / "h.pcap");
  std::ofstream(dir / "h.json") << R"({"packets": 999, "mount_roll_pitch_deg": [0, 0]})";
  expect_refused(dir / "h.pcap", test::project_pcap("hills_demo.labels").string(),
                 "describes 999 packets, the capture has 135");
  // Its own labels still score.
  const auto ok = run_cli(
      {kCli, "eval", hills.string(), "--labels", test::project_pcap("hills_demo.labels").string()});
  CHECK(ok.code == 0);
}

TEST_CASE("15.5 live summaries claim only what was measured") {
  SECTION("nothing received: an error unless --allow-empty, and no verdict") {
    const std::string port = std::to_string(test::free_port());
    const std::vector<std::string> args{kCli,         "live", "--bind",          "127.0.0.1",
                                        "--port",     port,   "--position-port", "0",
                                        "--duration", "0.2"};
    const auto r = run_cli(args);
    CHECK(r.code == 1);
    CHECK(r.err.find("no packets received on udp 127.0.0.1:" + port) != std::string::npos);
    CHECK(r.out.find(": met") == std::string::npos);
    CHECK(r.out.find("MISSED") == std::string::npos);
    auto allowed = args;
    allowed.push_back("--allow-empty");
    CHECK(run_cli(allowed).code == 0);
  }
  SECTION(
      "few samples: no percentiles, the silence-flushed frame apart, throughput from the "
      "first packet") {
    const auto pcap = test::shared_file("sim", "urban_strongest.pcap");
    VLPGROUND_REQUIRE_SHARED(pcap);
    const auto [port, position_port] = test::free_port_pair();
    test::ChildProcess child({kCli, "live", "--bind", "127.0.0.1", "--port", std::to_string(port),
                              "--position-port", std::to_string(position_port), "--queue", "16",
                              "--duration", "1.5", "--json"});
    REQUIRE(child.wait_for_stderr("listening", 20'000));
    test::send_capture(pcap->string(), port, position_port, 0.0);  // as fast as it goes
    REQUIRE(child.wait_exit(30'000) == 0);
    INFO(child.out);
    const auto j = nlohmann::json::parse(child.out);
    const auto delivered = j["frames"]["delivered"].get<std::uint64_t>();
    REQUIRE(delivered >= 2);
    REQUIRE(delivered < 10);                   // too few samples for any percentile
    CHECK(j["silence_frames"]["count"] == 1);  // the last frame, flushed by the timeout
    CHECK(j["timings"]["latency"]["samples"] == delivered - 1);
    CHECK(j["timings"]["latency"]["p50_ms"].is_null());
    CHECK(j["timings"]["latency"]["p99_ms"].is_null());
    CHECK(j["timings"]["latency"]["max_ms"].get<double>() <
          j["silence_frames"]["latency_max_ms"].get<double>());
    // 1.5 s of running, well under a second of packets.
    CHECK(j["active_s"].get<double>() < 0.5 * j["elapsed_s"].get<double>());
    CHECK(j["frames_per_s"].get<double>() >
          2 * static_cast<double>(delivered) / j["elapsed_s"].get<double>());
  }
}

TEST_CASE("15.11 a run without any ground says why in one line") {
  const auto floor = test::shared_file("real", "vlp16_dual_close_range.pcap");
  VLPGROUND_REQUIRE_SHARED(floor);
  const auto r = run_cli({kCli, "replay", floor->string(), "--json"});
  CHECK(r.code == 0);
  CHECK(one_line(r.err));
  CHECK(r.err.find("no ground in any frame") != std::string::npos);
  CHECK(r.err.find("--min-sensor-height 0") != std::string::npos);
  const auto found = run_cli({kCli, "replay", floor->string(), "--min-sensor-height", "0"});
  CHECK(found.err.find("no ground") == std::string::npos);
}

TEST_CASE("15.1 one sign convention: tilted simulator captures score through eval like a level one") {
  const auto dir = test::temp_dir("cli_tilt");
  const auto f1_of = [](const std::string& out) {
    const auto j = nlohmann::json::parse(out);
    return j["f1"].get<double>();
  };
  const auto score = [&](const std::string& stem, const std::vector<std::string>& tilt,
                         const std::vector<std::string>& eval_extra) {
    std::vector<std::string> sim{kCli, "sim", "urban", "--frames", "2", "--seed", "3",
                                 "--height-m", "1.8", "--out", (dir / stem).string()};
    sim.insert(sim.end(), tilt.begin(), tilt.end());
    REQUIRE(run_cli(sim).code == 0);
    std::vector<std::string> eval{kCli, "eval", (dir / (stem + ".pcap")).string(), "--labels",
                                  (dir / (stem + ".labels")).string(), "--json"};
    eval.insert(eval.end(), eval_extra.begin(), eval_extra.end());
    const auto r = run_cli(eval);
    REQUIRE(r.code == 0);
    return f1_of(r.out);
  };
  const double level = score("level", {}, {});
  REQUIRE(level > 0.99);
  for (const char* option : {"--pitch-deg", "--roll-deg"}) {
    for (const char* degrees : {"8", "-8"}) {
      INFO(option << " " << degrees);
      const std::string stem = std::string(option + 2) + degrees;
      // The pose from STEM.json beside the capture...
      CHECK(score(stem, {option, degrees}, {}) > level - 0.01);
      // ...and the same pose given as --extrinsics x,y,z,roll,pitch,yaw.
      const bool pitch = std::string(option) == "--pitch-deg";
      const std::string pose = std::string("0,0,1.8,") + (pitch ? "0" : degrees) + "," +
                               (pitch ? degrees : "0") + ",0";
      CHECK(score(stem, {option, degrees}, {"--extrinsics", pose}) > level - 0.01);
    }
  }
}

TEST_CASE("15.12 docs/cli.md is the reference generated from the parser") {
  const auto r = run_cli({kCli, "help", "--all-markdown"});
  REQUIRE(r.code == 0);
  std::ifstream in(std::filesystem::path(VLPGROUND_SOURCE_DIR) / "docs" / "cli.md");
  const std::string committed((std::istreambuf_iterator<char>(in)),
                              std::istreambuf_iterator<char>());
  INFO("regenerate it: cmake --build build --target cli_docs");
  CHECK(committed == r.out);
  // It documents what users asked about.
  for (const char* text : {"| `--frames` |", "## vlpground sim", "## vlpground info",
                           "`--frames 0` means every frame", "label` is 0 no return, 1 ground",
                           "column `return`", "sensor frame", "Exit status", "--version",
                           "help SUBCOMMAND"}) {
    INFO(text);
    CHECK(r.out.find(text) != std::string::npos);
  }
}

TEST_CASE("15.9 info: verdicts only where they mean something, rpm of short captures") {
  const auto real = [](const char* name) { return test::shared_file("real", name); };
  const auto position_only = real("vlp16_one_position_packet.pcap");
  VLPGROUND_REQUIRE_SHARED(position_only);
  const auto info = [](const std::filesystem::path& p, std::vector<std::string> extra = {}) {
    std::vector<std::string> args{kCli, "info", p.string()};
    args.insert(args.end(), extra.begin(), extra.end());
    return run_cli(args);
  };
  const auto none = info(*position_only);
  CHECK(none.out.find("none (no data packets)") != std::string::npos);
  CHECK(none.out.find("NOT agree") == std::string::npos);
  const auto none_json = nlohmann::json::parse(info(*position_only, {"--json"}).out);
  CHECK(none_json["product_byte_agrees_with_timing"].is_null());
  // An HDL-32E whose byte and timing agree.
  const auto hdl = info(*real("hdl32e_short.pcap"));
  CHECK(hdl.out.find("0x21 (HDL-32E, agrees with the packet timing)") != std::string::npos);
  // Short captures without a complete rotation still get their rpm.
  const auto fair = nlohmann::json::parse(
      info(*real("vlp16_county_fair_productbyte21.pcap"), {"--json"}).out);
  CHECK(fair["rpm"].get<double>() == Approx(600).margin(10));
  const auto slow = info(*real("vlp16_short.pcap"));
  CHECK(slow.out.find("rpm            0.0") == std::string::npos);
  CHECK(slow.out.find("1 truncated") != std::string::npos);  // truncated records shown
  CHECK(info(*real("vlp16_one_packet.pcap")).out.find("(1 frame with") != std::string::npos);
  // --model is accepted as by replay.
  CHECK(info(*real("vlp16_short.pcap"), {"--model", "vlp16"}).code == 0);
}

TEST_CASE("15.10 --frames N counts full rotations unless --partial") {
  const auto pcap = test::shared_file("sim", "urban_strongest.pcap");
  VLPGROUND_REQUIRE_SHARED(pcap);
  const auto frames = [&](std::vector<std::string> extra) {
    std::vector<std::string> args{kCli, "replay", pcap->string(), "--json"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = run_cli(args);
    REQUIRE(r.code == 0);
    return nlohmann::json::parse(r.out)["frames"];
  };
  const auto full = frames({"--frames", "2"});
  CHECK(full["delivered"].get<int>() - full["incomplete"].get<int>() == 2);
  CHECK(full["incomplete"] == 1);  // the capture starts mid-rotation
  const auto partial = frames({"--frames", "2", "--partial"});
  CHECK(partial["delivered"] == 2);
  CHECK(partial["incomplete"] == 1);
}

namespace {

// JSON's own types; signed and unsigned integers are one.
std::string json_kind(const nlohmann::json& v) {
  return v.is_number_integer() ? "integer" : v.type_name();
}

// Fields present in both documents (recursively) whose types differ, as "path: a vs b".
void type_mismatches(const nlohmann::json& a, const nlohmann::json& b, const std::string& path,
                     std::vector<std::string>& out, int& shared) {
  for (auto it = a.begin(); it != a.end(); ++it) {
    if (!b.contains(it.key())) continue;
    const auto& other = b[it.key()];
    const std::string where = path + "/" + it.key();
    ++shared;
    if (json_kind(*it) != json_kind(other)) {
      out.push_back(where + ": " + json_kind(*it) + " vs " + json_kind(other));
    } else if (it->is_object()) {
      type_mismatches(*it, other, where, out, shared);
    }
  }
}

}  // namespace

TEST_CASE("15.9 info --json and replay --json: one type per field, the same measured facts") {
  std::vector<std::filesystem::path> captures{test::project_pcap("urban_demo.pcap"),
                                              test::project_pcap("hills_demo.pcap"),
                                              test::project_pcap("slope_dual.pcap")};
  const auto dir = test::temp_dir("cli_json_shapes");
  const auto sim = run_cli({kCli, "sim", "flat", "--frames", "2", "--model", "hires", "--mode",
                            "last", "--out", (dir / "flat_hires_last").string()});
  REQUIRE(sim.code == 0);
  captures.push_back(dir / "flat_hires_last.pcap");
  const std::size_t required = captures.size();  // these must replay
  if (const auto real = test::shared_file("real", "README.md")) {
    for (const auto& e : std::filesystem::directory_iterator(real->parent_path())) {
      if (e.path().extension() == ".pcap") captures.push_back(e.path());
    }
  } else {
    WARN("real captures skipped: ../shared/data/real not found (set VLPGROUND_SHARED_DIR)");
  }
  int compared = 0;
  for (std::size_t k = 0; k < captures.size(); ++k) {
    const std::string pcap = captures[k].string();
    INFO(pcap);
    const auto info = run_cli({kCli, "info", pcap, "--json"});
    const auto replay = run_cli({kCli, "replay", pcap, "--json"});
    if (k >= required && (info.code != 0 || replay.code != 0)) continue;  // not a VLP-16 capture
    REQUIRE(info.code == 0);
    REQUIRE(replay.code == 0);
    const auto i = nlohmann::json::parse(info.out);
    const auto r = nlohmann::json::parse(replay.out);
    std::vector<std::string> mismatches;
    int shared = 0;
    type_mismatches(i, r, "", mismatches, shared);
    CAPTURE(mismatches);
    CHECK(mismatches.empty());
    CHECK(shared >= 20);  // model, rpm, gps, packets..., not a handful
    // Measured facts of the capture: the same values.
    for (const char* key : {"model", "return_mode", "time_source", "calibration", "gps"}) {
      INFO(key);
      CHECK(i[key] == r[key]);
    }
    CHECK(i["model"].is_string());
    CHECK(i["gps"].is_object());
    for (const char* key : {"delivered", "complete", "incomplete"}) {
      CHECK(i["frames"][key] == r["frames"][key]);
    }
    for (const char* key : {"data", "position", "lost"}) {
      CHECK(i["packets"][key] == r["packets"][key]);
    }
    CHECK(i["rpm"].get<double>() == Approx(r["rpm"].get<double>()));
    CHECK(i["duration_s"].get<double>() == Approx(r["duration_s"].get<double>()));
    ++compared;
  }
  CHECK(compared >= static_cast<int>(required));
}

namespace {

// One frame of a `--csv` file: returns, first firing time, whole degrees of azimuth covered.
struct CsvFrame {
  std::uint64_t returns = 0;
  double first_us = 1e300;
  std::set<int> degrees;
};

std::map<int, CsvFrame> csv_frames(const std::filesystem::path& csv) {
  std::map<int, CsvFrame> frames;
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  const auto header = test::split(line);
  const auto column = [&](const char* name) {
    return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  };
  const std::size_t frame = column("frame"), time = column("timestamp_us"),
                    azimuth = column("azimuth_deg");
  REQUIRE(azimuth < header.size());
  while (std::getline(in, line)) {
    const auto f = test::split(line);
    CsvFrame& out = frames[std::stoi(f[frame])];
    ++out.returns;
    out.first_us = std::min(out.first_us, std::stod(f[time]));
    out.degrees.insert(static_cast<int>(std::stod(f[azimuth])));
  }
  return frames;
}

// "frame 3: 1808 columns, 16902 returns, ..." lines: columns and whether partial.
std::vector<std::pair<int, bool>> frame_line_columns(const std::string& out) {
  std::vector<std::pair<int, bool>> frames;
  std::istringstream lines(out);
  for (std::string l; std::getline(lines, l);) {
    int sequence = 0, columns = 0;
    if (std::sscanf(l.c_str(), "frame %d: %d columns", &sequence, &columns) != 2) continue;
    frames.emplace_back(columns, l.find("(partial rotation)") != std::string::npos);
  }
  return frames;
}

double median_of(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

TEST_CASE("15.10 --loop joins the end of the file to its start: full rotations across the wraps") {
  SECTION("single and dual return: after the first frame, every frame is one whole turn") {
    for (const char* name : {"urban_demo.pcap", "slope_dual.pcap"}) {
      INFO(name);
      const auto csv = test::temp_dir("cli_loop") / "loop.csv";
      // About three passes of a file with three full rotations.
      const auto r = run_cli({kCli, "replay", test::project_pcap(name).string(), "--loop",
                              "--frames", "12", "--csv", csv.string(), "--json"});
      INFO(r.err);
      REQUIRE(r.code == 0);
      const auto j = nlohmann::json::parse(r.out);
      CHECK(j["loop"]["wraps"].get<int>() >= 3);
      CHECK(j["loop"]["skipped_packets"].get<int>() > 0);
      CHECK(j["frames"]["incomplete"] == 1);  // the first frame only: the file starts mid-turn
      CHECK(j["packets"]["lost"] == 0);
      const auto frames = csv_frames(csv);
      REQUIRE(frames.size() == 13);
      std::vector<double> returns;
      for (const auto& [k, f] : frames) {
        if (k > 0) returns.push_back(static_cast<double>(f.returns));
      }
      const double typical = median_of(returns);
      double previous_us = 0;
      for (const auto& [k, f] : frames) {
        INFO("frame " << k);
        if (k > 0) {
          CHECK(static_cast<double>(f.returns) == Approx(typical).epsilon(0.02));
          CHECK(f.degrees.size() >= 358);
        }
        if (k > 1) CHECK(f.first_us - previous_us == Approx(100'000).epsilon(0.01));  // 600 rpm
        previous_us = f.first_us;
      }
    }
  }
  SECTION("a capture that never gives a full rotation: --frames ends with an error, not never") {
    const auto pcap = test::shared_file("real", "vlp16_short.pcap");  // gaps, < one rotation
    VLPGROUND_REQUIRE_SHARED(pcap);
    const auto r = run_cli({kCli, "replay", pcap->string(), "--loop", "--frames", "5"});
    CHECK(r.code == 1);
    CHECK(r.err.find("--frames 5 counts full rotations") != std::string::npos);
    CHECK(r.err.find("add --partial") != std::string::npos);
    CHECK(run_cli({kCli, "replay", pcap->string(), "--loop", "--frames", "5", "--partial"}).code ==
          0);
  }
  SECTION("a real capture at 1200 rpm without GPS, over two wraps") {
    const auto pcap = test::shared_file("real", "vlp16_1200rpm_productbyte21.pcap");
    VLPGROUND_REQUIRE_SHARED(pcap);
    const auto r = run_cli({kCli, "replay", pcap->string(), "--loop", "--frames", "110"});
    REQUIRE(r.code == 0);
    const auto frames = frame_line_columns(r.out);
    REQUIRE(frames.size() == 111);
    CHECK(frames[0].second);  // the partial first frame
    std::vector<double> columns;
    for (std::size_t k = 1; k < frames.size(); ++k) columns.push_back(frames[k].first);
    const double typical = median_of(columns);
    for (std::size_t k = 1; k < frames.size(); ++k) {
      INFO("frame " << k);
      CHECK_FALSE(frames[k].second);
      CHECK(frames[k].first >= 0.95 * typical);
      CHECK(frames[k].first <= 1.01 * typical);
    }
    int wraps = 0;
    const auto at = r.out.find("  loop ");
    REQUIRE(at != std::string::npos);
    std::sscanf(r.out.c_str() + at, "  loop %d wraps", &wraps);
    CHECK(wraps >= 2);
  }
}

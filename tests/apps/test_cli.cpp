// End-to-end tests of the built `vlpground` executable.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "child_process.hpp"
#include "cli_helpers.hpp"
#include "test_data.hpp"
#include "udp_sender.hpp"
#include "vlpground/driver/packet_source.hpp"

using namespace vlpground;
using test::free_port;
using test::one_line;
using test::read_lines;
using test::run_cli;
using test::split;

namespace {

const std::string kCli = VLPGROUND_CLI;
const std::string kHeader =
    "frame,laser_id,ring,return,timestamp_us,azimuth_deg,distance_m,x,y,z,intensity,ground";

struct PcapFacts {
  std::uint64_t returns = 0;   // distances != 0 over all data packets
  double first_stamp_us = -1;  // stamp of the first data packet
};

// Independent of the decoder: raw bytes of the data packets.
PcapFacts pcap_facts(const std::filesystem::path& path) {
  PcapSourceConfig c;
  c.path = path.string();
  auto source = open_pcap_source(c);
  PcapFacts f;
  PacketView v;
  while (source->next(v, 1000) == SourceStatus::packet) {
    if (v.kind != PacketKind::data) continue;
    for (std::size_t b = 0; b < 12; ++b) {
      for (std::size_t ch = 0; ch < 32; ++ch) {
        const std::size_t at = b * 100 + 4 + ch * 3;
        if ((v.bytes[at] | v.bytes[at + 1]) != 0) ++f.returns;
      }
    }
    if (f.first_stamp_us < 0) {
      std::uint32_t stamp = 0;
      for (int i = 3; i >= 0; --i)
        stamp = (stamp << 8) | v.bytes[1200 + static_cast<std::size_t>(i)];
      f.first_stamp_us = stamp;
    }
  }
  return f;
}

}  // namespace

TEST_CASE("replay --csv writes one row per return with exact firing times") {
  for (const char* stem : {"urban_strongest", "fences_dual", "urban_hires_last", "flat_20hz"}) {
    const auto pcap = test::shared_file("sim", std::string(stem) + ".pcap");
    VLPGROUND_REQUIRE_SHARED(pcap);
    INFO(stem);
    const auto csv = test::temp_dir("cli_csv") / "out.csv";
    const auto r = run_cli({kCli, "replay", pcap->string(), "--csv", csv.string()});
    REQUIRE(r.code == 0);
    CHECK(r.out.find("frame 1: ") != std::string::npos);
    CHECK(r.out.find("summary") != std::string::npos);
    const auto lines = read_lines(csv);
    REQUIRE(!lines.empty());
    CHECK(lines[0] == kHeader);
    const PcapFacts facts = pcap_facts(*pcap);
    CHECK(lines.size() - 1 == facts.returns);
    std::size_t bad_time = 0, bad_fields = 0;
    for (std::size_t i = 1; i < lines.size(); ++i) {
      const auto f = split(lines[i]);
      if (f.size() != 12 || (f[11] != "0" && f[11] != "1") || (f[3] != "0" && f[3] != "1")) {
        ++bad_fields;
        continue;
      }
      // Firing time = packet stamp (whole us) + 55.296 us * s + 2.304 us * laser, s < 24.
      const double t = std::stod(f[4]) - 2.304 * std::stoi(f[1]);
      bool on_grid = false;
      for (int seq = 0; seq < 24 && !on_grid; ++seq) {
        const double stamp = t - 55.296 * seq;
        on_grid = std::fabs(stamp - std::round(stamp)) < 0.002;
      }
      if (!on_grid || std::stod(f[4]) < facts.first_stamp_us) ++bad_time;
    }
    CHECK(bad_fields == 0);
    CHECK(bad_time == 0);
  }
}

TEST_CASE("eval prints precision, recall and F1") {
  const auto pcap = test::shared_file("sim", "urban_strongest.pcap");
  const auto labels = test::shared_file("sim", "urban_strongest.labels");
  VLPGROUND_REQUIRE_SHARED(pcap);
  const auto r = run_cli({kCli, "eval", pcap->string(), "--labels", labels->string()});
  REQUIRE(r.code == 0);
  const auto at = r.out.find("F1");
  REQUIRE(at != std::string::npos);
  const double f1 = std::stod(r.out.substr(r.out.find_first_of("0123456789", at)));
  CHECK(f1 > 0.8);
  CHECK(f1 <= 1.0);
}

TEST_CASE("bad input gives a one-line error and a non-zero exit") {
  SECTION("missing file") {
    const auto r = run_cli({kCli, "replay", "/nonexistent/capture.pcap"});
    CHECK(r.code == 1);
    CHECK(one_line(r.err));
  }
  SECTION("malformed options") {
    for (const auto& args :
         std::vector<std::vector<std::string>>{{kCli, "replay", "x.pcap", "--frames", "ten"},
                                               {kCli, "replay", "x.pcap", "--method", "magic"},
                                               {kCli, "live", "--port", "70000"},
                                               {kCli, "info"},
                                               {kCli, "eval", "x.pcap"},
                                               {kCli, "replay", "--bogus"}}) {
      const auto r = run_cli(args);
      CHECK(r.code == 2);
      CHECK(one_line(r.err));
    }
  }
  SECTION("not a VLP-16 capture") {
    const auto pcap = test::shared_file("real", "hdl32e_short.pcap");
    VLPGROUND_REQUIRE_SHARED(pcap);
    const auto r = run_cli({kCli, "replay", pcap->string()});
    CHECK(r.code == 1);
    CHECK(one_line(r.err));
    CHECK(r.err.find("HDL-32E") != std::string::npos);
    const auto info = run_cli({kCli, "info", pcap->string()});
    CHECK(info.code == 1);
    CHECK(info.out.find("not a VLP-16") != std::string::npos);
  }
  SECTION("port in use") {
    const int fd = socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    REQUIRE(bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
    socklen_t len = sizeof a;
    getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
    const auto r = run_cli({kCli, "live", "--bind", "127.0.0.1", "--port",
                            std::to_string(ntohs(a.sin_port)), "--position-port", "0"});
    close(fd);
    CHECK(r.code == 1);
    CHECK(one_line(r.err));
  }
}

TEST_CASE("replay --min-sensor-height lets a sensor standing on the floor find it") {
  const auto pcap = test::shared_file("real", "vlp16_dual_close_range.pcap");
  VLPGROUND_REQUIRE_SHARED(pcap);
  const auto ground_share = [&](const std::vector<std::string>& extra) {
    std::vector<std::string> args{kCli, "replay", pcap->string(), "--json"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = run_cli(args);
    REQUIRE(r.code == 0);
    const auto at = r.out.find("\"ground_share\":");
    REQUIRE(at != std::string::npos);
    return std::stod(r.out.substr(at + 15));
  };
  // The floor is 5 cm under the optical centre (docs/detector.md): the vehicle prior refuses it.
  CHECK(ground_share({}) < 0.01);
  // 11 % with the column profiles (33 % with the cells alone, which also take the feet of the
  // vertical surfaces next to the sensor): docs/detector.md.
  CHECK(ground_share({"--min-sensor-height", "0"}) > 0.08);
  CHECK(run_cli({kCli, "replay", pcap->string(), "--min-sensor-height", "-1"}).code == 2);
}

TEST_CASE("help documents every command") {
  for (const char* cmd : {"replay", "live", "info", "eval", "sim"}) {
    INFO(cmd);
    const auto r = run_cli({kCli, cmd, "--help"});
    CHECK(r.code == 0);
    CHECK(r.out.find(std::string("usage: vlpground ") + cmd) != std::string::npos);
    const auto h = run_cli({kCli, "help", cmd});
    CHECK(h.code == 0);
    CHECK(h.out == r.out);
  }
  // Defaults come from the config structs and are printed.
  const auto live = run_cli({kCli, "live", "--help"});
  CHECK(live.out.find("=2368") != std::string::npos);
  CHECK(live.out.find("=0.0.0.0") != std::string::npos);
  CHECK(live.out.find("x forward, y left, z up") != std::string::npos);
  const auto bad = run_cli({kCli, "help", "bogus"});
  CHECK(bad.code == 2);
  CHECK(one_line(bad.err));
}

TEST_CASE("vlpground --version prints the project version") {
  const auto r = run_cli({kCli, "--version"});
  CHECK(r.code == 0);
  CHECK(r.out == std::string("vlpground ") + VLPGROUND_VERSION + "\n");
}

TEST_CASE("replay --config FILE.yaml sets every option, the command line wins") {
  const auto pcap = test::shared_file("sim", "urban_strongest.pcap");
  VLPGROUND_REQUIRE_SHARED(pcap);
  const auto dir = test::temp_dir("cli_config");
  const auto yaml = dir / "run.yaml";
  std::ofstream(yaml) << "json: true\nframes: 2\nextrinsics: [0, 0, 1.8, 0, 0, 0]\n"
                         "csv: "
                      << (dir / "out.csv").string() << "\n";
  const auto delivered = [](const std::string& out) {
    const auto at = out.find("\"delivered\":");
    REQUIRE(at != std::string::npos);
    return std::stoi(out.substr(at + 12));
  };
  const auto from_file = run_cli({kCli, "replay", pcap->string(), "--config", yaml.string()});
  REQUIRE(from_file.code == 0);
  CHECK(delivered(from_file.out) == 2 + 1);  // 2 full rotations after the partial first frame
  CHECK(read_lines(dir / "out.csv").size() > 1);
  const auto cli_wins =
      run_cli({kCli, "replay", pcap->string(), "--config", yaml.string(), "--frames", "3"});
  REQUIRE(cli_wins.code == 0);
  CHECK(delivered(cli_wins.out) == 3 + 1);
  for (const char* bad : {"bogus: 1\n", "queue: 0\n", "[1, 2]\n"}) {
    INFO(bad);
    std::ofstream(yaml) << bad;
    const auto r = run_cli({kCli, "replay", pcap->string(), "--config", yaml.string()});
    CHECK(r.code == 2);
    CHECK(one_line(r.err));
    CHECK(r.err.find("--config") != std::string::npos);
  }
}

TEST_CASE("live over loopback UDP labels like replay, and SIGINT ends a run cleanly") {
  const auto pcap = test::shared_file("sim", "urban_strongest.pcap");
  VLPGROUND_REQUIRE_SHARED(pcap);
  const auto dir = test::temp_dir("cli_live");
  const auto replay_csv = dir / "replay.csv", live_csv = dir / "live.csv";
  REQUIRE(run_cli({kCli, "replay", pcap->string(), "--csv", replay_csv.string()}).code == 0);
  const auto replay_lines = read_lines(replay_csv);
  REQUIRE(replay_lines.size() > 1);
  const int frames = std::stoi(split(replay_lines.back())[0]);  // the last, partial frame
  REQUIRE(frames >= 2);

  const auto [port, position_port] = test::free_port_pair();
  test::ChildProcess child({kCli, "live", "--bind", "127.0.0.1", "--port", std::to_string(port),
                            "--position-port", std::to_string(position_port), "--frames",
                            std::to_string(frames), "--partial", "--queue", "16", "--csv", live_csv.string()});
  REQUIRE(child.wait_for_stderr("listening", 20'000));

  // Send the capture at its own pace (rate 1.0: a live sensor's timing).
  test::send_capture(pcap->string(), port, position_port);
  const int code = child.wait_exit(30'000);
  INFO(child.err);
  REQUIRE(code == 0);
  CHECK(child.out.find("summary (live)") != std::string::npos);
  // The GPS hour that takes over from the host clock re-bases the frame in progress rather
  // than splitting it: the complete rotations are the same frames, row for row.
  const auto rows_of = [&](const std::vector<std::string>& lines, int first, int last) {
    std::vector<std::string> rows;
    for (std::size_t i = 1; i < lines.size(); ++i) {
      const int f = std::stoi(split(lines[i])[0]);
      if (f >= first && f <= last) rows.push_back(lines[i]);
    }
    return rows;
  };
  const auto live_lines = read_lines(live_csv);
  REQUIRE(live_lines.size() > 1);
  const auto expected = rows_of(replay_lines, 1, frames - 2);  // complete rotations
  const auto got = rows_of(live_lines, 1, frames - 2);
  CHECK(got.size() == expected.size());
  std::size_t differing = 0;
  for (std::size_t i = 0; i < std::min(got.size(), expected.size()); ++i) {
    if (got[i] != expected[i]) ++differing;
  }
  CHECK(differing == 0);

  test::ChildProcess idle({kCli, "live", "--bind", "127.0.0.1", "--port",
                           std::to_string(free_port()), "--position-port", "0",
                           "--allow-empty"});
  REQUIRE(idle.wait_for_stderr("listening", 20'000));
  idle.signal(SIGINT);
  CHECK(idle.wait_exit(20'000) == 0);
  CHECK(idle.out.find("summary (live)") != std::string::npos);
}

#include <catch2/catch.hpp>
#include <fstream>
#include <stdexcept>
#include <string>

#include "test_data.hpp"
#include "test_frames.hpp"
#include "vlpground/evaluation/evaluation.hpp"

using vlpground::Frame;
using vlpground::ReturnMode;
using vlpground::eval::GroundTruth;
using vlpground::eval::slot_of_cell;
using vlpground::eval::TruthLabel;

namespace {

std::filesystem::path write_bytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return path;
}

std::filesystem::path write_file(const std::string& tag, std::size_t size, std::uint8_t value) {
  return write_bytes(vlpground::test::temp_dir(tag) / "capture.labels",
                     std::string(size, static_cast<char>(value)));
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("labels loader reads one byte per slot in packet order", "[evaluation]") {
  std::vector<std::uint8_t> bytes(2 * 384, 0);
  bytes[384 + 5 * 32 + 17] = 2;  // packet 1, block 5, channel 17
  bytes[3] = 1;
  const GroundTruth truth(bytes);
  CHECK(truth.packets() == 2);
  CHECK(truth.at(1, 5 * 32 + 17) == TruthLabel::obstacle);
  CHECK(truth.at(0, 3) == TruthLabel::ground);
  CHECK(truth.at(0, 4) == TruthLabel::none);
  CHECK(truth.at(2, 0) == TruthLabel::none);  // past the end
  CHECK(truth.at(0, 384) == TruthLabel::none);
}

TEST_CASE("labels loader reports missing and malformed files clearly", "[evaluation]") {
  const auto missing = vlpground::test::temp_dir("eval-missing") / "nope.labels";
  CHECK_THROWS_AS(GroundTruth::load(missing), std::runtime_error);
  CHECK(message_of([&] { (void)GroundTruth::load(missing); }).find("nope.labels") !=
        std::string::npos);

  const auto odd = write_file("eval-odd", 383, 1);
  CHECK_THROWS_AS(GroundTruth::load(odd), std::invalid_argument);
  const std::string odd_message = message_of([&] { (void)GroundTruth::load(odd); });
  CHECK(odd_message.find("384") != std::string::npos);
  CHECK(odd_message.find("capture.labels") != std::string::npos);

  const auto bad_value = write_file("eval-bad", 384, 7);
  CHECK_THROWS_AS(GroundTruth::load(bad_value), std::invalid_argument);

  const auto good = write_file("eval-good", 3 * 384, 3);
  const GroundTruth truth = GroundTruth::load(good);
  CHECK(truth.packets() == 3);
  CHECK(truth.at(2, 383) == TruthLabel::ambiguous);
}

TEST_CASE("heights beside the labels: int16 little-endian centimetres per slot", "[evaluation]") {
  CHECK(vlpground::eval::heights_path_beside("dir/x.labels") ==
        std::filesystem::path("dir/x.heights"));
  const auto labels = write_file("eval-heights", 384, 2);
  CHECK_FALSE(GroundTruth::load_with_heights(labels).has_heights());  // no file: estimate
  CHECK_FALSE(GroundTruth::load_with_heights(labels).height_above_terrain_m(0, 0).has_value());

  std::string heights(2 * 384, '\0');
  heights[2 * 7] = static_cast<char>(0x2C);  // slot 7: 0x012C = 300 cm
  heights[2 * 7 + 1] = static_cast<char>(0x01);
  heights[2 * 9] = static_cast<char>(0xFB);  // slot 9: 0xFFFB = -5 cm
  heights[2 * 9 + 1] = static_cast<char>(0xFF);
  write_bytes(vlpground::eval::heights_path_beside(labels), heights);
  const GroundTruth truth = GroundTruth::load_with_heights(labels);
  REQUIRE(truth.has_heights());
  CHECK(truth.height_above_terrain_m(0, 7).value() == Approx(3.0f));
  CHECK(truth.height_above_terrain_m(0, 9).value() == Approx(-0.05f));
  CHECK(truth.height_above_terrain_m(0, 8).value() == Approx(0.0f));
  CHECK_FALSE(truth.height_above_terrain_m(1, 0).has_value());  // past the end
  CHECK(truth.at(0, 7) == TruthLabel::obstacle);
}

TEST_CASE("a heights file that does not match the labels is refused clearly", "[evaluation]") {
  const auto labels = write_file("eval-heights-size", 2 * 384, 1);
  const auto heights = vlpground::eval::heights_path_beside(labels);
  for (const std::size_t size : {std::size_t{384}, std::size_t{4 * 384 - 1}, std::size_t{0}}) {
    write_bytes(heights, std::string(size, '\0'));
    INFO(size << " bytes");
    CHECK_THROWS_AS(GroundTruth::load_with_heights(labels), std::invalid_argument);
    const std::string message = message_of([&] { (void)GroundTruth::load(labels, heights); });
    CHECK(message.find("capture.heights") != std::string::npos);
    CHECK(message.find("expected 1536") != std::string::npos);
  }
  write_bytes(heights, std::string(4 * 384, '\0'));
  CHECK(GroundTruth::load_with_heights(labels).has_heights());

  std::filesystem::remove(heights);
  CHECK_THROWS_AS(GroundTruth::load(labels, heights), std::runtime_error);  // named, missing
  CHECK(message_of([&] { (void)GroundTruth::load(labels, heights); }).find("capture.heights") !=
        std::string::npos);
  CHECK_THROWS_AS(GroundTruth(std::vector<std::uint8_t>(384, 1), std::vector<std::int16_t>(383)),
                  std::invalid_argument);
}

TEST_CASE("slot mapping: single return uses two sequences per block", "[evaluation]") {
  Frame frame(8);
  vlpground::test::set_vlp16_rings(frame);
  frame.meta.mode = ReturnMode::strongest;
  const int col = frame.append_column();
  frame.column_packet_index[0] = 41;
  frame.column_in_packet[0] = 5;  // sequence 5: block 2, channels 16..31
  // ring 9 is laser 3 (elevation +3 deg), ring 0 laser 0 (-15 deg), ring 15 laser 15.
  auto s = slot_of_cell(frame, 9, col, 0);
  CHECK(s.packet == 41);
  CHECK(s.block == 2);
  CHECK(s.channel == 19);
  CHECK(s.slot() == 83);
  frame.column_in_packet[0] = 22;  // block 11, channels 0..15
  s = slot_of_cell(frame, 0, col, 0);
  CHECK(s.slot() == 11 * 32 + 0);
  s = slot_of_cell(frame, 15, col, 0);
  CHECK(s.slot() == 11 * 32 + 15);
}

TEST_CASE("slot mapping: dual return, last in the even block, strongest in the odd",
          "[evaluation]") {
  Frame frame(8);
  vlpground::test::set_vlp16_rings(frame);
  frame.meta.mode = ReturnMode::dual;
  const int col = frame.append_column();
  frame.column_packet_index[0] = 7;
  frame.column_in_packet[0] = 5;  // pair 2 (blocks 4, 5), second sequence (channels 16..31)
  const auto strongest = slot_of_cell(frame, 9, col, vlpground::kStrongestLayer);
  const auto last = slot_of_cell(frame, 9, col, vlpground::kLastLayer);
  CHECK(strongest.block == 5);
  CHECK(last.block == 4);
  CHECK(strongest.channel == 19);
  CHECK(last.channel == 19);
  frame.column_in_packet[0] = 10;  // pair 5 (blocks 10, 11), first sequence
  CHECK(slot_of_cell(frame, 1, col, vlpground::kStrongestLayer).slot() == 11 * 32 + 2);
  CHECK(slot_of_cell(frame, 1, col, vlpground::kLastLayer).slot() == 10 * 32 + 2);
}

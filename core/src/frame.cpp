#include "vlpground/frame.hpp"

#include <algorithm>

namespace vlpground {

void ReturnLayer::resize(std::size_t cells) {
  for (auto* v : {&range_m, &x_m, &y_m, &z_m, &azimuth_deg, &time_offset_us}) v->assign(cells, 0.f);
  intensity.assign(cells, 0);
  valid.assign(cells, 0);
}

void Frame::reserve(int capacity_columns) {
  capacity_ = capacity_columns;
  stride_ = (capacity_ + 15) / 16 * 16 + 16;  // one extra cache line of floats per row
  const auto cells = static_cast<std::size_t>(kLasers) * static_cast<std::size_t>(stride_);
  for (auto& l : layer) l.resize(cells);
  same_echo.assign(cells, 0);
  column_azimuth_deg.assign(static_cast<std::size_t>(capacity_), 0.f);
  column_time_ns.assign(static_cast<std::size_t>(capacity_), 0);
  column_valid.assign(static_cast<std::size_t>(capacity_), 0);
  column_packet_index.assign(static_cast<std::size_t>(capacity_), 0);
  column_in_packet.assign(static_cast<std::size_t>(capacity_), 0);
  columns_ = 0;
}

void Frame::clear() {
  columns_ = 0;
  meta = FrameMeta{};
}

int Frame::append_column() {
  if (columns_ >= capacity_) return -1;
  const int col = columns_++;
  for (int ring = 0; ring < kLasers; ++ring) {
    const auto i = index(ring, col);
    for (auto& l : layer) {
      l.range_m[i] = 0.f;
      l.valid[i] = 0;
    }
    same_echo[i] = 0;
  }
  column_valid[static_cast<std::size_t>(col)] = 0;
  return col;
}

}  // namespace vlpground

#include "trig_table.hpp"

#include <cmath>
#include <numbers>

namespace vlpground::driver_detail {

TrigTable::TrigTable() {
  for (std::size_t i = 0; i < table_.size(); ++i) {
    const double rad = static_cast<double>(i) * std::numbers::pi / 18000.0;
    table_[i] = {std::cos(rad), std::sin(rad)};
  }
}

const TrigTable& TrigTable::instance() {
  static const TrigTable table;
  return table;
}

}  // namespace vlpground::driver_detail

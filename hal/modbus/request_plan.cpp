#include "request_plan.hpp"

#include <algorithm>
#include <numeric>

namespace sinew::hal::modbus {

std::vector<ReadRequest> plan_requests(std::span<const ChannelConfig> channels, uint16_t max_registers,
                                       uint16_t max_gap) {
  std::vector<uint16_t> order(channels.size());
  std::iota(order.begin(), order.end(), uint16_t{0});
  std::stable_sort(order.begin(), order.end(), [&](uint16_t a, uint16_t b) {
    const ChannelConfig& ca = channels[a];
    const ChannelConfig& cb = channels[b];
    if (ca.table != cb.table) return ca.table < cb.table;
    return ca.address < cb.address;
  });

  std::vector<ReadRequest> plan;
  uint32_t end = 0;  // one past the last register of the open request
  for (uint16_t index : order) {
    const ChannelConfig& c = channels[index];
    const uint32_t first = c.address;
    const uint32_t last = first + register_count(c.width);  // one past
    if (!plan.empty()) {
      ReadRequest& open = plan.back();
      const uint32_t merged_end = std::max(end, last);
      const bool same_table = open.table == c.table;
      const bool close_enough = first <= end + max_gap;
      const bool fits = merged_end - open.address <= max_registers;
      if (same_table && close_enough && fits) {
        end = merged_end;
        open.count = static_cast<uint16_t>(end - open.address);
        open.channels.push_back(index);
        continue;
      }
    }
    plan.push_back(ReadRequest{c.table, c.address, static_cast<uint16_t>(last - first), {index}});
    end = last;
  }
  return plan;
}

}  // namespace sinew::hal::modbus

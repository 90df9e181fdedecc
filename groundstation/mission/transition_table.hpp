// The shape of the project's transition tables (the vehicles' sequencer, the attempt's phases,
// after the firmware's supervisor): rows "from any of these states, when all of these condition
// bits hold and none of those, go to that state for this reason", the first matching row in table
// order winning; and condition words printed by their bits' names.
#pragma once

#include <cstdint>
#include <string>

namespace gs::mission {

template <typename State, typename Reason>
struct TableRow {
  std::uint32_t from;  // a set of states, bit per state
  std::uint32_t all;   // every one of these bits holds
  std::uint32_t none;  // none of these bits holds
  State to;
  Reason reason;
};

// The first row of `table` whose `from` holds `state_bit` and whose bits match `conditions`.
template <typename Table>
const typename Table::value_type* first_matching_row(const Table& table, std::uint32_t state_bit,
                                                     std::uint32_t conditions) {
  for (const auto& row : table) {
    if ((row.from & state_bit) == 0) continue;
    if ((conditions & row.all) != row.all) continue;
    if ((conditions & row.none) != 0) continue;
    return &row;
  }
  return nullptr;
}

// The set bits of `word` below `count` by name, "a|b", or "0".
template <typename NameOf>
std::string bit_names(std::uint32_t word, int count, NameOf name_of) {
  std::string out;
  for (int b = 0; b < count; ++b) {
    if ((word & (std::uint32_t{1} << b)) == 0) continue;
    if (!out.empty()) out += '|';
    out += name_of(b);
  }
  return out.empty() ? "0" : out;
}

}  // namespace gs::mission

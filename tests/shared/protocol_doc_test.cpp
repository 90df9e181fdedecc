// docs/protocol.md is the table a person reads; this test keeps it in step with the catalogue.
#include <catch2/catch.hpp>

#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "pa/protocol.hpp"

namespace {

const char* direction_name(pa::proto::Direction d) {
  switch (d) {
    case pa::proto::Direction::ground_to_vehicle: return "ground_to_vehicle";
    case pa::proto::Direction::vehicle_to_ground: return "vehicle_to_ground";
    case pa::proto::Direction::plant_to_vehicle: return "plant_to_vehicle";
    case pa::proto::Direction::vehicle_to_plant: return "vehicle_to_plant";
    case pa::proto::Direction::plant_to_ground: return "plant_to_ground";
    case pa::proto::Direction::ground_to_plant: return "ground_to_plant";
  }
  return "?";
}

std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, '|')) {
    const auto b = cell.find_first_not_of(' ');
    const auto e = cell.find_last_not_of(' ');
    out.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
  }
  return out;
}

}  // namespace

TEST_CASE("docs/protocol.md lists exactly the catalogue's frames with their lengths and directions") {
  std::ifstream doc(std::string(PA_SOURCE_DIR) + "/docs/protocol.md");
  REQUIRE(doc.good());
  struct Row {
    std::string name;
    int length;
    std::string direction;
  };
  std::map<int, Row> rows;
  std::string line;
  while (std::getline(doc, line)) {
    if (line.rfind("| 0x", 0) != 0) continue;
    const auto c = cells(line);
    REQUIRE(c.size() >= 6);
    const int type = std::stoi(c[1], nullptr, 16);
    CHECK(rows.count(type) == 0);
    rows[type] = Row{c[2], std::stoi(c[3]), c[4]};
  }
  CHECK(rows.size() == pa::proto::kCatalogue.size());
  for (const auto& info : pa::proto::kCatalogue) {
    const int type = static_cast<int>(info.type);
    INFO("type 0x" << std::hex << type);
    REQUIRE(rows.count(type) == 1);
    CHECK(rows[type].name == info.name);
    CHECK(rows[type].length == info.length);
    CHECK(rows[type].direction == direction_name(info.direction));
  }
}

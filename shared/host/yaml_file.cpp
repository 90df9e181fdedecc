#include "pa/yaml_file.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

namespace pa::yaml {

namespace {

std::string at(const std::string& name, const YAML::Mark& mark) {
  return name + ":" + std::to_string(mark.is_null() ? 1 : mark.line + 1) + ": ";
}

}  // namespace

bool entries_of(const YAML::Node& map, const std::string& name, std::vector<Entry>& out, std::string& error) {
  out.clear();
  if (!map.IsMap()) {
    error = at(name, map.Mark()) + "expected a map of `key: value` lines";
    return false;
  }
  for (const auto& pair : map) {
    const YAML::Node& key = pair.first;
    if (!key.IsScalar()) {
      error = at(name, key.Mark()) + "a key must be a plain name";
      return false;
    }
    Entry entry{key.Scalar(), pair.second, key.Mark().line + 1};
    // yaml-cpp keeps a repeated key as a second entry; the file would be ambiguous.
    for (const Entry& e : out) {
      if (e.key == entry.key) {
        error = at(name, key.Mark()) + "'" + entry.key + "' is given twice (first on line " +
                std::to_string(e.line) + ")";
        return false;
      }
    }
    out.push_back(std::move(entry));
  }
  return true;
}

bool parse_document(std::string_view text, const std::string& name, YAML::Node& root, std::string& error) {
  try {
    root = YAML::Load(std::string(text));
  } catch (const YAML::Exception& e) {
    error = at(name, e.mark) + e.msg;
    return false;
  }
  return true;
}

bool read_file(const std::string& path, std::string& text, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream buffer;
  if (in) buffer << in.rdbuf();
  if (!in || in.bad()) {
    error = path + ": cannot read the file";
    return false;
  }
  text = buffer.str();
  return true;
}

std::string where(const std::string& name, const Entry& entry) {
  // A value left empty (null) is marked where the next line starts: name the key's line.
  const YAML::Mark mark = entry.value.Mark();
  const int line = entry.value.IsNull() || mark.is_null() || mark.line < 0 ? entry.line : mark.line + 1;
  return name + ":" + std::to_string(line) + ": ";
}

std::string text(const YAML::Node& node) { return node.IsScalar() ? node.Scalar() : std::string(); }

std::optional<double> finite_number(const YAML::Node& node) {
  double value = 0.0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, value) || !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

std::optional<long long> integer(const YAML::Node& node) {
  long long value = 0;
  if (!node.IsScalar() || !YAML::convert<long long>::decode(node, value)) return std::nullopt;
  return value;
}

std::optional<bool> boolean(const YAML::Node& node) {
  bool value = false;
  if (!node.IsScalar() || !YAML::convert<bool>::decode(node, value)) return std::nullopt;
  return value;
}

std::optional<std::vector<double>> numbers(const YAML::Node& node, std::size_t count) {
  if (!node.IsSequence() || node.size() != count) return std::nullopt;
  std::vector<double> values;
  for (const YAML::Node& item : node) {
    const std::optional<double> v = finite_number(item);
    if (!v) return std::nullopt;
    values.push_back(*v);
  }
  return values;
}

}  // namespace pa::yaml

// The configuration files of the host side (the plant, the scenarios, the vehicle limits) are
// YAML, read with yaml-cpp. This adds what they share: every error is "file:line: message"
// (yaml-cpp's marks give the line), for a syntax error as for a value out of range, and the
// scalar readers never throw.
#pragma once

#include <yaml-cpp/yaml.h>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace pa::yaml {

// One `key: value` of a file's top-level map (or of a map inside it), with where it stands.
struct Entry {
  std::string key;
  YAML::Node value;
  int line = 0;  // 1-based, of the key
};

// Parses `text` as one YAML document; `name` (the path as given) heads every message. False
// with "name:line: message" on a syntax error. An empty document is a null node.
bool parse_document(std::string_view text, const std::string& name, YAML::Node& root, std::string& error);
// The entries of a map node (a document's top level, or a map inside it such as a scenario's
// `plant:` overrides). False with "name:line: message" for a node that is not a map, a key that
// is not a plain scalar or a key given twice.
bool entries_of(const YAML::Node& map, const std::string& name, std::vector<Entry>& out, std::string& error);
// The whole file as text; false with "path: cannot read the file" otherwise.
bool read_file(const std::string& path, std::string& text, std::string& error);

// "name:line: " for an entry's value (its own line where yaml-cpp knows it, else the key's).
std::string where(const std::string& name, const Entry& entry);

// A scalar's text as written ("" for a map, a list or null), for messages.
std::string text(const YAML::Node& node);

// Strict readers: the whole scalar must be the value.
std::optional<double> finite_number(const YAML::Node& node);  // not .inf or .nan
std::optional<long long> integer(const YAML::Node& node);
std::optional<bool> boolean(const YAML::Node& node);  // true/false, yes/no, on/off
// A list of `count` finite numbers, e.g. [1.5, 0, 2.0].
std::optional<std::vector<double>> numbers(const YAML::Node& node, std::size_t count);

}  // namespace pa::yaml

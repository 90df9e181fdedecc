#include "hil/plant/key_value_file.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace hil {

namespace {

std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r");
  return s.substr(first, last - first + 1);
}

bool valid_key(std::string_view key) {
  if (key.empty()) return false;
  for (const char c : key) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
                    c == '.';
    if (!ok) return false;
  }
  return true;
}

}  // namespace

bool parse_key_values(std::string_view text, const std::string& name, KeyValueFile& out, std::string& error) {
  out = KeyValueFile{};
  out.name = name;
  int line_number = 0;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_number;
    if (const auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    line = trim(line);
    if (line.empty()) {
      if (end == text.size()) break;
      continue;
    }
    const auto eq = line.find('=');
    const std::string prefix = name + ":" + std::to_string(line_number) + ": ";
    if (eq == std::string_view::npos) {
      error = prefix + "expected `key = value`, got '" + std::string(line) + "'";
      return false;
    }
    const std::string_view key = trim(line.substr(0, eq));
    const std::string_view value = trim(line.substr(eq + 1));
    if (!valid_key(key)) {
      error = prefix + "'" + std::string(key) + "' is not a key (letters, digits, '_' and '.')";
      return false;
    }
    if (value.empty()) {
      error = prefix + "'" + std::string(key) + "' has no value";
      return false;
    }
    for (const KeyValue& e : out.entries) {
      if (e.key == key) {
        error = prefix + "'" + std::string(key) + "' is given twice (first on line " + std::to_string(e.line) + ")";
        return false;
      }
    }
    out.entries.push_back(KeyValue{std::string(key), std::string(value), line_number});
    if (end == text.size()) break;
  }
  return true;
}

bool read_text_file(const std::string& path, std::string& text, std::string& error) {
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

bool read_key_values(const std::string& path, KeyValueFile& out, std::string& error) {
  std::string text;
  return read_text_file(path, text, error) && parse_key_values(text, path, out, error);
}

std::optional<double> parse_real(std::string_view text) {
  const std::string s(trim(text));
  if (s.empty()) return std::nullopt;
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size() || errno == ERANGE || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::optional<long long> parse_integer(std::string_view text) {
  const std::string s(trim(text));
  if (s.empty()) return std::nullopt;
  errno = 0;
  char* end = nullptr;
  const long long v = std::strtoll(s.c_str(), &end, 10);
  if (end != s.c_str() + s.size() || errno == ERANGE) return std::nullopt;
  return v;
}

std::optional<bool> parse_bool(std::string_view text) {
  const std::string_view s = trim(text);
  if (s == "true" || s == "yes" || s == "on" || s == "1") return true;
  if (s == "false" || s == "no" || s == "off" || s == "0") return false;
  return std::nullopt;
}

std::optional<std::vector<double>> parse_reals(std::string_view text) {
  std::vector<double> values;
  std::string token;
  auto flush = [&]() -> bool {
    if (token.empty()) return true;
    const auto v = parse_real(token);
    token.clear();
    if (!v) return false;
    values.push_back(*v);
    return true;
  };
  for (const char c : text) {
    if (c == ' ' || c == '\t' || c == ',' || c == '\r') {
      if (!flush()) return std::nullopt;
    } else {
      token.push_back(c);
    }
  }
  if (!flush()) return std::nullopt;
  return values;
}

std::optional<Vec3> parse_vec3(std::string_view text) {
  const auto values = parse_reals(text);
  if (!values || values->size() != 3) return std::nullopt;
  return Vec3((*values)[0], (*values)[1], (*values)[2]);
}

std::string where(const KeyValueFile& file, const KeyValue& entry) {
  return file.name + ":" + std::to_string(entry.line) + ": ";
}

}  // namespace hil

#include "pa/link_key_file.hpp"

#include <cctype>
#include <fstream>
#include <sstream>

namespace pa::auth {

namespace {
int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}
}  // namespace

bool read_key_file(const std::string& path, Key& key, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = path + ": cannot read the key file";
    return false;
  }
  std::ostringstream text;
  text << in.rdbuf();
  std::string digits = text.str();
  const auto first = digits.find_first_not_of(" \t\r\n");
  const auto last = digits.find_last_not_of(" \t\r\n");
  digits = first == std::string::npos ? std::string() : digits.substr(first, last - first + 1);
  if (digits.size() != 2 * key.size()) {
    error = path + ": a link key is 32 hexadecimal digits (128 bits), found " +
            std::to_string(digits.size()) + " characters";
    return false;
  }
  Key parsed{};
  for (std::size_t i = 0; i < parsed.size(); ++i) {
    const int hi = hex_value(digits[2 * i]);
    const int lo = hex_value(digits[2 * i + 1]);
    if (hi < 0 || lo < 0) {
      error =
          path + ": character " + std::to_string(2 * i + (hi < 0 ? 1 : 2)) + " is not a hexadecimal digit";
      return false;
    }
    parsed[i] = static_cast<std::uint8_t>(hi * 16 + lo);
  }
  if (!provisioned(parsed)) {
    error = path +
            ": all zeros or all ones is not a key (make one: od -An -tx1 -N16 /dev/urandom | tr -d ' \\n')";
    return false;
  }
  key = parsed;
  return true;
}

}  // namespace pa::auth

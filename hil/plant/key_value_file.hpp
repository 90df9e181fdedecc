// The `key = value` text format of the plant configuration and the scenario files: one pair
// per line, `#` starts a comment, blank lines are ignored. Every error names the file and line
// ("plant.conf:12: ..."); nothing here throws or aborts on bad input.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "hil/plant/types.hpp"

namespace hil {

struct KeyValue {
  std::string key;
  std::string value;
  int line = 0;
};

struct KeyValueFile {
  std::string name;  // for messages: the path as given
  std::vector<KeyValue> entries;
};

// Splits `text` into entries. Returns false with `error` = "name:line: message" on a line that
// is not `key = value`, or on a key given twice.
bool parse_key_values(std::string_view text, const std::string& name, KeyValueFile& out, std::string& error);
// The whole file as text; false with "<path>: cannot read the file" otherwise.
bool read_text_file(const std::string& path, std::string& text, std::string& error);
// Reads the file and parses it; a file that cannot be read is an error too.
bool read_key_values(const std::string& path, KeyValueFile& out, std::string& error);

// Strict value parsers: the whole string must be the value (surrounding blanks allowed).
std::optional<double> parse_real(std::string_view text);  // finite only
std::optional<long long> parse_integer(std::string_view text);
std::optional<bool> parse_bool(std::string_view text);    // true/false, yes/no, on/off, 1/0
// Three reals separated by blanks and/or commas.
std::optional<Vec3> parse_vec3(std::string_view text);
// Any count of reals separated by blanks and/or commas.
std::optional<std::vector<double>> parse_reals(std::string_view text);

// "name:line: " for a message about an entry.
std::string where(const KeyValueFile& file, const KeyValue& entry);

}  // namespace hil

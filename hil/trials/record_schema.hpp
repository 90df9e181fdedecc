// A record's fields named once, for every text a record is written as: the workers' reports
// (one line, every field exact: reals to 17 significant digits, so that a report decodes to the
// very values encoded) and the CSV files people read (the columns a file chooses, each field
// with its own printf format and unit). A field added to a schema is carried through the pipe and
// offered to every CSV; nothing writes a record's fields by hand.
//
//   field("flight_s", &AttemptResult::flight_s, "%.4f")   // a member: int, uint64, double, bool,
//                                                          // string, or an enum (as its number;
//   named_field("outcome", &AttemptResult::outcome, to_string, parse_throw_outcome)  // by name)
//   encode(schema, r) / decode(schema, line, r)             // tab-separated, every field
//   csv_header(columns) / csv_row(columns, r)               // comma-separated, the chosen columns
//
// Text fields must not contain the separators (tab, '|', newline, and ',' in a CSV).
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>
#include <initializer_list>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace hil::trials {

template <class R>
struct Field {
  std::string name;                                  // the CSV column
  std::function<std::string(const R&)> exact;        // the report's text: exact
  std::function<void(R&, const std::string&)> read;  // back from exact; throws on a bad text
  std::function<std::string(const R&)> cell;         // the CSV cell
  // (a CSV-only column, column() or column_of(), has neither exact nor read: never encode it)
};

template <class R>
using Schema = std::vector<Field<R>>;

// Splits at every `separator`; a trailing one ends with an empty field, "" is no field.
std::vector<std::string> split(const std::string& text, char separator);

namespace detail {

inline std::string format_real(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

}  // namespace detail

// A field of member `member`, written in a CSV with `csv_format` (reals: their printf format,
// after multiplying by `csv_scale`; other kinds take none: %d, %llu, the text as it is).
template <class R, class M>
Field<R> field(std::string name, M R::*member, const char* csv_format = nullptr, double csv_scale = 1.0) {
  Field<R> f;
  f.name = std::move(name);
  if constexpr (std::is_same_v<M, double>) {
    if (csv_format == nullptr) throw std::logic_error("a real field needs its CSV format: " + f.name);
    const std::string format = csv_format;
    f.exact = [member](const R& r) { return detail::format_real("%.17g", r.*member); };
    f.read = [member](R& r, const std::string& text) { r.*member = std::stod(text); };
    f.cell = [member, format, csv_scale](const R& r) {
      return detail::format_real(format.c_str(), csv_scale * (r.*member));
    };
  } else if constexpr (std::is_same_v<M, bool>) {
    f.exact = f.cell = [member](const R& r) { return std::string(r.*member ? "1" : "0"); };
    f.read = [member](R& r, const std::string& text) {
      if (text != "0" && text != "1") throw std::invalid_argument("not a flag: " + text);
      r.*member = text == "1";
    };
  } else if constexpr (std::is_same_v<M, std::string>) {
    f.exact = f.cell = [member](const R& r) { return r.*member; };
    f.read = [member](R& r, const std::string& text) { r.*member = text; };
  } else if constexpr (std::is_same_v<M, std::uint64_t>) {
    f.exact = f.cell = [member](const R& r) { return std::to_string(r.*member); };
    f.read = [member](R& r, const std::string& text) { r.*member = std::stoull(text); };
  } else if constexpr (std::is_integral_v<M>) {
    f.exact = f.cell = [member](const R& r) { return std::to_string(r.*member); };
    f.read = [member](R& r, const std::string& text) { r.*member = static_cast<M>(std::stoi(text)); };
  } else if constexpr (std::is_enum_v<M>) {
    using U = std::underlying_type_t<M>;
    f.exact = f.cell = [member](const R& r) { return std::to_string(static_cast<long long>(r.*member)); };
    f.read = [member](R& r, const std::string& text) {
      r.*member = static_cast<M>(static_cast<U>(std::stoi(text)));
    };
  } else {
    static_assert(std::is_same_v<M, double>, "a field is an int, uint64, double, bool, string or enum");
  }
  return f;
}

// A field of enum member `member` written as its name, in the report and the CSV alike:
// `name_of(value)`, and back `parse(text)` (an optional: none for a name it does not know).
template <class R, class E, class NameOf, class Parse>
Field<R> named_field(std::string name, E R::*member, NameOf name_of, Parse parse) {
  Field<R> f;
  f.name = std::move(name);
  f.exact = f.cell = [member, name_of](const R& r) { return std::string(name_of(r.*member)); };
  f.read = [member, parse](R& r, const std::string& text) {
    const auto value = parse(text);
    if (!value) throw std::invalid_argument("not a name: " + text);
    r.*member = *value;
  };
  return f;
}

// `inner`'s field as a CSV column of Outer (its cell only: a column of a view, not reported),
// reached through `get` (a callable taking const Outer&).
template <class Outer, class Inner, class Get>
Field<Outer> column_of(const Field<Inner>& inner, Get get) {
  Field<Outer> f;
  f.name = inner.name;
  f.cell = [c = inner.cell, get](const Outer& o) { return c(get(o)); };
  return f;
}

// A CSV-only column: `name`, its cell `cell(record)`.
template <class R>
Field<R> column(std::string name, std::function<std::string(const R&)> cell) {
  Field<R> f;
  f.name = std::move(name);
  f.cell = std::move(cell);
  return f;
}

// `inner`'s field as a field of Outer, reached through `get` (a callable taking Outer& and const
// Outer& alike, e.g. [](auto& o) -> auto& { return o.vehicles[0]; }).
template <class Outer, class Inner, class Get>
Field<Outer> lift(const Field<Inner>& inner, Get get) {
  Field<Outer> f = column_of<Outer>(inner, get);
  f.exact = [e = inner.exact, get](const Outer& o) { return e(get(o)); };
  f.read = [r = inner.read, get](Outer& o, const std::string& text) { r(get(o), text); };
  return f;
}

// The fields of `schema` named `names`, in that order (a CSV's choice of columns). Throws
// std::logic_error for a name the schema does not have.
template <class R>
Schema<R> columns(const Schema<R>& schema, std::initializer_list<std::string_view> names) {
  Schema<R> out;
  for (const std::string_view name : names) {
    bool found = false;
    for (const Field<R>& f : schema) {
      if (f.name == name) {
        out.push_back(f);
        found = true;
        break;
      }
    }
    if (!found) throw std::logic_error("no field " + std::string(name));
  }
  return out;
}

// Every field, exact, separated by `separator` (no newline).
template <class R>
std::string encode(const Schema<R>& schema, const R& r, char separator = '\t') {
  std::string out;
  for (std::size_t i = 0; i < schema.size(); ++i) {
    if (i > 0) out += separator;
    out += schema[i].exact(r);
  }
  return out;
}

// What encode() wrote, back into `r`; false (r partly written) for a line with another number of
// fields or a field that does not read.
template <class R>
bool decode(const Schema<R>& schema, const std::string& line, R& r, char separator = '\t') {
  const std::vector<std::string> fields = split(line, separator);
  if (fields.size() != schema.size()) return false;
  try {
    for (std::size_t i = 0; i < schema.size(); ++i) schema[i].read(r, fields[i]);
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

template <class R>
std::string csv_header(const Schema<R>& columns) {
  std::string out;
  for (std::size_t i = 0; i < columns.size(); ++i) out += (i > 0 ? "," : "") + columns[i].name;
  return out;
}

template <class R>
std::string csv_row(const Schema<R>& columns, const R& r) {
  std::string out;
  for (std::size_t i = 0; i < columns.size(); ++i) out += (i > 0 ? "," : "") + columns[i].cell(r);
  return out;
}

// A CSV file: the header, then a row per record, each line ended by '\n'.
template <class R, class Rows>
void write_csv(std::ostream& out, const Schema<R>& columns, const Rows& rows) {
  out << csv_header(columns) << "\n";
  for (const R& r : rows) out << csv_row(columns, r) << "\n";
}

}  // namespace hil::trials

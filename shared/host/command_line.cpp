#include "pa/command_line.hpp"

#include <charconv>
#include <cmath>
#include <exception>
#include <iostream>
#include <memory>

namespace pa::cli {

namespace {

// CLI11's layout with the usage line first and in the tools' own words.
class Help : public CLI::Formatter {
 public:
  explicit Help(std::string usage) : usage_(std::move(usage)) { column_width(24); }

  std::string make_usage(const CLI::App*, std::string) const override { return usage_ + "\n"; }

  std::string make_help(const CLI::App* app, std::string name, CLI::AppFormatMode mode) const override {
    if (mode == CLI::AppFormatMode::Sub) return make_expanded(app);
    std::string text = make_usage(app, name);
    if (!app->get_description().empty()) text += "\n" + app->get_description() + "\n";
    text += make_groups(app, mode);
    text += make_subcommands(app, mode);
    if (!app->get_footer().empty()) text += "\n" + app->get_footer() + "\n";
    return text;
  }

 private:
  std::string usage_;
};

std::string got(const std::string& need, const std::string& value) { return need + ", got '" + value + "'"; }

std::optional<double> finite(const std::string& text) {
  double value = 0.0;
  if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value)) return std::nullopt;
  return value;
}

// The flag a CLI11 message starts with ("--out: 1 required TEXT missing" -> "--out").
std::string flag_of(const std::string& message) {
  const std::size_t colon = message.find(": ");
  return colon == std::string::npos ? std::string() : message.substr(0, colon);
}

// The message in the tools' words; every one names the flag (or the argument) concerned.
std::string message_of(const CLI::App& app, const CLI::ParseError& e) {
  const std::string what = e.what();
  // An unknown argument first, as a typo is the likelier mistake: CLI11 would report a missing
  // required flag before it.
  const std::vector<std::string> extras = app.remaining();
  const bool unknown = dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr ||
                       dynamic_cast<const CLI::RequiredError*>(&e) != nullptr;
  if (unknown && !extras.empty()) return "unknown argument '" + extras.front() + "'";
  if (dynamic_cast<const CLI::ArgumentMismatch*>(&e) != nullptr && !flag_of(what).empty() &&
      what.size() >= 8 && what.compare(what.size() - 8, 8, " missing") == 0) {
    return flag_of(what) + " needs a value";
  }
  // Our checks continue the flag's name: "--seed: needs ..." reads "--seed needs ...".
  if (dynamic_cast<const CLI::ValidationError*>(&e) != nullptr && !flag_of(what).empty()) {
    return flag_of(what) + " " + what.substr(flag_of(what).size() + 2);
  }
  return what;
}

}  // namespace

void describe(CLI::App& app, std::string usage, std::string description, std::string footer) {
  app.formatter(std::make_shared<Help>(std::move(usage)));
  app.description(std::move(description));
  app.footer(std::move(footer));
}

std::optional<int> parse(CLI::App& app, const std::vector<std::string>& args, std::ostream& out,
                         std::ostream& err) {
  // CLI11 takes the arguments last first.
  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    app.parse(reversed);
  } catch (const CLI::CallForHelp&) {
    out << app.help();
    return 0;
  } catch (const CLI::ParseError& e) {
    err << app.get_name() << ": " << message_of(app, e) << "\n\n" << app.help();
    return 2;
  }
  return std::nullopt;
}

std::optional<int> parse(CLI::App& app, int argc, const char* const* argv, std::ostream& out,
                         std::ostream& err) {
  std::vector<std::string> args;
  for (int i = 1; i < argc; ++i) args.emplace_back(argv[i]);
  return parse(app, args, out, err);
}

CLI::Validator finite_number(std::string need) {
  return CLI::Validator([need](std::string& text) { return finite(text) ? std::string() : got(need, text); },
                        "");
}

CLI::Validator number_in(double lo, double hi, std::string need) {
  return CLI::Validator(
      [=](std::string& text) {
        const std::optional<double> v = finite(text);
        return v && *v >= lo && *v <= hi ? std::string() : got(need, text);
      },
      "");
}

CLI::Validator count(std::uint64_t lo, std::uint64_t hi, std::string need) {
  return CLI::Validator(
      [=](std::string& text) {
        // Decimal digits only, no leading zero: CLI11 alone would read "-1" as 2^64 - 1 and
        // "010" as octal.
        std::uint64_t n = 0;
        const char* end = text.data() + text.size();
        const auto [ptr, ec] = std::from_chars(text.data(), end, n);
        const bool ok = !text.empty() && ec == std::errc{} && ptr == end &&
                        (text.size() == 1 || text[0] != '0') && n >= lo && n <= hi;
        return ok ? std::string() : got(need, text);
      },
      "");
}

CLI::Validator number_pair(std::string need) {
  return CLI::Validator(
      [need](std::string& text) {
        const std::size_t comma = text.find(',');
        const bool ok =
            comma != std::string::npos && finite(text.substr(0, comma)) && finite(text.substr(comma + 1));
        return ok ? std::string() : got(need, text);
      },
      "");
}

NumberPair to_number_pair(const std::string& text) {
  const std::size_t comma = text.find(',');
  if (comma == std::string::npos) return {};
  return {finite(text.substr(0, comma)).value_or(0.0), finite(text.substr(comma + 1)).value_or(0.0)};
}

CLI::Validator one_of(std::vector<std::string> choices, std::string need) {
  return CLI::Validator(
      [=](std::string& text) {
        for (const std::string& c : choices) {
          if (c == text) return std::string();
        }
        return got(need, text);
      },
      "");
}

CLI::Validator non_empty(std::string need) {
  return CLI::Validator([need](std::string& text) { return text.empty() ? need : std::string(); }, "");
}

namespace {

int unknown_subcommand(CLI::App& app, const std::string& name) {
  std::cerr << app.get_name() << ": unknown subcommand '" << name << "'\n\n" << app.help();
  return 2;
}

int dispatch(CLI::App& app, std::span<const Subcommand> table, int argc, char** argv) {
  // CLI11 reads only the subcommand's name (or --help); the subcommand parses the rest itself.
  if (argc >= 2) {
    try {
      app.parse(std::vector<std::string>{argv[1]});
    } catch (const CLI::CallForHelp&) {
      std::cout << app.help();
      return 0;
    } catch (const CLI::ParseError&) {
      return unknown_subcommand(app, argv[1]);
    }
  }
  const std::vector<CLI::App*> chosen = app.get_subcommands();
  const bool help = !chosen.empty() && chosen.front()->get_name() == "help";
  const std::string name = chosen.empty()      ? std::string()
                           : help && argc >= 3 ? argv[2]
                                               : chosen.front()->get_name();
  app.clear();  // CLI11 would show the chosen subcommand's help, not the list
  if (chosen.empty() || (help && argc < 3)) {
    std::cout << app.help();
    return 0;
  }
  for (const Subcommand& c : table) {
    if (c.name != name) continue;
    if (!help) return c.run(argc - 1, argv + 1);
    char help_flag[] = "--help";
    char* sub_argv[] = {argv[2], help_flag, nullptr};
    return c.run(2, sub_argv);
  }
  return unknown_subcommand(app, name);
}

}  // namespace

int run_subcommand(std::string_view program, std::span<const Subcommand> table, int argc, char** argv) {
  const std::string name(program);
  try {
    CLI::App app(std::string(), name);
    describe(app, "usage: " + name + " <subcommand> [arguments]",
             "`" + name + " help <subcommand>` or `" + name + " <subcommand> --help` shows its arguments.");
    app.add_subcommand("help", "this list; `help <subcommand>` for its arguments");
    for (const Subcommand& c : table) app.add_subcommand(std::string(c.name), std::string(c.help));
    app.require_subcommand(0, 1);
    return dispatch(app, table, argc, argv);
  } catch (const std::exception& e) {
    std::cerr << name << ": internal error: " << e.what() << "\n";
  } catch (...) {
    std::cerr << name << ": internal error\n";
  }
  return 1;
}

}  // namespace pa::cli

// The repository documents itself: every file that a comment, test, document or build file
// refers to must be in the repository. Design notes and paper notes kept elsewhere are not
// (docs/architecture.md and docs/paper-notes.md are their replacements), and neither is a path
// that was renamed or deleted.
//
// The rule, kept simple on purpose:
//  - Files read: every *.cpp *.hpp *.h *.c *.cmake *.md *.yaml *.conf *.scenario *.sh *.json *.ld *.txt
//    and Makefile under the source tree, skipping hidden folders (.git, .ci, ...) and build*/
//    (the build trees). This file is skipped too: it names missing files on purpose.
//  - A token is a maximal run of letters, digits and _ . + - / * ; trailing dots are dropped
//    (end of a sentence), and so are leading slashes (paths joined to PA_SOURCE_DIR or
//    ${PROJECT_SOURCE_DIR}).
//  - A token is a reference when it ends in one of the extensions above (or .csv), contains no
//    wildcard, and
//      a) starts with ../ or ./, or
//      b) its first component is a top-level file or folder of the repository, or a folder at
//         the top of an include root (pa/, fw/, cortex_m/ ...), or
//      c) it is the bare name of a top-level file, or any bare *.md, or
//      d) its last component is one of the design documents that live outside the repository
//         (ARCHITECTURE.md, NOTES.md, STYLE.md, pole-acrobatics-paper.md).
//    So names a tool writes (DIR/throws.csv, $out/throw.csv, /tmp/x.csv) are not references.
//  - A reference exists when, resolved without leaving the repository, it names a file or folder
//    relative to the citing file's folder, or (unless it starts with ../ or ./) relative to the
//    repository root or one of the include roots below.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace fs = std::filesystem;

namespace {

// Where #include "x/y.hpp" is looked up (the target_include_directories of the build).
constexpr std::array<std::string_view, 9> kIncludeRoots = {
    "",                           // the repository root: groundstation/..., hil/...
    "shared/include",             // pa/...
    "firmware/core/include",      // fw/...
    "firmware/drivers/include",   // fw/drivers/...
    "firmware/selftest/include",  // fw/...
    "shared/host/include",        // pa/command_line.hpp
    "firmware/ports",             // cortex_m/...
    "firmware/ports/posix",       // hil_vehicle_node.hpp
    "hil/sil",                    // firmware_vehicle.hpp
};

constexpr std::array<std::string_view, 14> kReferenceExtensions = {
    ".md",       ".hpp", ".cpp",   ".h",  ".c",    ".yaml", ".conf",
    ".scenario", ".sh",  ".cmake", ".ld", ".json", ".txt",  ".csv"};
constexpr std::array<std::string_view, 13> kTextExtensions = {
    ".cpp",  ".hpp",      ".h",  ".c",    ".cmake", ".md", ".yaml",
    ".conf", ".scenario", ".sh", ".json", ".ld",    ".txt"};
constexpr std::array<std::string_view, 4> kOutsideDocuments = {"ARCHITECTURE.md", "NOTES.md", "STYLE.md",
                                                               "pole-acrobatics-paper.md"};

bool ends_with(std::string_view s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.substr(s.size() - suffix.size()) == suffix;
}
bool starts_with(std::string_view s, std::string_view prefix) { return s.substr(0, prefix.size()) == prefix; }

bool skipped_folder(const std::string& name) {
  return name.empty() || name[0] == '.' || starts_with(name, "build");
}

bool is_text_file(const fs::path& p) {
  const std::string name = p.filename().string();
  if (name == "Makefile") return true;
  return std::any_of(kTextExtensions.begin(), kTextExtensions.end(),
                     [&](std::string_view ext) { return ends_with(name, ext); });
}

bool is_token_char(char c) {
  const auto u = static_cast<unsigned char>(c);
  return (u >= 'a' && u <= 'z') || (u >= 'A' && u <= 'Z') || (u >= '0' && u <= '9') || c == '_' || c == '.' ||
         c == '+' || c == '-' || c == '/' || c == '*';
}

// "a/./b/../c" -> "a/c"; nullopt if it climbs above the repository root.
std::optional<std::string> normalise(const std::string& path) {
  std::vector<std::string> parts;
  std::stringstream in(path);
  std::string part;
  while (std::getline(in, part, '/')) {
    if (part.empty() || part == ".") continue;
    if (part == "..") {
      if (parts.empty()) return std::nullopt;
      parts.pop_back();
    } else {
      parts.push_back(part);
    }
  }
  std::string out;
  for (const std::string& p : parts) out += (out.empty() ? "" : "/") + p;
  return out;
}

std::string joined(std::string_view folder, std::string_view path) {
  if (folder.empty()) return std::string(path);
  return std::string(folder) + "/" + std::string(path);
}

struct Missing {
  std::string file;
  int line = 0;
  std::string reference;
};

class ReferenceChecker {
 public:
  explicit ReferenceChecker(fs::path root) : root_(std::move(root)) {
    for (const fs::directory_entry& e : fs::directory_iterator(root_)) {
      const std::string name = e.path().filename().string();
      if (e.is_directory() && skipped_folder(name)) continue;
      top_level_.insert(name);
      if (!e.is_directory()) top_level_files_.insert(name);
    }
    prefixes_ = top_level_;
    for (std::string_view include_root : kIncludeRoots) {
      if (include_root.empty() || !fs::is_directory(root_ / include_root)) continue;
      for (const fs::directory_entry& e : fs::directory_iterator(root_ / include_root))
        if (e.is_directory()) prefixes_.insert(e.path().filename().string());
    }
  }

  // The tokens of one line that the rule counts as references to repository files.
  std::vector<std::string> references_in(std::string_view line) const {
    std::vector<std::string> out;
    std::size_t i = 0;
    while (i < line.size()) {
      if (!is_token_char(line[i])) {
        ++i;
        continue;
      }
      std::size_t j = i;
      while (j < line.size() && is_token_char(line[j])) ++j;
      std::string token(line.substr(i, j - i));
      i = j;
      while (!token.empty() && token.back() == '.') token.pop_back();
      if (is_reference(token)) out.push_back(token);
    }
    return out;
  }

  // Does `reference`, cited from the file `citing` (relative to the root), name something here?
  bool exists(const std::string& reference, const std::string& citing) const {
    const std::string citing_folder = fs::path(citing).parent_path().generic_string();
    if (starts_with(reference, "../") || starts_with(reference, "./"))
      return exists_at(joined(citing_folder, reference));
    const std::string path = reference.substr(reference.find_first_not_of('/'));
    if (exists_at(joined(citing_folder, path))) return true;
    return std::any_of(kIncludeRoots.begin(), kIncludeRoots.end(),
                       [&](std::string_view include_root) { return exists_at(joined(include_root, path)); });
  }

  // The references in `text` (the contents of `citing`) that name nothing in the repository.
  std::vector<Missing> missing_in(std::string_view text, const std::string& citing,
                                  int* checked = nullptr) const {
    std::vector<Missing> missing;
    int line_number = 0;
    std::size_t start = 0;
    while (start <= text.size()) {
      const std::size_t end = std::min(text.find('\n', start), text.size());
      ++line_number;
      for (const std::string& reference : references_in(text.substr(start, end - start))) {
        if (checked) ++*checked;
        if (!exists(reference, citing)) missing.push_back({citing, line_number, reference});
      }
      start = end + 1;
    }
    return missing;
  }

  // Every text file of the tree, relative to the root, in a stable order.
  std::vector<std::string> text_files(const std::string& except) const {
    std::vector<std::string> files;
    for (auto it = fs::recursive_directory_iterator(root_); it != fs::recursive_directory_iterator(); ++it) {
      if (it->is_directory()) {
        if (skipped_folder(it->path().filename().string())) it.disable_recursion_pending();
        continue;
      }
      if (!it->is_regular_file() || !is_text_file(it->path())) continue;
      const std::string relative = fs::relative(it->path(), root_).generic_string();
      if (relative != except) files.push_back(relative);
    }
    std::sort(files.begin(), files.end());
    return files;
  }

  const fs::path& root() const { return root_; }

 private:
  bool is_reference(const std::string& token) const {
    if (token.find('*') != std::string::npos) return false;
    const bool has_extension = std::any_of(kReferenceExtensions.begin(), kReferenceExtensions.end(),
                                           [&](std::string_view ext) { return ends_with(token, ext); });
    if (!has_extension) return false;
    const std::size_t first = token.find_first_not_of('/');
    if (first == std::string::npos) return false;
    const std::string path = token.substr(first);
    const std::string last = path.substr(path.rfind('/') == std::string::npos ? 0 : path.rfind('/') + 1);
    if (last.empty() || last[0] == '.') return false;  // ".md" alone is an extension, not a file
    if (std::find(kOutsideDocuments.begin(), kOutsideDocuments.end(), last) != kOutsideDocuments.end())
      return true;
    if (starts_with(token, "../") || starts_with(token, "./")) return true;
    const std::size_t slash = path.find('/');
    if (slash == std::string::npos) return top_level_files_.count(path) > 0 || ends_with(path, ".md");
    return prefixes_.count(path.substr(0, slash)) > 0;
  }

  bool exists_at(const std::string& relative) const {
    const std::optional<std::string> inside = normalise(relative);
    if (!inside) return false;  // above the repository root: not in the repository
    std::error_code ec;
    return fs::exists(root_ / *inside, ec);
  }

  fs::path root_;
  std::set<std::string> top_level_;
  std::set<std::string> top_level_files_;
  std::set<std::string> prefixes_;
};

constexpr const char* kThisFile = "tests/repository/references_test.cpp";

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

TEST_CASE("every file the repository's comments, tests and documents cite is in the repository",
          "[repository]") {
  const ReferenceChecker checker(PA_SOURCE_DIR);
  REQUIRE(fs::exists(checker.root() / kThisFile));
  const std::vector<std::string> files = checker.text_files(kThisFile);
  int checked = 0;
  std::vector<Missing> missing;
  for (const std::string& file : files) {
    const std::vector<Missing> here = checker.missing_in(read_file(checker.root() / file), file, &checked);
    missing.insert(missing.end(), here.begin(), here.end());
  }
  std::ostringstream report;
  for (const Missing& m : missing) report << m.file << ":" << m.line << ": " << m.reference << "\n";
  INFO("references to files that are not in the repository:\n" << report.str());
  CHECK(missing.empty());
  // The rule finds the references a newcomer follows (hundreds of them), not none.
  INFO(files.size() << " files read, " << checked << " references checked");
  CHECK(files.size() > 100);
  CHECK(checked > 200);
}

TEST_CASE("a reference to a missing file is caught, wherever it points", "[repository]") {
  const ReferenceChecker checker(PA_SOURCE_DIR);
  const std::string citing = "groundstation/model/example.hpp";
  const std::string text = "// Derivation in NOTES.md; layering in ARCHITECTURE.md, \"One tick\".\n"
                           "// See ../shared/reference/pole-acrobatics-paper.md and docs/no_such_page.md.\n"
                           "#include \"groundstation/model/no_such_model.hpp\"\n"
                           "#include \"fw/no_such_module.hpp\"\n"
                           "// Format of hil/config/no_such.yaml; ../../../outside/the/repository.cpp.\n";
  const std::vector<Missing> missing = checker.missing_in(text, citing);
  std::vector<std::string> names;
  for (const Missing& m : missing) names.push_back(m.reference);
  CHECK(names == std::vector<std::string>{
                     "NOTES.md", "ARCHITECTURE.md", "../shared/reference/pole-acrobatics-paper.md",
                     "docs/no_such_page.md", "groundstation/model/no_such_model.hpp", "fw/no_such_module.hpp",
                     "hil/config/no_such.yaml", "../../../outside/the/repository.cpp"});
  REQUIRE(missing.size() == 8);
  CHECK(missing[0].line == 1);
  CHECK(missing[2].line == 2);
  CHECK(missing[4].line == 3);
  CHECK(missing[7].line == 5);
}

TEST_CASE("references to files that are here pass, by any of the stated routes", "[repository]") {
  const ReferenceChecker checker(PA_SOURCE_DIR);
  const std::string text =
      "// docs/architecture.md, \"Libraries\"; docs/paper-notes.md. README.md, CMakeLists.txt.\n"
      "#include \"pa/protocol.hpp\"\n"                        // shared/include
      "#include \"fw/config.hpp\"\n"                          // firmware/core/include
      "#include \"cortex_m/runtime.hpp\"\n"                   // firmware/ports
      "#include \"hil_vehicle_node.hpp\"\n"                   // bare: not a reference
      "set(x ${PROJECT_SOURCE_DIR}/hil/config/plant.yaml)\n"  // root-relative after a variable
      "// ../plant.yaml\n";                                   // relative to the citing folder
  const std::string citing = "hil/config/scenarios/example.yaml";
  int checked = 0;
  CHECK(checker.missing_in(text, citing, &checked).empty());
  CHECK(checked == 9);
}

TEST_CASE("names a tool writes, globs and absolute paths are not references", "[repository]") {
  const ReferenceChecker checker(PA_SOURCE_DIR);
  const std::string text = "// writes DIR/throws.csv and $out/throw.csv; reads /nonexistent/throw.csv\n"
                           "file(GLOB s ${CMAKE_CURRENT_SOURCE_DIR}/model/*.cpp hil/plant/*.cpp)\n"
                           "// build/host/groundstation/plan.csv, e.g. a value 1.33 or a ratio 0.5.\n"
                           "// the extension .md alone, mocap.csv, throw.csv\n";
  CHECK(checker.references_in(text.substr(0, text.find('\n'))).empty());
  CHECK(checker.missing_in(text, "tests/CMakeLists.txt").empty());
}

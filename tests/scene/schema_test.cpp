// The scene reference (src/scene/README.md) documents every key the reader accepts: the keys come
// from the reader's own schema (scene/schema.hpp, the list its unknown-key check uses), so a key
// added to the reader without its line in the reference fails here.
//
// Where a key counts as documented: the reference has a section per top-level table (a heading
// naming `[table]` or `[[table]]`, up to the next `## ` heading, its `###` subsections included).
// A top-level key must be in the first column of a table row of its section (`left`, `right`
// count for both); a key of a nested table (a support's table, a segment, the gap, a moving load,
// an initial shape) in a code span of its parent's section, alone (`stiffness`) or as `key =`
// (`{ at = [...], value = [...] }`).
#include "scene/schema.hpp"

#include <catch2/catch.hpp>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

using namespace liftoff;

namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  REQUIRE(in.good());
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The contents of the code spans (`...`) of a piece of Markdown.
std::vector<std::string> code_spans(const std::string& text) {
  std::vector<std::string> spans;
  static const std::regex span("`([^`]+)`");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), span); it != std::sregex_iterator(); ++it)
    spans.push_back((*it)[1].str());
  return spans;
}

// A top-level table's section: from the heading naming it to the next level-2 heading.
std::vector<std::string> section_of(const std::vector<std::string>& lines, std::string_view table) {
  const std::string plain = "`[" + std::string(table) + "]`", array = "`[[" + std::string(table) + "]]`";
  std::vector<std::string> section;
  bool inside = false;
  for (const std::string& line : lines) {
    const bool heading = line.rfind("#", 0) == 0;
    if (heading && line.rfind("## ", 0) == 0) inside = false;
    if (heading && !inside && (line.find(plain) != std::string::npos || line.find(array) != std::string::npos) &&
        line.rfind("## ", 0) == 0)
      inside = true;
    if (inside) section.push_back(line);
  }
  return section;
}

// The code spans in the first column of the section's table rows (an escaped \| stays in a cell).
std::vector<std::string> first_column_keys(const std::vector<std::string>& section) {
  std::vector<std::string> keys;
  for (const std::string& line : section) {
    if (line.rfind("|", 0) != 0) continue;
    std::size_t end = 1;
    while (end < line.size() && !(line[end] == '|' && line[end - 1] != '\\')) ++end;
    for (const std::string& span : code_spans(line.substr(1, end - 1))) keys.push_back(span);
  }
  return keys;
}

bool mentioned(const std::vector<std::string>& section, const std::string& key) {
  std::string text;
  for (const std::string& line : section) text += line + "\n";
  const std::regex assignment("(^|[^A-Za-z0-9_])" + key + "\\s*=");
  for (const std::string& span : code_spans(text))
    if (span == key || std::regex_search(span, assignment)) return true;
  return false;
}

// "[table] key" for every key of the schema the reference does not document.
std::vector<std::string> undocumented_keys(const std::string& reference) {
  const std::vector<std::string> lines = lines_of(reference);
  std::vector<std::string> missing;
  for (const scene::TableSpec* spec : scene::every_table()) {
    const std::string name(spec->name);
    const std::string top = name.substr(0, name.find('.'));
    const std::vector<std::string> section = section_of(lines, top);
    if (section.empty()) {
      missing.push_back("[" + top + "] (no section)");
      continue;
    }
    const bool nested = top != name;
    const std::vector<std::string> rows = first_column_keys(section);
    for (std::string_view key_view : spec->key_names()) {
      const std::string key(key_view);
      const bool documented = nested ? mentioned(section, key) : std::find(rows.begin(), rows.end(), key) != rows.end();
      if (!documented) missing.push_back("[" + name + "] " + key);
    }
  }
  return missing;
}

std::string joined(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "" : "; ") + item;
  return text;
}

}  // namespace

TEST_CASE("scene reference: every key the reader accepts is documented in src/scene/README.md", "[scene][schema]") {
  const std::string reference = read_text(std::string(LIFTOFF_SOURCE_DIR) + "/src/scene/README.md");
  const std::vector<std::string> missing = undocumented_keys(reference);
  INFO("undocumented: " << joined(missing));
  CHECK(missing.empty());
}

TEST_CASE("scene reference check: a key missing from its section is found", "[scene][schema]") {
  // The reference with one row removed, and with a table's section gone: the check must notice
  // both, or the test above proves nothing.
  const std::string reference = read_text(std::string(LIFTOFF_SOURCE_DIR) + "/src/scene/README.md");
  const std::string row = "| `max_modes` |";
  REQUIRE(reference.find(row) != std::string::npos);
  std::string without_row = reference;
  without_row.replace(without_row.find(row), row.size(), "| max modes |");
  CHECK(undocumented_keys(without_row) == std::vector<std::string>{"[ritz] max_modes"});

  std::string without_section = reference;
  const std::string heading = "## `[compare]`";
  REQUIRE(without_section.find(heading) != std::string::npos);
  without_section.replace(without_section.find(heading), heading.size(), "## compare");
  CHECK(undocumented_keys(without_section) == std::vector<std::string>{"[compare] (no section)"});
}

TEST_CASE("scene schema: every table has keys, and no key is listed twice", "[scene][schema]") {
  for (const scene::TableSpec* spec : scene::every_table()) {
    CAPTURE(spec->name);
    CHECK_FALSE(spec->keys.empty());
    std::vector<std::string_view> keys = spec->key_names();
    std::sort(keys.begin(), keys.end());
    CHECK(std::adjacent_find(keys.begin(), keys.end()) == keys.end());
  }
}

#include "sdcb/io/batch/batch_manifest.h"

namespace sdcb {
namespace {

bool IsSeparator(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// Splits one line (without its '\n') into fields; false with `error` set
// when the line is malformed.
bool SplitFields(std::string_view line, std::vector<std::string>* fields,
                 std::string* error) {
  size_t i = 0;
  while (true) {
    while (i < line.size() && IsSeparator(line[i])) ++i;
    if (i == line.size() || line[i] == '#') return true;
    std::string field;
    if (line[i] == '"') {
      ++i;
      bool closed = false;
      while (i < line.size()) {
        const char c = line[i++];
        if (c == '"') {
          closed = true;
          break;
        }
        if (c == '\\' && i < line.size() &&
            (line[i] == '"' || line[i] == '\\')) {
          field += line[i++];
        } else {
          field += c;
        }
      }
      if (!closed) {
        *error = "unterminated quote";
        return false;
      }
      if (i < line.size() && !IsSeparator(line[i])) {
        *error = "a closing quote must be followed by a space or tab";
        return false;
      }
    } else {
      while (i < line.size() && !IsSeparator(line[i])) field += line[i++];
    }
    fields->push_back(std::move(field));
  }
}

}  // namespace

StatusOr<std::vector<ManifestRow>> ParseBatchManifest(std::string_view text) {
  if (text.find('\0') != std::string_view::npos) {
    return CorruptFileError("contains a NUL byte (not a text manifest)");
  }
  std::vector<ManifestRow> rows;
  int line_number = 0;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    ++line_number;
    std::vector<std::string> fields;
    std::string error;
    if (!SplitFields(text.substr(start, end - start), &fields, &error)) {
      return CorruptFileError("line " + std::to_string(line_number) + ": " +
                              error);
    }
    start = end + 1;
    if (fields.empty()) continue;
    if (fields.size() < 2) {
      return CorruptFileError("line " + std::to_string(line_number) +
                              ": a row needs INPUT and OUTPUT, found only '" +
                              fields[0] + "'");
    }
    ManifestRow row;
    row.line = line_number;
    row.input = std::move(fields[0]);
    row.output = std::move(fields[1]);
    row.options.assign(std::make_move_iterator(fields.begin() + 2),
                       std::make_move_iterator(fields.end()));
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace sdcb

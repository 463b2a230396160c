#include "rtmini/io/text_fields.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "rtmini/io/error.hpp"

namespace rtmini::detail {

// Binary mode: the bytes are the file's (no newline translation), so byte offsets in error
// messages match the file; the line parsers strip '\r' themselves. A path that cannot be opened
// is the user's input (InputError, exit 2); a read failing after that is the system's (exit 3).
// A regular file is read at once into a buffer of its size (a copy through an ostringstream costs
// as much as parsing the mesh); anything else (a pipe, a folder) goes through the stream.
std::string read_text_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot open file");
  std::error_code ec;
  if (std::filesystem::is_regular_file(path, ec)) {
    const std::uintmax_t size = std::filesystem::file_size(path, ec);
    if (!ec) {
      std::string text(static_cast<std::size_t>(size), '\0');
      in.read(text.data(), static_cast<std::streamsize>(size));
      if (in.bad()) throw IoError(path + ": read error");
      text.resize(static_cast<std::size_t>(in.gcount()));  // a file that shrank meanwhile
      return text;
    }
  }
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw IoError(path + ": read error");
  return buffer.str();
}

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t i = 0;
  // '\r' is a separator too, so files saved with CRLF line ends parse like Unix ones.
  const auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > start) fields.push_back(line.substr(start, i - start));
  }
  return fields;
}

// Views into the one text buffer, no copy per line: .bs maps reach gigabytes. line_ counts
// every line, blank ones included, so "file:line" errors point at the line an editor shows.
bool LineCursor::next(std::string_view& line) {
  if (pos_ >= text_.size()) return false;
  const std::size_t end = text_.find('\n', pos_);
  const std::size_t stop = end == std::string_view::npos ? text_.size() : end;
  line = text_.substr(pos_, stop - pos_);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  pos_ = end == std::string_view::npos ? text_.size() : end + 1;
  ++line_;
  return true;
}

}  // namespace rtmini::detail

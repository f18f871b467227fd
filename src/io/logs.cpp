// 3DMatch benchmark logs: gt.log / est.log (header "i j n" + 4x4 T_i_j) and gt.info (header +
// 6x6 information matrix).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "io/text_parsing.hpp"
#include "zeroreg/error.hpp"
#include "zeroreg/io.hpp"

namespace zeroreg {

namespace {

// Line-oriented reader that skips blank lines and remembers line numbers for messages.
class LineReader {
 public:
  LineReader(const std::string& path, const std::string& what) : path_(path), in_(path) {
    detail::RequireFile(path, what);
    if (!in_) throw MakeInputError(path, what + " cannot be opened for reading");
  }

  // Next non-blank line split into tokens; false at end of file.
  bool Next(std::vector<std::string>* tokens) {
    std::string line;
    while (std::getline(in_, line)) {
      ++line_number_;
      std::istringstream ss(line);
      tokens->clear();
      std::string token;
      while (ss >> token) tokens->push_back(token);
      if (!tokens->empty()) return true;
    }
    return false;
  }

  [[noreturn]] void Fail(const std::string& problem) const {
    throw MakeInputError(path_, "line " + std::to_string(line_number_) + ": " + problem);
  }
  int line_number() const { return line_number_; }

 private:
  std::string path_;
  std::ifstream in_;
  int line_number_ = 0;
};

void ParseHeader(LineReader& reader, const std::vector<std::string>& tokens, int* i, int* j,
                 int* n) {
  int* out[3] = {i, j, n};
  bool ok = tokens.size() == 3;
  for (size_t k = 0; ok && k < 3; ++k) {
    double v = 0;
    ok = detail::ParseDouble(tokens[k], &v) && std::isfinite(v) && v == std::floor(v) && v >= 0 &&
         v < 1e9;
    if (ok) *out[k] = static_cast<int>(v);
  }
  if (!ok) reader.Fail("malformed header; expected three non-negative integers 'i j n'");
}

// Reads `rows` lines of `cols` finite numbers into `values` (row-major).
void ParseRows(LineReader& reader, int rows, int cols, const std::string& what,
               std::vector<double>* values) {
  values->clear();
  std::vector<std::string> tokens;
  for (int r = 0; r < rows; ++r) {
    if (!reader.Next(&tokens)) {
      reader.Fail("file ends inside an entry; expected " + std::to_string(rows) + " rows of " +
                  what + " after the header");
    }
    if (static_cast<int>(tokens.size()) != cols) {
      reader.Fail("row holds " + std::to_string(tokens.size()) + " values; expected " +
                  std::to_string(cols) + " numbers per row of " + what);
    }
    for (const std::string& token : tokens) {
      double v = 0;
      if (!detail::ParseDouble(token, &v) || !std::isfinite(v)) {
        reader.Fail("'" + token + "' is not a finite number (row of " + what + ")");
      }
      values->push_back(v);
    }
  }
}

}  // namespace

std::vector<LogEntry> ReadLogFile(const std::string& path) {
  LineReader reader(path, "log file");
  std::vector<LogEntry> entries;
  std::vector<std::string> tokens;
  std::vector<double> values;
  while (reader.Next(&tokens)) {
    LogEntry e;
    e.line = reader.line_number();
    ParseHeader(reader, tokens, &e.i, &e.j, &e.n);
    ParseRows(reader, 4, 4, "the 4x4 transform", &values);
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) e.T_i_j(r, c) = values[static_cast<size_t>(4 * r + c)];
    }
    entries.push_back(e);
  }
  return entries;
}

std::vector<InfoEntry> ReadInfoFile(const std::string& path) {
  LineReader reader(path, "info file");
  std::vector<InfoEntry> entries;
  std::vector<std::string> tokens;
  std::vector<double> values;
  while (reader.Next(&tokens)) {
    InfoEntry e;
    ParseHeader(reader, tokens, &e.i, &e.j, &e.n);
    ParseRows(reader, 6, 6, "the 6x6 information matrix", &values);
    for (int r = 0; r < 6; ++r) {
      for (int c = 0; c < 6; ++c) e.information(r, c) = values[static_cast<size_t>(6 * r + c)];
    }
    entries.push_back(e);
  }
  return entries;
}

void WriteLogFile(const std::string& path, const std::vector<LogEntry>& entries) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) throw MakeInputError(path, "cannot open the log file for writing");
  bool ok = true;
  // Same layout as the official gt.log (3dmatch-toolbox), byte for byte.
  for (const LogEntry& e : entries) {
    ok = ok && std::fprintf(f, "%d\t %d\t %d\t\n", e.i, e.j, e.n) > 0;
    for (int r = 0; r < 4; ++r) {
      ok = ok && std::fprintf(f, "%15.8e\t %15.8e\t %15.8e\t %15.8e\t\n", e.T_i_j(r, 0),
                              e.T_i_j(r, 1), e.T_i_j(r, 2), e.T_i_j(r, 3)) > 0;
    }
  }
  ok = (std::fclose(f) == 0) && ok;
  if (!ok) throw MakeInputError(path, "failed writing the log file");
}

}  // namespace zeroreg

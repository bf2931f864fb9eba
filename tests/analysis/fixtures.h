// Readers for the peer-tool fixtures in tests/analysis/fixtures/: psignifit
// 2.5.6 batch output ("#NAME" then comma-separated rows, blank line) and the
// CSV files the R script writes.
#ifndef BURRLAB_TESTS_ANALYSIS_FIXTURES_H_
#define BURRLAB_TESTS_ANALYSIS_FIXTURES_H_

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace burrlab::analysis::testing {

inline std::filesystem::path FixtureDir(const std::string& tool) {
  return std::filesystem::path(BURRLAB_SOURCE_DIR) / "tests" / "analysis" /
         "fixtures" / tool;
}

inline std::string ReadText(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

using Matrix = std::vector<std::vector<double>>;

// Splits "a, b, c" (or tab/space separated) into numbers; "nan", "-nan" and
// "inf" are read as such.
inline std::vector<double> ParseRow(const std::string& line) {
  std::vector<double> row;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) {
    std::istringstream words(cell);
    std::string word;
    while (words >> word) row.push_back(std::stod(word));
  }
  return row;
}

// psignifit batch output: every "#NAME" block as a matrix.
inline std::map<std::string, Matrix> ReadPsignifit(
    const std::filesystem::path& path) {
  std::map<std::string, Matrix> blocks;
  std::istringstream in(ReadText(path));
  std::string line, name;
  while (std::getline(in, line)) {
    if (line.starts_with("#")) {
      name = line.substr(1);
      blocks[name];
    } else if (!line.empty() && !name.empty()) {
      blocks[name].push_back(ParseRow(line));
    }
  }
  return blocks;
}

// A CSV with a header line: one map per row from column name to text.
inline std::vector<std::map<std::string, std::string>> ReadCsv(
    const std::filesystem::path& path) {
  std::vector<std::map<std::string, std::string>> rows;
  std::istringstream in(ReadText(path));
  std::string line;
  std::vector<std::string> header;
  const auto split = [](const std::string& text) {
    std::vector<std::string> cells;
    std::string cell;
    std::istringstream cin(text);
    while (std::getline(cin, cell, ',')) {
      if (cell.size() >= 2 && cell.front() == '"' && cell.back() == '"') {
        cell = cell.substr(1, cell.size() - 2);
      }
      cells.push_back(cell);
    }
    return cells;
  };
  if (!std::getline(in, line)) return rows;
  header = split(line);
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const std::vector<std::string> cells = split(line);
    std::map<std::string, std::string> row;
    for (std::size_t k = 0; k < header.size() && k < cells.size(); ++k) {
      row[header[k]] = cells[k];
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace burrlab::analysis::testing

#endif  // BURRLAB_TESTS_ANALYSIS_FIXTURES_H_

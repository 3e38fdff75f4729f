#include "observe/table.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace sphib {

int Table::col(const std::string& name) const {
  const auto it = std::find(cols.begin(), cols.end(), name);
  return it == cols.end() ? -1 : static_cast<int>(it - cols.begin());
}

Table read_table(const std::string& path, const std::string& who) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(who + ": cannot read the reference table " + path);
  Table t;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream ss(line);
    std::vector<std::string> cells;
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    if (t.cols.empty()) { t.cols = cells; continue; }
    std::vector<double> r;
    try {
      for (const auto& c : cells) r.push_back(std::stod(c));
    } catch (const std::exception&) {
      throw std::runtime_error(who + ": " + path + ": not a row of numbers: " + line);
    }
    t.rows.push_back(r);
  }
  return t;
}

}  // namespace sphib

#pragma once
// Reference tables of the analyses (cases/reference/): CSV with a header row, then rows of numbers;
// lines starting with '#' are comments (the source of the data).
#include <string>
#include <vector>

namespace sphib {

struct Table {
  std::vector<std::string> cols;
  std::vector<std::vector<double>> rows;
  int col(const std::string& name) const;  // its index, -1 if there is none
};

// Throws std::runtime_error "<who>: cannot read the reference table <path>" (or naming a bad cell).
Table read_table(const std::string& path, const std::string& who);

}  // namespace sphib

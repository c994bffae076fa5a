// Dense matrices as JSON for the commands that print or write them (`tmpc model
// --matrices`, `tmpc export-qp`): an array of rows, each an array of numbers.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace tmpc::cli {

inline nlohmann::json json_rows(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    std::vector<double> r(static_cast<std::size_t>(m.cols()));
    for (Eigen::Index j = 0; j < m.cols(); ++j) r[static_cast<std::size_t>(j)] = m(i, j);
    rows.push_back(r);
  }
  return rows;
}

}  // namespace tmpc::cli

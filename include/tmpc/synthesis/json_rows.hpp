// Dense matrices as JSON: an array of rows, each an array of numbers (the design
// report, `tmpc model --matrices`, `tmpc export-qp`).
#pragma once

#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace tmpc {

inline nlohmann::json json_rows(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    std::vector<double> r(static_cast<std::size_t>(m.cols()));
    for (Eigen::Index j = 0; j < m.cols(); ++j) r[static_cast<std::size_t>(j)] = m(i, j);
    rows.push_back(r);
  }
  return rows;
}

}  // namespace tmpc

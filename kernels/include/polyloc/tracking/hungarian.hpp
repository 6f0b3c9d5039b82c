// Minimum-cost assignment (Hungarian method, Kuhn-Munkres with potentials, O(n^2 m)): rows to
// columns, rectangular matrices allowed. Tracking assigns detections to tracks with it, the MOT
// metrics ground truth to hypotheses. No Debian package ships one.
//
//   Eigen::MatrixXd cost(2, 3);  cost << 4, 1, 3,
//                                        2, 0, 5;
//   solveAssignment(cost) == {1, 0}   // row 0 -> column 1, row 1 -> column 0, total 3
#pragma once

#include <Eigen/Core>
#include <vector>

namespace polyloc {

// For each row the column assigned to it, or -1. Entries that are +inf or NaN are forbidden
// pairs: the result has as many pairs as possible without them and, among those, the lowest
// total cost. Every row gets a column when rows <= columns and nothing is forbidden.
std::vector<int> solveAssignment(const Eigen::MatrixXd& cost);

}  // namespace polyloc

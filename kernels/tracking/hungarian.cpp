#include <polyloc/tracking/hungarian.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace polyloc {

std::vector<int> solveAssignment(const Eigen::MatrixXd& cost) {
  const Eigen::Index rows = cost.rows(), cols = cost.cols();
  std::vector<int> result(size_t(rows), -1);
  if (rows == 0 || cols == 0) return result;
  // The method below wants rows <= columns: solve the transpose otherwise.
  const bool transposed = rows > cols;
  const Eigen::MatrixXd a0 = transposed ? Eigen::MatrixXd(cost.transpose()) : cost;
  const Eigen::Index n = a0.rows(), m = a0.cols();
  // Forbidden pairs cost more than any assignment of allowed ones, so the solver takes as few
  // of them as it can; they are removed from the result afterwards.
  double largest = 0;
  for (Eigen::Index i = 0; i < a0.size(); ++i)
    if (std::isfinite(a0.data()[i])) largest = std::max(largest, std::abs(a0.data()[i]));
  const double forbidden = 4.0 * (double(n) * largest + 1.0);
  Eigen::MatrixXd a = a0.unaryExpr([&](double v) { return std::isfinite(v) ? v : forbidden; });

  // 1-based potentials u (rows), v (columns); p[j]: row matched to column j (0: none).
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(size_t(n) + 1, 0.0), v(size_t(m) + 1, 0.0);
  std::vector<Eigen::Index> p(size_t(m) + 1, 0), way(size_t(m) + 1, 0);
  for (Eigen::Index i = 1; i <= n; ++i) {
    p[0] = i;
    Eigen::Index j0 = 0;
    std::vector<double> minv(size_t(m) + 1, inf);
    std::vector<char> used(size_t(m) + 1, 0);
    do {  // grow the alternating tree from row i until it reaches a free column
      used[size_t(j0)] = 1;
      const Eigen::Index i0 = p[size_t(j0)];
      double delta = inf;
      Eigen::Index j1 = 0;
      for (Eigen::Index j = 1; j <= m; ++j) {
        if (used[size_t(j)]) continue;
        const double cur = a(i0 - 1, j - 1) - u[size_t(i0)] - v[size_t(j)];
        if (cur < minv[size_t(j)]) minv[size_t(j)] = cur, way[size_t(j)] = j0;
        if (minv[size_t(j)] < delta) delta = minv[size_t(j)], j1 = j;
      }
      for (Eigen::Index j = 0; j <= m; ++j) {
        if (used[size_t(j)]) u[size_t(p[size_t(j)])] += delta, v[size_t(j)] -= delta;
        else minv[size_t(j)] -= delta;
      }
      j0 = j1;
    } while (p[size_t(j0)] != 0);
    do {  // flip the augmenting path
      const Eigen::Index j1 = way[size_t(j0)];
      p[size_t(j0)] = p[size_t(j1)];
      j0 = j1;
    } while (j0 != 0);
  }
  for (Eigen::Index j = 1; j <= m; ++j) {
    const Eigen::Index i = p[size_t(j)];
    if (i == 0 || !std::isfinite(a0(i - 1, j - 1))) continue;
    if (transposed) result[size_t(j - 1)] = int(i - 1);
    else result[size_t(i - 1)] = int(j - 1);
  }
  return result;
}

}  // namespace polyloc

// The Hungarian method: known matrices (square, rectangular both ways, forbidden pairs) and
// random ones against brute force over all assignments.
#include <polyloc/geometry/random.hpp>
#include <polyloc/tracking/hungarian.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

// Each test file in a namespace of its own: the suite is compiled in batches (unity build).
namespace polyloc::t_tracking_hungarian {

using namespace polyloc;


constexpr double kInf = std::numeric_limits<double>::infinity();

double total(const Eigen::MatrixXd& c, const std::vector<int>& a) {
  double s = 0;
  for (size_t r = 0; r < a.size(); ++r)
    if (a[r] >= 0) s += c(Eigen::Index(r), a[r]);
  return s;
}

size_t pairs(const std::vector<int>& a) { return size_t(std::count_if(a.begin(), a.end(), [](int v) { return v >= 0; })); }

// Most pairs without forbidden ones, then the lowest cost: by trying every injection.
std::pair<size_t, double> bruteForce(const Eigen::MatrixXd& c) {
  const int rows = int(c.rows()), cols = int(c.cols());
  std::pair<size_t, double> best{0, 0};
  // Each row picks a column or none (-1), columns used once: enumerate recursively.
  std::vector<int> pick(size_t(rows), -1);
  std::vector<char> used(size_t(cols), 0);
  auto rec = [&](auto&& self, int r, size_t n, double s) -> void {
    if (r == rows) {
      if (n > best.first || (n == best.first && s < best.second - 1e-12)) best = {n, s};
      return;
    }
    self(self, r + 1, n, s);
    for (int k = 0; k < cols; ++k)
      if (!used[size_t(k)] && std::isfinite(c(r, k))) {
        used[size_t(k)] = 1;
        self(self, r + 1, n + 1, s + c(r, k));
        used[size_t(k)] = 0;
      }
  };
  rec(rec, 0, 0, 0.0);
  return best;
}


TEST(Hungarian, SquareKnownOptimum) {
  Eigen::MatrixXd c(3, 3);
  c << 4, 1, 3,
       2, 0, 5,
       3, 2, 2;
  const std::vector<int> a = solveAssignment(c);
  EXPECT_EQ(a, (std::vector<int>{1, 0, 2}));  // 1 + 2 + 2 = 5, the optimum
  EXPECT_DOUBLE_EQ(total(c, a), 5.0);
}

TEST(Hungarian, RectangularBothWays) {
  Eigen::MatrixXd wide(2, 4);
  wide << 9, 2, 7, 8,
          6, 4, 3, 7;
  EXPECT_EQ(solveAssignment(wide), (std::vector<int>{1, 2}));  // 2 + 3
  Eigen::MatrixXd tall = wide.transpose();                   // 4 rows, 2 columns
  const std::vector<int> t = solveAssignment(tall);
  EXPECT_EQ(t, (std::vector<int>{-1, 0, 1, -1}));
  EXPECT_DOUBLE_EQ(total(tall, t), 5.0);
}

TEST(Hungarian, ForbiddenPairsAreNeverChosen) {
  Eigen::MatrixXd c(2, 2);
  c << 1, kInf,
       0.5, kInf;  // column 1 is out of every gate: one pair, the cheaper one
  EXPECT_EQ(solveAssignment(c), (std::vector<int>{-1, 0}));
  c << kInf, kInf,
       kInf, std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(solveAssignment(c), (std::vector<int>{-1, -1}));
  // More pairs beat a lower total: 10 + 10 rather than 1 alone.
  c << 1, 10,
       10, kInf;
  EXPECT_EQ(solveAssignment(c), (std::vector<int>{1, 0}));
}

TEST(Hungarian, EmptyMatrices) {
  EXPECT_TRUE(solveAssignment(Eigen::MatrixXd(0, 3)).empty());
  EXPECT_EQ(solveAssignment(Eigen::MatrixXd(2, 0)), (std::vector<int>{-1, -1}));
}

TEST(Hungarian, RandomMatricesMatchBruteForce) {
  const CounterRng rng(5);
  for (uint64_t trial = 0; trial < 200; ++trial) {
    const int rows = 1 + int(rng.uniform(0, 5.999, trial, 0)), cols = 1 + int(rng.uniform(0, 5.999, trial, 1));
    Eigen::MatrixXd c(rows, cols);
    for (int r = 0; r < rows; ++r)
      for (int k = 0; k < cols; ++k) {
        const uint64_t i = uint64_t(2 + r * cols + k);
        c(r, k) = rng.uniform(0, 1, trial, i) < 0.25 ? kInf : std::round(rng.uniform(-5, 20, trial, 100 + i));
      }
    const std::vector<int> a = solveAssignment(c);
    ASSERT_EQ(a.size(), size_t(rows));
    std::vector<int> seen;
    for (size_t r = 0; r < a.size(); ++r)
      if (a[r] >= 0) {
        ASSERT_TRUE(std::isfinite(c(Eigen::Index(r), a[r])));
        seen.push_back(a[r]);
      }
    std::sort(seen.begin(), seen.end());
    ASSERT_TRUE(std::adjacent_find(seen.begin(), seen.end()) == seen.end()) << "a column used twice";
    const auto [n, s] = bruteForce(c);
    EXPECT_EQ(pairs(a), n) << "trial " << trial;
    EXPECT_NEAR(total(c, a), s, 1e-9) << "trial " << trial;
  }
}

}  // namespace polyloc::t_tracking_hungarian

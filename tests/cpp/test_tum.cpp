// TUM trajectories: exact time round trip, quaternion normalisation, bad lines counted with
// file:line while the good ones around them are read.
#include <polyloc/io/tum.hpp>

#include "temp_dir.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace polyloc::t_tum {  // the file's own: the suite is compiled in batches (unity build)
namespace {

TEST(Tum, RoundTripKeepsNanosecondsAndMicrometres) {
  test::TempDir dir;
  std::vector<StampedPose> poses;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int64_t stamps[] = {1305031102175304123, 0, 1, 999999999, 1000000000, -1500000000, 42};
  for (int64_t s : stamps) {
    Eigen::Quaterniond q(u(rng), u(rng), u(rng), u(rng));
    poses.push_back({s, Pose(q.normalized(), Eigen::Vector3d(1234.567891 * u(rng), u(rng) * 1e-6, 3.25))});
  }
  {
    TumWriter w(dir.file("traj.txt"));
    for (const auto& p : poses) w.write(p);
  }
  TumReader r(dir.file("traj.txt"));
  StampedPose p;
  size_t i = 0;
  while (r.next(p)) {
    ASSERT_LT(i, poses.size());
    EXPECT_EQ(p.stamp_ns, poses[i].stamp_ns);
    EXPECT_LT((p.pose.translation() - poses[i].pose.translation()).norm(), 1e-8);
    EXPECT_NEAR(std::fabs(p.pose.rotation().dot(poses[i].pose.rotation())), 1.0, 1e-12);
    ++i;
  }
  EXPECT_EQ(i, poses.size());
  EXPECT_EQ(r.rejected(), 0u) << (r.warnings().empty() ? "" : r.warnings()[0]);
  EXPECT_EQ(readTum(dir.file("traj.txt")).size(), poses.size());
}

TEST(Tum, WritesNineDecimalsOfSeconds) {
  test::TempDir dir;
  {
    TumWriter w(dir.file("t.txt"));
    w.write({1305031102175304123, Pose::planar(1, 2, 0)});
  }
  std::ifstream in(dir.file("t.txt"));
  std::string header, line;
  std::getline(in, header);
  std::getline(in, line);
  EXPECT_EQ(header[0], '#');
  EXPECT_EQ(line.substr(0, line.find(' ')), "1305031102.175304123");
}

TEST(Tum, BadLinesAreCountedWithFileAndLine) {
  test::TempDir dir;
  const std::string path = dir.write("bad.txt",
                                     "# timestamp x y z qx qy qz qw\n"   // 1
                                     "\n"                                // 2
                                     "1.5 1 2 3 0 0 0 2\n"               // 3 ok, |q| = 2
                                     "2.0 1 2 3 0 0 0\n"                 // 4 seven fields
                                     "abc 1 2 3 0 0 0 1\n"               // 5 bad time
                                     "3.0 1 x 3 0 0 0 1\n"               // 6 bad y
                                     "4.0 1 2 3 0 0 0 0\n"               // 7 zero quaternion
                                     "5.0 nan 2 3 0 0 0 1\n"             // 8 NaN
                                     "6.0,1,2,3,0,0,0.7071068,0.7071068\r\n"  // 9 ok, commas, CRLF
                                     "7.0 1 2 3 0 0 0 1 extra\n");       // 10 nine fields
  TumReader r(path);
  std::vector<StampedPose> got;
  StampedPose p;
  while (r.next(p)) got.push_back(p);
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0].stamp_ns, 1500000000);
  EXPECT_NEAR(got[0].pose.rotation().norm(), 1.0, 1e-12);
  EXPECT_NEAR(got[0].pose.rotation().w(), 1.0, 1e-12);
  EXPECT_EQ(got[1].stamp_ns, 6000000000);
  EXPECT_NEAR(got[1].pose.yaw(), M_PI / 2, 1e-6);
  EXPECT_EQ(r.rejected(), 6u);
  ASSERT_EQ(r.warnings().size(), 6u);
  const int lines[] = {4, 5, 6, 7, 8, 10};
  for (int k = 0; k < 6; ++k)
    EXPECT_EQ(r.warnings()[k].rfind(path + ":" + std::to_string(lines[k]) + ": ", 0), 0u) << r.warnings()[k];
}

TEST(Tum, MissingFileThrowsNamingIt) {
  try {
    TumReader r("/nonexistent/dir/traj.txt");
    FAIL() << "no exception";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/traj.txt"), std::string::npos);
  }
  EXPECT_THROW(TumWriter("/nonexistent/dir/out.txt"), IoError);
}

}  // namespace
}  // namespace polyloc

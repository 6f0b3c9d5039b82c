// Depth data sets read as recordings (io/rgbd_dataset.hpp): the shared 7-Scenes frames, a TUM
// layout written here, the rig made from their camera info, and bad input counted, not fatal.
#include <polyloc/config/yaml.hpp>
#include <polyloc/io/message_pose.hpp>
#include <polyloc/io/recording.hpp>
#include <polyloc/io/rgbd_dataset.hpp>
#include <polyloc/sensors/depth_camera.hpp>
#include <polyloc/sensors/rig.hpp>

#include "reloc/recorded_rig.hpp"
#include "reloc/topic_router.hpp"
#include "temp_dir.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace polyloc::t_rgbd_dataset {
namespace {

namespace fs = std::filesystem;
const std::string kRedkitchen = std::string(POLYLOC_SOURCE_DIR) + "/../shared/data/rgbd/7scenes-redkitchen";

float pixel(const msg::Image& img, int u, int v) {
  float d;
  std::memcpy(&d, img.data.data() + size_t(v) * img.step + size_t(u) * 4, 4);
  return d;
}

std::vector<RecordedMessage> readAll(RecordingReader& r, size_t limit = SIZE_MAX) {
  std::vector<RecordedMessage> out;
  RecordedMessage m;
  while (out.size() < limit && r.next(m)) out.push_back(m);
  return out;
}

TEST(RgbdDataset, SevenScenesFramesAreMetresAndPosesAreTheBodyFrame) {
  if (!fs::exists(kRedkitchen)) GTEST_SKIP() << kRedkitchen << " is not here";
  auto reader = openRecording(kRedkitchen);
  EXPECT_EQ(reader->format(), "7scenes");
  const auto topics = reader->topics();
  ASSERT_EQ(topics.size(), 3u);
  for (const TopicInfo& t : topics) EXPECT_EQ(t.count, 1000u) << t.name;
  EXPECT_NEAR(topics[1].rateHz(), 30.0, 1e-6);
  const auto msgs = readAll(*reader, 6);  // two frames: info, image, truth each
  ASSERT_EQ(msgs.size(), 6u);
  EXPECT_EQ(msgs[0].topic, kRgbdInfoTopic);
  EXPECT_EQ(msgs[1].topic, kRgbdImageTopic);
  EXPECT_EQ(msgs[2].topic, "/ground_truth");
  EXPECT_EQ(msgs[0].log_time_ns, 1000000000);
  EXPECT_EQ(msgs[3].log_time_ns, 1000000000 + 33333333);
  const auto& info = std::get<msg::CameraInfo>(msgs[0].message);
  EXPECT_EQ(info.k[0], 585.0);
  EXPECT_EQ(info.k[2], 320.0);
  EXPECT_EQ(info.width, 640u);

  // Pixels: the PNG's millimetres in metres, 0 and 65535 as NaN.
  const auto& img = std::get<msg::Image>(msgs[1].message);
  ASSERT_EQ(img.encoding, "32FC1");
  const cv::Mat raw = cv::imread(kRedkitchen + "/frame-000000.depth.png", cv::IMREAD_UNCHANGED);
  ASSERT_EQ(raw.type(), CV_16UC1);
  size_t checked = 0, invalid = 0;
  for (int v = 0; v < raw.rows; v += 7)
    for (int u = 0; u < raw.cols; u += 5) {
      const uint16_t d = raw.at<uint16_t>(v, u);
      if (d == 0 || d == 65535) {
        EXPECT_TRUE(std::isnan(pixel(img, u, v)));
        ++invalid;
      } else {
        EXPECT_FLOAT_EQ(pixel(img, u, v), d * 1e-3f);
        ++checked;
      }
    }
  EXPECT_GT(checked, 1000u);
  EXPECT_GT(invalid, 0u);

  // The truth is the pose file's optical frame turned into the body frame: the body's x axis is
  // the camera's optical axis (the matrix's third column).
  std::ifstream pf(kRedkitchen + "/frame-000000.pose.txt");
  Eigen::Matrix4d t;
  for (int i = 0; i < 16; ++i) pf >> t(i / 4, i % 4);
  const Pose body = fromMsgPose(std::get<msg::PoseStamped>(msgs[2].message).pose);
  EXPECT_LT((body.translation() - t.block<3, 1>(0, 3)).norm(), 1e-9);
  EXPECT_LT((body.rotate({1, 0, 0}) - t.block<3, 1>(0, 2).normalized()).norm(), 1e-3);
  EXPECT_LT((body.rotate({0, 0, 1}) + t.block<3, 1>(0, 1).normalized()).norm(), 1e-3);  // up = -optical y
}

// A TUM folder: depth.txt, depth/*.png at 5000 per metre, groundtruth.txt at its own rate.
struct TumFolder {
  test::TempDir tmp;
  fs::path dir = tmp.path() / "rgbd_dataset_freiburg2_test";
  TumFolder() {
    fs::create_directories(dir / "depth");
    for (int i = 0; i < 3; ++i) {
      cv::Mat d(480, 640, CV_16UC1, cv::Scalar(10000 + 500 * i));  // 2.0, 2.1, 2.2 m
      d.at<uint16_t>(1, 2) = 0;
      cv::imwrite((dir / "depth" / (std::to_string(i) + ".png")).string(), d);
    }
    std::ofstream(dir / "depth" / "broken.png") << "not a png";
    cv::imwrite((dir / "depth" / "grey8.png").string(), cv::Mat(480, 640, CV_8UC1, cv::Scalar(9)));
    std::ofstream(dir / "depth.txt") << "# depth maps\n# timestamp filename\n"
                                        "100.000 depth/0.png\n"
                                        "100.033 depth/broken.png\n"
                                        "100.050 depth/grey8.png\n"
                                        "100.040 depth/1.png\n"  // goes back: skipped
                                        "100.066 depth/1.png\n"
                                        "garbage\n"
                                        "101.000 depth/2.png\n";
    std::ofstream(dir / "groundtruth.txt") << "# timestamp tx ty tz qx qy qz qw\n"
                                              "99.99 0 0 0 0 0 0 1\n"
                                              "100.01 1 0 0 0 0 0 1\n"
                                              "100.06 2 0 0 0 0 0 1\n"
                                              "100.07 3 0 0 0 0 0 1\n"
                                              "100.08 1e19 0 0 0 0 0 1\n";  // skipped, counted
  }
};

TEST(RgbdDataset, TumLayoutInterpolatesTruthAndCountsBadFrames) {
  TumFolder f;
  auto reader = openRecording(f.dir.string());
  EXPECT_EQ(reader->format(), "tum-rgbd");
  const auto msgs = readAll(*reader);
  std::vector<const msg::Image*> images;
  std::vector<std::pair<int64_t, Pose>> truth;
  const msg::CameraInfo* info = nullptr;
  for (const auto& m : msgs) {
    if (const auto* i = std::get_if<msg::Image>(&m.message)) images.push_back(i);
    if (const auto* c = std::get_if<msg::CameraInfo>(&m.message)) info = c;
    if (const auto* p = std::get_if<msg::PoseStamped>(&m.message)) truth.emplace_back(m.log_time_ns, fromMsgPose(p->pose));
  }
  ASSERT_EQ(images.size(), 3u);  // 0, 1, 2; the broken and the 8-bit image skipped
  EXPECT_FLOAT_EQ(pixel(*images[0], 0, 0), 2.0f);
  EXPECT_FLOAT_EQ(pixel(*images[1], 5, 3), 2.1f);
  EXPECT_TRUE(std::isnan(pixel(*images[2], 2, 1)));
  ASSERT_NE(info, nullptr);
  EXPECT_EQ(info->k[0], 520.9);  // freiburg2, by the folder's name
  EXPECT_EQ(tumIntrinsics(f.dir.string() + "/").fx, 520.9);                      // a trailing slash
  EXPECT_EQ(tumIntrinsics((f.dir / "depth" / "..").string()).fx, 520.9);          // and ".." say the same
  EXPECT_EQ(tumIntrinsics(f.tmp.path().string()).fx, 525.0);                     // no freiburg: ROS's default
  // Truth: 100.000 between 99.99 and 100.01 (x 0.5), 100.033 and 100.050 (x 1.46, 1.8) for the
  // skipped images too, 100.066 (x 2.6); 101.0 has no sample within 50 ms.
  ASSERT_EQ(truth.size(), 4u);
  EXPECT_EQ(truth[0].first, 100000000000);
  // The optical frame at x = 0.5 (identity rotation): the body's translation is the same.
  EXPECT_NEAR(truth[0].second.translation().x(), 0.5, 1e-9);
  EXPECT_NEAR(truth[3].second.translation().x(), 2.6, 1e-9);
  EXPECT_LT((truth[0].second.rotate({1, 0, 0}) - Eigen::Vector3d(0, 0, 1)).norm(), 1e-9);
  const ReadStats& st = reader->stats();
  EXPECT_EQ(st.rejected, 5u);  // two depth.txt lines, two images, a pose 1e19 m away
  bool named = false;
  for (const auto& w : st.warnings) named |= w.find("broken.png") != std::string::npos;
  EXPECT_TRUE(named);
}

TEST(RgbdDataset, IntrinsicsYamlOverridesAndBadOnesNameTheKey) {
  TumFolder f;
  std::ofstream(f.dir / "intrinsics.yaml") << "fx: 500\nfy: 501\ncx: 2.5\ncy: 1.5\ndepth_scale: 1000\n";
  auto reader = openRecording(f.dir.string());
  const auto msgs = readAll(*reader, 2);
  const auto& info = std::get<msg::CameraInfo>(msgs[0].message);
  EXPECT_EQ(info.k[0], 500.0);
  EXPECT_FLOAT_EQ(pixel(std::get<msg::Image>(msgs[1].message), 0, 0), 10.0f);  // 10000 mm

  std::ofstream(f.dir / "intrinsics.yaml") << "fx: 500\ndepth_scale: 1000\n";
  EXPECT_THROW(openRecording(f.dir.string()), ConfigError);
  std::ofstream(f.dir / "intrinsics.yaml") << "fx: 500\nfy: 501\ncx: 2.5\ncy: 1.5\nfocal: 3\n";
  try {
    openRecording(f.dir.string());
    FAIL() << "unknown key accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("focal"), std::string::npos) << e.what();
  }
  // A principal point outside the 640x480 images.
  std::ofstream(f.dir / "intrinsics.yaml") << "fx: 500\nfy: 501\ncx: 700\ncy: 240\n";
  EXPECT_THROW(openRecording(f.dir.string()), IoError);
}

TEST(RgbdDataset, RecordedRigIsTheCameraOfTheCameraInfo) {
  TumFolder f;
  auto reader = openRecording(f.dir.string());
  PolylocConfig cfg;
  cfg.rig_from_recording = true;
  std::vector<std::string> notes;
  const Rig rig = reloc::recordedRig(cfg, *reader, f.dir.string(), &notes);
  ASSERT_EQ(rig.size(), 1u);
  EXPECT_EQ(rig.sensors[0].name, "camera");
  const auto& cam = std::get<DepthCameraSpec>(rig.sensors[0].spec);
  EXPECT_EQ(cam.width, 640);
  EXPECT_NEAR(cam.fx(), 520.9, 1e-12);
  EXPECT_NEAR(cam.cx(), 325.6, 1e-12);  // polyloc's continuous pixel coordinates: K's + 0.5
  EXPECT_EQ(cam.range_max, reloc::kRecordedDepthRange[1]);
  ASSERT_FALSE(notes.empty());

  // The router turns the image's depth into ranges along each pixel's ray.
  auto again = openRecording(f.dir.string());
  reloc::TopicRouter router(rig, {});
  std::vector<float> ranges;
  const BeamSet beams = rig.sensors[0].beams();
  RecordedMessage m;
  while (again->next(m))
    if (m.topic == kRgbdImageTopic) break;
  const auto r = router.route(m.topic, m.log_time_ns, m.message, ranges);
  ASSERT_EQ(r.kind, reloc::TopicRouter::Kind::Frame) << r.why;
  ASSERT_EQ(ranges.size(), 640u * 480u);
  for (size_t b = 0; b < ranges.size(); b += (b < 700 ? 1 : 997)) {
    if (b == 1 * 640 + 2) {
      EXPECT_TRUE(std::isnan(ranges[b]));
    } else {
      EXPECT_NEAR(ranges[b] * beams.dx[b], 2.0f, 1e-5) << b;  // range x cos = depth
    }
  }
}

TEST(RgbdDataset, RouterTakesMillimetreImagesAsRos) {
  Rig rig;
  rig.add({"camera_depth", depthCameraFromIntrinsics(4, 2, 300, 300, 1.5, 0.5, 0.1, 10, 30), Pose()}, "test");
  reloc::TopicRouter router(rig, {});
  msg::Image img;
  img.width = 4, img.height = 2, img.encoding = "16UC1", img.step = 10;  // 2 bytes of padding per row
  img.data.assign(20, 0);
  const uint16_t mm = 1500;
  std::memcpy(img.data.data() + 10 + 2, &mm, 2);  // pixel (1, 1)
  std::vector<float> ranges;
  const auto r = router.route("/camera/depth/image_raw", 0, img, ranges);
  ASSERT_EQ(r.kind, reloc::TopicRouter::Kind::Frame) << r.why;
  EXPECT_TRUE(std::isnan(ranges[0]));  // 0 mm: no return
  EXPECT_NEAR(ranges[5] * rig.sensors[0].beams().dx[5], 1.5f, 1e-6);
  img.encoding = "16SC1";
  EXPECT_EQ(router.route("/camera/depth/image_raw", 0, img, ranges).kind, reloc::TopicRouter::Kind::BadImage);
}

TEST(RgbdDataset, CalibratedPinholeGivesTheRaysOfK) {
  // K's principal point is a pixel centre: that pixel's ray is the optical axis.
  const DepthCameraSpec c = depthCameraFromIntrinsics(640, 480, 585, 585, 320, 240, 0.1, 10, 30);
  const BeamSet b = c.beams();
  const size_t centre = 240 * 640 + 320;
  EXPECT_NEAR(b.dx[centre], 1.0f, 1e-7);
  EXPECT_NEAR(b.dy[centre], 0.0f, 1e-7);
  // Pixel (0, 0) is 320 px left and 240 px up of it.
  EXPECT_NEAR(b.dy[0] / b.dx[0], 320.0 / 585, 1e-6);
  EXPECT_NEAR(b.dz[0] / b.dx[0], 240.0 / 585, 1e-6);
  EXPECT_NEAR(c.hfov_rad, std::atan(320.5 / 585) + std::atan(319.5 / 585), 1e-12);
  EXPECT_THROW(depthCameraFromIntrinsics(640, 480, -1, 585, 320, 240, 0.1, 10, 30), std::invalid_argument);
  EXPECT_THROW(depthCameraFromIntrinsics(640, 480, 585, 585, 1e19, 240, 0.1, 10, 30), std::invalid_argument);
  // The rig file's keys: all four or none, and not with a field of view.
  auto parse = [](const std::string& spec) {
    return parseRig(ConfigMap::parse("sensors:\n  - name: cam\n    preset: pmd_o3d100\n    spec: " + spec + "\n"));
  };
  const Rig rig = parse("{width: 640, height: 480, fx: 585, fy: 585, cx: 320, cy: 240}");
  EXPECT_NEAR(std::get<DepthCameraSpec>(rig.sensors[0].spec).cx(), 320.5, 1e-12);
  EXPECT_THROW(parse("{width: 640, height: 480, fx: 585}"), ConfigError);
  EXPECT_THROW(parse("{width: 640, height: 480, fx: 585, fy: 585, cx: 320, cy: 240, hfov: 60}"), ConfigError);
}

}  // namespace
}  // namespace polyloc::t_rgbd_dataset

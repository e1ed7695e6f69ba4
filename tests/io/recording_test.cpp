#include "inertia/io/recording.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <type_traits>

#include <gtest/gtest.h>

using namespace inertia;

namespace {
std::string readFile(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

TEST(Recording, HeaderAndRowFormat) {
  auto path = std::filesystem::temp_directory_path() / "inertia_recording_test.csv";
  {
    io::BodyRecorder r(path);
    Transform pose{Vec3(1, Real(2.5), -3), Quat::Identity()};
    r.write(Real(0.5), "ball", pose, Vec3(0, -1, 0), Vec3(0, 0, 2));
    r.close();
  }
  EXPECT_EQ(readFile(path),
            "time,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n"
            "0.5,ball,1,2.5,-3,1,0,0,0,0,-1,0,0,0,2\n");
  std::filesystem::remove(path);
}

TEST(Recording, ValuesRoundTrip) {
  // %.9g (float) and %.17g (double) are the shortest fixed precisions that always round-trip.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1e6, 1e6);
  std::string s;
  for (int i = 0; i < 10000; ++i) {
    Real x = Real(u(rng)) / Real(1 + i);
    s.clear();
    io::appendReal(s, x);
    Real back;
    if constexpr (std::is_same_v<Real, float>) back = std::strtof(s.c_str(), nullptr);
    else back = std::strtod(s.c_str(), nullptr);
    ASSERT_EQ(back, x) << s;
  }
}

TEST(Recording, UnwritableFileIsAnError) {
  EXPECT_THROW(io::BodyRecorder("/nonexistent/dir/out.csv"), std::runtime_error);
}

TEST(Recording, JointHeaderAndRowFormat) {
  auto path = std::filesystem::temp_directory_path() / "inertia_joint_recording_test.csv";
  {
    io::JointRecorder r(path);
    r.write(Real(0.25), "elbow", false, Vec3(0, Real(19.5), 0), Vec3(0, 0, Real(-2.5)),
            JointError{.position = Real(0.125), .angle = Real(0.0625)});
    r.write(Real(0.5), "3", true, Vec3::Zero(), Vec3::Zero(), JointError{});
    r.close();
  }
  EXPECT_EQ(readFile(path),
            "time,joint,broken,fx,fy,fz,tx,ty,tz,position_error,angle_error\n"
            "0.25,elbow,0,0,19.5,0,0,0,-2.5,0.125,0.0625\n"
            "0.5,3,1,0,0,0,0,0,0,0,0\n");
  std::filesystem::remove(path);
  EXPECT_THROW(io::JointRecorder("/nonexistent/dir/joints.csv"), std::runtime_error);
}

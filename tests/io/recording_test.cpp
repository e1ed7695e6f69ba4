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

// The inertia command end to end: exit codes 0 / 2 and messages that name what is wrong.
#include <algorithm>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace fs = std::filesystem;

namespace {

struct Result {
  int code = -1;
  std::string output;  // stdout and stderr together
};

// `environment`: assignments put before the command, e.g. "INERTIA_SIMD=sse2".
Result run(const std::string& args, const std::string& environment = "") {
  std::string command = environment + " " + std::string(INERTIA_CLI) + " " + args + " 2>&1";
  Result r;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return r;
  char buffer[4096];
  std::size_t n;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) r.output.append(buffer, n);
  int status = pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}

}  // namespace

// Outside the anonymous namespace: the tests derive from it, and in a unity batch, which
// includes this file, GCC rejects a base of internal linkage (-Wsubobject-linkage).
class Cli : public testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("inertia_cli_" + std::string(testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string& name, const std::string& text) {
    fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
  std::string read(const std::string& name) {
    std::ifstream in(dir_ / name);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  std::string path(const std::string& name) { return (dir_ / name).string(); }

  fs::path dir_;
};

namespace {

const char* kGood = R"({"world": {"dt": 0.01, "substeps": 2}})";

}  // namespace

TEST_F(Cli, ValidateAcceptsAGoodScene) {
  Result r = run("validate " + write("good.json", kGood));
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("ok"), std::string::npos) << r.output;
}

TEST_F(Cli, MalformedJsonIsBadInputWithLineAndColumn) {
  std::string file = write("bad.json", "{\n  \"world\": {\"dt\": 0.01,}\n}");
  for (const char* cmd : {"validate ", "run "}) {
    Result r = run(cmd + file);
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find(file + ":2:"), std::string::npos) << r.output;
  }
}

TEST_F(Cli, UnknownKeyNamesItsPointer) {
  Result r = run("run " + write("typo.json", R"({"world": {"gravty": [0, -9.81, 0]}})"));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("/world/gravty"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("did you mean \"gravity\""), std::string::npos) << r.output;
}

TEST_F(Cli, DuplicateBodyNamesAreBadInput) {
  // Issue 21, defect 4: two bodies named "c" would be two bodies "c" in the recording.
  const std::string file = write("twins.json", R"({"bodies": [{"name": "c", "position": [0, 1, 0]},
                                                              {"name": "c", "position": [1, 1, 0]}]})");
  for (const char* cmd : {"validate ", "run "}) {
    Result r = run(cmd + file);
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find("/bodies/1/name: duplicate body name \"c\""), std::string::npos)
        << r.output;
  }
}

TEST_F(Cli, NaNIsBadInput) {
  Result r = run("run " + write("nan.json", R"({"world": {"dt": NaN}})"));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("nan.json:1:"), std::string::npos) << r.output;
  Result overflow = run("run " + write("inf.json", R"({"world": {"gravity": [0, -1e400, 0]}})"));
  EXPECT_EQ(overflow.code, 2) << overflow.output;
  EXPECT_NE(overflow.output.find("inf.json:1:"), std::string::npos) << overflow.output;
}

TEST_F(Cli, NegativeDtInSceneNamesItsPointer) {
  Result r = run("run " + write("neg.json", R"({"world": {"dt": -0.01}})"));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("/world/dt"), std::string::npos) << r.output;
}

TEST_F(Cli, BadArgumentsNameTheArgument) {
  std::string file = write("good.json", kGood);
  for (const char* arg : {"--dt -1", "--dt nan", "--dt 0", "--duration inf", "--threads -2",
                          "--steps 0", "--record-every 0"}) {
    Result r = run("run " + file + " " + arg);
    EXPECT_EQ(r.code, 2) << arg << ": " << r.output;
    std::string option(arg, std::string(arg).find(' '));
    EXPECT_NE(r.output.find(option), std::string::npos) << arg << ": " << r.output;
  }
  Result both = run("run " + file + " --steps 3 --duration 1");
  EXPECT_EQ(both.code, 2) << both.output;
  Result none = run("");
  EXPECT_EQ(none.code, 2) << none.output;
}

TEST_F(Cli, MissingFileIsNamed) {
  Result r = run("run " + path("absent.json"));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("absent.json: no such file"), std::string::npos) << r.output;
}

TEST_F(Cli, UnwritableOutputIsBadInput) {
  Result r = run("run " + write("good.json", kGood) + " --steps 1 --record " + path("no/such/dir.csv"));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("--record"), std::string::npos) << r.output;
}

TEST_F(Cli, RunWritesStatsAndRecording) {
  std::string file = write("good.json", kGood);
  Result r = run("run " + file + " --duration 1 --stats " + path("stats.json") + " --record " +
                 path("rec.csv"));
  ASSERT_EQ(r.code, 0) << r.output;
  nlohmann::json stats = nlohmann::json::parse(read("stats.json"));
  // 1 s at dt = 0.01 s is exactly 100 steps.
  EXPECT_EQ(stats["steps"], 100);
  EXPECT_NEAR(stats["sim_time"].get<double>(), 1.0, 1e-6);
  for (const char* key : {"wall_time", "bodies", "contacts", "phases", "particle_systems"})
    EXPECT_TRUE(stats.contains(key)) << key;
  EXPECT_EQ(read("rec.csv"), "time,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n");

  Result dt = run("run " + file + " --duration 1 --dt 0.05 --stats " + path("stats2.json"));
  ASSERT_EQ(dt.code, 0) << dt.output;
  EXPECT_EQ(nlohmann::json::parse(read("stats2.json"))["steps"], 20);
}

TEST_F(Cli, ParticleRecordingIsIdenticalAtOneAndTwoThreads) {
  std::string file = write("fountain.json", R"({
    "world": {"dt": 0.02},
    "particle_systems": [{ "name": "f", "capacity": 20000, "radius": 0.02, "particle_collisions": true,
      "emitters": [{"type": "cone", "angle": 0.4, "burst": 5000, "rate": 3000, "speed": [3, 6],
                    "lifetime": [1, 2], "seed": 11}],
      "fields": [{"type": "gravity"}, {"type": "drag", "k": 0.0001}],
      "obstacles": [{"type": "plane"}, {"type": "sphere", "radius": 0.5, "position": [0, 1.5, 0]}] }]
  })");
  for (const char* threads : {"1", "2"}) {
    Result r = run("run " + file + " --steps 40 --record-every 10 --threads " + threads +
                   " --record-particles " + path(std::string("p") + threads + ".csv") + " --stats " +
                   path(std::string("s") + threads + ".json"));
    ASSERT_EQ(r.code, 0) << r.output;
  }
  const std::string one = read("p1.csv"), two = read("p2.csv");
  EXPECT_GT(one.size(), 100000u);
  EXPECT_EQ(one.substr(0, 37), "time,system,id,px,py,pz,vx,vy,vz,age\n");
  EXPECT_TRUE(one == two) << "recordings differ between 1 and 2 threads";
  nlohmann::json stats = nlohmann::json::parse(read("s1.json"));
  ASSERT_EQ(stats["particle_systems"].size(), 1u);
  const auto& ps = stats["particle_systems"][0];
  EXPECT_EQ(ps["name"], "f");
  EXPECT_EQ(ps["emitted"].get<long long>(), ps["alive"].get<long long>() + ps["died"].get<long long>());
}

TEST_F(Cli, BodyRecordingIsIdenticalAtOneAndTwoThreads) {
  std::string file = write("rain.json", R"({
    "bodies": [
      {"name": "ground", "type": "static", "shapes": [{"type": "plane", "normal": [0, 1, 0], "offset": 0}]},
      {"type": "rain", "count": 30, "lower": [-1, 1, -1], "upper": [1, 5, 1], "seed": 3,
       "shape": {"type": "box", "half_extents": [0.2, 0.1, 0.3]}}
    ]
  })");
  for (const char* threads : {"1", "2"}) {
    Result r = run("run " + file + " --steps 90 --record-every 30 --threads " + threads + " --record " +
                   path(std::string("b") + threads + ".csv") + " --stats " +
                   path(std::string("t") + threads + ".json"));
    ASSERT_EQ(r.code, 0) << r.output;
  }
  const std::string one = read("b1.csv"), two = read("b2.csv");
  EXPECT_EQ(one.substr(0, 49), "time,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n");
  // The header and 31 bodies at 4 recorded times (0, 30, 60, 90 steps).
  EXPECT_EQ(std::count(one.begin(), one.end(), '\n'), 1 + 31 * 4);
  EXPECT_TRUE(one == two) << "recordings differ between 1 and 2 threads";
  nlohmann::json stats = nlohmann::json::parse(read("t1.json"));
  EXPECT_EQ(stats["bodies"].get<int>(), 31);
  EXPECT_GT(stats["contacts"].get<int>(), 0);  // the boxes have landed after 1.5 s
}

// The contact kernels of every instruction set give the same bits (the bundles' lanes compute
// lane-wise IEEE arithmetic): capping them with INERTIA_SIMD leaves the recording unchanged. On
// a processor without AVX-512 or AVX2 two of the runs use the same set.
TEST_F(Cli, BodyRecordingIsIdenticalInEveryInstructionSet) {
  std::string file = write("pile.json", R"({
    "bodies": [
      {"name": "ground", "type": "static", "shapes": [{"type": "plane", "normal": [0, 1, 0], "offset": 0}]},
      {"type": "rain", "count": 40, "lower": [-1, 1, -1], "upper": [1, 6, 1], "seed": 5,
       "shape": {"type": "box", "half_extents": [0.2, 0.15, 0.25]}}
    ]
  })");
  std::vector<std::string> recordings;
  for (const char* set : {"avx512", "avx2", "sse2"}) {
    const std::string out = path(std::string("r_") + set + ".csv");
    Result r = run("run " + file + " --steps 120 --record-every 40 --record " + out,
                   std::string("INERTIA_SIMD=") + set);
    ASSERT_EQ(r.code, 0) << r.output;
    EXPECT_EQ(r.output.find("ignored"), std::string::npos) << r.output;
    recordings.push_back(read(std::string("r_") + set + ".csv"));
  }
  EXPECT_EQ(std::count(recordings[0].begin(), recordings[0].end(), '\n'), 1 + 41 * 4);
  EXPECT_TRUE(recordings[0] == recordings[1]) << "AVX-512 and AVX2 recordings differ";
  EXPECT_TRUE(recordings[0] == recordings[2]) << "AVX-512 and SSE2 recordings differ";
  // An unknown set is named and ignored; the run goes on.
  Result r = run("run " + file + " --steps 1", "INERTIA_SIMD=neon");
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("INERTIA_SIMD=neon ignored"), std::string::npos) << r.output;
}

TEST_F(Cli, BadBodyInputNamesThePointer) {
  std::string file = write("bad_body.json", R"({
    "bodies": [{"name": "ball", "shapes": [{"type": "sphere", "radius": 1, "material": "unobtainium"}]}]
  })");
  Result r = run("run " + file + " --steps 1");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.output.find("/bodies/0/shapes/0/material"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("unknown material"), std::string::npos) << r.output;
}

namespace {

// The rows of a joint recording after its header, split at the commas.
std::vector<std::vector<std::string>> csvRows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(text);
  std::string line;
  std::getline(lines, line);  // the header
  while (std::getline(lines, line)) {
    std::vector<std::string>& row = rows.emplace_back();
    std::istringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ',')) row.push_back(field);
  }
  return rows;
}

// A 2 kg ball hanging at rest 1 m below a ball joint, a 2 kg beam welded to the world 1 m
// from its centre of mass, and an unnamed hinge.
const char* kHanging = R"({
  "bodies": [
    {"name": "bob", "position": [0, 1, 0], "mass": 2, "shapes": [{"type": "sphere", "radius": 0.1}]},
    {"name": "beam", "position": [3, 3, 0], "mass": 2, "inertia": [0.1, 0.1, 0.1],
     "shapes": [{"type": "box", "half_extents": [0.5, 0.05, 0.05]}]},
    {"name": "door", "position": [-3, 1, 0], "shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.05]}]}
  ],
  "joints": [
    {"name": "hang", "type": "ball", "body_a": null, "body_b": "bob", "anchor_a": [0, 2, 0],
     "anchor_b": [0, 1, 0]},
    {"name": "wall", "type": "weld", "body_b": "beam", "anchor_a": [2, 3, 0], "anchor_b": [-1, 0, 0]},
    {"type": "hinge", "body_b": "door", "anchor_a": [-3.5, 1, 0], "anchor_b": [-0.5, 0, 0],
     "axis_a": [0, 1, 0], "limits": [-1, 1]}
  ]
})";

}  // namespace

TEST_F(Cli, RecordJointsWritesOneRowPerJointPerRecordedStep) {
  Result r = run("run " + write("hang.json", kHanging) +
                 " --steps 120 --record-every 40 --record-joints " + path("joints.csv") +
                 " --stats " + path("stats.json"));
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string text = read("joints.csv");
  EXPECT_EQ(text.substr(0, text.find('\n')),
            "time,joint,broken,fx,fy,fz,tx,ty,tz,position_error,angle_error");
  const auto rows = csvRows(text);
  // Three joints at the steps 0, 40, 80 and 120, in creation order; the unnamed one by its index.
  ASSERT_EQ(rows.size(), 3u * 4u);
  const char* names[] = {"hang", "wall", "2"};
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].size(), 11u) << i;
    EXPECT_EQ(rows[i][1], names[i % 3]) << i;
    EXPECT_EQ(rows[i][2], "0") << i;  // none broken
    EXPECT_NEAR(std::stod(rows[i][0]), 0.01666667 * 40 * double(i / 3), 1e-4) << i;
  }
  // The initial state comes before any step: no constraint force yet.
  for (std::size_t k = 3; k < 9; ++k) EXPECT_EQ(rows[0][k], "0");

  const double mg = 2 * 9.81;
  const auto& hang = rows[9];  // at rest after 2 s: the joint carries the ball's weight
  EXPECT_NEAR(std::stod(hang[4]), mg, 0.01 * mg);
  EXPECT_NEAR(std::stod(hang[3]), 0, 0.01 * mg);
  EXPECT_NEAR(std::stod(hang[5]), 0, 0.01 * mg);
  for (std::size_t k = 6; k < 9; ++k)
    EXPECT_NEAR(std::stod(hang[k]), 0, 1e-3) << k;  // a ball transmits no torque
  EXPECT_LT(std::stod(hang[9]), 1e-3);              // position_error (m)
  // The weld holds the beam's weight and its moment about the anchor: m g times 1 m about z.
  const auto& wall = rows[10];
  EXPECT_NEAR(std::stod(wall[4]), mg, 0.01 * mg);
  EXPECT_NEAR(std::stod(wall[8]), mg * 1.0, 0.01 * mg);
  EXPECT_LT(std::stod(wall[10]), 0.01);  // angle_error (rad)

  nlohmann::json stats = nlohmann::json::parse(read("stats.json"));
  EXPECT_EQ(stats["joints"], 3);
  EXPECT_EQ(stats["broken_joints"], 0);
}

TEST_F(Cli, ABrokenJointIsRecordedCountedAndReported) {
  // The 10 kg ball pulls with 98 N on a joint that holds 50 N.
  std::string file = write("weak.json", R"({
    "bodies": [{"name": "ball", "position": [0, 1, 0], "mass": 10, "shapes": [{"type": "sphere", "radius": 0.1}]}],
    "joints": [{"name": "weak", "type": "ball", "body_b": "ball", "anchor_a": [0, 2, 0], "anchor_b": [0, 1, 0],
                "break_force": 50}]
  })");
  Result r = run("run " + file + " --steps 10 --record-joints " + path("j.csv") + " --stats " +
                 path("s.json"));
  ASSERT_EQ(r.code, 0) << r.output;
  const auto rows = csvRows(read("j.csv"));
  ASSERT_EQ(rows.size(), 11u);
  EXPECT_EQ(rows.front()[2], "0");
  EXPECT_EQ(rows.back()[2], "1");
  nlohmann::json stats = nlohmann::json::parse(read("s.json"));
  EXPECT_EQ(stats["joints"], 1);
  EXPECT_EQ(stats["broken_joints"], 1);
  EXPECT_NE(r.output.find("joint \"weak\" broke at"), std::string::npos) << r.output;
}

TEST_F(Cli, BadJointIsBadInputNamingThePointer) {
  std::string file = write("bad_joint.json", R"({
    "bodies": [{"name": "a"}, {"name": "b"}],
    "joints": [{"type": "ball", "body_b": "a"}, {"type": "hinge", "body_a": "a", "body_b": "c"}]
  })");
  for (const char* cmd : {"validate ", "run "}) {
    Result r = run(cmd + file);
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find(file + ": /joints/1/body_b: no body is named \"c\""), std::string::npos)
        << r.output;
  }
  Result badAxis = run("run " + write("u.json", R"({"bodies": [{"name": "a"}],
      "joints": [{"type": "six_dof", "body_b": "a", "axes": {"w": "free"}}]})"));
  EXPECT_EQ(badAxis.code, 2) << badAxis.output;
  EXPECT_NE(badAxis.output.find("/joints/0/axes/w"), std::string::npos) << badAxis.output;
  EXPECT_NE(badAxis.output.find("unknown key"), std::string::npos) << badAxis.output;

  Result unwritable = run("run " + write("hang.json", kHanging) + " --steps 1 --record-joints " +
                          path("no/such/dir.csv"));
  EXPECT_EQ(unwritable.code, 2) << unwritable.output;
  EXPECT_NE(unwritable.output.find("--record-joints"), std::string::npos) << unwritable.output;
}

// The shipped joint scene holds together: every joint within 2 cm of its constraint (the
// chain's whipping tip, the worst, reaches about 1.1 cm at the scene's 4 substeps), none
// broken, and the same bytes at 1 and 2 threads.
TEST_F(Cli, PendulumsSceneKeepsItsJoints) {
  const char* root = std::getenv("INERTIA_SOURCE_DIR");
  ASSERT_NE(root, nullptr);
  const std::string scene = (fs::path(root) / "scenes" / "pendulums.json").string();
  Result ok = run("validate " + scene);
  EXPECT_EQ(ok.code, 0) << ok.output;
  EXPECT_NE(ok.output.find("14 joints"), std::string::npos) << ok.output;
  for (const char* threads : {"1", "2"}) {
    Result r = run("run " + scene + " --duration 3 --record-every 15 --quiet --threads " + threads +
                   " --record-joints " + path(std::string("j") + threads + ".csv"));
    ASSERT_EQ(r.code, 0) << r.output;
  }
  const std::string one = read("j1.csv");
  EXPECT_TRUE(one == read("j2.csv")) << "joint recordings differ between 1 and 2 threads";
  const auto rows = csvRows(one);
  EXPECT_EQ(rows.size(), 14u * (180 / 15 + 1));
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), 11u);
    EXPECT_EQ(row[2], "0") << row[0] << " " << row[1];
    EXPECT_LT(std::stod(row[9]), 0.02) << row[0] << " " << row[1];
  }
}

// A rope hanging from its pinned top vertex: rows per vertex per recorded step, the pinned
// vertex where it started, a tear reported in the summary and counted in the stats.
TEST_F(Cli, RecordDeformablesWritesOneRowPerVertexPerRecordedStep) {
  const std::string file = write("rope.json", R"({
    "world": {"dt": 0.02},
    "deformables": [{"name": "rope", "type": "rope", "from": [0, 1, 0], "to": [1, 1, 0], "segments": 4,
                     "pinned": [0], "mass": 0.5, "stiffness": {"stretch": 200, "bend": 0},
                     "fields": [{"type": "gravity"}], "tear_strain": 0.05}]
  })");
  Result r = run("run " + file + " --steps 30 --record-every 10 --record-deformables " +
                 path("d.csv") + " --stats " + path("s.json"));
  ASSERT_EQ(r.code, 0) << r.output;
  const std::string text = read("d.csv");
  EXPECT_EQ(text.substr(0, text.find('\n')), "time,deformable,vertex,px,py,pz,vx,vy,vz");
  const auto rows = csvRows(text);
  ASSERT_EQ(rows.size(), 5u * 4u);  // 5 vertices at the steps 0, 10, 20, 30
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ASSERT_EQ(rows[i].size(), 9u);
    EXPECT_EQ(rows[i][1], "rope");
    EXPECT_EQ(rows[i][2], std::to_string(i % 5));
    EXPECT_NEAR(std::stod(rows[i][0]), 0.02 * 10 * double(i / 5), 1e-6);
    if (i % 5 == 0) {
      EXPECT_EQ(rows[i][4], "1") << "the pinned vertex stays";
    }
  }
  EXPECT_LT(std::stod(rows.back()[4]), 0.5) << "the free end fell";
  nlohmann::json stats = nlohmann::json::parse(read("s.json"));
  ASSERT_EQ(stats["deformables"].size(), 1u);
  EXPECT_EQ(stats["deformables"][0]["vertices"], 5);
  EXPECT_GT(stats["deformables"][0]["broken_springs"], 0);
  EXPECT_NE(r.output.find("deformable \"rope\": spring "), std::string::npos) << r.output;
}

TEST_F(Cli, BadDeformableIsBadInputNamingThePointer) {
  const std::string file =
      write("bad.json", R"({"deformables": [{"type": "cloth", "resolution": [4, -1]}]})");
  for (const char* cmd : {"validate ", "run "}) {
    Result r = run(cmd + file);
    EXPECT_EQ(r.code, 2) << r.output;
    EXPECT_NE(r.output.find(file + ": /deformables/0/resolution/1"), std::string::npos) << r.output;
  }
}

TEST_F(Cli, BadUrdfIsBadInputNamingThePointerAndTheFile) {
  const std::string good = R"(<robot name="r"><link name="a"/><link name="b"><inertial>
      <mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
      <joint name="hinge" type="continuous"><parent link="a"/><child link="b"/></joint></robot>)";
  write("good.urdf", good);
  const std::string planar =
      write("planar.urdf", std::string(good).replace(good.find("continuous"), 10, "planar"));
  const std::string broken = write("broken.urdf", "<robot name=\"r\"><link name=\"a\">");
  const std::string ok =
      write("ok.json", R"({"articulations": [{"urdf": "good.urdf", "q": {"hinge": 0.5}}]})");
  EXPECT_EQ(run("validate " + ok).code, 0);
  struct Case {
    std::string scene, expected;
  };
  for (const Case& c : {Case{R"({"articulations": [{"urdf": "planar.urdf"}]})",
                             ": /articulations/0/urdf: " + planar + ": joint 'hinge' is planar"},
                        Case{R"({"articulations": [{"urdf": "broken.urdf"}]})",
                             ": /articulations/0/urdf: " + broken + ": urdfdom cannot parse it"},
                        Case{R"({"articulations": [{"urdf": "absent.urdf"}]})",
                             ": /articulations/0/urdf: " + path("absent.urdf") + ": no such file"},
                        Case{R"({"articulations": [{"urdf": "good.urdf", "q": {"knee": 1}}]})",
                             ": /articulations/0/q/knee: no joint named \"knee\""}}) {
    const std::string file = write("bad.json", c.scene);
    for (const char* cmd : {"validate ", "run "}) {
      Result r = run(cmd + file);
      EXPECT_EQ(r.code, 2) << r.output;
      EXPECT_NE(r.output.find(file + c.expected), std::string::npos) << r.output;
    }
  }
}

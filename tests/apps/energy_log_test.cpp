// Energy and momenta: measureEnergy against closed forms, and `inertia run --energy` on a free
// fall, whose total energy is conserved up to the integrator's known error.
#include "energy_log.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <sstream>
#include <vector>

#include "run_cli.h"

namespace inertia::test {
namespace {

using app::EnergySample;
using app::measureEnergy;

constexpr double kPi = std::numbers::pi;

TEST(EnergyLog, MeasureMatchesClosedForms) {
  World world({.gravity = {0, Real(-9.81), 0}});
  BodyId ground = world.createBody({.type = BodyType::Static});
  world.addShape(ground, Plane{{0, 1, 0}, 0});
  BodyId ball = world.createBody(
      {.position = {1, 2, 0}, .linearVelocity = {3, 0, 0}, .angularVelocity = {0, 0, 2}});
  world.addShape(ball, Sphere{Real(0.5)}, Material{.density = 1000});
  const double m = 1000 * 4.0 / 3.0 * kPi * 0.125, I = 0.4 * m * 0.25;
  const std::vector<Real> scale = {1, 1};
  const EnergySample s = measureEnergy(world, scale);
  const double rel = 1e-5;  // float mass properties
  EXPECT_NEAR(s.kinetic, 0.5 * m * 9 + 0.5 * I * 4, rel * s.kinetic);
  EXPECT_NEAR(s.potential, m * 9.81 * 2, rel * s.potential);  // relative to y = 0
  EXPECT_NEAR(s.total, s.kinetic + s.potential, 1e-9 * s.total);
  EXPECT_NEAR(s.momentum.x(), 3 * m, rel * 3 * m);
  EXPECT_NEAR(s.momentum.y(), 0, 1e-6);
  // L = c x m v + I w about the origin: z = m (x vy - y vx) + I wz = -6 m + 2 I.
  EXPECT_NEAR(s.angularMomentum.z(), -6 * m + 2 * I, rel * 6 * m);
  // Gravity scale 0: no potential energy.
  const std::vector<Real> noGravity = {1, 0};
  EXPECT_EQ(measureEnergy(world, noGravity).potential, 0.0);
}

std::vector<std::vector<double>> readCsv(const std::string& file, std::string& header) {
  std::ifstream in(file);
  std::getline(in, header);
  std::vector<std::vector<double>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<double>& row = rows.emplace_back();
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) row.push_back(std::stod(cell));
  }
  return rows;
}

using Energy = CliTest;

TEST_F(Energy, FreeFallConservesEnergyToTheIntegratorsError) {
  // A spinning ball thrown sideways, no ground: gravity is the only force.
  const std::string scene = write("fall.json", R"({
    "world": {"dt": 0.01, "substeps": 4, "gravity": [0, -9.81, 0], "integrator": "symplectic_euler"},
    "bodies": [{"name": "ball", "position": [0, 10, 0], "velocity": [1, 2, 0],
                "angular_velocity": [0, 0, 3],
                "shapes": [{"type": "sphere", "radius": 0.5, "material": {"density": 1000}}]}]
  })");
  CliResult r = runCli("run " + scene + " -q --steps 100 --energy " + path("e.csv"));
  ASSERT_EQ(r.code, 0) << r.output;
  std::string header;
  const auto rows = readCsv(path("e.csv"), header);
  EXPECT_EQ(header, "time,kinetic,potential,total,px,py,pz,lx,ly,lz");
  ASSERT_EQ(rows.size(), 101u);  // the initial state and each step

  const double g = 9.81, m = 1000 * 4.0 / 3.0 * kPi * 0.125, I = 0.4 * m * 0.25;
  const double e0 = 0.5 * m * 5 + 0.5 * I * 9 + m * g * 10;
  EXPECT_NEAR(rows[0][3], e0, 1e-5 * e0);
  // Symplectic Euler under uniform gravity loses exactly m g^2 h^2 / 2 per step of h
  // (v' = v + g h, x' = x + h v' gives dE = -m g^2 h^2 / 2), so after time T the drift is
  // m g^2 h T / 2, with h = dt / substeps = 0.0025 s: 63 J here. Allowed: 10% more, plus float
  // rounding of positions (1e-6 relative). A wrong sign or a missing term of the potential would
  // change E by ~2 m g * 1.9 m, 300x this bound; steps not split into substeps would drift 4x.
  const double T = 1.0, h = 0.01 / 4;
  const double bound = 1.1 * 0.5 * m * g * g * h * T + 1e-6 * e0;
  double worst = 0;
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), 10u);
    worst = std::max(worst, std::abs(row[3] - e0));
    EXPECT_NEAR(row[3], row[1] + row[2], 1e-9 * e0);
  }
  EXPECT_LE(worst, bound) << "worst drift " << worst << " J";
  // Momentum: constant horizontally, changed by m g t vertically.
  const auto& last = rows.back();
  EXPECT_NEAR(last[0], 1.0, 1e-6);
  EXPECT_NEAR(last[4], m * 1, 1e-4 * m);
  EXPECT_NEAR(last[5], m * (2 - g * last[0]), 1e-4 * m);
  // Angular momentum about the origin at t = 0: m (x vy - y vx) + I wz = -10 m + 3 I.
  EXPECT_NEAR(rows[0][9], -10 * m + 3 * I, 1e-5 * 10 * m);
}

TEST_F(Energy, UnwritableFileIsBadInput) {
  const std::string scene = write("s.json", R"({"world": {"dt": 0.01}})");
  CliResult r = runCli("run " + scene + " --steps 1 --energy " + path("no/dir/e.csv"));
  EXPECT_EQ(r.code, 2) << r.output;
  EXPECT_NE(r.output.find("--energy"), std::string::npos) << r.output;
}

TEST_F(Energy, PlotScriptWritesAPng) {
  // scripts/setup installs python3-matplotlib and scripts/test runs setup first, so a missing
  // package is a setup defect: fail rather than skip.
  ASSERT_EQ(std::system("/usr/bin/python3 -c 'import matplotlib' 2>/dev/null"), 0)
      << "python3-matplotlib is missing: run scripts/setup";
  const std::string scene = write("s.json", R"({"bodies": [{"position": [0, 1, 0],
      "shapes": [{"type": "sphere", "radius": 0.5}]}]})");
  ASSERT_EQ(runCli("run " + scene + " -q --steps 10 --energy " + path("e.csv")).code, 0);
  const std::string script =
      std::string(std::getenv("INERTIA_SOURCE_DIR")) + "/scripts/plot_energy.py";
  const std::string command = "/usr/bin/python3 " + script + " " + path("e.csv") + " --out " +
                              path("e.png") + " >/dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0);
  std::ifstream png(path("e.png"), std::ios::binary);
  char magic[8] = {};
  png.read(magic, 8);
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
}

}  // namespace
}  // namespace inertia::test

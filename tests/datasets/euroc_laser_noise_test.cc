// euroc-laser's IMU noise model: the stated densities of imu0/sensor.yaml by default, another
// file's with imu_noise_model=PATH, every density scaled by imu_noise_scale; bad values and files
// without IMU densities are refused with the setting named.
#include <gtest/gtest.h>

#include <string>

#include "core/errors.h"
#include "datasets/scenarios/scenario.h"
#include "tests/test_support.h"

namespace mavloc {
namespace {

Dataset EurocLaser(const std::map<std::string, std::string>& settings) {
  ScenarioOptions options;
  options.seed = 1;
  options.duration_s = 5.0;
  options.settings = settings;
  options.settings["data"] = testing::SharedDataDir() + "/euroc_v1_01_easy";
  return FindScenario("euroc-laser")->generate(options);
}

TEST(EurocLaserNoise, ScaleMultipliesEveryStatedDensity) {
  REQUIRE_SHARED_DATA();
  const ImuNoise stated = EurocLaser({}).imu.noise;
  EXPECT_NEAR(stated.gyroscope_noise_density, 1.6968e-4, 1e-10);  // imu0/sensor.yaml
  EXPECT_NEAR(stated.accelerometer_random_walk, 3.0e-3, 1e-12);
  const Dataset scaled = EurocLaser({{"imu_noise_scale", "3"}});
  EXPECT_DOUBLE_EQ(scaled.imu.noise.gyroscope_noise_density, 3 * stated.gyroscope_noise_density);
  EXPECT_DOUBLE_EQ(scaled.imu.noise.gyroscope_random_walk, 3 * stated.gyroscope_random_walk);
  EXPECT_DOUBLE_EQ(scaled.imu.noise.accelerometer_noise_density,
                   3 * stated.accelerometer_noise_density);
  EXPECT_DOUBLE_EQ(scaled.imu.noise.accelerometer_random_walk,
                   3 * stated.accelerometer_random_walk);
  EXPECT_NE(scaled.scenario_info.at("imu_noise").find("x 3"), std::string::npos);
}

TEST(EurocLaserNoise, ModelFileReplacesTheStatedDensities) {
  REQUIRE_SHARED_DATA();
  const std::string dir = testing::MakeTempDir();
  const std::string path = dir + "/imu.yaml";
  testing::WriteFileBytes(path,
                          "accelerometer_noise_density: 0.02\naccelerometer_random_walk: 0.004\n"
                          "gyroscope_noise_density: 0.002\ngyroscope_random_walk: 0.00004\n"
                          "rostopic: /imu0\nupdate_rate: 200.0\n");
  const ImuNoise noise =
      EurocLaser({{"imu_noise_model", path}, {"imu_noise_scale", "2"}}).imu.noise;
  EXPECT_DOUBLE_EQ(noise.accelerometer_noise_density, 0.04);
  EXPECT_DOUBLE_EQ(noise.accelerometer_random_walk, 0.008);
  EXPECT_DOUBLE_EQ(noise.gyroscope_noise_density, 0.004);
  EXPECT_DOUBLE_EQ(noise.gyroscope_random_walk, 0.00008);
}

TEST(EurocLaserNoise, BadScaleAndFilesWithoutImuAreRefused) {
  REQUIRE_SHARED_DATA();
  for (const char* scale : {"0", "-1", "nan", "1e6"}) {
    try {
      EurocLaser({{"imu_noise_scale", scale}});
      ADD_FAILURE() << scale << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("imu_noise_scale"), std::string::npos) << e.what();
    }
  }
  const std::string dir = testing::MakeTempDir();
  testing::WriteFileBytes(dir + "/target.yaml", "target_type: aprilgrid\ntagCols: 6\n");
  try {
    EurocLaser({{"imu_noise_model", dir + "/target.yaml"}});
    ADD_FAILURE() << "a file without IMU densities accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("target.yaml"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mavloc

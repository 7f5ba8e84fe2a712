// libFuzzer targets for the files of an ASL/EuRoC dataset folder (datasets/io/euroc_io.h), one
// executable per file built from this one object: the program's name (fuzz_euroc_imu_csv, ...,
// kTargets below) picks the file the input becomes, and the whole folder is read with
// ReadEurocDataset. A sensor folder needs both its files, so the other one is written once with
// valid content (as `mavloc simulate` writes it).
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "datasets/io/euroc_io.h"
#include "fuzz/fuzz_support.h"

namespace {

// Program name -> the file of the dataset root the input becomes (fuzz/CMakeLists.txt builds one
// executable per entry).
struct Target {
  const char* program;
  const char* file;
};
constexpr Target kTargets[] = {
    {"fuzz_euroc_imu_csv", "mav0/imu0/data.csv"},
    {"fuzz_euroc_imu_yaml", "mav0/imu0/sensor.yaml"},
    {"fuzz_euroc_camera_csv", "mav0/cam0/data.csv"},
    {"fuzz_euroc_camera_yaml", "mav0/cam0/sensor.yaml"},
    {"fuzz_euroc_ground_truth", "mav0/state_groundtruth_estimate0/data.csv"},
    {"fuzz_euroc_features", "mav0/features0/data.csv"},
    {"fuzz_euroc_laser", "mav0/laser0/data.csv"},
    {"fuzz_euroc_tags", "mav0/tags0/data.csv"},
    {"fuzz_euroc_truth_quantities", "mav0/truth_quantities0/data.csv"},
    {"fuzz_map_yaml", "map.yaml"},
    {"fuzz_scenario_yaml", "scenario.yaml"},
};

std::string g_file;  // set by LLVMFuzzerInitialize

constexpr char kImuSensorYaml[] =
    "sensor_type: imu\n"
    "T_BS:\n  cols: 4\n  rows: 4\n  data: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\n"
    "rate_hz: 100\n"
    "gyroscope_noise_density: 0.00033937\ngyroscope_random_walk: 3.8785e-05\n"
    "accelerometer_noise_density: 0.004\naccelerometer_random_walk: 0.006\n";
constexpr char kImuCsv[] =
    "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
    "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n"
    "1000000000000,0.0006,0.0008,0.002,0.013,0.028,9.85\n"
    "1000010000000,0.0026,-0.006,-0.007,0.063,-0.032,9.89\n";
constexpr char kCameraSensorYaml[] =
    "sensor_type: camera\n"
    "T_BS:\n  cols: 4\n  rows: 4\n  data: [0, -1, 0, 0.05, -1, 0, 0, 0, 0, 0, -1, -0.03, 0, 0, 0, "
    "1]\n"
    "rate_hz: 10\nresolution: [752, 480]\ncamera_model: pinhole\n"
    "intrinsics: [458.654, 457.296, 367.215, 248.375]\n"
    "distortion_model: radial-tangential\n"
    "distortion_coefficients: [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]\n";
constexpr char kCameraCsv[] =
    "#timestamp [ns],filename\n1000000000000,1000000000000.png\n1000100000000,1000100000000.png\n";

// The other file of the fuzzed file's sensor folder.
void WriteCompanion(const std::string& file) {
  if (file == "mav0/imu0/data.csv")
    mavloc::fuzz::WriteScratchFile("dataset/mav0/imu0/sensor.yaml", kImuSensorYaml);
  if (file == "mav0/imu0/sensor.yaml")
    mavloc::fuzz::WriteScratchFile("dataset/mav0/imu0/data.csv", kImuCsv);
  if (file == "mav0/cam0/data.csv")
    mavloc::fuzz::WriteScratchFile("dataset/mav0/cam0/sensor.yaml", kCameraSensorYaml);
  if (file == "mav0/cam0/sensor.yaml")
    mavloc::fuzz::WriteScratchFile("dataset/mav0/cam0/data.csv", kCameraCsv);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** argv) {
  const std::string program = std::filesystem::path((*argv)[0]).filename().string();
  for (const Target& target : kTargets)
    if (program == target.program) g_file = target.file;
  if (g_file.empty()) {
    std::fprintf(stderr, "fuzz: unknown program name %s (see kTargets)\n", program.c_str());
    std::exit(1);
  }
  // ReadEurocDataset refuses a root without mav0/ (map.yaml and scenario.yaml live beside it).
  std::filesystem::create_directories(mavloc::fuzz::ScratchFolder() + "/dataset/mav0");
  WriteCompanion(g_file);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  mavloc::fuzz::WriteScratchFile("dataset/" + g_file, data, size);
  const std::string root = mavloc::fuzz::ScratchFolder() + "/dataset";
  mavloc::fuzz::ExpectInputErrorOnly([&root] { (void)mavloc::ReadEurocDataset(root); });
  return 0;
}

#include "datasets/scenarios/euroc_laser.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

#include "core/errors.h"
#include "core/random.h"
#include "core/rotation.h"
#include "datasets/io/calibration_io.h"
#include "datasets/io/euroc_io.h"
#include "datasets/io/tum_io.h"
#include "datasets/scenarios/laser_plane.h"

namespace mavloc {

namespace {

constexpr const char* kEurocLaser = "euroc-laser";
constexpr const char* kRelativeData = "../shared/data/euroc_v1_01_easy";

std::vector<std::filesystem::path> CandidateDataPaths() {
  namespace fs = std::filesystem;
  std::vector<fs::path> candidates = {fs::current_path() / kRelativeData};
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (!error) {
    for (fs::path dir = exe.parent_path(); !dir.empty(); dir = dir.parent_path()) {
      candidates.push_back(dir / kRelativeData);
      if (dir == dir.root_path()) break;
    }
  }
  return candidates;
}

// Linear interpolation of position, slerp of attitude; clamped at the ends.
Pose InterpolatePose(const std::vector<StampedPose>& poses, TimeNs t) {
  const auto it =
      std::lower_bound(poses.begin(), poses.end(), t,
                       [](const StampedPose& p, TimeNs value) { return p.t_ns < value; });
  if (it == poses.begin()) return poses.front().T_W_B;
  if (it == poses.end()) return poses.back().T_W_B;
  const StampedPose& b = *it;
  const StampedPose& a = *(it - 1);
  const double s = static_cast<double>(t - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  return Pose(a.T_W_B.q.slerp(s, b.T_W_B.q).normalized(), (1 - s) * a.T_W_B.p + s * b.T_W_B.p);
}

}  // namespace

ImuSensor ImuFromGroundTruth(const std::vector<GroundTruthState>& truth) {
  constexpr size_t kHalf = 10;
  ImuSensor imu;
  imu.name = "imu0";
  imu.rate_hz = 200.0;
  imu.noise.gyroscope_noise_density = 1e-4;
  imu.noise.accelerometer_noise_density = 5e-3;
  imu.gyroscope_bias_sigma = 0.0;  // derived from the truth: no bias
  imu.accelerometer_bias_sigma = 0.0;
  for (size_t i = kHalf; i + kHalf < truth.size(); ++i) {
    const double dt1 = NsToSeconds(truth[i + 1].t_ns - truth[i - 1].t_ns);
    const Eigen::Quaterniond dq = truth[i - 1].T_W_B.q.conjugate() * truth[i + 1].T_W_B.q;
    const double h = NsToSeconds(truth[i + kHalf].t_ns - truth[i - kHalf].t_ns) / 2.0;
    const Eigen::Vector3d a_W =
        (truth[i + kHalf].T_W_B.p - 2.0 * truth[i].T_W_B.p + truth[i - kHalf].T_W_B.p) / (h * h);
    ImuSample sample;
    sample.t_ns = truth[i].t_ns;
    sample.gyro_rad_s = LogQuaternion(dq) / dt1;
    sample.accel_m_s2 = truth[i].T_W_B.q.conjugate() * (a_W - GravityW());
    imu.samples.push_back(sample);
  }
  return imu;
}

std::vector<GroundTruthState> EurocGroundTruth(const std::vector<StampedPose>& poses,
                                               const GroundTruthState& bias_source, TimeNs t_begin,
                                               TimeNs t_end) {
  std::vector<GroundTruthState> truth;
  for (size_t i = 0; i < poses.size(); ++i) {
    if (poses[i].t_ns < t_begin || poses[i].t_ns > t_end) continue;
    const size_t lo = i >= 2 ? i - 2 : 0, hi = std::min(poses.size() - 1, i + 2);
    GroundTruthState row;
    row.t_ns = poses[i].t_ns;
    row.T_W_B = poses[i].T_W_B;
    row.v_W =
        (poses[hi].T_W_B.p - poses[lo].T_W_B.p) / NsToSeconds(poses[hi].t_ns - poses[lo].t_ns);
    row.b_g = bias_source.b_g;
    row.b_a = bias_source.b_a;
    truth.push_back(row);
  }
  return truth;
}

std::string FindDefaultEurocLaserData() {
  for (const auto& candidate : CandidateDataPaths()) {
    if (std::filesystem::is_directory(candidate / "mav0")) {
      return std::filesystem::weakly_canonical(candidate).string();
    }
  }
  return "";
}

// The IMU noise model the estimators and the bound take: imu_noise_model=PATH (Kalibr imu.yaml,
// EuRoC sensor.yaml or a yac config: the four densities) in place of the stated one, then every
// density times imu_noise_scale. Returns how it was chosen, for the scenario's info.
std::string ApplyImuNoiseSettings(const ScenarioOptions& options, const std::string& prefix,
                                  ImuNoise* noise) {
  std::string source = "imu0/sensor.yaml (stated)";
  const std::string path = options.GetString("imu_noise_model", "");
  if (!path.empty()) {
    const CalibrationSource calibration = ReadCalibrationSource(path);
    if (!calibration.imu)
      throw InputError(path, 0, "imu_noise_model",
                       prefix +
                           "no IMU noise densities in this file (Kalibr imu.yaml, EuRoC "
                           "imu0/sensor.yaml or a yac config)");
    *noise = calibration.imu->noise;
    source = calibration.imu->from;
  }
  const double scale = options.GetDouble("imu_noise_scale", 1.0);
  if (!(scale > 0.0 && scale <= 1e3))
    throw InputError(prefix + "imu_noise_scale must be in (0, 1000]");
  *noise = ScaledImuNoise(*noise, scale);
  return fmt::format(
      "{}{}: gyro {:.3g} rad/s/sqrt(Hz), {:.3g} rad/s^2/sqrt(Hz); accel {:.3g} m/s^2/sqrt(Hz), "
      "{:.3g} m/s^3/sqrt(Hz)",
      source, scale == 1.0 ? std::string() : fmt::format(" x {:g}", scale),
      noise->gyroscope_noise_density, noise->gyroscope_random_walk,
      noise->accelerometer_noise_density, noise->accelerometer_random_walk);
}

Dataset GenerateEurocLaser(const ScenarioOptions& options) {
  CheckRegisteredScenarioOptions(kEurocLaser, options);
  const std::string prefix = fmt::format("scenario {}: ", kEurocLaser);
  std::string data = options.GetString("data", "");
  if (data.empty()) {
    data = FindDefaultEurocLaserData();
    if (data.empty()) {
      std::string tried;
      for (const auto& c : CandidateDataPaths()) tried += (tried.empty() ? "" : ", ") + c.string();
      throw InputError(prefix + "EuRoC V1_01_easy data not found (set data=PATH); tried " + tried);
    }
  }
  const std::string tum_path = data + "/groundtruth_full_tum.txt";
  if (!std::filesystem::is_directory(data + "/mav0/imu0"))
    throw InputError(data, 0, "data", prefix + "no mav0/imu0 folder in this EuRoC dataset");
  if (!std::filesystem::is_regular_file(tum_path))
    throw InputError(tum_path, 0, "", prefix + "missing: the full ground truth in TUM format");
  const double alpha_deg = options.GetDouble("alpha_deg", 22.5);
  const double L = options.GetDouble("L", 0.3);
  const double clearance_m = options.GetDouble("clearance_m", 0.5);
  const double camera_rate_hz = options.GetDouble("camera_rate_hz", 10.0);
  const double bearing_noise_deg = options.GetDouble("bearing_noise_deg", 1.0);
  const std::string imu_source = options.GetString("imu", "real");
  if (imu_source != "real" && imu_source != "from_ground_truth")
    throw InputError(prefix + "imu must be real or from_ground_truth");
  if (!(alpha_deg >= 0.0 && alpha_deg < 90.0)) throw InputError(prefix + "alpha_deg in [0, 90)");
  if (!(L > 0.0 && clearance_m > L)) throw InputError(prefix + "need 0 < L < clearance_m");
  if (!(camera_rate_hz > 0.0 && bearing_noise_deg >= 0.0))
    throw InputError(prefix + "camera_rate_hz > 0 and bearing_noise_deg >= 0 needed");

  EurocReadOptions read_options;
  read_options.load_cameras = false;
  const Dataset euroc = ReadEurocDataset(data, read_options);
  const std::vector<StampedPose> poses = ReadTumTrajectory(tum_path);
  if (poses.size() < 10) throw InputError(tum_path, 0, "", prefix + "too few poses");

  Dataset d;
  d.name = kEurocLaser;
  d.scenario = kEurocLaser;
  d.root = "";
  d.imu = euroc.imu;
  // Ground truth: T_W_B from the TUM file (B = imu0), v by central differences over +-2 rows.
  const GroundTruthState bias_source =
      euroc.ground_truth.empty() ? GroundTruthState{} : euroc.ground_truth.front();
  d.ground_truth =
      EurocGroundTruth(poses, bias_source, d.imu.samples.front().t_ns, d.imu.samples.back().t_ns);
  if (imu_source == "from_ground_truth") {
    d.imu = ImuFromGroundTruth(d.ground_truth);
    for (auto& row : d.ground_truth) row.b_g = row.b_a = Eigen::Vector3d::Zero();
  }
  const std::string imu_noise = ApplyImuNoiseSettings(options, prefix, &d.imu.noise);

  // The virtual down-looking laser camera at the IMU origin.
  Eigen::Matrix3d R_B_C;
  R_B_C.col(0) = Eigen::Vector3d::UnitY();   // x_C = y_B
  R_B_C.col(1) = -Eigen::Vector3d::UnitZ();  // y_C = -z_B
  R_B_C.col(2) = -Eigen::Vector3d::UnitX();  // z_C = -x_B
  CameraSensor cam0;
  cam0.name = "cam0";
  cam0.rate_hz = camera_rate_hz;
  cam0.model = CameraModel(752, 480, Eigen::Vector4d(300.0, 300.0, 376.0, 240.0));
  cam0.T_B_C = Pose(R_B_C, Eigen::Vector3d::Zero());

  // The plane: normal Rx(alpha) e_z, clearance_m below the lowest camera position.
  const Eigen::Vector3d n_W = Rx(alpha_deg * kDeg).col(2);
  double lowest = 1e18;
  for (const auto& row : d.ground_truth) lowest = std::min(lowest, n_W.dot(row.T_W_B.p));
  const Plane plane{n_W, lowest - clearance_m};
  d.map.plane = plane;
  AddLaserParameters(L, &d.map);
  d.map.parameters["plane_alpha_rad"] = alpha_deg * kDeg;

  std::vector<TimeNs> frame_times;
  const TimeNs period_ns = SecondsToNs(1.0 / camera_rate_hz);
  for (TimeNs t = d.ground_truth.front().t_ns; t <= d.ground_truth.back().t_ns; t += period_ns)
    frame_times.push_back(t);
  for (const TimeNs t : frame_times) cam0.frames.push_back({t, ""});
  const SimulationSeeds seeds = SimulationSeeds::FromMaster(options.seed);
  const LaserStreamsSummary laser =
      AddLaserStreams([&](TimeNs t) { return InterpolatePose(poses, t); }, cam0, frame_times, L,
                      plane, bearing_noise_deg * kDeg, seeds.camera, &d);
  d.cameras.push_back(cam0);
  d.scenario_info = {
      {"scenario", kEurocLaser},
      {"seed", std::to_string(options.seed)},
      {"paper", "Martinelli & Troiani, INRIA RR-7906, 2012, section 5.2"},
      {"data", data},
      {"imu", imu_source == "real"
                  ? "real EuRoC V1_01_easy imu0 (ADIS16448, 200 Hz)"
                  : "derived from the ground truth (no bias; rates from attitude differences, "
                    "accelerations from second differences over +-50 ms)"},
      {"ground_truth",
       "groundtruth_full_tum.txt = T_W_B of the IMU frame (EuRoC state_groundtruth_estimate0); v "
       "by central differences; biases constant, the ASL estimate's first row"},
      {"laser_camera",
       "virtual down-looking camera at the IMU origin: z_C = -x_B, x_C = y_B, y_C = -z_B"},
      {"laser", fmt::format("L = {} m at [L, 0, 0] along z_C", L)},
      {"plane", fmt::format("normal Rx({} deg) e_z, {} m below the lowest camera position",
                            alpha_deg, clearance_m)},
      {"distance_range_m", fmt::format("{:.3f} .. {:.3f}", laser.min_d_m, laser.max_d_m)},
      {"camera_rate_hz", fmt::format("{}", camera_rate_hz)},
      {"bearing_noise_deg", fmt::format("{} per bearing angle", bearing_noise_deg)},
      {"spots_missed", std::to_string(laser.missed)},
      {"imu_noise", imu_noise},
  };
  return d;
}

}  // namespace mavloc

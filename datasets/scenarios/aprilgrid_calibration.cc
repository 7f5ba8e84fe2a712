#include "datasets/scenarios/aprilgrid_calibration.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <sstream>

#include "core/aprilgrid.h"
#include "core/atomic_file.h"
#include "core/board_frame.h"
#include "core/errors.h"
#include "core/image_codec.h"
#include "core/interrupt.h"
#include "core/number_text.h"
#include "core/progress.h"
#include "core/random.h"
#include "core/rotation.h"
#include "core/tag_geometry.h"
#include "datasets/rendering/aprilgrid_renderer.h"
#include "datasets/simulation/bspline.h"
#include "datasets/simulation/imu_simulator.h"
#include "datasets/simulation/trajectory.h"

namespace mavloc {

namespace {

const char* kAprilgridCalibration = "aprilgrid-calibration";
constexpr int kCalibrationSplineDegree = 5;

struct CalibrationSettings {
  double pixel_noise_px = 0.3;
  bool imu_noise = true;
  bool bias = true;
  double time_offset_s = 0.005;
  double extrinsics_error_m = 0.0;
  double extrinsics_error_rad = 0.0;
  double board_roll_rad = 95.0 * kDeg;
  double board_pitch_rad = 10.0 * kDeg;
  double distance_m = 0.9;
  double distance_amplitude_m = 0.3;
  double target_amplitude_m = 0.1;
  double rotation_amplitude_rad = 30.0 * kDeg;
  double control_interval_s = 0.2;
  double camera_rate_hz = 20.0;
  double imu_rate_hz = 200.0;
  bool stereo = true;
};

CalibrationSettings ReadCalibrationSettings(const ScenarioOptions& options) {
  CheckRegisteredScenarioOptions(kAprilgridCalibration, options);
  CalibrationSettings s;
  s.pixel_noise_px = options.GetDouble("pixel_noise_px", s.pixel_noise_px);
  s.imu_noise = options.GetBool("imu_noise", s.imu_noise);
  s.bias = options.GetBool("bias", s.bias);
  s.time_offset_s = options.GetDouble("time_offset_ms", 5.0) * 1e-3;
  s.extrinsics_error_m = options.GetDouble("extrinsics_error_m", 0.0);
  s.extrinsics_error_rad = options.GetDouble("extrinsics_error_deg", 0.0) * kDeg;
  s.board_roll_rad = options.GetDouble("board_roll_deg", 95.0) * kDeg;
  s.board_pitch_rad = options.GetDouble("board_pitch_deg", 10.0) * kDeg;
  s.distance_m = options.GetDouble("distance_m", s.distance_m);
  s.distance_amplitude_m = options.GetDouble("distance_amplitude_m", s.distance_amplitude_m);
  s.target_amplitude_m = options.GetDouble("target_amplitude_m", s.target_amplitude_m);
  s.rotation_amplitude_rad = options.GetDouble("rotation_amplitude_deg", 30.0) * kDeg;
  s.control_interval_s = options.GetDouble("control_interval_s", s.control_interval_s);
  s.camera_rate_hz = options.GetDouble("camera_rate_hz", s.camera_rate_hz);
  s.imu_rate_hz = options.GetDouble("imu_rate_hz", s.imu_rate_hz);
  s.stereo = options.GetBool("stereo", s.stereo);
  const bool valid =
      s.pixel_noise_px >= 0.0 && std::abs(s.time_offset_s) <= 0.05 && s.extrinsics_error_m >= 0.0 &&
      s.extrinsics_error_rad >= 0.0 && std::abs(s.board_pitch_rad) < 80.0 * kDeg &&
      std::abs(s.board_roll_rad) <= M_PI && s.distance_m >= 0.3 && s.distance_amplitude_m >= 0.0 &&
      s.distance_m - s.distance_amplitude_m >= 0.25 && s.target_amplitude_m >= 0.0 &&
      s.rotation_amplitude_rad >= 0.0 && s.rotation_amplitude_rad <= 60.0 * kDeg &&
      s.control_interval_s >= 0.05 && s.control_interval_s <= 1.0 && s.camera_rate_hz > 0.0 &&
      s.camera_rate_hz <= 100.0 && s.imu_rate_hz >= 2.0 * s.camera_rate_hz &&
      s.imu_rate_hz <= 2000.0;
  if (!valid)
    throw InputError(
        std::string("scenario ") + kAprilgridCalibration +
        ": need pixel_noise_px >= 0, |time_offset_ms| <= 50, extrinsics errors >= 0, "
        "|board_pitch_deg| < 80, |board_roll_deg| <= 180, distance_m - distance_amplitude_m >= "
        "0.25, amplitudes >= 0, rotation_amplitude_deg <= 60, 0.05 <= control_interval_s <= 1, "
        "0 < camera_rate_hz <= 100, 2 camera_rate_hz <= imu_rate_hz <= 2000");
  return s;
}

// Body angular velocity of R = Rz(a2) Ry(a1) Rx(a0), and its time derivative.
void EulerRates(const Eigen::Vector3d& a, const Eigen::Vector3d& ad, const Eigen::Vector3d& add,
                Eigen::Vector3d* w, Eigen::Vector3d* wd) {
  const double sf = std::sin(a[0]), cf = std::cos(a[0]);
  const double st = std::sin(a[1]), ct = std::cos(a[1]);
  const double fd = ad[0], td = ad[1], pd = ad[2];
  const double fdd = add[0], tdd = add[1], pdd = add[2];
  *w = Eigen::Vector3d(fd - pd * st, td * cf + pd * ct * sf, -td * sf + pd * ct * cf);
  *wd = Eigen::Vector3d(
      fdd - pdd * st - pd * td * ct,
      tdd * cf - td * fd * sf + pdd * ct * sf - pd * td * st * sf + pd * fd * ct * cf,
      -tdd * sf - td * fd * cf + pdd * ct * cf - pd * td * st * cf - pd * fd * ct * sf);
}

// The waving motion: a 6-D quintic spline x(t) = (angles a0..a2 of R_dev, target offset u, v in
// the board plane, distance offset), mapped to cam0 and then to the body, in W.
class CalibrationMotion : public Trajectory {
 public:
  CalibrationMotion(TimeNs start_ns, double duration_s, const CalibrationSettings& s,
                    const Eigen::Matrix3d& R_W_M, const Eigen::Vector3d& board_centre_M,
                    const Pose& T_B_C0, uint64_t motion_seed)
      : start_ns_(start_ns),
        end_ns_(start_ns + SecondsToNs(duration_s)),
        R_W_M_(R_W_M),
        centre_M_(board_centre_M),
        distance_m_(s.distance_m),
        T_B_C0_(T_B_C0) {
    // Control points every h, covering [-0.5 s, duration + 0.5 s] with margin, sampled from two
    // sinusoids per component (frequencies in [0.15, 0.6] Hz, random phases, amplitudes 0.6 and
    // 0.4 of the component's): a smooth, non-periodic motion that reaches most of its amplitude.
    const double h = s.control_interval_s;
    const double t0 = -0.5 - kCalibrationSplineDegree * h;
    const int segments =
        static_cast<int>(std::ceil((duration_s + 1.0 + 2.0 * kCalibrationSplineDegree * h) / h));
    const int n = segments + kCalibrationSplineDegree;
    Rng rng(motion_seed);
    const double tilt = s.rotation_amplitude_rad / 1.2;
    const Eigen::Matrix<double, 6, 1> amplitude =
        (Eigen::Matrix<double, 6, 1>() << tilt, tilt, s.rotation_amplitude_rad,
         s.target_amplitude_m, s.target_amplitude_m, s.distance_amplitude_m)
            .finished();
    Eigen::MatrixXd control(6, n);
    for (int r = 0; r < 6; ++r) {
      double f[2], phase[2];
      for (int i = 0; i < 2; ++i) {
        f[i] = rng.Uniform(0.15, 0.6);
        phase[i] = rng.Uniform(0.0, 2.0 * M_PI);
      }
      for (int j = 0; j < n; ++j) {
        // Control point j shapes segments j - K .. j: centred at t0 + (j - (K - 1) / 2) h.
        const double t = t0 + (j - 0.5 * (kCalibrationSplineDegree - 1)) * h;
        control(r, j) = amplitude[r] * (0.6 * std::sin(2.0 * M_PI * f[0] * t + phase[0]) +
                                        0.4 * std::sin(2.0 * M_PI * f[1] * t + phase[1]));
      }
    }
    spline_ = std::make_unique<UniformBSpline>(kCalibrationSplineDegree, t0, h, control);
  }

  TimeNs start_ns() const override { return start_ns_; }
  TimeNs end_ns() const override { return end_ns_; }

  // Defined (not clamped) slightly beyond [start, end]: exposures at stamp + t_d near the ends.
  TrajectorySample At(TimeNs t_ns) const override {
    const double t = NsToSeconds(t_ns - start_ns_);
    const Eigen::VectorXd x = spline_->Evaluate(t, 0);
    const Eigen::VectorXd xd = spline_->Evaluate(t, 1);
    const Eigen::VectorXd xdd = spline_->Evaluate(t, 2);
    const Eigen::Vector3d a = x.head<3>(), ad = xd.head<3>(), add = xdd.head<3>();
    // cam0 facing the board: z_C = -z_M, x_C = x_M (Rx(pi)), turned by R_dev.
    const Eigen::Matrix3d R_M_C = Rx(M_PI) * RotationFromEuler({a[0], a[1], a[2]});
    Eigen::Vector3d w_C, wd_C;
    EulerRates(a, ad, add, &w_C, &wd_C);
    const Eigen::Vector3d e = R_M_C.col(2);  // optical axis in M
    const Eigen::Matrix3d W = Skew(w_C);
    const Eigen::Vector3d ed = R_M_C * (W * Eigen::Vector3d::UnitZ());
    const Eigen::Vector3d edd = R_M_C * ((W * W + Skew(wd_C)) * Eigen::Vector3d::UnitZ());
    const Eigen::Vector3d target = centre_M_ + Eigen::Vector3d(x[3], x[4], 0.0);
    const Eigen::Vector3d target_d(xd[3], xd[4], 0.0), target_dd(xdd[3], xdd[4], 0.0);
    const double d = distance_m_ + x[5], dd = xd[5], ddd = xdd[5];
    const Eigen::Vector3d p_M_C = target - d * e;
    const Eigen::Vector3d v_M_C = target_d - dd * e - d * ed;
    const Eigen::Vector3d a_M_C = target_dd - ddd * e - 2.0 * dd * ed - d * edd;
    // The body from cam0: R_M_B = R_M_C R_B_C^T, p_M_B = p_M_C - R_M_B p_B_C.
    const Eigen::Matrix3d R_B_C = T_B_C0_.R();
    const Eigen::Matrix3d R_M_B = R_M_C * R_B_C.transpose();
    const Eigen::Vector3d w_B = R_B_C * w_C, wd_B = R_B_C * wd_C;
    const Eigen::Vector3d& p_B_C = T_B_C0_.p;
    const Eigen::Matrix3d Wb = Skew(w_B);
    TrajectorySample sample;
    sample.t_ns = t_ns;
    sample.p_W = R_W_M_ * (p_M_C - R_M_B * p_B_C);
    sample.v_W = R_W_M_ * (v_M_C - R_M_B * (Wb * p_B_C));
    sample.a_W = R_W_M_ * (a_M_C - R_M_B * ((Wb * Wb + Skew(wd_B)) * p_B_C));
    sample.q_W_B = Eigen::Quaterniond(R_W_M_ * R_M_B).normalized();
    sample.w_B = w_B;
    return sample;
  }

 private:
  TimeNs start_ns_, end_ns_;
  Eigen::Matrix3d R_W_M_;
  Eigen::Vector3d centre_M_;
  double distance_m_;
  Pose T_B_C0_;
  std::unique_ptr<UniformBSpline> spline_;
};

// The truth moved by `meters` and `radians` in random directions.
Pose Perturb(const Pose& T, double meters, double radians, Rng& rng) {
  auto direction = [&rng]() {
    Eigen::Vector3d v = rng.Gaussian3(1.0);
    return v.norm() > 1e-9 ? Eigen::Vector3d(v.normalized()) : Eigen::Vector3d::UnitX();
  };
  const Eigen::Vector3d dp = meters * direction();
  const Eigen::Vector3d dtheta = radians * direction();
  return Pose((T.q * ExpQuaternion(dtheta)).normalized(), T.p + dp);
}

std::string PoseText(const Pose& T) {
  const Eigen::Quaterniond q = T.q.normalized();
  return fmt::format("{:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g}", T.p.x(), T.p.y(),
                     T.p.z(), q.w(), q.x(), q.y(), q.z());
}

// The `count` blank-separated numbers of a scenario_info value (PoseText, "x y z"), each read
// whole; InputError naming scenario.yaml and the key otherwise.
std::vector<double> NumbersOfSetting(const std::string& text, size_t count,
                                     const std::string& key) {
  std::vector<double> values;
  std::istringstream words(text);
  std::string word;
  while (words >> word) {
    const ParsedNumber<double> value = ParseDoubleText(word);
    if (!value.ok()) throw InputError("scenario.yaml", 0, key, DescribeNumberText(word, value));
    values.push_back(value.value);
  }
  if (values.size() != count)
    throw InputError(
        "scenario.yaml", 0, key,
        fmt::format("expected {} numbers, found {} in '{}'", count, values.size(), text));
  return values;
}

Pose PoseFromText(const std::string& text, const std::string& key) {
  const std::vector<double> v = NumbersOfSetting(text, 7, key);
  return Pose(QuaternionFromWxyz(v[3], v[4], v[5], v[6]).normalized(),
              Eigen::Vector3d(v[0], v[1], v[2]));
}

// Corners of every tag the camera sees fully, from the exposure pose T_M_C.
std::vector<TagObservation> ObserveTags(const CameraSensor& camera, int camera_index,
                                        const Pose& T_M_C, const std::map<int, TagInfo>& tags,
                                        TimeNs stamp_ns, double noise_px, Rng& rng) {
  std::vector<TagObservation> out;
  const Pose T_C_M = T_M_C.Inverse();
  // The board faces the camera: the camera centre on +z_M, within 75 deg of the normal.
  for (const auto& [id, tag] : tags) {
    const Eigen::Vector3d to_camera = T_M_C.p - tag.T_W_T.p;
    if (!(to_camera.z() > std::cos(75.0 * kDeg) * to_camera.norm())) continue;
    const auto corners_M = TagCornersInWorld(tag);
    std::array<Eigen::Vector2d, 4> uv;
    bool visible = true;
    for (int k = 0; k < 4 && visible; ++k) {
      const auto projected = camera.model.Project(T_C_M * corners_M[k], 0.05);
      if (!projected || !camera.model.IsInside(*projected, 2.0)) visible = false;
      if (projected) uv[k] = *projected;
    }
    if (!visible) continue;
    TagObservation obs;
    obs.t_ns = stamp_ns;
    obs.tag_id = id;
    obs.camera = camera_index;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector2d noise{rng.Gaussian(), rng.Gaussian()};
      obs.corners_px[k] = uv[k] + noise_px * noise;
    }
    out.push_back(obs);
  }
  return out;
}

}  // namespace

CameraModel EurocCam1Model() {
  return CameraModel(752, 480, Eigen::Vector4d(457.587, 456.134, 379.999, 255.238),
                     DistortionModel::kRadialTangential,
                     {-0.28368365, 0.07451284, -0.00010473, -3.55590700e-05});
}

Pose EurocCameraExtrinsic(int camera_index) {
  Eigen::Matrix4d T;
  if (camera_index == 0) {
    T << 0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975, 0.999557249008,
        0.0149672133247, 0.025715529948, -0.064676986768, -0.0257744366974, 0.00375618835797,
        0.999660727178, 0.00981073058949, 0.0, 0.0, 0.0, 1.0;
  } else {
    T << 0.0125552670891, -0.999755099723, 0.0182237714554, -0.0198435579556, 0.999598781151,
        0.0130119051815, 0.0251588363115, 0.0453689425024, -0.0253898008918, 0.0179005838253,
        0.999517347078, 0.00786212447038, 0.0, 0.0, 0.0, 1.0;
  }
  // The files print 12 digits: project onto SO(3).
  return Pose(Eigen::Matrix3d(NearestRotation(T.topLeftCorner<3, 3>())),
              Eigen::Vector3d(T.topRightCorner<3, 1>()));
}

Dataset GenerateAprilgridCalibration(const ScenarioOptions& options) {
  const double duration_s = options.duration_s.value_or(30.0);
  if (!(duration_s >= 3.0))
    throw InputError(std::string("scenario ") + kAprilgridCalibration +
                     ": --duration must be >= 3 s");
  const CalibrationSettings s = ReadCalibrationSettings(options);
  const SimulationSeeds seeds = SimulationSeeds::FromMaster(options.seed);

  AprilgridTarget target;
  target.tag_rows = 6;
  target.tag_cols = 6;
  target.tag_size_m = 0.088;
  target.tag_spacing = 0.3;
  const double extent = target.tag_cols * target.tag_size_m +
                        (target.tag_cols - 1) * target.tag_spacing * target.tag_size_m;
  const Eigen::Vector3d centre_M(0.5 * extent, 0.5 * extent, 0.0);

  // The board's tilt, and the W of core/board_frame.h for that gravity direction.
  const Eigen::Matrix3d R_W_M_tilted = Ry(s.board_pitch_rad) * Rx(s.board_roll_rad);
  const Eigen::Vector3d up_M = UpInBoard(R_W_M_tilted);
  const Eigen::Matrix3d R_W_M = BoardToWorldRotation(up_M);
  const BoardTilt tilt = BoardTiltFromUp(up_M);

  const Pose T_B_C_true[2] = {EurocCameraExtrinsic(0), EurocCameraExtrinsic(1)};
  const CalibrationMotion motion(kScenarioStartNs, duration_s, s, R_W_M, centre_M, T_B_C_true[0],
                                 seeds.motion);

  Dataset d;
  d.name = kAprilgridCalibration;
  d.scenario = kAprilgridCalibration;
  d.map.frame = MapFrame::kBoard;
  d.map.tags = AprilgridTags(target);

  ImuSimulationOptions imu_options =
      EurocLikeImuOptions(s.imu_rate_hz, s.imu_noise, s.bias, SplitMix64(seeds.other + 1));
  AddSimulatedImu(motion, imu_options, seeds.imu, &d);

  // Cameras: what the dataset states (perturbed extrinsics) and the frames.
  Rng perturbation_rng(SplitMix64(seeds.other + 2));
  const int num_cameras = s.stereo ? 2 : 1;
  const TimeNs period_ns = SecondsToNs(1.0 / s.camera_rate_hz);
  std::vector<TimeNs> stamps;
  for (TimeNs t = motion.start_ns() + SecondsToNs(0.05); t <= motion.end_ns() - SecondsToNs(0.05);
       t += period_ns)
    stamps.push_back(t);
  for (int c = 0; c < num_cameras; ++c) {
    CameraSensor camera;
    camera.name = "cam" + std::to_string(c);
    camera.rate_hz = s.camera_rate_hz;
    camera.model = c == 0 ? EurocCam0Model() : EurocCam1Model();
    camera.T_B_C =
        Perturb(T_B_C_true[c], s.extrinsics_error_m, s.extrinsics_error_rad, perturbation_rng);
    for (const TimeNs t : stamps) camera.frames.push_back({t, ""});
    d.cameras.push_back(camera);
  }

  // Corners seen at the exposure time stamp + t_d, through the true extrinsics.
  Rng camera_rng(seeds.camera);
  const Pose T_M_W(Eigen::Matrix3d(R_W_M.transpose()), Eigen::Vector3d::Zero());
  for (const TimeNs t : stamps) {
    const Pose T_M_B = T_M_W * motion.At(t + SecondsToNs(s.time_offset_s)).T_W_B();
    for (int c = 0; c < num_cameras; ++c) {
      auto observations = ObserveTags(d.cameras[c], c, T_M_B * T_B_C_true[c], d.map.tags, t,
                                      s.pixel_noise_px, camera_rng);
      auto& stream = c == 0 ? d.tags : d.tags1;
      stream.insert(stream.end(), observations.begin(), observations.end());
    }
  }

  // --render: each camera's images of the grid at the exposure time (then `mavloc detect-tags
  // --family aprilgrid` measures the corners from them), in options.image_dir (the simulate
  // command's scratch folder, copied by the dataset writer) or a temporary folder.
  if (options.render_images) {
    const std::string folder = !options.image_dir.empty()
                                   ? options.image_dir
                                   : (std::filesystem::temp_directory_path() /
                                      fmt::format("mavloc_render_{}_{}_{}", kAprilgridCalibration,
                                                  options.seed, static_cast<long>(getpid())))
                                         .string();
    std::error_code error;
    CreateOutputDirectories(folder, error);
    if (error) throw InputError(folder, 0, "", "cannot create folder: " + error.message());
    const Pose T_W_M(R_W_M, Eigen::Vector3d::Zero());
    for (int c = 0; c < num_cameras; ++c) {
      TagRenderOptions render_options;
      render_options.noise_sigma_grey = 1.0;
      const TagRenderer renderer =
          MakeAprilgridRenderer(d.cameras[c].model, target, T_W_M, render_options);
      for (size_t i = 0; i < d.cameras[c].frames.size(); ++i) {
        CameraFrame& frame = d.cameras[c].frames[i];
        const Pose T_W_C =
            motion.At(frame.t_ns + SecondsToNs(s.time_offset_s)).T_W_B() * T_B_C_true[c];
        const cv::Mat image = renderer.Render({T_W_C}, SplitMix64(seeds.camera + 7919 * i + c));
        frame.image_path =
            (std::filesystem::path(folder) / fmt::format("cam{}_{}.png", c, frame.t_ns)).string();
        WriteFileAtomically(frame.image_path, EncodePng(image));
        if (i % 50 == 0)
          ReportProgress("render", fmt::format("{} cam{} frame {}/{}", kAprilgridCalibration, c,
                                               i + 1, d.cameras[c].frames.size()));
      }
    }
  }

  d.truth_quantities = QuantityTable({"board_roll", "board_pitch"}, {"rad", "rad"});
  for (const TimeNs t : stamps) d.truth_quantities.Append(t, {tilt.roll_rad, tilt.pitch_rad});

  d.scenario_info = {
      {"seed", std::to_string(options.seed)},
      {"duration_s", fmt::format("{}", duration_s)},
      {"imu_rate_hz", fmt::format("{}", s.imu_rate_hz)},
      {"camera_rate_hz", fmt::format("{}", s.camera_rate_hz)},
      {"pixel_noise_px", fmt::format("{}", s.pixel_noise_px)},
      {"imu_noise", s.imu_noise ? "EuRoC ADIS16448 densities" : "none"},
      {"bias",
       s.bias ? "turn-on N(0, 0.002 rad/s), N(0, 0.05 m/s^2), random walk with noise" : "none"},
      {"time_offset_s", fmt::format("{:.17g}", s.time_offset_s)},
      {"cam0_T_B_C_true", PoseText(T_B_C_true[0])},
      {"cam1_T_B_C_true", PoseText(T_B_C_true[1])},
      {"extrinsics_error", fmt::format("{} m, {} deg (sensor.yaml T_BS = truth moved by these)",
                                       s.extrinsics_error_m, s.extrinsics_error_rad / kDeg)},
      {"board_roll_deg", fmt::format("{:.17g}", tilt.roll_rad / kDeg)},
      {"board_pitch_deg", fmt::format("{:.17g}", tilt.pitch_rad / kDeg)},
      {"board_up_M", fmt::format("{:.17g} {:.17g} {:.17g}", up_M.x(), up_M.y(), up_M.z())},
      {"target", "aprilgrid 6 x 6, tag 0.088 m, spacing 0.3 (map.yaml frame: board)"},
      {"motion", fmt::format("waved in front of the board at {} +- {} m, +-{} deg, target +-{} m, "
                             "control points every {} s",
                             s.distance_m, s.distance_amplitude_m, s.rotation_amplitude_rad / kDeg,
                             s.target_amplitude_m, s.control_interval_s)},
      {"cameras", s.stereo ? "cam0, cam1 (EuRoC), shared stamps" : "cam0 (EuRoC)"},
  };
  return d;
}

std::optional<AprilgridCalibrationTruth> AprilgridCalibrationTruthOf(const Dataset& dataset) {
  const auto& info = dataset.scenario_info;
  auto get = [&](const std::string& key) -> std::optional<std::string> {
    auto it = info.find(key);
    return it == info.end() ? std::nullopt : std::optional<std::string>(it->second);
  };
  const auto cam0 = get("cam0_T_B_C_true"), cam1 = get("cam1_T_B_C_true");
  const auto offset = get("time_offset_s"), up = get("board_up_M");
  if (!cam0 || !cam1 || !offset || !up) return std::nullopt;
  // A dataset carrying the keys carries the truth: a value that is not its numbers is an error,
  // never "no truth".
  AprilgridCalibrationTruth truth;
  truth.T_B_C[0] = PoseFromText(*cam0, "cam0_T_B_C_true");
  truth.T_B_C[1] = PoseFromText(*cam1, "cam1_T_B_C_true");
  const std::vector<double> up_M = NumbersOfSetting(*up, 3, "board_up_M");
  truth.up_M = Eigen::Vector3d(up_M[0], up_M[1], up_M[2]);
  truth.time_offset_s = NumbersOfSetting(*offset, 1, "time_offset_s")[0];
  return truth;
}

}  // namespace mavloc

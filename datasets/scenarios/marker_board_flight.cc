#include "datasets/scenarios/marker_board_flight.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "core/errors.h"
#include "core/random.h"
#include "core/rotation.h"
#include "core/tag_geometry.h"
#include "datasets/simulation/camera_simulator.h"
#include "datasets/simulation/imu_simulator.h"
#include "datasets/simulation/spline_trajectory.h"

namespace mavloc {

namespace {

void Require(bool condition, const std::string& message) {
  if (!condition) throw InputError("scenario marker-board-flight: " + message);
}

// Take-off at A, rectangle A-B-C-D-A, crossings A-C, C-D, D-B, hover above B, landing at B.
std::vector<Waypoint> FlightWaypoints(double altitude_m, double speed_m_s, double yaw_start_rad,
                                      double yaw_end_rad) {
  const double ground_z = 0.1;  // body origin on the landing gear
  const Eigen::Vector2d A(0, 0), B(3, 0), C(3, 2), D(0, 2);
  struct Leg {
    Eigen::Vector3d p;
    double duration_s;  // to reach p from the previous waypoint (0 = computed from speed)
  };
  const auto at = [&](const Eigen::Vector2d& xy, double z) {
    return Eigen::Vector3d(xy.x(), xy.y(), z);
  };
  const std::vector<Leg> legs = {
      {at(A, ground_z), 0.0},   {at(A, ground_z), 1.0},    // on the ground
      {at(A, altitude_m), 3.0}, {at(A, altitude_m), 1.0},  // take-off, settle
      {at(B, altitude_m), -1},  {at(C, altitude_m), -1},  {at(D, altitude_m), -1},
      {at(A, altitude_m), -1},  {at(C, altitude_m), -1},  {at(D, altitude_m), -1},
      {at(B, altitude_m), -1},  {at(B, altitude_m), 3.0},  // hover
      {at(B, ground_z), 3.0},   {at(B, ground_z), 1.0},    // landing, on the ground
  };
  std::vector<Waypoint> waypoints;
  double t = 0.0;
  for (size_t i = 0; i < legs.size(); ++i) {
    if (i > 0) {
      const double d = (legs[i].p - legs[i - 1].p).norm();
      t += legs[i].duration_s >= 0.0 ? legs[i].duration_s : d / speed_m_s;
    }
    Waypoint wp;
    wp.t_s = t;
    wp.p_W = legs[i].p;
    waypoints.push_back(wp);
  }
  for (auto& wp : waypoints)
    wp.yaw_rad = WrapAngle(yaw_start_rad + (yaw_end_rad - yaw_start_rad) * wp.t_s / t);
  return waypoints;
}

// Waypoints cut at t_end (the last one interpolated).
std::vector<Waypoint> TruncateWaypoints(const std::vector<Waypoint>& waypoints, double t_end_s) {
  std::vector<Waypoint> out;
  for (size_t i = 0; i < waypoints.size(); ++i) {
    if (waypoints[i].t_s <= t_end_s) {
      out.push_back(waypoints[i]);
      continue;
    }
    const Waypoint& a = waypoints[i - 1];
    const Waypoint& b = waypoints[i];
    const double u = (t_end_s - a.t_s) / (b.t_s - a.t_s);
    Waypoint cut = a;
    cut.t_s = t_end_s;
    cut.p_W = a.p_W + u * (b.p_W - a.p_W);
    cut.yaw_rad = WrapAngle(a.yaw_rad + u * WrapAngle(b.yaw_rad - a.yaw_rad));
    if (t_end_s > a.t_s) out.push_back(cut);
    break;
  }
  return out;
}

}  // namespace

Dataset GenerateMarkerBoardFlight(const ScenarioOptions& options) {
  const double altitude_m = options.GetDouble("altitude_m", 1.2);
  const double speed_m_s = options.GetDouble("speed_m_s", 0.5);
  const double yaw_start_deg = options.GetDouble("yaw_start_deg", 150.0);
  const double yaw_end_deg = options.GetDouble("yaw_end_deg", 210.0);
  const double marker_size_m = options.GetDouble("marker_size_m", 0.2);
  const double marker_spacing_m = options.GetDouble("marker_spacing_m", 0.6);
  const double camera_rate_hz = options.GetDouble("camera_rate_hz", 30.0);
  const double imu_rate_hz = options.GetDouble("imu_rate_hz", 200.0);
  const double pixel_noise_px = options.GetDouble("pixel_noise_px", 1.0);
  const int max_markers = options.GetInt("max_markers", 0);
  const double outlier_fraction = options.GetDouble("outlier_fraction", 0.0);
  const double outlier_min_px = options.GetDouble("outlier_min_px", 20.0);
  const double outlier_max_px = options.GetDouble("outlier_max_px", 60.0);
  const double drop_fraction = options.GetDouble("frame_drop_fraction", 0.0);
  const std::string stamping = options.GetString("image_stamping", "exposure");
  const double delay_min_ms = options.GetDouble("transfer_delay_min_ms", 16.0);
  const double delay_max_ms = options.GetDouble("transfer_delay_max_ms", 19.0);
  const bool imu_noise = options.GetBool("imu_noise", true);
  const bool bias = options.GetBool("bias", true);
  Require(altitude_m >= 0.3, "altitude_m must be >= 0.3");
  Require(speed_m_s > 0.0, "speed_m_s must be > 0");
  Require(marker_size_m > 0.0 && marker_spacing_m > marker_size_m,
          "need 0 < marker_size_m < marker_spacing_m");
  Require(camera_rate_hz > 0.0 && imu_rate_hz > 0.0, "rates must be > 0");
  Require(pixel_noise_px >= 0.0, "pixel_noise_px must be >= 0");
  Require(max_markers >= 0, "max_markers must be >= 0 (0 = all)");
  Require(outlier_fraction >= 0.0 && outlier_fraction <= 1.0, "outlier_fraction must be in [0, 1]");
  Require(outlier_min_px >= 0.0 && outlier_max_px >= outlier_min_px,
          "need 0 <= outlier_min_px <= outlier_max_px");
  Require(drop_fraction >= 0.0 && drop_fraction < 1.0, "frame_drop_fraction must be in [0, 1)");
  Require(stamping == "exposure" || stamping == "arrival",
          "image_stamping must be 'exposure' or 'arrival'");
  Require(
      delay_min_ms >= 0.0 && delay_max_ms >= delay_min_ms && delay_max_ms < 1000.0 / camera_rate_hz,
      "need 0 <= transfer_delay_min_ms <= transfer_delay_max_ms < frame period");
  const SimulationSeeds seeds = SimulationSeeds::FromMaster(options.seed);

  std::vector<Waypoint> waypoints =
      FlightWaypoints(altitude_m, speed_m_s, yaw_start_deg * kDeg, yaw_end_deg * kDeg);
  if (options.duration_s) {
    Require(*options.duration_s >= 1.0, "--duration must be >= 1 s");
    waypoints = TruncateWaypoints(waypoints, *options.duration_s);
  }
  const auto trajectory =
      SplineTrajectory::FromWaypoints(kScenarioStartNs, waypoints, AttitudeMode::kQuadrotor, 0.5);

  Dataset d;
  d.scenario = "marker-board-flight";
  d.name = "marker-board-flight";

  const ImuSimulationOptions imu_options =
      EurocLikeImuOptions(imu_rate_hz, imu_noise, bias, seeds.other);
  AddSimulatedImu(*trajectory, imu_options, seeds.imu, &d);

  // The marker board: a grid over the flight area plus a margin.
  int next_id = 0;
  for (double y = -1.2; y <= 3.2 + 1e-9; y += marker_spacing_m) {
    for (double x = -1.2; x <= 4.2 + 1e-9; x += marker_spacing_m) {
      TagInfo tag;
      tag.id = next_id++;
      tag.size_m = marker_size_m;
      tag.T_W_T = Pose(Eigen::Quaterniond::Identity(), Eigen::Vector3d(x, y, 0.0));
      d.map.tags[tag.id] = tag;
    }
  }

  CameraSensor cam0;
  cam0.name = "cam0";
  cam0.rate_hz = camera_rate_hz;
  cam0.model = CameraModel(640, 480, Eigen::Vector4d(420.0, 420.0, 319.5, 239.5),
                           DistortionModel::kRadialTangential, {-0.08, 0.012, 0.0002, -0.0001});
  // Down-looking: optical axis along -z_B, image x along x_B, image y along -y_B.
  cam0.T_B_C = Pose(Eigen::Matrix3d(Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal()),
                    Eigen::Vector3d(0.03, 0.0, -0.05));

  Rng noise_rng(seeds.camera);
  Rng outlier_rng(SplitMix64(seeds.other + 1));
  Rng drop_rng(SplitMix64(seeds.other + 2));
  Rng delay_rng(SplitMix64(seeds.other + 3));
  const bool arrival = stamping == "arrival";
  d.truth_quantities = QuantityTable({"image_delay"}, {"s"});
  const Eigen::Vector2d centre(cam0.model.cu(), cam0.model.cv());
  for (const TimeNs t_exposure : CameraFrameTimes(*trajectory, camera_rate_hz)) {
    // Draw every random number of a frame whether or not it is used, so that the settings do not
    // shift the streams of other frames.
    const bool dropped = drop_rng.Uniform() < drop_fraction;
    const double delay_s = 1e-3 * delay_rng.Uniform(delay_min_ms, delay_max_ms);
    const TimeNs t_stamp = arrival ? t_exposure + SecondsToNs(delay_s) : t_exposure;
    const Pose T_C_W = (trajectory->At(t_exposure).T_W_B() * cam0.T_B_C).Inverse();
    struct Seen {
      TagObservation obs;
      double centre_distance_px;
    };
    std::vector<Seen> seen;
    for (const auto& [id, tag] : d.map.tags) {
      Seen s;
      s.obs.t_ns = t_stamp;
      s.obs.tag_id = id;
      bool visible = true;
      const auto corners_W = TagCornersInWorld(tag);
      Eigen::Vector2d mean = Eigen::Vector2d::Zero();
      for (int k = 0; k < 4 && visible; ++k) {
        const Eigen::Vector3d p_C = T_C_W * corners_W[k];
        const auto uv = cam0.model.Project(p_C, 0.05);
        visible = uv && cam0.model.IsInside(*uv, 1.0);
        if (visible) {
          s.obs.corners_px[k] = *uv;
          mean += 0.25 * *uv;
        }
      }
      if (!visible) continue;
      s.centre_distance_px = (mean - centre).norm();
      seen.push_back(s);
    }
    if (max_markers > 0 && static_cast<int>(seen.size()) > max_markers) {
      std::stable_sort(seen.begin(), seen.end(), [](const Seen& a, const Seen& b) {
        return a.centre_distance_px < b.centre_distance_px;
      });
      seen.resize(max_markers);
      std::stable_sort(seen.begin(), seen.end(),
                       [](const Seen& a, const Seen& b) { return a.obs.tag_id < b.obs.tag_id; });
    }
    for (auto& s : seen) {
      for (auto& corner : s.obs.corners_px) {
        corner += pixel_noise_px * noise_rng.GaussianVector<2>();
        const double u = outlier_rng.Uniform();
        const double angle = outlier_rng.Uniform(-M_PI, M_PI);
        const double magnitude = outlier_rng.Uniform(outlier_min_px, outlier_max_px);
        if (u < outlier_fraction)
          corner += magnitude * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      }
    }
    if (dropped) continue;
    cam0.frames.push_back({t_stamp, ""});
    d.truth_quantities.Append(t_stamp, {arrival ? delay_s : 0.0});
    for (const auto& s : seen) d.tags.push_back(s.obs);
  }
  d.cameras.push_back(cam0);

  d.scenario_info = {
      {"seed", std::to_string(options.seed)},
      {"duration_s", fmt::format("{}", NsToSeconds(trajectory->end_ns() - trajectory->start_ns()))},
      {"path", fmt::format("take-off at (0,0), rectangle 3 m x 2 m and two diagonals at {} m, "
                           "{} m/s, hover, landing at (3,0)",
                           altitude_m, speed_m_s)},
      {"yaw_deg", fmt::format("{} to {}", yaw_start_deg, yaw_end_deg)},
      {"markers", fmt::format("{} on the floor, {} m, spacing {} m", d.map.tags.size(),
                              marker_size_m, marker_spacing_m)},
      {"camera_rate_hz", fmt::format("{}", camera_rate_hz)},
      {"imu_rate_hz", fmt::format("{}", imu_rate_hz)},
      {"pixel_noise_px", fmt::format("{}", pixel_noise_px)},
      {"max_markers", max_markers == 0 ? "all" : std::to_string(max_markers)},
      {"outlier_fraction", fmt::format("{}", outlier_fraction)},
      {"outlier_px", fmt::format("{} to {}", outlier_min_px, outlier_max_px)},
      {"frame_drop_fraction", fmt::format("{}", drop_fraction)},
      {"image_stamping", stamping},
      {"transfer_delay_ms", arrival ? fmt::format("{} to {}", delay_min_ms, delay_max_ms) : "0"},
      {"imu_noise", imu_noise ? "EuRoC ADIS16448 densities" : "none"},
      {"bias", bias ? "random initial bias, random walk" : "none"},
  };
  return d;
}

}  // namespace mavloc

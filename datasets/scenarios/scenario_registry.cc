// The list of synthetic scenarios, in the order `mavloc list` shows them. Adding a scenario is one
// entry here.
#include "datasets/scenarios/aprilgrid_calibration.h"
#include "datasets/scenarios/euroc_laser.h"
#include "datasets/scenarios/euroc_vision.h"
#include "datasets/scenarios/figure_eight.h"
#include "datasets/scenarios/laser_plane.h"
#include "datasets/scenarios/marker_board_flight.h"
#include "datasets/scenarios/scenario.h"
#include "datasets/scenarios/stereo_obstacles.h"
#include "datasets/scenarios/tag_arena.h"
#include "datasets/scenarios/textured_room_frames.h"
#include "datasets/scenarios/three_point_hover.h"

namespace mavloc {

namespace {

// An entry whose generate checks the options (CheckScenarioOptions: unknown keys, duration and
// rate limits) before generating, and hands the declared keys to the getters.
ScenarioEntry Entry(std::string name, std::string description, std::set<std::string> settings,
                    Dataset (*generate)(const ScenarioOptions&)) {
  ScenarioEntry entry{std::move(name), std::move(description), std::move(settings), nullptr};
  auto declared = std::make_shared<const std::set<std::string>>(entry.settings);
  entry.generate = [checked = entry, declared, generate](const ScenarioOptions& options) {
    CheckScenarioOptions(checked, options);
    ScenarioOptions tracked = options;
    tracked.declared_settings = declared;
    return generate(tracked);
  };
  return entry;
}

ScenarioEntry ImageEntry(ScenarioEntry entry) {
  entry.measures_by_images = true;
  return entry;
}

// Settings shared by several scenarios.
const std::set<std::string> kTagArenaSettings = {
    "blur_samples",     "camera_offset_s", "corner_noise_px",    "exposure_s",     "image_dir",
    "image_noise_grey", "imu_noise",       "processing_delay_s", "projected_tags", "supersampling"};

std::set<std::string> With(std::set<std::string> keys, const std::set<std::string>& more) {
  keys.insert(more.begin(), more.end());
  return keys;
}

}  // namespace

const std::vector<ScenarioEntry>& ScenarioRegistry() {
  static const std::vector<ScenarioEntry> kEntries = {
      Entry("mav-figure-eight",
            "default: quadrotor figure-eight in a room of known landmarks; IMU 200 Hz, cam0 20 Hz, "
            "1 px",
            {"imu_rate_hz", "camera_rate_hz", "pixel_noise_px", "landmarks", "imu_noise", "bias"},
            GenerateFigureEight),
      Entry(
          "tag-arena-hover",
          "AprilTag paper V-B: hover over 21 floor tags; IMU 100 Hz, cam0 10 Hz (--render: images)",
          With(kTagArenaSettings, {"hover_height_m"}), GenerateTagArenaHover),
      Entry("tag-arena-dynamic",
            "AprilTag paper V-C: take-off from (0, 0, 0.08) m, fast-turn loop over 21 floor tags",
            kTagArenaSettings, GenerateTagArenaDynamic),
      Entry(
          "three-point-hover",
          "three-point paper V-A: hover over 3 ground features, D = 0.1 m; IMU 100 Hz, cam0 0.3 s",
          {"D",
           "p3_x",
           "p3_y",
           "start_x",
           "start_y",
           "start_z",
           "start_yaw_deg",
           "goal_x",
           "goal_y",
           "goal_z",
           "goal_yaw_deg",
           "move_start_s",
           "move_end_s",
           "imu_rate_hz",
           "gyro_sigma_deg_s",
           "accel_sigma_m_s2",
           "gyro_bias_deg_s",
           "accel_bias_m_s2",
           "camera_period_s",
           "bearing_noise_deg"},
          GenerateThreePointHover),
      Entry(
          "stereo-obstacles",
          "PIXHAWK 7.3: stereo pair flies past boxes and cylinders in a textured room (--render)",
          {"camera_rate_hz", "image_noise_grey", "image_dir", "imu_noise", "cam1_misalignment_deg"},
          GenerateStereoObstacles),
      Entry(
          "marker-board-flight",
          "PIXHAWK 7.2: marker board on the floor, rectangle + crossings; IMU 200 Hz, cam0 30 Hz, "
          "1 px",
          {"altitude_m", "speed_m_s", "yaw_start_deg", "yaw_end_deg", "marker_size_m",
           "marker_spacing_m", "camera_rate_hz", "imu_rate_hz", "pixel_noise_px", "max_markers",
           "outlier_fraction", "outlier_min_px", "outlier_max_px", "frame_drop_fraction",
           "image_stamping", "transfer_delay_min_ms", "transfer_delay_max_ms", "imu_noise", "bias"},
          GenerateMarkerBoardFlight),
      Entry(
          "laser-plane",
          "laser paper 5.1: laser spot on a plane at 22.5 deg, random motion; IMU 100 Hz, spot 10 "
          "Hz",
          {"alpha_deg", "L", "distance_m", "speed_m_s", "sigma_accel", "sigma_rate_deg_s",
           "correlation_time_s", "tilt_deg", "imu_rate_hz", "gyro_sigma_deg_s", "accel_sigma_m_s2",
           "bias", "gyro_bias_deg_s", "accel_bias_m_s2", "camera_rate_hz", "bearing_noise_deg"},
          GenerateLaserPlane),
      Entry("euroc-laser",
            "laser paper 5.2: real EuRoC V1_01_easy IMU + ground truth, simulated laser spot at 10 "
            "Hz",
            {"data", "alpha_deg", "L", "clearance_m", "camera_rate_hz", "bearing_noise_deg", "imu",
             "imu_noise_model", "imu_noise_scale"},
            GenerateEurocLaser),
      ImageEntry(Entry(
          "euroc-vision",
          "real EuRoC V1_01_easy IMU + ground truth, cam0/cam1 rendered at 20 Hz in "
          "a room painted with photographs (natural features)",
          With(TexturedFrameSettingKeys(),
               {"data", "cameras", "camera_rate_hz", "image_scale", "imu", "texel_m", "start_s"}),
          GenerateEurocVision)),
      Entry("aprilgrid-calibration",
            "stereo rig waved before a tilted 6x6 aprilgrid (board map), "
            "known T_B_C and time offset; IMU 200 Hz, cams 20 Hz",
            {"pixel_noise_px", "imu_noise", "bias", "time_offset_ms", "extrinsics_error_m",
             "extrinsics_error_deg", "board_roll_deg", "board_pitch_deg", "distance_m",
             "distance_amplitude_m", "target_amplitude_m", "rotation_amplitude_deg",
             "control_interval_s", "camera_rate_hz", "imu_rate_hz", "stereo"},
            GenerateAprilgridCalibration),
  };
  return kEntries;
}

}  // namespace mavloc

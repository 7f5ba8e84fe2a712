// The in-memory dataset every estimator consumes: the EuRoC/ASL streams plus mavloc's extension
// streams (DESIGN.md, "Datasets on disk"). Pure data: reading and writing live in datasets/.
#pragma once

#include <Eigen/Core>
#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/camera_model.h"
#include "core/imu.h"
#include "core/pose.h"
#include "core/quantities.h"
#include "core/time.h"

namespace mavloc {

// One row of state_groundtruth_estimate0 (EuRoC columns): the pose of B (= IMU) in W, its velocity
// in W and the IMU biases.
struct GroundTruthState {
  TimeNs t_ns = 0;
  Pose T_W_B;
  Eigen::Vector3d v_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d b_g = Eigen::Vector3d::Zero();  // gyro bias, rad/s
  Eigen::Vector3d b_a = Eigen::Vector3d::Zero();  // accelerometer bias, m/s^2
};

struct ImuSensor {
  std::string name = "imu0";
  Pose T_B_S;  // sensor frame in B (identity for EuRoC's imu0)
  double rate_hz = 0.0;
  ImuNoise noise;
  // Turn-on bias standard deviation per axis, as the dataset states it (sensor.yaml keys
  // gyroscope_bias_sigma [rad/s] and accelerometer_bias_sigma [m/s^2], a mavloc extension): the
  // prior a smoother may put on the initial biases. Unset when unknown (real logs); zero when the
  // biases start at zero (ideal simulated sensors).
  std::optional<double> gyroscope_bias_sigma;
  std::optional<double> accelerometer_bias_sigma;
  std::vector<ImuSample> samples;
};

struct CameraFrame {
  TimeNs t_ns = 0;
  std::string image_path;  // absolute path; loaded on demand; may be missing on disk
};

struct CameraSensor {
  std::string name;  // "cam0", "cam1"
  Pose T_B_C;        // T_BS of the sensor.yaml: camera frame C in B
  double rate_hz = 0.0;
  CameraModel model;
  std::vector<CameraFrame> frames;
  std::vector<std::string> missing_images;  // listed in data.csv but absent on disk
};

// features0 / features1: a landmark seen at normalized (undistorted) image coordinates of cam0 /
// cam1. A landmark id that map.yaml does not list is an unknown landmark (a feature track of
// frontends/features/: the same id in features0 and features1 is one point seen by both cameras).
struct FeatureObservation {
  TimeNs t_ns = 0;
  int landmark_id = 0;
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();
  int camera = 0;  // index into Dataset::cameras: 0 for features0, 1 for features1
};

// laser0: the laser spot at normalized image coordinates of cam0.
struct LaserObservation {
  TimeNs t_ns = 0;
  Eigen::Vector2d xy = Eigen::Vector2d::Zero();
};

// tags0 / tags1: the 4 corners of a tag in pixels of cam0 / cam1 (distorted, as detected), in the
// order of libapriltag (counter-clockwise in the image starting bottom-left of the tag's own
// frame).
struct TagObservation {
  TimeNs t_ns = 0;
  int tag_id = 0;
  std::array<Eigen::Vector2d, 4> corners_px{};
  int camera = 0;  // index into Dataset::cameras: 0 for tags0, 1 for tags1
};

struct TagInfo {
  int id = 0;
  double size_m = 0.0;  // edge length of the black square
  Pose T_W_T;           // tag frame: origin at the centre, z out of the tag, x right, y up
};

// A plane n_W . p_W = d_m, with unit normal n_W.
struct Plane {
  Eigen::Vector3d n_W = Eigen::Vector3d::UnitZ();
  double d_m = 0.0;
};

// The frame the map's coordinates are given in (map.yaml key `frame`).
enum class MapFrame {
  kWorld,  // W: z up, gravity (0, 0, -9.81) (surveyed maps, simulated worlds)
  kBoard,  // M: a calibration board or a tag map surveyed without gravity. The gravity direction
           // in M is unknown (2 DoF); estimators estimate or initialise T_W_M (core/board_frame.h).
};

// map.yaml: what the world is known to contain. Positions and poses (landmarks_W, TagInfo::T_W_T,
// plane) are in W, or in the board frame M when frame == kBoard.
struct WorldMap {
  MapFrame frame = MapFrame::kWorld;
  std::map<int, Eigen::Vector3d> landmarks_W;  // landmark id -> position
  std::map<int, TagInfo> tags;
  std::optional<Plane> plane;
  // Free-form scalar parameters of the world (e.g. the three-point triangle's side D).
  std::map<std::string, double> parameters;
};

struct Dataset {
  std::string name;
  std::string root;      // folder it was read from (empty for in-memory simulations)
  std::string scenario;  // scenario name for synthetic datasets
  ImuSensor imu;
  std::vector<CameraSensor> cameras;
  std::vector<GroundTruthState> ground_truth;
  std::vector<FeatureObservation> features;   // features0: cam0 (camera = 0)
  std::vector<FeatureObservation> features1;  // features1: cam1 (camera = 1), stereo tracks
  std::vector<LaserObservation> laser;
  std::vector<TagObservation> tags;   // tags0: cam0 (camera = 0)
  std::vector<TagObservation> tags1;  // tags1: cam1 (camera = 1), stereo rigs
  WorldMap map;
  QuantityTable truth_quantities;  // extra ground-truth quantities (may be empty)
  // scenario.yaml as flat key -> value text (seed, rates, noises, ...), for reports.
  std::map<std::string, std::string> scenario_info;

  const CameraSensor* Camera(const std::string& camera_name) const;
};

// The leading number of a scenario.yaml value ("1 per bearing angle (...)" -> 1); nullopt only when
// the key is absent. Text that does not start with a finite number throws InputError naming the
// key (ReadScenarioInfo has already checked the values of a file with their lines; this catches
// in-memory datasets), never "not stated".
std::optional<double> ScenarioNumber(const Dataset& dataset, const std::string& key);

// What a dataset holds, stream by stream, each with its file (mav0/<stream>/data.csv for a folder
// read from disk) and its row count: "mav0/imu0/data.csv 1 row, ground truth 801 rows,
// mav0/tags0/data.csv 132 rows". The IMU and the ground truth are always named, other streams when
// they have rows. For a message that says why nothing could run on the dataset.
std::string DescribeDatasetStreams(const Dataset& dataset);

// The ground-truth row nearest to t_ns (rows are time-ordered, at least one).
const GroundTruthState& NearestTruth(const std::vector<GroundTruthState>& truth, TimeNs t_ns);

// The true state at t_ns, interpolated between the two rows around it (slerp for the attitude,
// linear for position, velocity and biases); the first or last row outside them.
GroundTruthState InterpolatedTruth(const std::vector<GroundTruthState>& truth, TimeNs t_ns);

}  // namespace mavloc

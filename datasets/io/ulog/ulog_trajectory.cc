// ReadUlogTrajectory: PX4 pose topics as mavloc trajectories (frames in ulog_frames.h). Field
// meanings from PX4's msg/VehicleAttitude.msg, msg/VehicleLocalPosition.msg and
// msg/VehicleOdometry.msg (v1.14 and later; v1.13 and earlier for the older layout).
#include <fmt/format.h>

#include <cmath>
#include <functional>
#include <optional>

#include "core/errors.h"
#include "core/physical_limits.h"
#include "datasets/io/ulog/ulog_format.h"
#include "datasets/io/ulog/ulog_frames.h"
#include "datasets/io/ulog/ulog_reader.h"
#include "datasets/io/ulog/ulog_topic_fields.h"

namespace mavloc {
namespace {

using Covariance6 = Eigen::Matrix<double, 6, 6>;

constexpr const char* kWorldEnu = "world_enu";  // from PX4's NED
constexpr const char* kWorldFlu = "world_flu";  // from PX4's FRD earth frame (arbitrary heading)
constexpr const char* kBodyFlu = "body_flu";    // from PX4's FRD body frame

// Column lookup by name in a TopicTable.
class Columns {
 public:
  explicit Columns(const ulog::TopicTable& table) : table_(table) {}
  size_t Index(const std::string& name) const {
    for (size_t i = 0; i < table_.fields.size(); ++i) {
      if (table_.fields[i] == name) return i;
    }
    return table_.fields.size();
  }
  bool Has(const std::string& name) const {
    const size_t i = Index(name);
    return i < table_.fields.size() && table_.has(i);
  }
  double Get(size_t row, const std::string& name) const { return table_.at(row, Index(name)); }
  Eigen::Vector3d Vec3(size_t row, const std::string& a, const std::string& b,
                       const std::string& c) const {
    return {Get(row, a), Get(row, b), Get(row, c)};
  }
  Eigen::Quaterniond Quat(size_t row) const {  // PX4 q[4] is (w, x, y, z)
    return {Get(row, "q[0]"), Get(row, "q[1]"), Get(row, "q[2]"), Get(row, "q[3]")};
  }
  // timestamp_sample (when the data was sampled) if the topic has it, else timestamp; nullopt
  // for a corrupt stamp (ulog::StampNs).
  std::optional<TimeNs> StampNs(size_t row) const {
    if (Has("timestamp_sample")) return ulog::StampNsOfField(Get(row, "timestamp_sample"));
    return ulog::StampNs(table_.t_us[row]);
  }

 private:
  const ulog::TopicTable& table_;
};

std::vector<ulog::FieldRequest> Optional(const std::vector<std::string>& names) {
  std::vector<ulog::FieldRequest> requests;
  for (const std::string& n : names) requests.push_back({n, false});
  return requests;
}

std::vector<std::string> Indexed(const std::string& name, int count) {
  std::vector<std::string> names;
  for (int i = 0; i < count; ++i) names.push_back(fmt::format("{}[{}]", name, i));
  return names;
}

void Append(std::vector<std::string>* a, const std::vector<std::string>& b) {
  a->insert(a->end(), b.begin(), b.end());
}

// A PX4 q is unit length within this (float32 q, normalised by PX4 before logging).
constexpr double kQuaternionNormTolerance = 0.1;

// One topic's reading: its messages' index, what was dropped, and the refusals (ulog_reader.h).
struct TopicReading {
  const std::string& path;
  const std::string& topic;
  ulog::DroppedMessages dropped;

  // false (dropped and counted) for a NaN q, PX4's "invalid/unknown"; throws for a finite q that
  // is not a rotation.
  bool QuaternionValid(const Eigen::Quaterniond& q, size_t index) {
    if (!q.coeffs().allFinite()) {
      dropped.Add("with a NaN or infinite q (invalid)", index);
      return false;
    }
    if (!(std::abs(q.norm() - 1.0) <= kQuaternionNormTolerance)) {
      throw InputError(path, 0, "q[0]",
                       fmt::format("topic {}, message {}: q = ({:g}, {:g}, {:g}, {:g}) has norm "
                                   "{:g}, not a unit quaternion (accepted within 1 +- {})",
                                   topic, index, q.w(), q.x(), q.y(), q.z(), q.norm(),
                                   kQuaternionNormTolerance));
    }
    return true;
  }

  // false (dropped and counted) for a NaN position, PX4's "invalid/unknown"; throws for a finite
  // one beyond limits::kMaxPosition_m.
  bool PositionValid(const Eigen::Vector3d& p, const std::string (&fields)[3], size_t index) {
    if (!p.allFinite()) {
      dropped.Add("with a NaN or infinite position (invalid)", index);
      return false;
    }
    for (int k = 0; k < 3; ++k)
      ulog::RequireWithin(path, topic, index, fields[k], p[k], limits::kMaxPosition_m, "m");
    return true;
  }

  // A finite velocity beyond limits::kMaxSpeed_m_s is refused.
  void CheckVelocity(const Eigen::Vector3d& v, const std::string (&fields)[3], size_t index) {
    for (int k = 0; k < 3; ++k) {
      if (std::isfinite(v[k]))
        ulog::RequireWithin(path, topic, index, fields[k], v[k], limits::kMaxSpeed_m_s, "m/s");
    }
  }

  // The message's stamp, or nullopt (dropped and counted) when it is corrupt.
  std::optional<TimeNs> Stamp(std::optional<TimeNs> t_ns, size_t index) {
    if (!t_ns) dropped.Add("with a corrupt timestamp_sample (negative or beyond the range)", index);
    return t_ns;
  }

  // Keeps states with increasing stamps (a repeated stamp keeps the first message); returns
  // whether the state was kept.
  bool PushState(LogTrajectory* trajectory, const GroundTruthState& state, size_t index) {
    const std::optional<TimeNs> previous =
        trajectory->states.empty() ? std::nullopt
                                   : std::optional<TimeNs>(trajectory->states.back().t_ns);
    if (dropped.DropNotIncreasing(state.t_ns, previous, index)) return false;
    trajectory->states.push_back(state);
    return true;
  }
};

void RequireStates(const LogTrajectory& trajectory, const std::string& path,
                   const std::string& topic, size_t messages) {
  if (trajectory.states.empty()) {
    throw InputError(path, 0, topic,
                     fmt::format("none of the topic's {} messages has a valid pose", messages));
  }
}

LogTrajectory FromAttitude(const std::string& path, const std::string& topic,
                           const UlogProgress& progress, std::vector<std::string>* notes) {
  std::vector<ulog::FieldRequest> requests;
  for (const std::string& n : Indexed("q", 4)) requests.push_back({n, true});
  requests.push_back({"timestamp_sample", false});
  const ulog::TopicTable table = ulog::ReadTopicFields(path, topic, requests, progress, notes);
  TopicReading reading{path, topic, {}};
  const Columns c(table);
  LogTrajectory trajectory;
  trajectory.parent_frame = kWorldEnu;
  trajectory.child_frame = kBodyFlu;
  trajectory.has_position = false;  // attitude only: p = 0 is not a position
  for (size_t i = 0; i < table.rows(); ++i) {
    const Eigen::Quaterniond q_ned_frd = c.Quat(i);
    if (!reading.QuaternionValid(q_ned_frd, i)) continue;
    const std::optional<TimeNs> t_ns = reading.Stamp(c.StampNs(i), i);
    if (!t_ns) continue;
    GroundTruthState state;
    state.t_ns = *t_ns;
    state.T_W_B.q = ulog::ToMavlocQuaternion(ulog::R_ENU_NED(), q_ned_frd);
    reading.PushState(&trajectory, state, i);
  }
  RequireStates(trajectory, path, topic, table.rows());
  reading.dropped.AppendNotes(topic, notes);
  return trajectory;
}

LogTrajectory FromLocalPosition(const std::string& path, const std::string& topic,
                                const UlogProgress& progress, std::vector<std::string>* notes) {
  std::vector<ulog::FieldRequest> requests = {{"x"}, {"y"}, {"z"}};
  const std::vector<ulog::FieldRequest> optional = Optional(
      {"vx", "vy", "vz", "xy_valid", "z_valid", "v_xy_valid", "v_z_valid", "timestamp_sample"});
  requests.insert(requests.end(), optional.begin(), optional.end());
  const ulog::TopicTable table = ulog::ReadTopicFields(path, topic, requests, progress, notes);
  TopicReading reading{path, topic, {}};
  static const std::string kPosition[3] = {"x", "y", "z"};
  static const std::string kVelocity[3] = {"vx", "vy", "vz"};
  const Columns c(table);
  const auto flag = [&](size_t row, const char* name) { return !c.Has(name) || c.Get(row, name); };
  LogTrajectory trajectory;
  trajectory.parent_frame = kWorldEnu;
  // vehicle_local_position carries no attitude: B keeps W's orientation (identity rotation).
  trajectory.child_frame = "body_position_only";
  trajectory.has_attitude = false;
  bool all_velocities = c.Has("vx") && c.Has("vy") && c.Has("vz");
  for (size_t i = 0; i < table.rows(); ++i) {
    const Eigen::Vector3d p_ned = c.Vec3(i, "x", "y", "z");
    // A message is kept when its horizontal or its vertical position is valid: PX4 logs z alone
    // (baro) without a horizontal fix, keeping x = y at their last value.
    // A finite value no MAV logs is refused even in a message flagged invalid (PX4 keeps stale
    // values there, never 1e30).
    if (p_ned.allFinite()) reading.PositionValid(p_ned, kPosition, i);
    if (!flag(i, "xy_valid") && !flag(i, "z_valid")) {
      reading.dropped.Add("with xy_valid and z_valid both false", i);
      continue;
    }
    if (!reading.PositionValid(p_ned, kPosition, i)) continue;
    const std::optional<TimeNs> t_ns = reading.Stamp(c.StampNs(i), i);
    if (!t_ns) continue;
    GroundTruthState state;
    state.t_ns = *t_ns;
    state.T_W_B.p = ulog::NedToEnu(p_ned);
    if (all_velocities) {
      const Eigen::Vector3d v_ned = c.Vec3(i, "vx", "vy", "vz");
      if (!flag(i, "v_xy_valid") || !flag(i, "v_z_valid") || !v_ned.allFinite()) {
        all_velocities = false;
      } else {
        reading.CheckVelocity(v_ned, kVelocity, i);
        state.v_W = ulog::NedToEnu(v_ned);
      }
    }
    reading.PushState(&trajectory, state, i);
  }
  RequireStates(trajectory, path, topic, table.rows());
  reading.dropped.AppendNotes(topic, notes);
  trajectory.has_velocity = all_velocities;
  if (!all_velocities) {
    for (GroundTruthState& s : trajectory.states) s.v_W.setZero();
  }
  return trajectory;
}

// The earth-frame code of a vehicle_odometry message -> the rotation into mavloc's W and its
// name. PX4 >= 1.14 pose_frame: 1 NED, 2 FRD; older local_frame: 0 NED, 1 FRD.
bool EarthFrame(bool new_layout, double code, Eigen::Matrix3d* R_W_Wpx4, const char** name) {
  // Compared as doubles: a corrupt log may declare the field as a float holding NaN or 1e300,
  // whose conversion to int would be undefined.
  const double frame = code;
  const double ned = new_layout ? 1 : 0;
  const double frd = new_layout ? 2 : 1;
  if (frame == ned) {
    *R_W_Wpx4 = ulog::R_ENU_NED();
    *name = kWorldEnu;
    return true;
  }
  if (frame == frd) {
    *R_W_Wpx4 = ulog::R_FLU_FRD();
    *name = kWorldFlu;
    return true;
  }
  return false;
}

LogTrajectory FromOdometry(const std::string& path, const std::string& topic,
                           const UlogProgress& progress, std::vector<std::string>* notes) {
  std::vector<std::string> names = {"timestamp_sample",
                                    "pose_frame",
                                    "local_frame",
                                    "velocity_frame",
                                    "x",
                                    "y",
                                    "z",
                                    "vx",
                                    "vy",
                                    "vz"};
  Append(&names, Indexed("q", 4));
  Append(&names, Indexed("position", 3));
  Append(&names, Indexed("velocity", 3));
  Append(&names, Indexed("position_variance", 3));
  Append(&names, Indexed("orientation_variance", 3));
  Append(&names, Indexed("pose_covariance", 21));
  const ulog::TopicTable table =
      ulog::ReadTopicFields(path, topic, Optional(names), progress, notes);
  TopicReading reading{path, topic, {}};
  const Columns c(table);
  const bool new_layout = c.Has("position[0]") && c.Has("pose_frame");
  const bool old_layout = c.Has("x") && c.Has("local_frame");
  if ((!new_layout && !old_layout) || !c.Has("q[0]")) {
    throw InputError(path, 0, topic,
                     "not a PX4 odometry topic: expected position[3], q[4], pose_frame "
                     "(PX4 >= 1.14) or x, y, z, q[4], local_frame (older)");
  }
  const std::string p_fields[3] = {new_layout ? "position[0]" : "x",
                                   new_layout ? "position[1]" : "y",
                                   new_layout ? "position[2]" : "z"};
  const std::string v_fields[3] = {new_layout ? "velocity[0]" : "vx",
                                   new_layout ? "velocity[1]" : "vy",
                                   new_layout ? "velocity[2]" : "vz"};
  const std::string &p0 = p_fields[0], &p1 = p_fields[1], &p2 = p_fields[2];
  const std::string &v0 = v_fields[0], &v1 = v_fields[1], &v2 = v_fields[2];
  const bool velocity_fields = c.Has(v0) && c.Has("velocity_frame");
  const bool covariance_fields =
      new_layout ? c.Has("position_variance[0]") && c.Has("orientation_variance[0]")
                 : c.Has("pose_covariance[0]");
  LogTrajectory trajectory;
  trajectory.child_frame = kBodyFlu;
  bool all_velocities = velocity_fields;
  bool all_covariances = covariance_fields;
  std::vector<Covariance6> covariances;
  for (size_t i = 0; i < table.rows(); ++i) {
    Eigen::Matrix3d R_W_Wpx4;
    const char* frame_name = nullptr;
    const double frame_code = c.Get(i, new_layout ? "pose_frame" : "local_frame");
    if (!EarthFrame(new_layout, frame_code, &R_W_Wpx4, &frame_name)) {
      throw InputError(path, 0, topic,
                       fmt::format("message {}: unsupported pose frame {} (only NED and FRD "
                                   "earth frames are converted)",
                                   i, frame_code));
    }
    if (trajectory.parent_frame.empty()) trajectory.parent_frame = frame_name;
    if (trajectory.parent_frame != frame_name) {
      throw InputError(path, 0, topic,
                       fmt::format("message {}: the pose frame changes from {} to {}", i,
                                   trajectory.parent_frame, frame_name));
    }
    const Eigen::Vector3d p = c.Vec3(i, p0, p1, p2);
    const Eigen::Quaterniond q = c.Quat(i);
    if (!reading.PositionValid(p, p_fields, i) || !reading.QuaternionValid(q, i)) continue;
    const std::optional<TimeNs> t_ns = reading.Stamp(c.StampNs(i), i);
    if (!t_ns) continue;
    GroundTruthState state;
    state.t_ns = *t_ns;
    state.T_W_B = Pose(ulog::ToMavlocQuaternion(R_W_Wpx4, q), R_W_Wpx4 * p);
    if (all_velocities) {
      const Eigen::Vector3d v = c.Vec3(i, v0, v1, v2);
      const double vframe = c.Get(i, "velocity_frame");  // as doubles, see EarthFrame
      // Velocity frames: PX4 >= 1.14 1 NED, 2 FRD earth, 3 FRD body; older 0 NED, 1 FRD earth,
      // 3 FRD body.
      const int ned = new_layout ? 1 : 0;
      const int frd = new_layout ? 2 : 1;
      reading.CheckVelocity(v, v_fields, i);
      if (!v.allFinite()) {
        all_velocities = false;
      } else if (vframe == 3) {
        state.v_W = state.T_W_B.R() * ulog::FrdToFlu(v);
      } else if (vframe == ned) {
        state.v_W = ulog::NedToEnu(v);
      } else if (vframe == frd) {
        state.v_W = ulog::R_FLU_FRD() * v;
      } else {
        all_velocities = false;
      }
    }
    Covariance6 cov = Covariance6::Zero();
    if (all_covariances) {
      if (new_layout) {
        // position_variance in the earth frame, orientation_variance about the body axes; the
        // fixed axis flips leave the variances' order (x, y, z) only permuted for NED -> ENU.
        const Eigen::Vector3d var_p =
            c.Vec3(i, "position_variance[0]", "position_variance[1]", "position_variance[2]");
        const Eigen::Vector3d var_r = c.Vec3(i, "orientation_variance[0]",
                                             "orientation_variance[1]", "orientation_variance[2]");
        cov.topLeftCorner<3, 3>() = R_W_Wpx4 * var_p.asDiagonal() * R_W_Wpx4.transpose();
        cov.bottomRightCorner<3, 3>() =
            ulog::R_FLU_FRD() * var_r.asDiagonal() * ulog::R_FLU_FRD().transpose();
      } else {
        // pose_covariance: upper-right triangle, row-major, of the 6x6 [x y z roll pitch yaw]
        // covariance in local_frame.
        int k = 0;
        for (int r = 0; r < 6; ++r) {
          for (int col = r; col < 6; ++col, ++k) {
            cov(r, col) = cov(col, r) = c.Get(i, fmt::format("pose_covariance[{}]", k));
          }
        }
        Covariance6 R6 = Covariance6::Zero();
        R6.topLeftCorner<3, 3>() = R_W_Wpx4;
        R6.bottomRightCorner<3, 3>() = R_W_Wpx4;
        cov = R6 * cov * R6.transpose();
      }
      if (!cov.allFinite() || cov.isZero() || (cov.diagonal().array() < 0.0).any()) {
        all_covariances = false;
      }
    }
    if (reading.PushState(&trajectory, state, i)) covariances.push_back(cov);
  }
  RequireStates(trajectory, path, topic, table.rows());
  reading.dropped.AppendNotes(topic, notes);
  trajectory.has_velocity = all_velocities;
  if (!all_velocities) {
    for (GroundTruthState& s : trajectory.states) s.v_W.setZero();
  }
  if (all_covariances) trajectory.covariance = std::move(covariances);
  return trajectory;
}

}  // namespace

LogTrajectory ReadUlogTrajectory(const LogTopicSpec& spec, const UlogProgress& progress,
                                 std::vector<std::string>* notes) {
  ulog::TopicSelector selector = ulog::ParseTopicSelector(spec.path, spec.topic);
  // The instance comes from the topic's ".N" suffix or, without one, from spec.instance.
  std::string topic = spec.topic;
  if (spec.topic.find('.') == std::string::npos && spec.instance > 0) {
    selector.multi_id = spec.instance;
    topic = fmt::format("{}.{}", spec.topic, spec.instance);
  }
  LogTrajectory trajectory;
  if (selector.name == "vehicle_attitude" || selector.name == "vehicle_attitude_groundtruth") {
    trajectory = FromAttitude(spec.path, topic, progress, notes);
  } else if (selector.name == "vehicle_local_position" ||
             selector.name == "vehicle_local_position_groundtruth") {
    trajectory = FromLocalPosition(spec.path, topic, progress, notes);
  } else if (selector.name == "vehicle_odometry" || selector.name == "vehicle_visual_odometry" ||
             selector.name == "vehicle_mocap_odometry" || selector.name == "estimator_odometry" ||
             selector.name == "estimator_visual_odometry_aligned") {
    trajectory = FromOdometry(spec.path, topic, progress, notes);
  } else {
    throw InputError(spec.path, 0, spec.topic,
                     "not a supported ULog trajectory topic (vehicle_attitude, "
                     "vehicle_local_position, vehicle_odometry, vehicle_visual_odometry, "
                     "vehicle_mocap_odometry, or .N instances of them)");
  }
  trajectory.source = fmt::format("{}:{}", spec.path, topic);
  trajectory.type = selector.name;
  return trajectory;
}

}  // namespace mavloc

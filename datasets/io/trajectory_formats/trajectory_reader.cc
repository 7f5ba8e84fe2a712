// ReadTrajectory (trajectory_format.h): text -> layout -> rows -> stamps ordered and unique.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numeric>

#include "core/errors.h"
#include "core/number_text.h"
#include "core/physical_limits.h"
#include "core/rotation.h"
#include "datasets/io/trajectory_formats/kitti_poses.h"
#include "datasets/io/trajectory_formats/trajectory_columns.h"
#include "datasets/io/trajectory_formats/trajectory_format.h"

#include "datasets/io/log_reader.h"
#include "datasets/io/trajectory_formats/trajectory_stamps.h"
#include "datasets/io/trajectory_formats/trajectory_text.h"

namespace mavloc {

namespace {

// One data row being parsed: its line and its fields (views into the file's text).
struct PoseRowFields {
  long line = 0;
  std::vector<std::string_view> fields;
};

double Number(const std::string& path, const PoseRowFields& row, const PoseColumnLayout& layout,
              int column) {
  const ParsedNumber<double> parsed = ParseDoubleText(row.fields[column]);
  if (parsed.ok()) return parsed.value;
  return RequireDoubleText(row.fields[column], path, row.line, layout.Name(column));  // throws
}

// The row's attitude: its quaternion (normalised within kQuaternionNormTolerance, counted in the
// report when it was off by more than 1e-6), or its roll, pitch and yaw.
Eigen::Quaterniond Attitude(const std::string& path, const PoseRowFields& row,
                            const PoseColumnLayout& layout, TrajectoryReadReport* report) {
  if (!layout.HasQuaternion()) {
    EulerRpy rpy;
    rpy.roll = layout.rpy_to_rad * Number(path, row, layout, layout.rpy[0]);
    rpy.pitch = layout.rpy_to_rad * Number(path, row, layout, layout.rpy[1]);
    rpy.yaw = layout.rpy_to_rad * Number(path, row, layout, layout.rpy[2]);
    return QuaternionFromEuler(rpy);
  }
  const Eigen::Quaterniond q(
      Number(path, row, layout, layout.q_wxyz[0]), Number(path, row, layout, layout.q_wxyz[1]),
      Number(path, row, layout, layout.q_wxyz[2]), Number(path, row, layout, layout.q_wxyz[3]));
  const double norm_error = std::abs(q.norm() - 1.0);
  if (!(norm_error <= kQuaternionNormTolerance))
    throw InputError(path, row.line, layout.Name(layout.q_wxyz[0]),
                     fmt::format("quaternion is not unit length (|q| = {:.6g}; accepted and "
                                 "normalised within 1 +- {})",
                                 q.norm(), kQuaternionNormTolerance));
  if (norm_error > 1e-6) ++report->quaternions_normalised;
  report->max_quaternion_norm_error = std::max(report->max_quaternion_norm_error, norm_error);
  return q.normalized();
}

// Throws unless the row has as many fields as the layout needs (exactly, for TUM's 8 or 20),
// naming the first missing or first extra column.
void RequireFieldCount(const std::string& path, const PoseRowFields& row,
                       const PoseColumnLayout& layout) {
  const size_t n = row.fields.size();
  if (layout.exact_fields > 0 && n != layout.exact_fields)
    throw InputError(
        path, row.line, layout.Name(n < layout.exact_fields ? n : layout.exact_fields),
        fmt::format("expected {} fields{}, found {}", layout.exact_fields,
                    layout.exact_fields == 8 ? " (timestamp tx ty tz qx qy qz qw)" : "", n));
  if (n < layout.min_fields)
    throw InputError(path, row.line, layout.Name(n),
                     fmt::format("expected {} fields, found {}", layout.min_fields, n));
}

// Three columns, each within +-max_abs (a sanity range of core/physical_limits.h).
Eigen::Vector3d Vector(const std::string& path, const PoseRowFields& row,
                       const PoseColumnLayout& layout, const std::array<int, 3>& columns,
                       double max_abs, const char* unit) {
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) {
    v[i] = Number(path, row, layout, columns[i]);
    if (!(std::abs(v[i]) <= max_abs))
      throw InputError(path, row.line, layout.Name(columns[i]),
                       "'" + std::string(row.fields[columns[i]]) + "' is outside " +
                           limits::RangeText(-max_abs, max_abs, unit));
  }
  return v;
}

// The rows of a file as they are read, before ordering: poses, their motion (when the file has
// it) and their lines, index by index.
struct ParsedRows {
  std::vector<StampedPose> poses;
  std::vector<TrajectoryMotion> motion;
  std::vector<long> lines;
};

// A TrajectoryText of the stream's first data row alone: what format detection and the layout
// look at (the header and the first row).
TrajectoryText HeadText(const TrajectoryRowStream& stream, long line, std::string_view row) {
  TrajectoryText head;
  head.path = stream.path();
  head.header = stream.header();
  head.header_line = stream.header_line();
  head.comma_separated = stream.comma_separated();
  head.had_bom = stream.had_bom();
  head.storage = std::string(row);
  head.bytes = head.storage;
  head.rows.push_back(TrajectoryRow{line, 0, row.size()});
  return head;
}

// "TUM", "EuRoC", ... for messages.
std::string FormatDisplayName(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::kTum:
      return "TUM";
    case TrajectoryFormat::kEuroc:
      return "EuRoC";
    case TrajectoryFormat::kAsl:
      return "ASL";
    case TrajectoryFormat::kKitti:
      return "KITTI";
    default:
      return TrajectoryFormatName(format);
  }
}

PoseColumnLayout ChooseLayout(const TrajectoryText& text, TrajectoryFormat format, bool forced) {
  const auto by_header = LayoutFromHeader(text);
  const size_t fields = text.Fields(text.rows.front()).size();
  if (!forced && by_header) return *by_header;
  switch (format) {
    case TrajectoryFormat::kTum:
      if (fields != 8 && fields != 20)
        throw InputError(text.path, text.rows.front().line,
                         TumLayout(8).Name(std::min<size_t>(fields, 8)),
                         fmt::format("expected 8 fields (timestamp tx ty tz qx qy qz qw), or 20 "
                                     "(ov_eval: with covariance), found {}",
                                     fields));
      return TumLayout(fields);
    case TrajectoryFormat::kEuroc:
      if (fields < 8)
        throw InputError(
            text.path, text.rows.front().line, EurocLayout(8).Name(fields),
            fmt::format("expected at least 8 fields (EuRoC: t_ns, p, q_wxyz), found {}", fields));
      return EurocLayout(fields);
    case TrajectoryFormat::kAsl:
      if (!by_header)
        throw InputError(text.path, 0, "",
                         text.header.empty()
                             ? "no header line names the columns (asl needs one, e.g. "
                               "'#timestamp,x,y,z,qw,qx,qy,qz')"
                             : "the header '" + text.header_line +
                                   "' does not name a timestamp, a position (x,y,z) and a "
                                   "quaternion (qw,qx,qy,qz)");
      return *by_header;
    default:
      break;
  }
  throw InputError(text.path, 0, "",
                   "internal: no layout for format " + TrajectoryFormatName(format));
}

// Stamps the layout takes for nanoseconds without a header stating it are refused when they look
// like seconds (trajectory_stamps.h), before any other column is read: the wrong layout is the
// reason, not the quaternion it would then take from the wrong columns. Rows whose stamp does not
// parse are left to ParsePoseRows.
void RequirePlausibleNanoseconds(const TrajectoryText& head, const PoseColumnLayout& layout) {
  if (layout.unit != StampUnit::kNanoseconds || layout.unit_stated) return;
  std::vector<TimeNs> stamps;
  std::vector<std::string_view> fields;
  TrajectoryRowStream stream(head.path);
  long line = 0;
  std::string_view text;
  while (stream.Next(&line, &text)) {
    SplitTrajectoryFields(text, stream.comma_separated(), &fields);
    TimeNs t_ns = 0;
    if (static_cast<size_t>(layout.t) < fields.size() && ParseNanoseconds(fields[layout.t], &t_ns))
      stamps.push_back(t_ns);
  }
  const std::string why = SecondsReadAsNanoseconds(stamps);
  if (!why.empty())
    throw InputError(head.path, head.rows.front().line, layout.Name(layout.t),
                     "not read as " + layout.description + ": " + why);
}

// One row into *rows (throws InputError naming the file, line and field).
void ParsePoseRow(const std::string& path, const PoseRowFields& row, const PoseColumnLayout& layout,
                  ParsedRows* rows, TrajectoryReadReport* report) {
  RequireFieldCount(path, row, layout);
  StampedPose& pose = rows->poses.emplace_back();
  rows->lines.push_back(row.line);
  const std::string_view stamp = row.fields[layout.t];
  const bool ok = layout.unit == StampUnit::kSeconds ? ParseSecondsAsNs(stamp, &pose.t_ns)
                                                     : ParseNanoseconds(stamp, &pose.t_ns);
  if (!ok)
    throw InputError(path, row.line, layout.Name(layout.t),
                     DescribeBadStamp(std::string(stamp), layout.unit == StampUnit::kSeconds,
                                      FormatDisplayName(layout.format)));
  pose.T_W_B.p = Vector(path, row, layout, layout.p, limits::kMaxPosition_m, "m");
  pose.T_W_B.q = Attitude(path, row, layout, report);
  if (!layout.HasVelocity() && !layout.HasBiases()) return;
  TrajectoryMotion& motion = rows->motion.emplace_back();
  if (layout.HasVelocity())
    motion.v_W = Vector(path, row, layout, layout.v, limits::kMaxSpeed_m_s, "m/s");
  if (layout.HasBiases()) {
    motion.b_g = Vector(path, row, layout, layout.b_g, limits::kMaxGyroBias_rad_s, "rad/s");
    motion.b_a = Vector(path, row, layout, layout.b_a, limits::kMaxAccelBias_m_s2, "m/s^2");
  }
}

// Every data row of the stream, the head's first: parsed as it is read (the file's text is never
// held whole). Room for the poses is reserved from the file's size and the first row's length
// (pages never written cost no memory).
ParsedRows ParsePoseRows(const TrajectoryText& head, TrajectoryRowStream* stream,
                         const PoseColumnLayout& layout, TrajectoryReadReport* report) {
  RequirePlausibleNanoseconds(head, layout);
  ParsedRows rows;
  std::error_code size_error;
  const auto file_size = std::filesystem::file_size(head.path, size_error);
  if (!size_error) {
    const size_t expected = static_cast<size_t>(file_size) / (head.bytes.size() / 2 + 1) + 16;
    rows.poses.reserve(expected);
    rows.lines.reserve(expected);
    if (layout.HasVelocity() || layout.HasBiases()) rows.motion.reserve(expected);
  }
  PoseRowFields row;
  row.line = head.rows.front().line;
  head.Fields(head.rows.front(), &row.fields);
  ParsePoseRow(head.path, row, layout, &rows, report);
  std::string_view text;
  while (stream->Next(&row.line, &text)) {
    SplitTrajectoryFields(text, stream->comma_separated(), &row.fields);
    ParsePoseRow(head.path, row, layout, &rows, report);
  }
  report->has_velocity = layout.HasVelocity();
  report->has_biases = layout.HasBiases();
  return rows;
}

// Rows in time order with unique stamps (rules in trajectory_format.h), in place: sorted (stable)
// only when sorting was asked for and a row is out of order, repeated stamps removed by moving the
// kept rows forward. stamp_path / stamp_field name where the stamps came from (the times file for
// KITTI).
void OrderRows(ParsedRows rows, const std::string& stamp_path, const std::string& stamp_field,
               const TrajectoryReadOptions& options, LoadedTrajectory* out) {
  TrajectoryReadReport* report = &out->report;
  std::vector<StampedPose>& poses = rows.poses;
  std::vector<TrajectoryMotion>& motion = rows.motion;
  std::vector<long>& lines = rows.lines;
  const bool has_motion = !motion.empty();
  if (options.sort) {
    report->sorted = true;
    TimeNs latest = 0;
    for (size_t i = 0; i < poses.size(); ++i) {
      if (i > 0 && poses[i].t_ns < latest) {
        ++report->rows_out_of_order;
        if (report->first_out_of_order_line == 0) report->first_out_of_order_line = lines[i];
      }
      latest = i == 0 ? poses[i].t_ns : std::max(latest, poses[i].t_ns);
    }
    if (report->rows_out_of_order > 0) {
      std::vector<size_t> order(poses.size());
      std::iota(order.begin(), order.end(), size_t{0});
      std::stable_sort(order.begin(), order.end(),
                       [&](size_t a, size_t b) { return poses[a].t_ns < poses[b].t_ns; });
      ParsedRows sorted;
      sorted.poses.reserve(poses.size());
      sorted.lines.reserve(poses.size());
      if (has_motion) sorted.motion.reserve(poses.size());
      for (size_t i : order) {
        sorted.poses.push_back(poses[i]);
        sorted.lines.push_back(lines[i]);
        if (has_motion) sorted.motion.push_back(motion[i]);
      }
      rows = std::move(sorted);
    }
  }
  size_t kept = 0;
  for (size_t i = 0; i < poses.size(); ++i) {
    if (kept > 0) {
      const TimeNs previous = poses[kept - 1].t_ns;
      const TimeNs t_ns = poses[i].t_ns;
      if (t_ns < previous)
        throw InputError(stamp_path, lines[i], stamp_field,
                         fmt::format("timestamp {} is earlier than the previous row's ({}); "
                                     "--sort sorts the rows",
                                     t_ns, previous));
      if (t_ns == previous) {
        if (options.refuse_duplicates)
          throw InputError(stamp_path, lines[i], stamp_field,
                           "duplicate timestamp " + std::to_string(t_ns));
        ++report->duplicates_dropped;
        if (report->first_duplicate_line == 0 || lines[i] < report->first_duplicate_line)
          report->first_duplicate_line = lines[i];
        continue;
      }
    }
    if (kept != i) {
      poses[kept] = poses[i];
      if (has_motion) motion[kept] = motion[i];
    }
    ++kept;
  }
  poses.resize(kept);
  if (has_motion) motion.resize(kept);
  out->poses = std::move(poses);
  out->motion = std::move(motion);
}

}  // namespace

// A trajectory topic of a log: full poses only (a topic carrying only attitude or only position
// is for `compare --reference`, which compares per quantity).
LoadedTrajectory ReadLogTopicTrajectory(const LogTopicSpec& spec, const std::string& path,
                                        const TrajectoryReadOptions& options) {
  if (options.format != TrajectoryFormat::kAuto || !options.times_path.empty())
    throw InputError(path, 0, "",
                     "a log topic has its own format and stamps: drop --gt-format/--est-format "
                     "and the times file for it");
  const LogTrajectory trajectory = ReadLogTrajectory(spec);
  if (!trajectory.has_position || !trajectory.has_attitude)
    throw InputError(spec.path, 0, spec.topic,
                     std::string("carries no ") +
                         (trajectory.has_position ? "attitude" : "position") +
                         ": eval needs full poses (compare per quantity with `mavloc compare "
                         "--reference LOG:TOPIC`)");
  LoadedTrajectory out;
  out.poses.reserve(trajectory.states.size());
  for (const GroundTruthState& s : trajectory.states) out.poses.push_back({s.t_ns, s.T_W_B});
  if (trajectory.has_velocity)
    for (const GroundTruthState& s : trajectory.states)
      out.motion.push_back(TrajectoryMotion{s.v_W, s.b_g, s.b_a});
  out.report.path = path;
  out.report.format = TrajectoryFormat::kLog;
  out.report.layout =
      trajectory.type + " " + trajectory.parent_frame + " -> " + trajectory.child_frame;
  out.report.rows = trajectory.states.size();
  out.report.has_velocity = trajectory.has_velocity;
  for (const std::string& note : trajectory.notes)
    out.report.log_notes.push_back(spec.path + ": " + note);
  return out;
}

std::optional<TrajectoryFormat> ParseTrajectoryFormat(const std::string& name) {
  if (name == "auto") return TrajectoryFormat::kAuto;
  if (name == "tum") return TrajectoryFormat::kTum;
  if (name == "euroc") return TrajectoryFormat::kEuroc;
  if (name == "asl") return TrajectoryFormat::kAsl;
  if (name == "kitti") return TrajectoryFormat::kKitti;
  return std::nullopt;
}

std::string TrajectoryFormatName(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::kAuto:
      return "auto";
    case TrajectoryFormat::kTum:
      return "tum";
    case TrajectoryFormat::kEuroc:
      return "euroc";
    case TrajectoryFormat::kAsl:
      return "asl";
    case TrajectoryFormat::kKitti:
      return "kitti";
    case TrajectoryFormat::kLog:
      return "log";
  }
  return "?";
}

std::vector<GroundTruthState> LoadedTrajectory::States() const {
  std::vector<GroundTruthState> states(poses.size());
  for (size_t i = 0; i < poses.size(); ++i) {
    states[i].t_ns = poses[i].t_ns;
    states[i].T_W_B = poses[i].T_W_B;
    if (i < motion.size()) {
      states[i].v_W = motion[i].v_W;
      states[i].b_g = motion[i].b_g;
      states[i].b_a = motion[i].b_a;
    }
  }
  return states;
}

namespace {

// A KITTI pose file (and its times file): read whole, 12 numbers a row.
LoadedTrajectory ReadKittiTrajectory(const std::string& path, const TrajectoryReadOptions& options,
                                     LoadedTrajectory out) {
  TrajectoryReadReport& report = out.report;
  const TrajectoryText text = ReadTrajectoryText(path);
  report.rows = text.rows.size();
  report.had_crlf = text.had_crlf;
  const KittiRowsResult kitti = ParseKittiRows(text);
  ParsedRows rows;
  rows.poses.resize(kitti.poses.size());
  rows.lines.resize(kitti.poses.size());
  std::string stamp_path = path, stamp_field = "index";
  if (!options.times_path.empty()) {
    const KittiTimes times = ReadKittiTimes(options.times_path);
    if (times.t_ns.size() != kitti.poses.size())
      throw InputError(options.times_path, 0, "",
                       fmt::format("has {} stamps but '{}' has {} poses", times.t_ns.size(), path,
                                   kitti.poses.size()));
    for (size_t i = 0; i < rows.poses.size(); ++i) {
      rows.poses[i].t_ns = times.t_ns[i];
      rows.lines[i] = times.lines[i];
    }
    stamp_path = options.times_path;
    stamp_field = "timestamp";
    report.times_path = options.times_path;
  } else {
    report.has_stamps = false;
    for (size_t i = 0; i < rows.poses.size(); ++i) {
      rows.poses[i].t_ns = static_cast<TimeNs>(i) * kNsPerSecond;
      rows.lines[i] = kitti.lines[i];
    }
  }
  for (size_t i = 0; i < rows.poses.size(); ++i) rows.poses[i].T_W_B = kitti.poses[i];
  report.quaternions_normalised = kitti.rotations_projected;
  report.max_quaternion_norm_error = kitti.max_orthonormality_error;
  report.layout =
      options.times_path.empty()
          ? "kitti (12 columns: T_W_C 3x4 row-major; no times file: pose i at i s, "
            "associated by index)"
          : "kitti (12 columns: T_W_C 3x4 row-major; stamps from " + options.times_path + ")";
  OrderRows(std::move(rows), stamp_path, stamp_field, options, &out);
  return out;
}

}  // namespace

LoadedTrajectory ReadTrajectory(const std::string& path, const TrajectoryReadOptions& options) {
  if (const auto log_topic = ParseLogTopicSpec(path))
    return ReadLogTopicTrajectory(*log_topic, path, options);
  TrajectoryRowStream stream(path);
  long first_line = 0;
  std::string_view first_row;
  if (!stream.Next(&first_line, &first_row)) throw InputError(path, 0, "", "file has no data rows");
  const TrajectoryText head = HeadText(stream, first_line, first_row);
  LoadedTrajectory out;
  TrajectoryReadReport& report = out.report;
  report.path = path;
  report.had_bom = stream.had_bom();
  report.format_forced = options.format != TrajectoryFormat::kAuto;
  report.format = report.format_forced ? options.format : DetectTrajectoryFormat(head);
  if (!options.times_path.empty() && report.format != TrajectoryFormat::kKitti)
    throw InputError(options.times_path, 0, "",
                     "a times file is only used with KITTI pose files, and '" + path + "' is " +
                         TrajectoryFormatName(report.format));
  if (report.format == TrajectoryFormat::kKitti)
    return ReadKittiTrajectory(path, options, std::move(out));

  const PoseColumnLayout layout = ChooseLayout(head, report.format, report.format_forced);
  report.format = layout.format == TrajectoryFormat::kAsl || !report.format_forced ? layout.format
                                                                                   : report.format;
  report.layout = layout.description;
  ParsedRows rows = ParsePoseRows(head, &stream, layout, &report);
  report.rows = rows.poses.size();
  report.had_crlf = stream.had_crlf();
  OrderRows(std::move(rows), path, layout.Name(layout.t), options, &out);
  return out;
}

std::string DescribeRowFixes(const TrajectoryReadReport& report) {
  std::string text;
  if (report.rows_out_of_order > 0)
    text +=
        fmt::format("{}: {} rows out of time order sorted (--sort), first at {}:{}", report.path,
                    report.rows_out_of_order, report.path, report.first_out_of_order_line);
  if (report.duplicates_dropped > 0) {
    if (!text.empty()) text += "; ";
    text += fmt::format(
        "{}: {} row{} with a repeated timestamp dropped (kept the first), first at {}:{}",
        report.path, report.duplicates_dropped, report.duplicates_dropped == 1 ? "" : "s",
        report.times_path.empty() ? report.path : report.times_path, report.first_duplicate_line);
  }
  return text;
}

std::string DescribeRowsKept(const TrajectoryReadReport& report, size_t poses) {
  if (poses == report.rows) return "";
  const size_t dropped = report.rows > poses ? report.rows - poses : 0;
  const std::string why =
      dropped == report.duplicates_dropped
          ? fmt::format("{} with a repeated timestamp dropped, kept the first", dropped)
          : fmt::format("{} dropped", dropped);
  return fmt::format("{} of {} rows ({})", poses, report.rows, why);
}

}  // namespace mavloc

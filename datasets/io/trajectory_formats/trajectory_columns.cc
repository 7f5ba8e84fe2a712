#include "datasets/io/trajectory_formats/trajectory_columns.h"

#include <fmt/format.h>
#include <algorithm>
#include <cctype>
#include <numbers>

#include "core/errors.h"
#include "core/text.h"

namespace mavloc {

namespace {

enum class Role {
  kNone,
  kTime,
  kHeaderStamp,
  kPx,
  kPy,
  kPz,
  kQw,
  kQx,
  kQy,
  kQz,
  kVx,
  kVy,
  kVz,
  kBgx,
  kBgy,
  kBgz,
  kBax,
  kBay,
  kBaz,
  kRoll,
  kPitch,
  kYaw,
};

struct Normalised {
  std::string name;  // lower case, units removed, '.', ' ', '-' -> '_', no leading '#'/'%'
  std::string unit;  // text inside [] or () when present, lower case
};

Normalised Normalise(const std::string& raw) {
  Normalised n;
  std::string text;
  for (size_t i = 0; i < raw.size(); ++i) {
    const char c = raw[i];
    if (c == '[' || c == '(') {
      const size_t close = raw.find(c == '[' ? ']' : ')', i);
      if (close == std::string::npos) break;
      for (size_t k = i + 1; k < close; ++k)
        n.unit += static_cast<char>(std::tolower(static_cast<unsigned char>(raw[k])));
      i = close;
      continue;
    }
    text += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  while (!text.empty() && (text.front() == '#' || text.front() == '%' || text.front() == ' '))
    text.erase(text.begin());
  while (!text.empty() && text.back() == ' ') text.pop_back();
  for (char& c : text)
    if (c == '.' || c == ' ' || c == '-') c = '_';
  n.name = text;
  return n;
}

bool OneOf(const std::string& s, std::initializer_list<const char*> options) {
  return std::any_of(options.begin(), options.end(), [&](const char* o) { return s == o; });
}

// Per axis a in {x,y,z} (or w for quaternions): the spellings of the tools this field uses.
Role RoleOf(const std::string& name) {
  if (OneOf(name, {"timestamp", "time", "t", "stamp", "ts", "t_ns", "t_s", "timestamp_ns",
                   "timestamp_s", "time_ns", "time_s", "timestamp_sec", "sec", "seconds"}))
    return Role::kTime;
  if (name == "field_header_stamp" || name == "header_stamp") return Role::kHeaderStamp;
  static const char kAxes[] = {'x', 'y', 'z'};
  for (int k = 0; k < 3; ++k) {
    const std::string a(1, kAxes[k]);
    if (name == a || name == "t" + a || name == "p" + a || name == "p_" + a || name == "t_" + a ||
        name == "pos_" + a || name == "pos" + a || name == "position_" + a ||
        name == "p_rs_r_" + a || name == "p_ws_w_" + a || name == "p_wb_" + a ||
        name == "p_wi_" + a || EndsWith(name, "position_" + a))
      return static_cast<Role>(static_cast<int>(Role::kPx) + k);
    if (name == "v" + a || name == "v_" + a || name == "vel_" + a || name == "v_rs_r_" + a ||
        name == "v_ws_w_" + a || name == "v_w_" + a || name == "velocity_" + a)
      return static_cast<Role>(static_cast<int>(Role::kVx) + k);
    if (name == "bg" + a || name == "bw" + a || name == "b_g_" + a || name == "b_w_" + a ||
        name == "b_w_rs_s_" + a || name == "bg_" + a)
      return static_cast<Role>(static_cast<int>(Role::kBgx) + k);
    if (name == "ba" + a || name == "b_a_" + a || name == "b_a_rs_s_" + a || name == "ba_" + a)
      return static_cast<Role>(static_cast<int>(Role::kBax) + k);
  }
  if (name == "roll") return Role::kRoll;
  if (name == "pitch") return Role::kPitch;
  if (name == "yaw") return Role::kYaw;
  static const char kQuat[] = {'w', 'x', 'y', 'z'};
  for (int k = 0; k < 4; ++k) {
    const std::string c(1, kQuat[k]);
    if (name == "q" + c || name == "q_" + c || name == "q_rs_" + c || name == "q_ws_" + c ||
        name == "q_wb_" + c || name == "q_wi_" + c || name == "quat_" + c || name == "rot_" + c ||
        name == "qw_" + c || EndsWith(name, "orientation_" + c))
      return static_cast<Role>(static_cast<int>(Role::kQw) + k);
  }
  return Role::kNone;
}

void Assign(PoseColumnLayout* layout, Role role, int column, bool* header_stamp_seen) {
  switch (role) {
    case Role::kTime:
      if (layout->t < 0 && !*header_stamp_seen) layout->t = column;
      break;
    case Role::kHeaderStamp:  // rostopic CSVs: the message's stamp wins over the receive time
      layout->t = column;
      *header_stamp_seen = true;
      break;
    case Role::kPx:
    case Role::kPy:
    case Role::kPz: {
      int& slot = layout->p[static_cast<int>(role) - static_cast<int>(Role::kPx)];
      if (slot < 0) slot = column;
      break;
    }
    case Role::kQw:
    case Role::kQx:
    case Role::kQy:
    case Role::kQz: {
      int& slot = layout->q_wxyz[static_cast<int>(role) - static_cast<int>(Role::kQw)];
      if (slot < 0) slot = column;
      break;
    }
    case Role::kVx:
    case Role::kVy:
    case Role::kVz: {
      int& slot = layout->v[static_cast<int>(role) - static_cast<int>(Role::kVx)];
      if (slot < 0) slot = column;
      break;
    }
    case Role::kBgx:
    case Role::kBgy:
    case Role::kBgz: {
      int& slot = layout->b_g[static_cast<int>(role) - static_cast<int>(Role::kBgx)];
      if (slot < 0) slot = column;
      break;
    }
    case Role::kBax:
    case Role::kBay:
    case Role::kBaz: {
      int& slot = layout->b_a[static_cast<int>(role) - static_cast<int>(Role::kBax)];
      if (slot < 0) slot = column;
      break;
    }
    case Role::kRoll:
    case Role::kPitch:
    case Role::kYaw: {
      int& slot = layout->rpy[static_cast<int>(role) - static_cast<int>(Role::kRoll)];
      if (slot < 0) slot = column;
      break;
    }
    case Role::kNone:
      break;
  }
}

bool AllSet(const std::array<int, 3>& columns) {
  return std::all_of(columns.begin(), columns.end(), [](int c) { return c >= 0; });
}

bool Complete(const PoseColumnLayout& l) {
  return l.t >= 0 && AllSet(l.p) && (l.HasQuaternion() || l.HasRollPitchYaw());
}

size_t MaxColumn(const PoseColumnLayout& l) {
  int m = l.t;
  for (int c : l.p) m = std::max(m, c);
  for (int c : l.q_wxyz) m = std::max(m, c);
  for (int c : l.rpy) m = std::max(m, c);
  return static_cast<size_t>(m) + 1;
}

// Whether the header names a timestamp and a position: then it describes the columns, and rows
// are never read by position instead (a positional layout would take other columns for the
// quaternion).
bool NamesStampAndPosition(const TrajectoryText& text) {
  PoseColumnLayout l;
  bool header_stamp_seen = false;
  for (size_t k = 0; k < text.header.size(); ++k)
    Assign(&l, RoleOf(Normalise(text.header[k]).name), static_cast<int>(k), &header_stamp_seen);
  return l.t >= 0 && AllSet(l.p);
}

// A comma row's stamp written with a decimal point is in seconds: the row is TUM's, not EuRoC's
// (whose stamps are integer nanoseconds).
bool DecimalStamp(const std::vector<std::string_view>& fields) {
  return !fields.empty() && fields[0].find('.') != std::string_view::npos;
}

// OpenVINS ov_msckf's state file names groups, not columns: "timestamp(s) q p v bg ba ...".
std::optional<PoseColumnLayout> OpenVinsGroupLayout(const std::vector<std::string>& header) {
  if (header.size() < 3) return std::nullopt;
  if (Normalise(header[0]).name != "timestamp" || Normalise(header[1]).name != "q" ||
      Normalise(header[2]).name != "p")
    return std::nullopt;
  PoseColumnLayout l;
  l.format = TrajectoryFormat::kAsl;
  l.t = 0;
  l.q_wxyz = {4, 1, 2, 3};  // stored x, y, z, w
  l.p = {5, 6, 7};
  l.names = {"timestamp", "qx", "qy", "qz", "qw", "px", "py", "pz"};
  size_t column = 8;
  for (size_t k = 3; k < header.size(); ++k) {
    const std::string g = Normalise(header[k]).name;
    std::array<int, 3>* target = g == "v"    ? &l.v
                                 : g == "bg" ? &l.b_g
                                 : g == "ba" ? &l.b_a
                                             : nullptr;
    if (target == nullptr) break;
    for (int a = 0; a < 3; ++a) {
      (*target)[a] = static_cast<int>(column + a);
      l.names.push_back(g + std::string(1, "xyz"[a]));
    }
    column += 3;
  }
  l.unit = StampUnit::kSeconds;
  l.min_fields = 8;
  l.description =
      "asl (OpenVINS state file by header groups: timestamp(s) q(JPL q_GtoI: x,y,z,w) p"
      "...)";
  return l;
}

}  // namespace

std::string PoseColumnLayout::Name(size_t k) const {
  if (k < names.size() && !names[k].empty()) return names[k];
  return "column " + std::to_string(k + 1);
}

bool PoseColumnLayout::HasQuaternion() const {
  return std::all_of(q_wxyz.begin(), q_wxyz.end(), [](int c) { return c >= 0; });
}

bool PoseColumnLayout::HasRollPitchYaw() const { return AllSet(rpy); }

bool PoseColumnLayout::HasBiases() const {
  for (int c : b_g)
    if (c < 0) return false;
  for (int c : b_a)
    if (c < 0) return false;
  return true;
}

PoseColumnLayout TumLayout(size_t fields) {
  PoseColumnLayout l;
  l.format = TrajectoryFormat::kTum;
  l.t = 0;
  l.p = {1, 2, 3};
  l.q_wxyz = {7, 4, 5, 6};
  l.unit = StampUnit::kSeconds;
  l.names = {"timestamp", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};
  l.min_fields = 8;
  l.exact_fields = fields == 20 ? 20 : 8;
  l.description = fields == 20 ? "tum (20 columns: OpenVINS ov_eval pose + covariance, "
                                 "covariance ignored)"
                               : "tum (8 columns: timestamp tx ty tz qx qy qz qw)";
  return l;
}

PoseColumnLayout EurocLayout(size_t fields) {
  PoseColumnLayout l;
  l.format = TrajectoryFormat::kEuroc;
  l.t = 0;
  l.p = {1, 2, 3};
  l.q_wxyz = {4, 5, 6, 7};
  l.unit = StampUnit::kNanoseconds;
  l.names = {"timestamp [ns]", "p_x", "p_y", "p_z", "q_w", "q_x", "q_y", "q_z"};
  l.min_fields = fields >= 17 ? 17 : fields >= 11 ? 11 : 8;
  if (fields >= 11) {
    l.v = {8, 9, 10};
    for (const char* n : {"v_x", "v_y", "v_z"}) l.names.push_back(n);
  }
  if (fields >= 17) {
    l.b_g = {11, 12, 13};
    l.b_a = {14, 15, 16};
    for (const char* n : {"b_w_x", "b_w_y", "b_w_z", "b_a_x", "b_a_y", "b_a_z"})
      l.names.push_back(n);
  }
  l.description =
      fields >= 17 ? fmt::format("euroc ({} columns: t_ns p q_wxyz v b_w b_a)", fields)
      : fields >= 11
          ? fmt::format("euroc ({} columns: t_ns p q_wxyz v, the VINS-Fusion layout)", fields)
          : fmt::format("euroc ({} columns: t_ns p q_wxyz)", fields);
  return l;
}

std::optional<PoseColumnLayout> LayoutFromHeader(const TrajectoryText& text) {
  if (text.header.empty()) return std::nullopt;
  if (auto groups = OpenVinsGroupLayout(text.header)) return groups;
  PoseColumnLayout l;
  l.format = TrajectoryFormat::kAsl;
  bool header_stamp_seen = false;
  bool euroc_names = false, tum_names = false;
  for (size_t k = 0; k < text.header.size(); ++k) {
    const Normalised n = Normalise(text.header[k]);
    l.names.push_back(text.header[k]);
    Assign(&l, RoleOf(n.name), static_cast<int>(k), &header_stamp_seen);
    if (n.name == "p_rs_r_x") euroc_names = true;
    if (n.name == "tx") tum_names = true;
  }
  if (!Complete(l)) return std::nullopt;
  if (l.HasQuaternion()) l.rpy = {-1, -1, -1};
  if (l.HasRollPitchYaw()) {
    const std::string unit = Normalise(text.header[l.rpy[0]]).unit;
    l.rpy_to_rad = unit == "deg" || unit == "degrees" ? std::numbers::pi / 180.0 : 1.0;
  }
  l.min_fields = MaxColumn(l);
  for (const auto* group : {&l.v, &l.b_g, &l.b_a})
    for (int c : *group) l.min_fields = std::max(l.min_fields, static_cast<size_t>(c + 1));
  // The stamp's unit: stated in the header ("[ns]", "(s)", "_ns", "_s"), else the convention of
  // the file's kind: TUM names and whitespace tables are seconds, ASL CSVs nanoseconds unless the
  // first stamp is written with a fraction.
  const Normalised stamp = Normalise(text.header[l.t]);
  const std::string& name = stamp.name;
  if (stamp.unit == "ns" || EndsWith(name, "_ns") || name == "field_header_stamp") {
    l.unit = StampUnit::kNanoseconds;
    l.unit_stated = true;
  } else if (stamp.unit == "s" || stamp.unit == "sec" || EndsWith(name, "_s") ||
             EndsWith(name, "_sec") || name == "sec" || name == "seconds") {
    l.unit = StampUnit::kSeconds;
    l.unit_stated = true;
  } else if (tum_names || !text.comma_separated)
    l.unit = StampUnit::kSeconds;
  else {
    const std::vector<std::string_view> fields =
        text.rows.empty() ? std::vector<std::string_view>() : text.Fields(text.rows[0]);
    const std::string_view first =
        static_cast<size_t>(l.t) >= fields.size() ? std::string_view() : fields[l.t];
    l.unit = first.find_first_not_of("0123456789") == std::string_view::npos
                 ? StampUnit::kNanoseconds
                 : StampUnit::kSeconds;
  }
  if (euroc_names) l.format = TrajectoryFormat::kEuroc;
  if (tum_names && !text.comma_separated) l.format = TrajectoryFormat::kTum;
  l.description =
      fmt::format("{} (columns by header name: '{}'; stamps in {})", TrajectoryFormatName(l.format),
                  text.header_line, l.unit == StampUnit::kSeconds ? "seconds" : "nanoseconds");
  return l;
}

TrajectoryFormat DetectTrajectoryFormat(const TrajectoryText& text) {
  if (text.rows.empty()) throw InputError(text.path, 0, "", "file has no data rows");
  if (auto layout = LayoutFromHeader(text)) return layout->format;
  const TrajectoryRow& first = text.rows.front();
  const std::vector<std::string_view> first_fields = text.Fields(first);
  const size_t n = first_fields.size();
  if (NamesStampAndPosition(text))
    throw InputError(text.path, 0, "",
                     "the header '" + text.header_line +
                         "' names a timestamp and a position but no attitude (qw,qx,qy,qz or "
                         "roll,pitch,yaw): the rows hold no pose");
  if (!text.comma_separated) {
    if (n == 8 || n == 20) return TrajectoryFormat::kTum;
    if (n == 12) return TrajectoryFormat::kKitti;
    throw InputError(text.path, first.line, "",
                     fmt::format("cannot tell the format from {} whitespace-separated fields "
                                 "(TUM has 8 or, from ov_eval, 20; KITTI 12); no header names the "
                                 "columns; force one with --gt-format/--est-format (eval) or "
                                 "--in-format (convert)",
                                 n));
  }
  if (DecimalStamp(first_fields)) {
    if (n == 8 || n == 20) return TrajectoryFormat::kTum;
    throw InputError(text.path, first.line, "",
                     fmt::format("a comma row whose stamp '{}' has a decimal point is a TUM row in "
                                 "seconds (8 fields: timestamp tx ty tz qx qy qz qw), but this one "
                                 "has {}; name the columns in a header line (e.g. "
                                 "'#timestamp [s],x,y,z,qw,qx,qy,qz')",
                                 first_fields[0], n));
  }
  if (n >= 8) return TrajectoryFormat::kEuroc;
  throw InputError(text.path, first.line, "",
                   fmt::format("cannot tell the format from {} comma-separated fields (EuRoC/ASL "
                               "has at least 8: t_ns, p, q_wxyz) and no header names the columns",
                               n));
}

}  // namespace mavloc

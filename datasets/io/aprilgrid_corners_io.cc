#include "datasets/io/aprilgrid_corners_io.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string_view>

#include "core/errors.h"
#include "core/input_file.h"
#include "core/number_text.h"
#include "core/physical_limits.h"

namespace fs = std::filesystem;

namespace mavloc {

namespace {

constexpr std::array<const char*, 12> kColumns = {
    "ts",   "tag_rows", "tag_cols", "tag_size", "tag_spacing", "kp_x",
    "kp_y", "p_x",      "p_y",      "p_z",      "tag_id",      "corner_idx"};
enum Column { kTs, kRows, kCols, kSize, kSpacing, kKpX, kKpY, kPx, kPy, kPz, kTagId, kCornerIdx };

std::string_view TrimCsvField(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r'))
    text.remove_suffix(1);
  return text;
}

// Splits on ',' into at most `max` fields; returns the number of fields found (which may exceed
// max: the rest is not stored).
size_t Split(std::string_view line, std::array<std::string_view, 12>* fields) {
  size_t count = 0;
  size_t begin = 0;
  while (true) {
    const size_t comma = line.find(',', begin);
    const std::string_view field = TrimCsvField(
        line.substr(begin, comma == std::string_view::npos ? line.npos : comma - begin));
    if (count < fields->size()) (*fields)[count] = field;
    ++count;
    if (comma == std::string_view::npos) return count;
    begin = comma + 1;
  }
}

std::optional<TimeNs> ParseTimestamp(std::string_view text) {
  if (text.empty() || text.front() == '-' || text.front() == '+') return std::nullopt;
  const ParsedNumber<long long> value = ParseIntegerText(text);
  if (!value.ok()) return std::nullopt;
  return value.value;
}

class FileParser {
 public:
  FileParser(const std::string& path, const AprilgridTarget& target,
             const AprilgridCornerFileOptions& options, TimeNs t_ns)
      : path_(path), target_(target), options_(options), t_ns_(t_ns) {}

  // column: an index of kColumns, one past them (an extra column), or -1 (no field).
  [[noreturn]] void Fail(long line, int column, const std::string& message) const {
    const int count = static_cast<int>(kColumns.size());
    throw InputError(path_, line,
                     column < 0       ? ""
                     : column < count ? std::string(kColumns[column])
                                      : "column " + std::to_string(column + 1),
                     message);
  }

  double Number(long line, int column, std::string_view text) const {
    const ParsedNumber<double> value = ParseDoubleText(text);
    if (!value.ok()) Fail(line, column, DescribeNumberText(text, value));
    return value.value;
  }

  int Integer(long line, int column, std::string_view text) const {
    const ParsedNumber<long long> value = ParseIntegerText(text);
    if (!value.ok()) Fail(line, column, DescribeNumberText(text, value, "an integer"));
    if (value.value < std::numeric_limits<int>::min() ||
        value.value > std::numeric_limits<int>::max())
      Fail(line, column, fmt::format("'{}' is out of range (not an int)", text));
    return static_cast<int>(value.value);
  }

  void Header(long line, std::string_view text) const {
    text.remove_prefix(1);  // '#'
    std::array<std::string_view, 12> names;
    const size_t count = Split(text, &names);
    for (size_t k = 0; k < kColumns.size(); ++k) {
      if (k >= count || names[k] != kColumns[k])
        Fail(line, static_cast<int>(k),
             fmt::format("header column {} is '{}', expected '{}' (columns: ts, tag_rows, "
                         "tag_cols, tag_size, tag_spacing, kp_x, kp_y, p_x, p_y, p_z, tag_id, "
                         "corner_idx)",
                         k + 1, k < count ? std::string(names[k]) : "", kColumns[k]));
    }
    if (count != kColumns.size())
      Fail(line, static_cast<int>(kColumns.size()),
           fmt::format("header has {} columns, expected 12", count));
  }

  void Row(long line, std::string_view text) {
    std::array<std::string_view, 12> f;
    const size_t count = Split(text, &f);
    if (count != kColumns.size())
      Fail(line, static_cast<int>(std::min(count, kColumns.size())),
           fmt::format("expected 12 columns, found {}", count));
    const auto ts = ParseTimestamp(f[kTs]);
    if (!ts) Fail(line, kTs, fmt::format("'{}' is not a timestamp in nanoseconds", f[kTs]));
    if (*ts != t_ns_)
      Fail(line, kTs, fmt::format("{} disagrees with the file name's timestamp {}", *ts, t_ns_));
    const int rows = Integer(line, kRows, f[kRows]);
    const int cols = Integer(line, kCols, f[kCols]);
    if (rows != target_.tag_rows)
      Fail(line, kRows, fmt::format("{} disagrees with the target's {}", rows, target_.tag_rows));
    if (cols != target_.tag_cols)
      Fail(line, kCols, fmt::format("{} disagrees with the target's {}", cols, target_.tag_cols));
    const double size = Number(line, kSize, f[kSize]);
    const double spacing = Number(line, kSpacing, f[kSpacing]);
    const double tolerance = options_.grid_tolerance_m;
    if (std::abs(size - target_.tag_size_m) > tolerance)
      Fail(line, kSize,
           fmt::format("{} disagrees with the target's {} m", f[kSize], target_.tag_size_m));
    if (std::abs(spacing - target_.tag_spacing) > tolerance)
      Fail(line, kSpacing,
           fmt::format("{} disagrees with the target's {}", f[kSpacing], target_.tag_spacing));
    const Eigen::Vector2d kp(Number(line, kKpX, f[kKpX]), Number(line, kKpY, f[kKpY]));
    if (options_.image_size) {
      const Eigen::Vector2i& size_px = *options_.image_size;
      for (int i = 0; i < 2; ++i) {
        if (kp[i] < -0.5 || kp[i] > size_px[i] - 0.5)
          Fail(line, kKpX + i,
               fmt::format("{} is outside the {}x{} image", kp[i], size_px.x(), size_px.y()));
      }
    }
    const Eigen::Vector3d p(Number(line, kPx, f[kPx]), Number(line, kPy, f[kPy]),
                            Number(line, kPz, f[kPz]));
    const int tag_id = Integer(line, kTagId, f[kTagId]);
    if (tag_id < 0 || tag_id >= target_.NumTags())
      Fail(line, kTagId,
           fmt::format("{} is not a tag of the {}x{} aprilgrid (ids 0..{})", tag_id,
                       target_.tag_rows, target_.tag_cols, target_.NumTags() - 1));
    const int corner = Integer(line, kCornerIdx, f[kCornerIdx]);
    if (corner < 0 || corner > 3) Fail(line, kCornerIdx, fmt::format("{} is not 0..3", corner));
    const Eigen::Vector3d expected = AprilgridCorner(target_, tag_id, corner);
    for (int i = 0; i < 3; ++i) {
      if (std::abs(p[i] - expected[i]) > tolerance)
        Fail(line, kPx + i,
             fmt::format("grid point ({}, {}, {}) is not tag {} corner {} of the target, which "
                         "is at ({:.6f}, {:.6f}, {:.6f}) m",
                         f[kPx], f[kPy], f[kPz], tag_id, corner, expected.x(), expected.y(),
                         expected.z()));
    }
    Partial& partial = tags_[tag_id];
    if (partial.line[corner] > 0)
      Fail(line, kCornerIdx,
           fmt::format("tag {} corner {} listed twice (first on line {})", tag_id, corner,
                       partial.line[corner]));
    partial.line[corner] = line;
    partial.corners_px[corner] = kp;
    ++corners_;
  }

  AprilgridCornerFrame Finish() const {
    AprilgridCornerFrame frame;
    frame.t_ns = t_ns_;
    frame.corners = corners_;
    for (const auto& [id, partial] : tags_) {
      const int seen = static_cast<int>(
          std::count_if(partial.line.begin(), partial.line.end(), [](long l) { return l > 0; }));
      if (seen < 4) {
        ++frame.incomplete_tags;
        frame.incomplete_corners += seen;
        continue;
      }
      TagObservation tag;
      tag.t_ns = t_ns_;
      tag.tag_id = id;
      tag.camera = options_.camera;
      tag.corners_px = partial.corners_px;
      frame.tags.push_back(tag);
    }
    return frame;
  }

 private:
  struct Partial {
    std::array<long, 4> line{0, 0, 0, 0};
    std::array<Eigen::Vector2d, 4> corners_px{};
  };
  const std::string& path_;
  const AprilgridTarget& target_;
  const AprilgridCornerFileOptions& options_;
  TimeNs t_ns_;
  std::map<int, Partial> tags_;
  int corners_ = 0;
};

TimeNs StemTimestamp(const fs::path& path) {
  const std::string stem = path.stem().string();
  const auto t = ParseTimestamp(stem);
  if (!t)
    throw InputError(path.string(), 0, "",
                     "file name '" + stem + "' is not a timestamp in nanoseconds");
  // The file name is the frame's ts (each row's ts must equal it): the range of every timestamp.
  if (*t > limits::kMaxTimestampNs)
    throw InputError(path.string(), 0, kColumns[kTs],
                     fmt::format("the file name's timestamp {} ns is beyond {} ns (year 2116)",
                                 stem, limits::kMaxTimestampNs));
  return *t;
}

}  // namespace

AprilgridCornerFrame ReadAprilgridCornerFile(const std::string& path, const AprilgridTarget& target,
                                             const AprilgridCornerFileOptions& options) {
  const TimeNs t_ns = StemTimestamp(fs::path(path));
  std::string text = ReadRegularFile(path);                  // a pipe, a device, a loop: refused
  if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);  // UTF-8 BOM, as text_table.cc
  FileParser parser(path, target, options, t_ns);
  long line_number = 0;
  bool header_seen = false;
  size_t begin = 0;
  while (begin < text.size()) {
    size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    const std::string_view line = TrimCsvField(std::string_view(text).substr(begin, end - begin));
    begin = end + 1;
    ++line_number;
    if (line.empty()) continue;
    if (line.front() == '#') {
      if (!header_seen) parser.Header(line_number, line);
      header_seen = true;
      continue;
    }
    header_seen = true;
    parser.Row(line_number, line);
  }
  return parser.Finish();
}

AprilgridCornerLog ReadAprilgridCornerFolder(const std::string& folder,
                                             const AprilgridTarget& target,
                                             const AprilgridCornerFileOptions& options) {
  if (!fs::is_directory(folder))
    throw InputError(folder, 0, "",
                     fs::exists(folder) ? "is not a folder of corner files" : "does not exist");
  std::vector<std::pair<TimeNs, fs::path>> files;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (!entry.is_regular_file() || entry.path().extension() != ".csv") continue;
    files.emplace_back(StemTimestamp(entry.path()), entry.path());
  }
  if (files.empty()) throw InputError(folder, 0, "", "holds no <timestamp>.csv corner files");
  std::sort(files.begin(), files.end());
  for (size_t i = 1; i < files.size(); ++i) {
    if (files[i].first == files[i - 1].first)
      throw InputError(files[i].second.string(), 0, "",
                       fmt::format("frame {} listed twice (also {})", files[i].first,
                                   files[i - 1].second.filename().string()));
  }
  AprilgridCornerLog log;
  log.frames_ns.reserve(files.size());
  for (const auto& [t_ns, path] : files) {
    AprilgridCornerFrame frame = ReadAprilgridCornerFile(path.string(), target, options);
    log.frames_ns.push_back(t_ns);
    ++log.stats.frames;
    if (frame.corners == 0) ++log.stats.empty_frames;
    log.stats.corners += frame.corners;
    log.stats.tags += static_cast<long>(frame.tags.size());
    log.stats.incomplete_tags += frame.incomplete_tags;
    log.stats.incomplete_corners += frame.incomplete_corners;
    log.tags.insert(log.tags.end(), frame.tags.begin(), frame.tags.end());
  }
  return log;
}

}  // namespace mavloc

// Reading per-image aprilgrid corner files, the layout yac (chutsu/yac `aprilgrid_t::save`) writes
// for Kalibr-style calibration logs such as EuRoC's imu_april: one file <timestamp ns>.csv per
// image, header
// `#ts,tag_rows,tag_cols,tag_size,tag_spacing,kp_x,kp_y,p_x,p_y,p_z,tag_id,corner_idx`, one row per
// detected corner: kp = the distorted pixel position (OpenCV convention, pixel centres at integer
// coordinates, as mavloc's tags0), p = the grid point in the board frame M [m], corner_idx 0..3 as
// core/aprilgrid.h (which is mavloc's corner order). A file with only the header is an image
// without detections.
//
// A frame's rows are grouped by tag into TagObservations (corners in corner_idx order); a tag with
// fewer than 4 corners is skipped and counted. Everything else that is inconsistent is an
// InputError naming the file, line and field: a wrong number of columns, a value that is not a
// finite number, ts disagreeing with the file name, the grid's tag_rows/tag_cols/tag_size/
// tag_spacing columns disagreeing with the target, tag_id or corner_idx out of range, a grid point
// p farther than 1e-6 m from AprilgridCorner(tag_id, corner_idx), a corner listed twice, a pixel
// outside the image (when its size is given), and two files with the same timestamp.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/aprilgrid.h"
#include "core/dataset.h"

namespace mavloc {

struct AprilgridCornerFileOptions {
  int camera = 0;                             // TagObservation::camera
  std::optional<Eigen::Vector2i> image_size;  // check kp within [-0.5, size - 0.5]
  double grid_tolerance_m = 1e-6;             // p vs AprilgridCorner and the tag_size column
};

struct AprilgridCornerFrame {
  TimeNs t_ns = 0;
  std::vector<TagObservation> tags;  // complete tags, by tag id
  int corners = 0;                   // rows read
  int incomplete_tags = 0;           // tags with 1-3 corners (skipped)
  int incomplete_corners = 0;        // their corners
};

struct AprilgridCornerStats {
  int frames = 0;
  int empty_frames = 0;  // header-only files
  long tags = 0;         // complete tags kept
  long corners = 0;      // rows read
  long incomplete_tags = 0;
  long incomplete_corners = 0;
};

struct AprilgridCornerLog {
  std::vector<TimeNs> frames_ns;     // every file, increasing (including empty frames)
  std::vector<TagObservation> tags;  // by time, then tag id
  AprilgridCornerStats stats;
};

// One file; its name's stem must be the timestamp [ns].
AprilgridCornerFrame ReadAprilgridCornerFile(const std::string& path, const AprilgridTarget& target,
                                             const AprilgridCornerFileOptions& options = {});

// Every *.csv of a folder (other files are ignored), one at a time, in timestamp order. Throws
// InputError for a missing folder, a folder without corner files, or any bad file.
AprilgridCornerLog ReadAprilgridCornerFolder(const std::string& folder,
                                             const AprilgridTarget& target,
                                             const AprilgridCornerFileOptions& options = {});

}  // namespace mavloc

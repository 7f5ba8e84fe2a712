// Reading and writing ASL/EuRoC dataset folders and mavloc's extension streams (DESIGN.md,
// "Datasets on disk"). Real EuRoC sequences load unchanged; sensor.yaml is accepted with or without
// the "%YAML:1.0" first line. Bad input throws InputError naming the file, line and field.
// Tag streams: mav0/tags0 (cam0) and mav0/tags1 (cam1, TagObservation::camera = 1), same columns.
// map.yaml's optional `frame: world|board` is WorldMap::frame (absent = world).
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "datasets/io/trajectory_formats/trajectory_format.h"

namespace mavloc {

struct EurocReadOptions {
  bool load_cameras = true;  // cam0/cam1 lists (images themselves are loaded on demand)
};

// Reads <root>/mav0/... and <root>/map.yaml, <root>/scenario.yaml when present. Images listed in a
// camera's data.csv but absent on disk are collected in CameraSensor::missing_images (not an
// error). Throws InputError for a missing folder, malformed rows, NaN/inf values, and
// non-increasing or duplicate timestamps.
Dataset ReadEurocDataset(const std::string& root, const EurocReadOptions& options = {});

// Writes the dataset in the same layout. Every file is written to a temporary name and renamed,
// so a failure never leaves a half-written file.
void WriteEurocDataset(const Dataset& dataset, const std::string& root);

// WriteEurocDataset into "<root>.tmp-<pid>" (plus extra_files: path relative to root -> text),
// then renamed to root: on any error nothing is left at root. root must not exist or be an empty
// folder, unless replace (the old folder is then swapped out after the new one is complete).
void WriteEurocDatasetAtomically(const Dataset& dataset, const std::string& root,
                                 const std::map<std::string, std::string>& extra_files = {},
                                 bool replace = false);

// An IMU CSV with EuRoC imu0's columns: timestamp [ns], w_x, w_y, w_z [rad/s], a_x, a_y, a_z
// [m/s^2] (yac/Kalibr logs: "#ts,wx,wy,wz,ax,ay,az"). Strictly increasing stamps.
std::vector<ImuSample> ReadImuCsv(const std::string& path);

// The streaming form of ReadImuCsv: `visit` gets each sample as its row is parsed (block reads,
// std::from_chars; memory does not grow with the file). Bad input throws the InputError
// ReadImuCsv throws (file, line, field), at the first bad row: the samples before it have been
// visited by then.
void ForEachImuCsvSample(const std::string& path,
                         const std::function<void(const ImuSample&)>& visit);

// The text of the tags0 stream ("#timestamp [ns],tag_id,u0 [px],v0 [px],...,v3 [px]"), as
// WriteEurocDataset writes it; `mavloc detect-tags` writes its detections with it too.
std::string TagsCsv(const std::vector<TagObservation>& tags);

// The text of a features0/features1 stream ("#timestamp [ns],landmark_id,x [normalized],
// y [normalized]"), as WriteEurocDataset writes it; `mavloc track-features` writes its tracks with
// it too.
std::string FeaturesCsv(const std::vector<FeatureObservation>& features);

// Reads a trajectory file in any format ReadTrajectory detects from its content
// (trajectory_formats/trajectory_format.h: TUM, EuRoC state_groundtruth CSV with or without v,
// b_w, b_a, ASL CSVs by header names, KITTI): repeated stamps keep the first row (counted in
// *report when given).
std::vector<GroundTruthState> ReadTrajectoryFile(const std::string& path,
                                                 TrajectoryReadReport* report = nullptr);

}  // namespace mavloc

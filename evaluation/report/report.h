// The results model: every report mavloc writes (compare, eval, sweep, obstacles, every
// reproduction) is one Report, written by one writer (report_folder.h) as report.json (one
// versioned JSON Schema, schemas/report.schema.json), report.md and CSV files.
//
// Values are SI (m, rad, s, m/s); every metric states its unit beside it. Degrees and millimetres
// appear only in the Markdown tables for people (report_markdown.h). Statistics are the evo
// statistics of trajectory_metrics.h (count, rmse, mean, median, population std, min, max) over
// the per-pair errors of one run.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "evaluation/trajectory_metrics.h"

namespace mavloc {

// The schema report.json follows (schemas/report.schema.json "$id" ends with this).
inline constexpr const char* kReportSchema = "mavloc-report/1";

// Who wrote the report and how: enough to run it again.
struct Provenance {
  std::string command;  // "mavloc compare --scenario ..." (the arguments as given)
  std::string version;  // mavloc's version
  std::string input;    // dataset folder, scenario name, or the truth file
  std::vector<uint64_t> seeds;
  int runs = 1;  // Monte-Carlo runs or files per estimate
  int jobs = 1;
  std::map<std::string, std::string> settings;  // scenario settings, estimator options
  double elapsed_s = 0.0;
};

// How estimates were compared with the truth (or the reference). Absent for reports that compare
// no trajectories (obstacles).
struct ReportProtocol {
  std::string reference = "truth";  // "truth", or "estimate" when against a reference estimate
  std::string alignment = "none";   // none, se3, sim3, posyaw, origin
  std::string association = "interpolate";  // nearest, interpolate, index
  double max_dt_s = 0.02;
  double time_offset_s = 0.0;
  std::string pose_relation = "translation";  // the headline APE relation
};

// How much of an estimate the numbers cover.
struct Coverage {
  std::size_t pairs = 0;           // poses compared
  std::size_t estimate_poses = 0;  // poses in the estimate
  double overlap_s = 0.0;          // seconds between the first and last compared pose
  double estimate_span_s = 0.0;    // seconds between the estimate's first and last pose
  double Fraction() const { return estimate_span_s > 0.0 ? overlap_s / estimate_span_s : 0.0; }
};

// A truth-covered fraction of an estimate below this is warned about in every table.
inline constexpr double kLowCoverageFraction = 0.9;

// A number with its unit: either one value or the statistics of a set of errors.
struct Metric {
  std::string unit;  // SI: "m", "rad", "s", "m/s", "%", "" (a count or a ratio)
  std::optional<double> value;
  std::optional<ErrorStatistics> statistics;
};

// An estimated constant (calibration, board tilt) with its standard deviation when known.
struct EstimatedValue {
  double value = 0.0;
  std::optional<double> sigma;
  std::string unit;
};

struct EstimatorResult {
  std::string name;  // estimator or estimate label
  bool ran = true;
  std::string skipped_reason;  // when !ran
  bool is_reference = false;   // the reference the others are compared with
  std::optional<Coverage> coverage;
  // "ate_translation" [m], "ate_rotation" [rad] (the angle of the rotation error, never Euler
  // differences), per-quantity errors by quantity name ("x", "roll", ...), reprojection, ...
  std::map<std::string, Metric> metrics;
  // Estimated constants: calibration (T_B_C parts, time offset), board tilt, solution statistics.
  std::map<std::string, EstimatedValue> parameters;
  int frames_without_pose = 0;          // frames the estimator gave no solution for
  int rejected_measurements = 0;        // measurements gated out (filters)
  std::map<std::string, int> failures;  // frames without a pose, by reason
  double runtime_s = 0.0;
  std::vector<std::string> warnings;
};

// A table for people and tools (a paper's table, a sweep's cells): columns with their units, rows
// of cells (numbers in the column's SI unit, or text; null for no value).
struct ReportTable {
  struct Column {
    std::string name;
    std::string unit;  // SI unit of the column's numbers; "" for text or counts
    // The unit people read in report.md ("ms" for "s", "mm" for "m"); "" for the default
    // (degrees for angles, else the SI unit). report.json keeps SI.
    std::string display_unit = {};
  };
  std::string name;   // identifier ("table1", "cells")
  std::string title;  // one sentence
  std::vector<Column> columns;
  std::vector<std::vector<nlohmann::json>> rows;
};

// A section of prose for people (a reproduction's discussion of its paper's numbers).
struct ReportSection {
  std::string title;
  std::string markdown;
  bool before_tables = false;  // shown before the tables (a setup), else after them (findings)
};

struct Report {
  std::string kind;  // compare, eval, sweep, obstacles, repro
  std::string title;
  Provenance provenance;
  std::optional<ReportProtocol> protocol;
  std::vector<EstimatorResult> estimators;
  std::vector<ReportTable> tables;
  std::vector<ReportSection> sections;
  std::vector<std::string> warnings;
  // Producer-specific detail (a reproduction's per-run numbers, the Cramér–Rao bound): part of the
  // schema as an object, its keys are the producer's.
  nlohmann::json details = nlohmann::json::object();
  // CSV and other files written beside report.json: name -> contents.
  std::map<std::string, std::string> files;
};

}  // namespace mavloc

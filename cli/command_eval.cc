// mavloc eval: several estimates (files, or folders of runs of one estimator) against one ground
// truth, with the metrics and options of evo (evo_ape / evo_rpe) and rpg_trajectory_evaluation
// (evaluation/trajectory_evaluation.h), in any trajectory format mavloc reads
// (datasets/io/trajectory_formats/trajectory_format.h). Prints one table (estimates x metrics,
// mean and standard deviation over runs); --out DIR writes the report folder of eval_report.h and
// its figures (evaluation/report_figures.h); --json FILE writes report.json alone.
#include <fmt/format.h>

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <future>
#include <map>
#include <optional>
#include <set>

#include "cli/commands.h"
#include "cli/option_checks.h"
#include "cli/output_folder.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "datasets/io/log_reader.h"
#include "datasets/io/trajectory_formats/trajectory_format.h"
#include "evaluation/eval/eval_report.h"
#include "evaluation/report/report_folder.h"
#include "evaluation/report_figures.h"
#include "evaluation/trajectory_evaluation.h"

namespace mavloc::cli {

namespace {

namespace fs = std::filesystem;

struct Args {
  std::string gt, gt_format = "auto", gt_times, out, json;
  std::vector<std::string> est, labels, est_formats, est_times;
  bool sort = false;
  // evo-compatible options.
  std::string align = "se3", pose_relation = "trans_part", delta_unit = "f";
  long n_to_align = -1;
  bool align_origin = false, all_pairs = false, nearest = false;
  bool align_given = false;  // --align on the command line
  bool force = false;        // replace an existing --out folder
  double delta = 1.0, t_max_diff_s = 0.01, t_offset_s = 0.0;
  std::vector<double> rel_lengths_m;
  // Older option names, still accepted (--max-dt = --t-max-diff) and extra RPE deltas. --delta,
  // --t-max-diff, --t-offset and --rel-lengths are checked in ProtocolFromArgs; the others by their
  // CLI11 validator.
  double max_dt_s = -1.0;
  std::vector<double> rpe_distances_m, rpe_times_s;
};

// Trajectory files of a runs folder: regular, not hidden, .txt/.csv/.tum/.kitti, sorted by name.
std::vector<std::string> RunFiles(const std::string& folder) {
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (!entry.is_regular_file()) continue;
    const std::string name = entry.path().filename().string();
    const std::string ext = entry.path().extension().string();
    if (name.empty() || name[0] == '.') continue;
    if (ext == ".txt" || ext == ".csv" || ext == ".tum" || ext == ".kitti")
      files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  if (files.empty())
    throw InputError(folder, 0, "", "folder holds no trajectory file (.txt, .csv, .tum, .kitti)");
  return files;
}

// Labels are used in file names and CSV cells: letters, digits, '-', '_', '.', '+' only.
std::string SafeLabel(const std::string& text) {
  std::string out;
  for (char c : text)
    out +=
        std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.' || c == '+'
            ? c
            : '_';
  return out.empty() ? "estimate" : out;
}

std::string DefaultLabel(const std::string& source) {
  if (const auto log_topic = ParseLogTopicSpec(source))  // "run.bag:/vio/odom" -> run_vio_odom
    return fs::path(log_topic->path).stem().string() + log_topic->topic;
  fs::path p(source);
  while (!p.empty() && p.filename().empty()) p = p.parent_path();  // "dir/" -> "dir"
  return fs::is_directory(p) ? p.filename().string() : p.stem().string();
}

// One value per --est, or one for all, or none (then `fallback`).
std::string PerEstimate(const std::vector<std::string>& values, size_t k, size_t count,
                        const char* flag, const std::string& fallback) {
  if (values.empty()) return fallback;
  if (values.size() == 1) return values[0];
  if (values.size() != count)
    throw InputError(flag, 0, "",
                     fmt::format("given {} times: give it once (for every --est) or once per "
                                 "--est ({})",
                                 values.size(), count));
  return values[k];
}

TrajectoryFormat FormatOption(const std::string& value, const char* flag) {
  const auto format = ParseTrajectoryFormat(value);
  if (!format)
    throw InputError(flag, 0, "", "'" + value + "' is not a format (auto, tum, euroc, asl, kitti)");
  return *format;
}

EvaluationProtocol ProtocolFromArgs(const Args& a) {
  EvaluationProtocol p;
  const auto align = ParseAlignmentMode(a.align);
  if (!align)
    throw InputError("--align", 0, "", "'" + a.align + "' is not none, se3, sim3, posyaw");
  p.alignment = *align;
  if (a.n_to_align == 0 || a.n_to_align < -1)
    throw InputError(
        "--n-to-align", 0, "",
        fmt::format("{} is not a number of pairs (-1 = all, or N >= 1)", a.n_to_align));
  p.n_to_align = a.n_to_align;
  p.align_origin = a.align_origin;
  // evo: --align_origin replaces the Umeyama alignment (given alone, without -a).
  if (a.align_origin) {
    if (a.align_given && p.alignment != AlignmentMode::kNone)
      throw InputError("--align-origin", 0, "",
                       "replaces the alignment: give it without --align (or with --align none)");
    p.alignment = AlignmentMode::kNone;
  }
  const auto relation = ParsePoseRelation(a.pose_relation);
  if (!relation)
    throw InputError("--pose-relation", 0, "",
                     "'" + a.pose_relation + "' is not trans_part, angle_deg, rot_part, full");
  p.ape_relation = *relation;
  const double max_diff = a.max_dt_s > 0.0 ? a.max_dt_s : a.t_max_diff_s;
  if (!(max_diff > 0.0) || !std::isfinite(max_diff))
    throw InputError("--t-max-diff", 0, "",
                     fmt::format("{:g} s: the association tolerance must be > 0", max_diff));
  p.max_dt_s = max_diff;
  if (!std::isfinite(a.t_offset_s))
    throw InputError("--t-offset", 0, "", "must be a finite number of seconds");
  p.time_offset_s = a.t_offset_s;
  p.association = a.nearest ? AssociationMode::kNearest : AssociationMode::kInterpolate;
  const auto unit = ParseDeltaUnit(a.delta_unit);
  if (!unit) throw InputError("--delta-unit", 0, "", "'" + a.delta_unit + "' is not f, m or s");
  if (!(a.delta > 0.0) || !std::isfinite(a.delta))
    throw InputError("--delta", 0, "", fmt::format("{:g}: the RPE delta must be > 0", a.delta));
  if (*unit == DeltaUnit::kFrames && a.delta != std::floor(a.delta))
    throw InputError("--delta", 0, "",
                     fmt::format("{:g}: a delta in frames must be a whole number", a.delta));
  p.rpe_deltas.clear();
  p.rpe_deltas.push_back(RpeDelta{a.delta, *unit, a.all_pairs});
  for (double d : a.rpe_distances_m) {
    if (!(d > 0.0)) throw InputError("--rpe-distance", 0, "", fmt::format("{:g}: must be > 0", d));
    p.rpe_deltas.push_back(RpeDelta{d, DeltaUnit::kMetres, a.all_pairs});
  }
  for (double t : a.rpe_times_s) {
    if (!(t > 0.0)) throw InputError("--rpe-time", 0, "", fmt::format("{:g}: must be > 0", t));
    p.rpe_deltas.push_back(RpeDelta{t, DeltaUnit::kSeconds, a.all_pairs});
  }
  for (double l : a.rel_lengths_m)
    if (!(l > 0.0) || !std::isfinite(l))
      throw InputError("--rel-lengths", 0, "", fmt::format("{:g} m: lengths must be > 0", l));
  p.relative_lengths_m = a.rel_lengths_m;
  return p;
}

// The readers' notes on rows they fixed (dropped repeated stamps, sorted rows, ...), printed only
// once the evaluation succeeded: a command that then fails prints its one error line alone.
void AddRowFixes(const TrajectoryReadReport& report, std::vector<std::string>* notes) {
  const std::string fixes = DescribeRowFixes(report);
  if (!fixes.empty()) notes->push_back(fixes);
}

// A trajectory for --gt or --est, with the readers' notes added to `notes` (printed with the row
// fixes once everything is evaluated; a LOG:TOPIC's log reader notes included).
LoadedTrajectory ReadEvalTrajectory(const std::string& path, const TrajectoryReadOptions& options,
                                    std::vector<std::string>* notes) {
  LoadedTrajectory loaded = ReadTrajectory(path, options);
  AddRowFixes(loaded.report, notes);
  notes->insert(notes->end(), loaded.report.log_notes.begin(), loaded.report.log_notes.end());
  return loaded;
}

// Every --est, read before anything is evaluated: a bad file stops the command before any output.
std::vector<EvalInput> ReadInputs(const Args& a, std::vector<std::string>* notes) {
  std::vector<EvalInput> inputs;
  std::set<std::string> used_labels;
  for (size_t k = 0; k < a.est.size(); ++k) {
    EvalInput input;
    input.source = a.est[k];
    if (!fs::exists(input.source) && !ParseLogTopicSpec(input.source))
      throw InputError(input.source, 0, "", "file does not exist");
    input.is_folder = fs::is_directory(input.source);
    std::string label = SafeLabel(a.labels.empty() ? DefaultLabel(input.source) : a.labels[k]);
    for (int n = 2; used_labels.count(label); ++n)
      label = SafeLabel(a.labels.empty() ? DefaultLabel(input.source) : a.labels[k]) + "_" +
              std::to_string(n);
    used_labels.insert(label);
    input.label = label;
    TrajectoryReadOptions options;
    options.format = FormatOption(
        PerEstimate(a.est_formats, k, a.est.size(), "--est-format", "auto"), "--est-format");
    options.sort = a.sort;
    options.times_path = PerEstimate(a.est_times, k, a.est.size(), "--est-times", "");
    const std::vector<std::string> files =
        input.is_folder ? RunFiles(input.source) : std::vector<std::string>{input.source};
    for (const auto& file : files) {
      LoadedTrajectory loaded = ReadEvalTrajectory(file, options, notes);
      input.runs.emplace_back(file, std::move(loaded));
    }
    inputs.push_back(std::move(input));
  }
  return inputs;
}

// The ground truth and the estimates. The truth is read on a second thread while the estimates are
// read on this one (plain files; a log topic's reader keeps to one thread); errors come in the
// order of a serial read, the truth's first. Notes: the truth's, then the estimates'.
std::pair<LoadedTrajectory, std::vector<EvalInput>> ReadTruthAndInputs(
    const Args& a, std::vector<std::string>* notes) {
  TrajectoryReadOptions truth_options;
  truth_options.format = FormatOption(a.gt_format, "--gt-format");
  truth_options.sort = a.sort;
  truth_options.times_path = a.gt_times;
  const bool any_log = ParseLogTopicSpec(a.gt).has_value() ||
                       std::any_of(a.est.begin(), a.est.end(), [](const std::string& est) {
                         return ParseLogTopicSpec(est).has_value();
                       });
  std::vector<std::string> truth_notes, input_notes;
  std::future<LoadedTrajectory> truth_future =
      std::async(any_log ? std::launch::deferred : std::launch::async,
                 [&] { return ReadEvalTrajectory(a.gt, truth_options, &truth_notes); });
  std::vector<EvalInput> inputs;
  std::exception_ptr input_error;
  try {
    inputs = ReadInputs(a, &input_notes);
  } catch (...) {
    input_error = std::current_exception();
  }
  LoadedTrajectory truth = truth_future.get();
  if (truth.poses.size() < 2)
    throw InputError(a.gt, 0, "",
                     fmt::format("the ground truth has {} pose{}: a trajectory evaluation needs at "
                                 "least 2",
                                 truth.poses.size(), truth.poses.size() == 1 ? "" : "s"));
  if (input_error) std::rethrow_exception(input_error);
  notes->insert(notes->end(), truth_notes.begin(), truth_notes.end());
  notes->insert(notes->end(), input_notes.begin(), input_notes.end());
  return {std::move(truth), std::move(inputs)};
}

void Run(const Args& a) {
  const EvaluationProtocol protocol = ProtocolFromArgs(a);
  // The report folder is checked before any work and written whole (cli/output_folder.h).
  std::optional<StagedFolder> out;
  if (!a.out.empty()) out.emplace(a.out, FolderKind::kReport, a.force);
  if (!a.labels.empty() && a.labels.size() != a.est.size())
    throw InputError("--label", 0, "",
                     fmt::format("given {} times for {} --est: give one label per --est",
                                 a.labels.size(), a.est.size()));
  std::vector<std::string> notes;  // printed once everything is evaluated
  // What is built follows the outputs: the per-pair series, the aligned estimates and the report's
  // files for the report folder alone; report.json needs the statistics, as the table does.
  EvalOutputs outputs;
  outputs.report_folder = out.has_value();
  outputs.report_json = !a.json.empty();
  auto [truth, inputs] = ReadTruthAndInputs(a, &notes);
  const EvalReport report = EvaluateInputs(std::move(truth), a.gt, inputs, protocol, outputs);
  for (const std::string& note : notes) std::fprintf(stderr, "mavloc: note: %s\n", note.c_str());

  // evo-style statistics per run, then the table.
  for (const auto& e : report.estimates)
    for (const auto& r : e.runs) {
      const auto& ev = r.evaluation;
      const auto& t = ev.ape_translation_m;
      // Poses fewer than the file's rows (repeated stamps dropped) are said with the count.
      const std::string kept = DescribeRowsKept(r.input, ev.estimate_count);
      std::printf(
          "%s%s: %zu of %zu poses associated%s; ATE translation rmse %.6f mean %.6f median "
          "%.6f std %.6f min %.6f max %.6f m; rotation rmse %.6f deg\n",
          e.label.c_str(), r.run > 0 ? fmt::format(" run {}", r.run).c_str() : "", ev.pair_count,
          ev.estimate_count, kept.empty() ? "" : (" (read " + kept + ")").c_str(), t.rmse, t.mean,
          t.median, t.std, t.min, t.max, ev.ape_rotation_deg.rmse);
    }
  std::printf("%s", EvalSummaryTable(report).c_str());
  const nlohmann::json json = EvalJson(report);
  for (const auto& line : json["protocol_lines"])
    std::printf("- %s\n", line.get<std::string>().c_str());
  for (const auto& e : report.estimates)
    for (const auto& r : e.runs)
      for (const auto& message : r.evaluation.diagnostics.Messages())
        std::printf("diagnostic: %s%s: %s\n", e.label.c_str(),
                    r.run > 0 ? fmt::format(" run {}", r.run).c_str() : "", message.c_str());
  if (!outputs.report_folder && !outputs.report_json) return;
  const Report model = EvalModel(report);
  if (!a.json.empty()) WriteFileAtomically(a.json, ReportJsonText(model));
  if (out) {
    WriteReport(out->path(), model);
    const FigureOutcome figures = WriteReportFigures(out->path(), out->ForUser(out->path()));
    out->Commit();
    std::printf(
        "report: %s (report.md, report.json, eval.tex, truth.tum, estimates, "
        "errors_over_time.csv, relative_errors.csv)\n",
        a.out.c_str());
    std::printf("%s\n", out->ForUser(DescribeFigureOutcome(figures)).c_str());
  }
}

}  // namespace

void RegisterEval(CLI::App& app, int* exit_code) {
  auto* command = app.add_subcommand(
      "eval",
      "APE, RPE (evo) and relative error (rpg) of one or more estimates against a ground truth; "
      "formats TUM, EuRoC/ASL CSV, KITTI detected from the content");
  auto a = std::make_shared<Args>();
  command->add_option("--gt", a->gt, "Ground truth trajectory file")->required();
  command
      ->add_option("--est", a->est,
                   "Estimate: a trajectory file, or a folder of runs of one estimator (every "
                   ".txt/.csv/.tum/.kitti inside); repeat for several")
      ->required();
  command->add_option("--label", a->labels, "Label of each --est (default: file or folder name)");
  command->add_option("--gt-format", a->gt_format, "auto, tum, euroc, asl or kitti")
      ->capture_default_str();
  command->add_option("--est-format", a->est_formats,
                      "auto, tum, euroc, asl or kitti (once for all, or once per --est)");
  command->add_option("--gt-times", a->gt_times, "KITTI ground truth: times file (s per line)");
  command->add_option("--est-times", a->est_times,
                      "KITTI estimate: times file (once for all, or once per --est)");
  command->add_flag("--sort", a->sort,
                    "Sort rows by time instead of refusing rows out of order (said in the report)");
  command
      ->add_option("--align", a->align,
                   "Alignment: none, se3, sim3 or posyaw (4-DoF); evo's default is none")
      ->capture_default_str();
  command
      ->add_option("--n-to-align", a->n_to_align,
                   "Estimate the alignment on the first N pairs (-1: all; evo --n_to_align)")
      ->check(WholeNumber(-1, 1'000'000'000'000))
      ->capture_default_str();
  command->add_flag("--align-origin", a->align_origin,
                    "Align the first poses (evo --align_origin)");
  command
      ->add_option("--pose-relation", a->pose_relation,
                   "Headline APE relation: trans_part, angle_deg, rot_part or full (evo -r)")
      ->capture_default_str();
  command->add_option("--delta", a->delta, "RPE delta (evo --delta)")->capture_default_str();
  command->add_option("--delta-unit", a->delta_unit, "RPE delta unit: f, m or s (evo --delta_unit)")
      ->capture_default_str();
  command->add_flag("--all-pairs", a->all_pairs, "RPE over all pairs (evo --all_pairs)");
  command
      ->add_option("--t-max-diff", a->t_max_diff_s, "Association tolerance [s] (evo --t_max_diff)")
      ->capture_default_str();
  command
      ->add_option("--t-offset", a->t_offset_s,
                   "Seconds added to the estimates' stamps (evo --t_offset)")
      ->capture_default_str();
  command->add_flag("--nearest", a->nearest,
                    "Pair with the nearest ground-truth stamp (evo) instead of interpolating");
  command->add_option("--rel-lengths", a->rel_lengths_m,
                      "Relative-error lengths [m] (default: 10..50 % of the trajectory length)");
  command->add_option("--out", a->out,
                      "Write the report folder (report.md, report.json, eval.tex, ...)");
  command->add_option("--json", a->json, "Also write report.json to this file");
  command->add_flag("--force", a->force, "Replace an existing --out folder (a mavloc report)");
  command->add_option("--max-dt", a->max_dt_s, "Same as --t-max-diff (older name)")
      ->check(PositiveFinite());
  command->add_option("--rpe-distance", a->rpe_distances_m, "Extra RPE deltas in metres")
      ->check(PositiveFinite());
  command->add_option("--rpe-time", a->rpe_times_s, "Extra RPE deltas in seconds")
      ->check(PositiveFinite());
  command->callback([a, exit_code, command] {
    a->align_given = command->get_option("--align")->count() > 0;
    Run(*a);
    *exit_code = 0;
  });
}

}  // namespace mavloc::cli

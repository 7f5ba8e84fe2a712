// mavloc compare: run every applicable estimator on a dataset or a simulated scenario, print one
// table and write a report folder (report.md, report.json, errors.csv, the trajectories, figures
// and report.html).
#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>

#include "cli/commands.h"
#include "cli/common.h"
#include "cli/option_checks.h"
#include "cli/output_folder.h"
#include "core/errors.h"
#include "core/heap_release.h"
#include "core/progress.h"
#include "datasets/io/euroc_io.h"
#include "datasets/io/log_reader.h"
#include "datasets/io/tum_io.h"
#include "evaluation/comparison.h"
#include "evaluation/comparison_report.h"
#include "evaluation/crlb/crlb_report.h"
#include "evaluation/feature_frontend.h"
#include "evaluation/report/report_folder.h"
#include "evaluation/report/report_markdown.h"
#include "evaluation/report_figures.h"
#include "evaluation/report_writer.h"
#include "evaluation/truth_checks.h"

namespace mavloc::cli {

namespace {

// The rows a report file keeps by default: an hour at 20 Hz thinned to about 6 MB per trajectory.
constexpr size_t kReportFileMaxRows = 50'000;

// Which files keep every k-th row only: in report.json (details.report_files) and as a warning.
void NoteThinnedFiles(const std::map<std::string, size_t>& strides, Report* model) {
  if (strides.empty()) return;
  nlohmann::json every_kth_row = nlohmann::json::object();
  std::string list;
  for (const auto& [file, stride] : strides) {
    every_kth_row[file] = stride;
    list += fmt::format("{}{}: 1 row in {}", list.empty() ? "" : "; ", file, stride);
  }
  model->details["report_files"] = {{"max_rows", kReportFileMaxRows},
                                    {"every_kth_row", every_kth_row}};
  model->warnings.push_back(
      fmt::format("report files thinned to at most {} rows ({}); the metrics use every row; "
                  "--full-rate-files writes them all",
                  kReportFileMaxRows, list));
}

}  // namespace

void RegisterCompare(CLI::App& app, int* exit_code) {
  auto* command = app.add_subcommand(
      "compare",
      "Run estimators on a dataset or a simulated scenario and compare them against ground truth.\n"
      "With no arguments: the default scenario, every applicable estimator, report in "
      "./mavloc_report");
  struct Args {
    std::string scenario, dataset, estimators, report = "mavloc_report", align = "none", reference;
    uint64_t seed = 1;
    double duration_s = 0.0, max_dt_s = 0.02;
    std::vector<std::string> settings, options;
    bool force = false;
    bool full_rate_files = false;
  };
  auto args = std::make_shared<Args>();
  auto* scenario =
      command->add_option("--scenario", args->scenario,
                          "Scenario to simulate (default: " + DefaultScenarioName() + ")");
  command->add_option("--dataset", args->dataset, "Dataset folder instead of a scenario")
      ->excludes(scenario);
  command->add_option("--estimators", args->estimators,
                      "Comma-separated estimator names (default: every estimator that applies)");
  AddSeedOption(command, &args->seed, "Scenario seed");
  AddScenarioDurationOption(command, &args->duration_s, "Scenario duration in seconds");
  command->add_option("--set", args->settings, "Scenario setting key=value (repeatable)");
  command->add_option("--option", args->options,
                      "Estimator option estimator:key=value or key=value for all (repeatable)");
  command->add_option("--report", args->report, "Report folder (created)")
      ->check(OutputFolder())
      ->capture_default_str();
  command->add_flag("--force", args->force,
                    "Replace an existing --report folder (a mavloc report)");
  command->add_option("--align", args->align, "ATE alignment: none, se3, sim3 or posyaw")
      ->check(CLI::IsMember({"none", "se3", "sim3", "posyaw"}))
      ->capture_default_str();
  command->add_option("--reference", args->reference,
                      "Compare against this estimator's output, this trajectory file (TUM or "
                      "EuRoC CSV) or a log topic (LOG.bag:/odom, LOG.ulg:vehicle_attitude) "
                      "instead of the ground truth: for logs without ground truth. The reference "
                      "is an estimate, not a truth");
  command->add_flag("--full-rate-files", args->full_rate_files,
                    "Write truth.tum, the estimates and errors.csv at every row (by default a "
                    "file keeps at most " +
                        std::to_string(kReportFileMaxRows) +
                        " rows: every k-th row of longer ones)");
  command->add_option("--max-dt", args->max_dt_s, "Association tolerance in seconds")
      ->check(PositiveFinite())
      ->capture_default_str();
  command->callback([args, exit_code] {
    const bool reference_is_estimator =
        !args->reference.empty() && FindEstimator(args->reference) != nullptr;
    std::vector<std::string> names;
    const bool explicit_list = !args->estimators.empty();
    if (explicit_list) {
      names = SplitList(args->estimators);
      if (names.empty())
        throw InputError(
            "--estimators '" + args->estimators +
            "': the list is empty (give names separated by commas; see `mavloc list`)");
      for (const auto& name : names)
        if (!FindEstimator(name))
          throw InputError("unknown estimator '" + name + "' (see `mavloc list`)");
    } else {
      for (const auto& entry : EstimatorRegistry()) names.push_back(entry.name);
    }
    if (reference_is_estimator) {  // the reference runs first, whether listed or not
      names.erase(std::remove(names.begin(), names.end(), args->reference), names.end());
      names.insert(names.begin(), args->reference);
    }
    // Estimator options: "name:key=value" for one estimator, "key=value" for every estimator that
    // has the option; unknown names and keys are refused before anything runs.
    std::map<std::string, EstimatorOptions> per_estimator =
        EstimatorOptionsFor(args->options, names);
    StagedFolder report(args->report, FolderKind::kReport, args->force);

    Dataset dataset;
    std::filesystem::path render_scratch;
    if (!args->dataset.empty() && !args->settings.empty())
      throw InputError("--set " + args->settings.front() +
                       ": scenario settings apply to --scenario, not to --dataset");
    if (!args->dataset.empty() && args->duration_s > 0)
      throw InputError("--duration: applies to --scenario, not to --dataset");
    if (!args->dataset.empty()) {
      ReportProgress("compare", "reading " + args->dataset);
      dataset = ReadEurocDataset(args->dataset);
    } else {
      ScenarioOptions options;
      options.seed = args->seed;
      if (args->duration_s > 0) options.duration_s = args->duration_s;
      options.settings = ParseKeyValues(args->settings, "--set");
      const std::string name = args->scenario.empty() ? DefaultScenarioName() : args->scenario;
      // A scenario measured by its images renders them into a scratch folder of the report,
      // removed once the features are tracked.
      const ScenarioEntry* entry = FindScenario(name);
      if (entry != nullptr && entry->measures_by_images) {
        options.render_images = true;
        render_scratch = std::filesystem::path(report.path()) / ".render-scratch";
        options.image_dir = render_scratch.string();
      }
      dataset = SimulateScenario(name, options);
    }
    // An image log without a feature stream: the smoother's visual residuals from tracked features.
    std::optional<FeatureFrontendRun> frontend;
    if (NeedsFeatureTracks(dataset, names)) {
      ReportProgress("compare", "tracking features in the images");
      frontend = AddFeatureTracks(&dataset, FeatureTrackingSettings{});
      std::printf("%s\n", frontend->note.c_str());
      for (const auto& warning : frontend->result.warnings)
        std::printf("warning: feature frontend: %s\n", warning.c_str());
    }
    if (!render_scratch.empty()) std::filesystem::remove_all(render_scratch);
    if (args->reference.empty() && dataset.ground_truth.empty() && dataset.truth_quantities.empty())
      throw InputError(args->dataset, 0, "",
                       "dataset has no ground truth to compare against: name a reference with "
                       "--reference ESTIMATOR (e.g. smoother) or --reference TRAJECTORY_FILE");
    if (args->reference.empty()) RequireUsableGroundTruth(dataset);
    std::optional<ComparisonReference> reference;
    if (!args->reference.empty() && !reference_is_estimator) {
      if (const auto log_topic = ParseLogTopicSpec(args->reference)) {
        const LogTrajectory trajectory = ReadLogTrajectory(*log_topic);
        reference = ReferenceFromLogTrajectory(args->reference, trajectory);
        // What the log reader dropped (ULog: repeated or earlier stamps, PX4 "invalid" markers,
        // truncated or corrupt messages), one stdout line each, as `log import` prints them.
        for (const std::string& note : trajectory.notes)
          std::printf("note: %s: %s\n", log_topic->path.c_str(), note.c_str());
      } else if (!std::filesystem::exists(args->reference))
        throw InputError(args->reference, 0, "--reference",
                         "neither an estimator name (see `mavloc list`) nor an existing file");
      else
        reference = ReferenceFromTrajectory(args->reference, ReadTrajectoryFile(args->reference));
      // Like a ground truth (RequireUsableGroundTruth): a reference that does not overlap the
      // sensor data in time can judge no estimate, so it is refused instead of a table of "-".
      TimeNs data_begin = std::numeric_limits<TimeNs>::max();
      TimeNs data_end = std::numeric_limits<TimeNs>::min();
      auto add = [&](TimeNs t) {
        data_begin = std::min(data_begin, t);
        data_end = std::max(data_end, t);
      };
      for (const auto& s : dataset.imu.samples) add(s.t_ns);
      for (const auto& camera : dataset.cameras)
        for (const auto& f : camera.frames) add(f.t_ns);
      for (const auto& f : dataset.features) add(f.t_ns);
      for (const auto& l : dataset.laser) add(l.t_ns);
      for (const auto& t : dataset.tags) add(t.t_ns);
      for (const auto& t : dataset.tags1) add(t.t_ns);
      std::vector<TimeNs> stamps = reference->quantities.t_ns;
      for (const auto& p : reference->poses) stamps.push_back(p.t_ns);
      const auto [ref_begin, ref_end] = std::minmax_element(stamps.begin(), stamps.end());
      if (!stamps.empty() && data_begin <= data_end &&
          (*ref_end < data_begin || *ref_begin > data_end))
        throw InputError(args->reference, 0, "--reference",
                         fmt::format("covers {:.3f} s to {:.3f} s but the sensor data cover "
                                     "{:.3f} s to {:.3f} s: no overlap, so no estimate can be "
                                     "judged",
                                     NsToSeconds(*ref_begin), NsToSeconds(*ref_end),
                                     NsToSeconds(data_begin), NsToSeconds(data_end)));
    }

    EvaluationOptions evaluation_options;
    evaluation_options.align = *ParseAlignmentMode(args->align);
    evaluation_options.max_dt_s = args->max_dt_s;
    std::vector<EstimatorEvaluation> evaluations;
    std::vector<std::string> left_out;  // "name (reason)" of estimators that do not apply
    for (size_t i = 0; i < names.size(); ++i) {
      const EstimatorOptions& options = per_estimator[names[i]];
      ReportProgress("compare",
                     std::to_string(i + 1) + "/" + std::to_string(names.size()) + " " + names[i]);
      evaluation_options.reference = reference ? &*reference : nullptr;
      EstimatorEvaluation evaluation =
          RunAndEvaluate(names[i], options, dataset, evaluation_options);
      ReleaseFreeHeapPages();  // what the estimator freed, before the next stage allocates
      if (reference_is_estimator && i == 0) {
        if (!evaluation.ran)
          throw InputError("reference estimator '" + names[0] +
                           "' does not apply to this dataset: " + evaluation.skipped_reason);
        if (evaluation.estimate.quantities.empty() && evaluation.estimate.poses.empty())
          throw InputError("reference estimator '" + names[0] + "' returned no estimate");
        reference = ReferenceFromEstimate(names[0], evaluation.estimate);
        evaluation.quantity_errors.clear();
        evaluation.ate.reset();
        evaluation.is_reference = true;
      }
      if (!evaluation.ran && !explicit_list) {  // not applicable: left out of the default table,
        left_out.push_back(names[i] + " (" + evaluation.skipped_reason + ")");  // with a word
        continue;
      }
      evaluations.push_back(std::move(evaluation));
    }
    if (std::none_of(evaluations.begin(), evaluations.end(),
                     [](const EstimatorEvaluation& e) { return e.ran; })) {
      std::string reasons;
      for (const auto& entry : left_out) reasons += (reasons.empty() ? "" : "; ") + entry;
      for (const auto& e : evaluations)
        reasons += (reasons.empty() ? "" : "; ") + e.estimator + " (" + e.skipped_reason + ")";
      throw InputError(
          "no estimator applies to " +
          (args->dataset.empty() ? "scenario " + dataset.scenario : "dataset " + args->dataset) +
          " (" + DescribeDatasetStreams(dataset) + "): " + reasons);
    }

    const std::string title = dataset.scenario.empty() ? dataset.name : dataset.scenario;
    Report model = ComparisonReport(title, dataset, evaluations, evaluation_options, left_out);
    if (frontend) AddFeatureFrontendToReport(*frontend, &model);
    if (reference) {
      model.details["reference"] = {
          {"kind", reference->kind == ComparisonReference::Kind::kEstimator  ? "estimator"
                   : reference->kind == ComparisonReference::Kind::kLogTopic ? "log_topic"
                                                                             : "trajectory_file"},
          {"name", reference->name},
          {"is_truth", false}};
      model.sections.push_back(
          {"Reference",
           "**Reference: " + reference->Describe() +
               ". The reference is an estimate, not a ground truth**: every number is a "
               "difference between two estimates, and a small difference does not prove either "
               "accurate. The reprojection RMS of the tag corners (when the dataset has tags) is "
               "the measure that needs no truth.\n"});
    }
    std::printf("mavloc compare on %s against %s (ATE alignment %s)\n\n%s", title.c_str(),
                reference ? ("the reference " + reference->Describe() +
                             ", an estimate, not a truth: the numbers are differences, not errors")
                                .c_str()
                          : "the ground truth",
                args->align.c_str(), RenderResultTables(model).c_str());
    if (!left_out.empty()) {
      std::string line;
      for (const auto& entry : left_out) line += (line.empty() ? "" : "; ") + entry;
      std::printf("\nNot applicable to this dataset: %s.\n", line.c_str());
    }
    // The Cramér–Rao bound beside the errors on simulated datasets.
    if (!reference && !dataset.scenario.empty() && !dataset.ground_truth.empty()) {
      ReportProgress("compare", "Cramér–Rao bound");
      const CrlbReport crlb = MakeCrlbReport(dataset, evaluations, per_estimator["smoother"]);
      if (crlb.available) {
        std::printf("\n%s", crlb.text.c_str());
        model.details["cramer_rao"] = crlb.json;
        model.sections.push_back({"", crlb.markdown});
      }
    }
    model.details["not_applicable"] = left_out;
    const size_t max_rows = args->full_rate_files ? 0 : kReportFileMaxRows;
    std::map<std::string, size_t> strides;
    size_t errors_stride = 1;
    model.files["errors.csv"] = ErrorsCsv(evaluations, max_rows, &errors_stride);
    if (errors_stride > 1) strides["errors.csv"] = errors_stride;
    model.files.merge(ComparisonTrajectoryFiles(dataset, evaluations, max_rows, &strides));
    NoteThinnedFiles(strides, &model);
    if (reference && !reference->poses.empty())
      model.files["reference.tum"] = TumTrajectoryText(reference->poses);
    WriteReport(report.path(), model);
    const FigureOutcome figures = WriteReportFigures(report.path(), report.ForUser(report.path()));
    report.Commit();
    std::printf("\nreport written to %s/ (report.md, report.json, errors.csv, trajectories)\n",
                args->report.c_str());
    std::printf("%s\n", report.ForUser(DescribeFigureOutcome(figures)).c_str());
    *exit_code = 0;
  });
}

}  // namespace mavloc::cli

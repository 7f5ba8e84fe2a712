// mavloc run: one estimator on one dataset; writes its trajectory (TUM) or its quantities (CSV).
#include <fmt/format.h>

#include <chrono>
#include <cstdio>

#include "cli/commands.h"
#include "cli/common.h"
#include "cli/option_checks.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/progress.h"
#include "core/text.h"
#include "datasets/io/euroc_io.h"
#include "datasets/io/tum_io.h"
#include "evaluation/estimator_option_ranges.h"
#include "evaluation/feature_frontend.h"
#include "solver/estimator.h"

namespace mavloc::cli {

namespace {

std::string QuantitiesCsv(const QuantityTable& q) {
  std::string csv = "#timestamp [ns]";
  for (size_t k = 0; k < q.names.size(); ++k) csv += "," + q.names[k] + " [" + q.units[k] + "]";
  csv += "\n";
  for (size_t i = 0; i < q.size(); ++i) {
    csv += std::to_string(q.t_ns[i]);
    for (double v : q.rows[i]) csv += fmt::format(",{:.12g}", v);
    csv += "\n";
  }
  return csv;
}

}  // namespace

void RegisterRun(CLI::App& app, int* exit_code) {
  auto* command = app.add_subcommand(
      "run",
      "Run one estimator on a dataset folder; --out FILE.txt writes its trajectory T_W_B as "
      "TUM, --out FILE.csv its named quantities");
  struct Args {
    std::string dataset, estimator, out;
    std::vector<std::string> options;
  };
  auto args = std::make_shared<Args>();
  command->add_option("--dataset", args->dataset, "Dataset folder (EuRoC/ASL layout)")->required();
  command->add_option("--estimator", args->estimator, "Estimator name (see `mavloc list`)")
      ->required();
  command
      ->add_option("--out", args->out, "Output file: .csv = quantities, otherwise TUM trajectory")
      ->check(OutputFile())
      ->required();
  command->add_option("--option", args->options, "Estimator option key=value (repeatable)");
  command->callback([args, exit_code] {
    const EstimatorEntry* entry = FindEstimator(args->estimator);
    if (!entry) throw InputError("unknown estimator '" + args->estimator + "' (see `mavloc list`)");
    const EstimatorOptions options(ParseKeyValues(args->options, "--option"));
    CheckEstimatorOptionValues(*entry, options);  // before the dataset is read
    auto estimator = entry->create(options);
    ReportProgress("run", "reading " + args->dataset);
    Dataset dataset = ReadEurocDataset(args->dataset);
    if (NeedsFeatureTracks(dataset, {args->estimator})) {
      ReportProgress("run", "tracking features in the images");
      const FeatureFrontendRun frontend = AddFeatureTracks(&dataset, FeatureTrackingSettings{});
      std::fprintf(stderr, "%s\n", frontend.note.c_str());
      for (const auto& warning : frontend.result.warnings)
        std::fprintf(stderr, "warning: feature frontend: %s\n", warning.c_str());
    }
    const Applicability applicability = estimator->AppliesTo(dataset);
    if (!applicability.applies)
      throw InputError(args->dataset, 0, "",
                       args->estimator + " does not apply: " + applicability.reason + " (" +
                           DescribeDatasetStreams(dataset) + ")");
    ReportProgress("run", "running " + args->estimator);
    const auto start = std::chrono::steady_clock::now();
    const Estimate estimate = estimator->Run(dataset);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (EndsWith(args->out, ".csv")) {
      WriteFileAtomically(args->out, QuantitiesCsv(estimate.quantities));
    } else {
      if (estimate.poses.empty())
        throw InputError(
            args->out, 0, "",
            args->estimator + " gives no full pose; write its quantities with --out FILE.csv");
      WriteTumTrajectory(estimate.poses, args->out);
    }
    std::printf("%s: %zu states in %.3f s, %d frames without solution; wrote %s\n",
                args->estimator.c_str(), estimate.quantities.size(), seconds,
                estimate.FailureCount(), args->out.c_str());
    // What the estimator noted about its run (windows, a fitted noise scale, a solve that did not
    // converge): the warnings a report shows beside its numbers.
    for (const std::string& event : estimate.events)
      std::fprintf(stderr, "%s: %s\n", args->estimator.c_str(), event.c_str());
    *exit_code = 0;
  });
}

}  // namespace mavloc::cli

// mavloc track-features: natural-feature tracks from a dataset's images
// (frontends/features/track_features.h) written into the dataset as features0 (cam0) and features1
// (cam1, stereo), with per-frame statistics (features0/tracking.csv) and the settings and summary
// (features0/frontend.yaml). `compare` and `run` do the same in memory when the smoother runs on an
// image log without a feature stream.
#include <cstdio>
#include <string>

#include "cli/commands.h"
#include "cli/option_checks.h"
#include "core/errors.h"
#include "core/progress.h"
#include "datasets/io/euroc_io.h"
#include "evaluation/feature_frontend.h"

namespace mavloc::cli {

namespace {

void AddTrackerOptions(CLI::App* command, FeatureTrackerOptions* o, std::string* rejection) {
  command->add_option("--max-features", o->detector.max_features, "Tracks per frame (target)")
      ->check(WholeNumber(1, 5000))
      ->capture_default_str();
  command->add_option("--min-distance", o->detector.min_distance_px, "Corner spacing (px)")
      ->check(FiniteRange(1.0, 200.0, "px"))
      ->capture_default_str();
  command
      ->add_option("--fast-threshold", o->detector.fast_threshold, "FAST threshold (grey levels)")
      ->check(WholeNumber(1, 255))
      ->capture_default_str();
  command->add_option("--window", o->klt_window_px, "Lucas-Kanade window (px, odd)")
      ->check(WholeNumber(5, 101))
      ->capture_default_str();
  command
      ->add_option("--forward-backward", o->forward_backward_px,
                   "Forward-backward check: largest return error (px)")
      ->check(FiniteRange(0.01, 50.0, "px"))
      ->capture_default_str();
  command
      ->add_option("--rejection", *rejection,
                   "Outlier rejection over each frame pair: two-point (gyro-aided), five-point "
                   "(OpenCV findEssentialMat) or none")
      ->check(CLI::IsMember({"two-point", "five-point", "none"}))
      ->capture_default_str();
  command->add_option("--ransac-threshold", o->ransac_threshold_px, "RANSAC threshold (px)")
      ->check(FiniteRange(0.01, 50.0, "px"))
      ->capture_default_str();
  command->add_option("--stereo-epipolar", o->stereo_epipolar_px, "Stereo epipolar gate (px)")
      ->check(FiniteRange(0.01, 50.0, "px"))
      ->capture_default_str();
}

}  // namespace

void RegisterTrackFeatures(CLI::App& app, int* exit_code) {
  auto* command = app.add_subcommand(
      "track-features",
      "Track natural features in a dataset's images (grid FAST corners, gyro-predicted "
      "Lucas-Kanade with a forward-backward check, 2-point RANSAC, stereo matching): writes "
      "DIR/mav0/features0 (and features1) with tracking.csv and frontend.yaml");
  struct Args {
    std::string dataset, rejection = "two-point";
    FeatureTrackingSettings settings;
    bool mono = false, no_gyro = false, force = false;
  };
  auto args = std::make_shared<Args>();
  command->add_option("--dataset", args->dataset, "Dataset folder (EuRoC/ASL layout)")->required();
  command->add_flag("--mono", args->mono, "cam0 only, even where the dataset has cam1");
  command->add_flag("--no-gyro", args->no_gyro,
                    "No gyro prediction (KLT starts at the previous position; 5-point RANSAC)");
  command->add_flag("--force", args->force, "Replace an existing features0 stream");
  AddTrackerOptions(command, &args->settings.tracker, &args->rejection);
  command->callback([args, exit_code] {
    FeatureTrackingSettings& s = args->settings;
    s.stereo = !args->mono;
    s.tracker.use_gyro = !args->no_gyro;
    s.tracker.rejection = args->rejection == "two-point"    ? FrameOutlierRejection::kTwoPoint
                          : args->rejection == "five-point" ? FrameOutlierRejection::kFivePoint
                                                            : FrameOutlierRejection::kNone;
    const std::string error = ValidateFeatureTrackerOptions(s.tracker);
    if (!error.empty()) throw InputError("track-features: " + error);
    ReportProgress("track-features", "reading " + args->dataset);
    Dataset dataset = ReadEurocDataset(args->dataset);
    ReportProgress("track-features", "tracking");
    const FeatureFrontendRun run = AddFeatureTracks(&dataset, s);
    WriteFeatureTracks(run, args->dataset, args->force);
    std::printf("%s\n", run.note.c_str());
    for (const auto& warning : run.result.warnings) std::printf("warning: %s\n", warning.c_str());
    std::printf("wrote %s/mav0/features0/ (data.csv, tracking.csv, frontend.yaml)%s\n",
                args->dataset.c_str(), run.result.stereo ? " and features1/data.csv" : "");
    *exit_code = 0;
  });
}

}  // namespace mavloc::cli

// mavloc detect-tags: AprilTag detection (libapriltag) on a dataset's camera images -> tags0 (cam0)
// / tags1 (cam1), or on a folder of photos or one image -> one CSV row per detection
// (frontends/apriltag/detect_tags.h). --family aprilgrid detects Kalibr aprilgrids
// (frontends/apriltag/aprilgrid_detector.h); with the board known (--target FILE, or the dataset's
// map.yaml aprilgrid_* parameters) the tags both detector passes missed are predicted from the grid
// and checked against their codes.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/option_checks.h"
#include "core/atomic_file.h"
#include "core/errors.h"
#include "core/interrupt.h"
#include "core/progress.h"
#include "datasets/io/aprilgrid_target_io.h"
#include "datasets/io/euroc_io.h"
#include "frontends/apriltag/detect_tags.h"

namespace mavloc::cli {

void RegisterDetectTags(CLI::App& app, int* exit_code) {
  auto* command = app.add_subcommand(
      "detect-tags",
      "Detect AprilTags: --dataset DIR writes DIR/mav0/tags0/data.csv for cam0 (tags1 for cam1; "
      "per-tag poses in poses.csv beside it); --images DIR|IMAGE --out FILE.csv writes one row "
      "per detection. --family aprilgrid: Kalibr aprilgrids");
  struct Args {
    std::string dataset, images, out, camera = "cam0", target;
    TagDetectorOptions detector;
    bool rectify = true;
  };
  auto args = std::make_shared<Args>();
  auto* dataset_option =
      command->add_option("--dataset", args->dataset, "Dataset folder (EuRoC/ASL layout)");
  auto* images_option =
      command->add_option("--images", args->images, "Folder of photos, or one image file");
  dataset_option->excludes(images_option);
  command
      ->add_option("--out", args->out,
                   "Output CSV (required with --images; with --dataset default "
                   "DIR/mav0/tags<k>/data.csv for the dataset's camera k)")
      ->check(OutputFile(/*parent_must_exist=*/false));  // created with --dataset
  command
      ->add_option("--camera", args->camera,
                   "Camera of the dataset (cam0 -> tags0, cam1 -> tags1), or 'all'")
      ->capture_default_str();
  command
      ->add_option("--family", args->detector.family,
                   "Tag family (tag36h11, ..., aprilgrid = Kalibr's tag36h11 with a 2-bit border)")
      ->capture_default_str();
  command->add_option("--decimate", args->detector.decimate, "quad_decimate (>= 1)")
      ->check(FiniteRange(1.0, 64.0))
      ->capture_default_str();
  command->add_option("--threads", args->detector.threads, "Detector threads")
      ->check(WholeNumber(1, 256))
      ->capture_default_str();
  command
      ->add_option("--refine-edges", args->detector.refine_edges,
                   "refine_edges (0/1; libapriltag 3.3.0's is biased, see README)")
      ->capture_default_str();
  command->add_option("--sigma", args->detector.sigma, "quad_sigma: blur before segmentation (px)")
      ->check(FiniteRange(0.0, 100.0, "px"))
      ->capture_default_str();
  command->add_option("--sharpening", args->detector.decode_sharpening, "decode_sharpening")
      ->check(FiniteRange(0.0, 100.0))
      ->capture_default_str();
  command->add_option("--target", args->target,
                      "--family aprilgrid: the board (Kalibr target.yaml or yac's config); tags "
                      "missed by the detector are then predicted from the grid (default with "
                      "--dataset: the map's aprilgrid_* parameters, when it has them)");
  command->add_flag(
      "--raw", args->detector.raw_output,
      "Keep libapriltag's corner order and pixel convention (top-left pixel corner at "
      "0, 0) instead of mavloc's");
  command->callback([args, exit_code] {
    if (args->dataset.empty() == args->images.empty())
      throw InputError("detect-tags needs exactly one of --dataset DIR or --images DIR");
    if (!args->target.empty()) {
      if (args->detector.family != "aprilgrid")
        throw InputError("--target " + args->target + ": a board is for --family aprilgrid");
      args->detector.aprilgrid.target = ReadAprilgridTarget(args->target);
    }
    if (!args->images.empty()) {
      if (args->out.empty()) throw InputError("detect-tags --images needs --out FILE.csv");
      TagDetector detector(args->detector);
      const auto detections = DetectTagsInFolder(args->images, detector);
      WriteFileAtomically(args->out, PhotoDetectionsCsv(detections));
      std::printf("wrote %s: %zu detections\n", args->out.c_str(), detections.size());
      *exit_code = 0;
      return;
    }
    ReportProgress("detect-tags", "reading " + args->dataset);
    EurocReadOptions read_options;
    const Dataset dataset = ReadEurocDataset(args->dataset, read_options);
    if (args->target.empty() && args->detector.family == "aprilgrid") {
      if (const auto target = AprilgridFromMap(dataset.map))
        args->detector.aprilgrid.target = *target;
    }
    std::vector<std::string> cameras;
    if (args->camera == "all") {
      for (const auto& camera : dataset.cameras) cameras.push_back(camera.name);
      if (cameras.empty()) throw InputError(args->dataset, 0, "", "the dataset has no camera");
      if (!args->out.empty() && cameras.size() > 1)
        throw InputError("detect-tags --camera all writes tags0/tags1; --out needs one camera");
    } else {
      cameras.push_back(args->camera);
    }
    for (const std::string& name : cameras) {
      const CameraSensor* camera = dataset.Camera(name);
      if (camera == nullptr)
        throw InputError(args->dataset, 0, "camera", "the dataset has no camera " + name);
      // The tag streams of the dataset format: tags0 for the first camera, tags1 for the second.
      const long index = camera - dataset.cameras.data();
      if (index > 1 && args->out.empty())
        throw InputError(args->dataset, 0, "camera",
                         name + " is the dataset's camera " + std::to_string(index) +
                             "; the format has tag streams tags0 and tags1 only (use --out)");
      const DatasetTagDetections result =
          DetectTagsInDataset(dataset, name, args->detector, args->rectify);
      if (result.frames == 0)
        throw InputError(args->dataset, 0, "",
                         "no image of " + name + " found on disk (" +
                             std::to_string(result.missing_images.size()) + " listed but missing)");
      const std::filesystem::path out = args->out.empty()
                                            ? std::filesystem::path(args->dataset) / "mav0" /
                                                  ("tags" + std::to_string(index)) / "data.csv"
                                            : std::filesystem::path(args->out);
      if (out.has_parent_path()) CreateOutputDirectories(out.parent_path());
      WriteFileAtomically(out.string(), TagsCsv(result.observations));
      const std::filesystem::path poses = out.parent_path() / "poses.csv";
      WriteFileAtomically(poses.string(), TagPosesCsv(result.poses));
      std::printf(
          "wrote %s: %zu detections in %d frames of %s (%zu images missing, %d tags not in map)\n",
          out.string().c_str(), result.observations.size(), result.frames, name.c_str(),
          result.missing_images.size(), result.tags_not_in_map);
    }
    *exit_code = 0;
  });
}

}  // namespace mavloc::cli

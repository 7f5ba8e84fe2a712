// mavloc import-tagslam: an ASL dataset from one of TagSLAM's test folders (tagslam.yaml,
// cameras.yaml, camera_poses.yaml, tag_detections.bag[.bz2]) -> cam0/cam1, tags0/tags1, map.yaml
// with the known tags (datasets/io/tagslam/tagslam_import.h).
#include <cstdio>

#include "cli/commands.h"
#include "cli/option_checks.h"
#include "cli/output_folder.h"
#include "core/interrupt.h"
#include "core/progress.h"
#include "datasets/io/euroc_io.h"
#include "datasets/io/tagslam/tagslam_import.h"

namespace mavloc::cli {

void RegisterImportTagslam(CLI::App& app, int* exit_code) {
  auto* command = app.add_subcommand(
      "import-tagslam",
      "Assemble an ASL dataset from a TagSLAM test folder: known tag map (tagslam.yaml), cameras "
      "(cameras.yaml, camera_poses.yaml) and AprilTag detections (tag_detections.bag[.bz2]) -> "
      "cam0/cam1, tags0/tags1, map.yaml (no IMU)");
  struct Args {
    TagslamImportOptions options;
    std::string out;
    bool force = false;
    bool no_trajectories = false;
  };
  auto args = std::make_shared<Args>();
  command->add_option("TEST_DIR", args->options.test_dir, "TagSLAM test folder")->required();
  command->add_option("--out", args->out, "Output dataset folder (must not exist or be empty)")
      ->check(OutputFolder())
      ->required();
  command->add_option("--tags", args->options.tags_bag,
                      "Detections bag (.bag or whole-file .bag.bz2; default: "
                      "TEST_DIR/tag_detections.bag[.bz2])");
  command->add_option("--camera", args->options.cameras,
                      "TagSLAM camera (camN) to import, in dataset order (repeatable, at most 2; "
                      "default: the first two with a supported model, a pose and a tag topic)");
  command->add_option("--reference", args->options.reference_bag,
                      "TagSLAM's output bag (default: TEST_DIR/reference.bag[.bz2] when present)");
  command->add_flag("--camera-poses-from-reference", args->options.camera_poses_from_reference,
                    "Cameras without a pose in camera_poses.yaml take TagSLAM's optimised "
                    "T_rig_cam from the reference bag's /tf (then not independent of TagSLAM)");
  command->add_flag("--no-trajectories", args->no_trajectories,
                    "Do not write reference/tagslam_<rig>.txt and reference/odometry_<rig>.txt");
  command->add_flag("--force", args->force, "Replace a non-empty --out folder");
  command->callback([args, exit_code] {
    args->options.trajectories = !args->no_trajectories;
    ReportProgress("import-tagslam", "reading " + args->options.test_dir);
    const TagslamImport result = ImportTagslamTest(args->options);
    ReportProgress("import-tagslam", "writing " + args->out);
    // Its staging folder is removed if the command is interrupted (core/interrupt.h).
    const TemporaryPathGuard staging(StagingPathFor(args->out));
    WriteEurocDatasetAtomically(result.dataset, args->out, result.ExtraFiles(), args->force);
    std::printf("map: %zu known tags (%zu listed)\n", result.map.map.tags.size(),
                result.map.listed_tags.size());
    for (const TagslamImportCamera& c : result.cameras) {
      std::printf(
          "%s = TagSLAM %s (%s): %ld detections in %ld frames, %ld of tags in the map, %ld "
          "remapped, %ld ignored\n",
          c.dataset_name.c_str(), c.tagslam_name.c_str(), c.tag_topic.c_str(), c.detections,
          c.frames, c.in_map, c.remapped, c.ignored);
    }
    for (const TagslamTrajectoryFile& t : result.trajectories)
      std::printf("%s: %zu poses from %s, frame %s\n", t.relative_path.c_str(), t.poses.size(),
                  t.source.c_str(), t.frame.c_str());
    for (const std::string& note : result.notes) std::printf("%s\n", note.c_str());
    std::printf("wrote %s\n", args->out.c_str());
    *exit_code = 0;
  });
}

}  // namespace mavloc::cli

// Scenario "euroc-vision": EuRoC V1_01_easy's real flight with rendered
// images. The real IMU (imu0, 200 Hz, 145.6 s) and the real ground truth of
// <data>/groundtruth_full_tum.txt, as euroc-laser takes them (T_W_B of the IMU frame; v by central
// differences over +-2 rows; biases constant, the ASL estimate's first row), and cam0 and cam1 with
// EuRoC's own calibration (intrinsics, radial-tangential distortion, T_BS of each camera's
// sensor.yaml), rendered at the poses T_W_B(t) * T_B_C inside a room painted with photographs
// (datasets/rendering/textured_room_renderer.h). Images come with `simulate --render` and with
// `compare --scenario` (ScenarioEntry::measures_by_images; the camera streams list frame times
// only otherwise), and are written as an
// ordinary ASL folder (mav0/cam0/data.csv + data/<t>.png, sensor.yaml): a frontend reads them as it
// reads a real EuRoC log. No features0 stream is written.
//
// The room (EurocVisionRoom) is the size of EuRoC's Vicon room: x in [-4.0, 3.6] m, y in [-3.7,
// 4.5] m, z in [0, 4] m, at least 1.2 m beyond the flight on every side (the flight spans x
// -2.27 .. 2.11, y -2.49 .. 3.30, z 0.91 .. 1.89 m). Six boxes stand on the floor: the take-off
// stand under the vehicle's resting position (its top 0.80 m, 0.15 m below the IMU at rest),
// four in the corners and one low box mid-room, none within 0.3 m of a camera during the flight.
// map.yaml carries the room and boxes (textured_room_* and textured_box_* parameters).
//
// Time: the log starts start_s after the first ground-truth row and lasts --duration seconds
// (default: to the end of the ground truth or the IMU); frames every 1 / camera_rate_hz from the
// start.
//
// Settings (`--set`): data (../shared/data/euroc_v1_01_easy, found as euroc-laser finds it),
// cameras (stereo | mono: cam0 only), camera_rate_hz (20), image_scale (1: 752 x 480; 0.25 gives
// 188 x 120 with the intrinsics scaled, for tests), texel_m (0.004 m per texel of the
// photographs), start_s (0), and the image settings of textured_room_frames.h: textures,
// exposure_s (0.004), blur_samples (8), gain (1), image_noise_grey (2), image_dir. The seed draws
// the image noise.
#pragma once

#include "core/dataset.h"
#include "datasets/rendering/textured_room_renderer.h"
#include "datasets/scenarios/scenario.h"

namespace mavloc {

Dataset GenerateEurocVision(const ScenarioOptions& options);

// The room and its boxes (texel_m as given).
TexturedRoom EurocVisionRoom(double texel_m = 0.004);

}  // namespace mavloc

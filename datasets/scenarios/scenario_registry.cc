// The list of synthetic scenarios, in the order `mavloc list` shows them. Adding a scenario is one
// entry here.
#include "datasets/scenarios/aprilgrid_calibration.h"
#include "datasets/scenarios/euroc_laser.h"
#include "datasets/scenarios/figure_eight.h"
#include "datasets/scenarios/laser_plane.h"
#include "datasets/scenarios/marker_board_flight.h"
#include "datasets/scenarios/scenario.h"
#include "datasets/scenarios/stereo_obstacles.h"
#include "datasets/scenarios/tag_arena.h"
#include "datasets/scenarios/three_point_hover.h"

namespace mavloc {

const std::vector<ScenarioEntry>& ScenarioRegistry() {
  static const std::vector<ScenarioEntry> kEntries = {
      {"mav-figure-eight",
       "default: quadrotor figure-eight in a room of known landmarks; IMU 200 Hz, cam0 20 Hz, 1 px",
       GenerateFigureEight},
      {"tag-arena-hover",
       "AprilTag paper V-B: hover over 21 floor tags; IMU 100 Hz, cam0 10 Hz (--render: images)",
       GenerateTagArenaHover},
      {"tag-arena-dynamic",
       "AprilTag paper V-C: take-off from (0, 0, 0.08) m, fast-turn loop over 21 floor tags",
       GenerateTagArenaDynamic},
      {"three-point-hover",
       "three-point paper V-A: hover over 3 ground features, D = 0.1 m; IMU 100 Hz, cam0 0.3 s",
       GenerateThreePointHover},
      {"stereo-obstacles",
       "PIXHAWK 7.3: stereo pair flies past boxes and cylinders in a textured room (--render)",
       GenerateStereoObstacles},
      {"marker-board-flight",
       "PIXHAWK 7.2: marker board on the floor, rectangle + crossings; IMU 200 Hz, cam0 30 Hz, 1 "
       "px",
       GenerateMarkerBoardFlight},
      {"laser-plane",
       "laser paper 5.1: laser spot on a plane at 22.5 deg, random motion; IMU 100 Hz, spot 10 Hz",
       GenerateLaserPlane},
      {"euroc-laser",
       "laser paper 5.2: real EuRoC V1_01_easy IMU + ground truth, simulated laser spot at 10 Hz",
       GenerateEurocLaser},
      {"aprilgrid-calibration",
       "issue 12: stereo rig waved before a tilted 6x6 aprilgrid (board map), "
       "known T_B_C and time offset; IMU 200 Hz, cams 20 Hz",
       GenerateAprilgridCalibration},
  };
  return kEntries;
}

}  // namespace mavloc

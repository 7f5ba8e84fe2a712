// `mavloc repro euroc-imu-april`: the papers' tag estimators and the smoother on a real
// 72-second calibration log, EuRoC's imu_april (aprilgrid corners of cam0 and cam1 at 20 Hz, raw
// ADIS16448 IMU at 200 Hz), judged with what is known about it instead of a motion-capture truth:
// EuRoC's official camera-IMU calibration (Kalibr's, from these sequences), the stereo calibration
// T_cam0_cam1, the hardware synchronisation, the reprojection of the corners, and the agreement of
// independent solutions (cam0 only against cam1 only).
//
// Settings (`--set key=value`):
//   data      the log folder (../shared/data/euroc_imu_april): imu0.csv, config.yaml, cam0/, cam1/
//   official  the EuRoC sequence whose camN/sensor.yaml T_BS is the official T_B_C
//             (../shared/data/euroc_v1_01_easy/mav0)
//   initial   coarse | official: the smoother's initial T_B_C. coarse (default): the official
//             rotation rounded to the nearest axis permutation (what a CAD drawing gives) and a
//             zero translation, so that the comparison with the official values is not circular
//   duration_s  use only the first seconds of the log (0 = all)
//   estimators  the papers' estimators compared with the smoother, NAME or NAME:KEY=VALUE
//               (tag-pnp,tag-ekf,tag-ekf:gate_chi2=0,pnp,upright-2p,pixhawk-kf)
//   smoother.KEY=VALUE  extra smoother options
#pragma once

#include "evaluation/repro/repro.h"

namespace mavloc {

// One run on one real log (seeds and --runs do not apply): it runs in one process, its
// intermediate results being whole estimates (poses, covariances, extrinsics) that several
// comparisons share.
ReproDefinition EurocImuAprilRepro();

}  // namespace mavloc

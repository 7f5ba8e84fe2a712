// `mavloc repro three-point`: Table I of Troiani, Al Zanati, Martinelli, ECMR 2013 (sect. V-A) on
// the scenario three-point-hover, and a sensitivity sweep.
//
// table1: mean error of x, y, z (in %) and roll, pitch, yaw (in deg) of the 3p-algorithm
//   (three-point, with the triangle-angle filter; and with the true angles) and the 2p-algorithm
//   (two-point), plus the gravity EKF's roll and pitch, over N Monte-Carlo seeds (default 20),
//   each beside the paper's value.
// sensitivity: the same errors for 2p and 3p, and the gravity EKF's roll/pitch error, on a grid
//   of bearing noise (0.001 to 1 deg; the usual 0.01-1 deg plus 0.001 deg to locate the
//   crossover) x hover height (0.2 to 1 m), then the noise axis again at 0.4 m with a biased
//   accelerometer (which the gravity EKF cannot see); per row whether 3p beats 2p on every column
//   and the first-order prediction of 3p's roll/pitch error from the bearing noise.
//
// Error definition (the paper gives none): an angle's error is |estimate - truth| in degrees
// (wrapped); a position coordinate's error in % is 100 |estimate - truth| / r, r the true distance
// from the vehicle to the feature P1 (the origin) at that frame; both are averaged over every
// frame with a solution of every run (the mean of the per-run means is the same to within the
// differing frame counts, and the JSON gives the per-run spread).
//
// Settings (`--set key=value`): noise_levels_deg (comma list, "0.001,0.01,0.03,0.1,0.3,1"),
// heights_m ("0.2,0.4,0.6,0.8,1"), bias_rows_accel_bias_m_s2 (0.05; 0 drops the biased rows); any
// other key goes to the scenario (e.g. gyro_bias_deg_s=0.5) and applies to every row.
// Sweep geometry for height h: start 1.25 h above the triangle's centroid, goal h (0.5, 0.3, 1)
// from it (h = 0.4 m is the scenario's default).
//
// Each (configuration, seed) is a unit (table1, row0, row1, ...) whose result is the sums of each
// variant's per-frame errors; `--jobs N` runs the units in N workers with the numbers of `--jobs
// 1`.
#pragma once

#include "evaluation/repro/repro.h"

namespace mavloc {

ReproDefinition ThreePointRepro();

}  // namespace mavloc

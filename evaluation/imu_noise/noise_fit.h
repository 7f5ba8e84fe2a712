// IMU noise parameters read from Allan deviation curves (evaluation/imu_noise/allan_deviation.h),
// as IEEE Std 952-1997 Annex C and IEEE Std 1554-2005 read them, each term on its own part of the
// curve of one axis:
//
//   white noise N         sigma(tau) = N / sqrt(tau)            slope -1/2, N read at tau = 1 s
//   bias instability B    sigma(tau) ~ 0.664 B (flat minimum)   slope  0,   B = min sigma / 0.664
//                         (0.664 = sqrt(2 ln 2 / pi), the flicker-noise floor of the Allan
//                         deviation)
//   rate random walk K    sigma(tau) = K sqrt(tau / 3)          slope +1/2, K read at tau = 3 s
//
// N is fitted as a line of slope -1/2 (in log-log) through the points whose local slope is within
// NoiseFitOptions::white_slope_tolerance of -1/2, K as a line of slope +1/2 through those within
// random_walk_slope_tolerance of +1/2 right of the minimum; each point weighted by its edf (the
// variance of ln sigma is about 1/(2 edf)). Neighbouring terms bias a point whose slope differs
// from +-1/2 by d: a white + random-walk curve reads 5 % high at d = 0.1 and 8.5 % at d = 0.15; the
// edf weights put most of the fit on the cleanest points. B is measured only where the curve has a
// flat floor: the local slope within flat_slope_tolerance of 0 over at least flat_min_decades
// around the minimum. A white + random-walk curve without bias instability has a V-shaped minimum
// (|slope| <= 0.15 over only 0.27 decade), for which B is reported as an upper bound.
//
// A term the curve does not show is not guessed: it gets an upper bound that holds for any
// independent noise terms (their Allan variances add): N <= min sigma(tau) sqrt(tau) over
// tau >= 10 tau0 (the anti-aliasing filters of real IMUs lower the shortest taus),
// K <= min sigma(tau) sqrt(3 / tau), B <= min sigma / 0.664, with a note saying why it was not
// measured (e.g. "not reached: the log is 146 s ..."): random walk needs a static log of hours.
// When AllanOptions::max_tau_s (`mavloc imu-noise --max-tau`) ended the curve before a quarter of
// the log did (AllanCurve::cut_at_max_tau), the notes blame the cap, not the log's length.
//
// Units: a gyroscope's curve in rad/s gives N in rad/s/sqrt(Hz), B in rad/s, K in
// rad/s^2/sqrt(Hz); an accelerometer's in m/s^2 gives m/s^2/sqrt(Hz), m/s^2, m/s^3/sqrt(Hz):
// Kalibr's imu.yaml keys (gyroscope_noise_density, gyroscope_random_walk,
// accelerometer_noise_density, accelerometer_random_walk). Per sensor, the value is the LARGEST of
// the three axes: a filter given one density per sensor must not be over-confident on any axis.
#pragma once

#include <array>
#include <string>

#include "core/imu.h"
#include "evaluation/imu_noise/allan_deviation.h"

namespace mavloc {

struct NoiseFitOptions {
  double white_slope_tolerance = 0.1;         // |slope + 1/2| for a white-noise point
  double random_walk_slope_tolerance = 0.15;  // |slope - 1/2| for a random-walk point
  double flat_slope_tolerance = 0.15;         // |slope| on the bias-instability floor
  double flat_min_decades = 0.5;              // width of a floor that is not just a V
  int min_points = 3;                         // a regime is a run of at least this many points
  // Above these Allan deviations at tau = 1 s (or the largest tau, if shorter) the IMU was not
  // static: static MEMS gyroscopes are near 1e-4..1e-3 rad/s there, accelerometers near
  // 1e-4..3e-3 m/s^2; a vehicle's motion gives 1e-2..1 (EuRoC V1_01: gyro 0.1 rad/s).
  double moving_gyro_adev_rad_s = 5e-3;
  double moving_accel_adev_m_s2 = 2e-2;
};

// One noise term of one axis (or, combined, of one sensor).
struct NoiseTerm {
  bool measured = false;     // the curve shows the regime and `value` was fitted there
  double value = 0.0;        // the measured value, else the upper bound below
  double upper_bound = 0.0;  // what any curve allows, whatever it shows (0: none)
  double tau_from_s = 0.0;   // the points the fit used (measured only)
  double tau_to_s = 0.0;
  int points = 0;
  std::string note;  // how it was measured, or why it was not
};

struct AxisNoiseFit {
  NoiseTerm white;             // N at tau = 1 s on the -1/2 line
  NoiseTerm bias_instability;  // B = min sigma / 0.664
  NoiseTerm random_walk;       // K at tau = 3 s on the +1/2 line
  double min_adev = 0.0;       // the curve's minimum and where it is
  double tau_at_min_s = 0.0;
};

// Fits one axis' curve. A curve with fewer than two points, or a constant series (adev 0), gives
// no measured term and a note saying so.
AxisNoiseFit FitAllanNoise(const AllanCurve& curve, const NoiseFitOptions& options = {});

struct SensorNoiseFit {
  std::array<AxisNoiseFit, 3> axes;  // x, y, z
  // The largest of the three axes; measured only when measured on all three.
  NoiseTerm white, bias_instability, random_walk;
  // The IMU was not static (NoiseFitOptions::moving_*): then no term is `measured` (the white
  // noise read on a moving IMU holds vibration: an upper bound of the sensor's).
  bool moving = false;
  double adev_at_1s = 0.0;  // largest over the axes, the value the motion check used
  std::string motion_note;
};

struct ImuNoiseFit {
  SensorNoiseFit gyro;   // rad/s units
  SensorNoiseFit accel;  // m/s^2 units
};

ImuNoiseFit FitImuNoise(const ImuAllanDeviation& curves, const NoiseFitOptions& options = {});

// Kalibr's four densities (each the measured value or, where not measured, the upper bound).
ImuNoise KalibrNoise(const ImuNoiseFit& fit);

// Kalibr's imu.yaml: the four densities, rostopic and update_rate, with comment lines saying what
// was measured (source, samples, rate, duration, which values are upper bounds and why, bias
// instability).
std::string KalibrImuYaml(const ImuNoiseFit& fit, const ImuAllanDeviation& curves,
                          const std::string& source, const std::string& rostopic);

// allan_deviation.csv: one row per tau: tau_s, cluster_size, then for gyro_x..z [rad/s] and
// accel_x..z [m/s^2] the Allan deviation and its confidence bounds.
std::string AllanDeviationCsv(const ImuAllanDeviation& curves);

// The table printed by `mavloc imu-noise`: per axis N, B, K (upper bounds marked "<="), the
// per-sensor values, and the notes.
std::string ImuNoiseTable(const ImuNoiseFit& fit, const ImuAllanDeviation& curves);

}  // namespace mavloc

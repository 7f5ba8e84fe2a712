// Physical sanity ranges for every value a reader accepts, in one place.
//
// A value outside its range is refused with the file, line and field, instead of poisoning the
// estimators silently (an accelerometer value of 1e308 is finite but no MAV ever measured it). The
// ranges are wide on purpose: they refuse what is clearly not a measurement of a micro aerial
// vehicle, never a real log. The reasons are stated beside each one.
#pragma once

#include <string>

#include "core/time.h"

namespace mavloc::limits {

// IMU: MEMS gyroscopes saturate at 2000 deg/s (35 rad/s) and accelerometers at 16-40 g; the
// limits are three to ten times above, so saturated real samples still load.
inline constexpr double kMaxAngularRate_rad_s = 100.0;
inline constexpr double kMaxSpecificForce_m_s2 = 2000.0;
// Biases as a ground-truth file states them: a tenth of the measurement range.
inline constexpr double kMaxGyroBias_rad_s = 10.0;
inline constexpr double kMaxAccelBias_m_s2 = 200.0;
// White-noise densities (rad/s/sqrt(Hz), m/s^2/sqrt(Hz)) and random walks: the worst consumer
// IMUs are near 1e-2 and 1e-1; 10 and 100 are far beyond any sensor.
inline constexpr double kMaxGyroNoise = 10.0;
inline constexpr double kMaxAccelNoise = 100.0;

// Positions: 10,000 km covers Earth-centred coordinates (6,378 km) of a GNSS log.
inline constexpr double kMaxPosition_m = 1e7;
// Speeds: a MAV flies at tens of m/s; 1 km/s is beyond any of them.
inline constexpr double kMaxSpeed_m_s = 1000.0;

// Normalized image coordinates x/z, y/z: 1000 is a ray 0.06 deg from the image plane.
inline constexpr double kMaxNormalizedCoordinate = 1000.0;
// Pixel coordinates may fall outside the image (a corner predicted off-frame), not by 10^6 px.
inline constexpr double kMaxPixelCoordinate = 1e6;
// Camera geometry: resolution in pixels and focal length in pixels.
inline constexpr int kMaxResolution_px = 100000;
inline constexpr double kMaxFocalLength_px = 1e6;
inline constexpr double kMaxDistortionCoefficient = 1000.0;

// Sensor rates: 1 MHz is above any IMU or camera.
inline constexpr double kMaxRate_hz = 1e6;
// Output rate of an estimator's trajectory (option rate_hz): 1 kHz is above the IMU rate of MAV
// logs, and an hour at 1 kHz is 3.6e6 poses (~0.5 GB); more only fills memory.
inline constexpr double kMaxEstimateRate_hz = 1000.0;
// Timestamps: 2^62 ns (year 2116) leaves room for differences and sums without int64 overflow.
inline constexpr TimeNs kMaxTimestampNs = TimeNs{1} << 62;

// Angular measurement noise (bearings, laser-spot angles) stated by a simulated dataset: a sigma
// above 180 deg is no measurement of a direction.
inline constexpr double kMaxAngleNoise_deg = 180.0;
// Delay between a camera exposure and its processed measurement (scenario.yaml
// processing_delay_s): tens of ms on a MAV; a minute is beyond any on-board pipeline.
inline constexpr double kMaxProcessingDelay_s = 60.0;

// Extra ground-truth quantities (truth_quantities0: distances in m, speeds in m/s, angles in rad,
// biases): the position bound is above all of them.
inline constexpr double kMaxQuantityMagnitude = kMaxPosition_m;

// Tags: edge length of the black square, metres.
inline constexpr double kMaxTagSize_m = 100.0;

// Ids (landmarks, tags) are integers in [0, kMaxId]: int32 without the sign.
inline constexpr long long kMaxId = 2147483647LL;

// Unit quaternions and normals printed with few decimals are normalised when their norm is within
// this of 1 (|q| off by 2e-3 is common in hand-written or 4-decimal files); anything further off
// is not a rotation (or a direction) and is refused. Shared with the trajectory readers.
inline constexpr double kUnitNormTolerance = 0.05;
// Rotation matrices (T_BS): max |R^T R - I| entry and det within this, then made orthonormal.
inline constexpr double kRotationMatrixTolerance = 0.01;

// "[lo, hi] unit (core/physical_limits.h)" for messages.
std::string RangeText(double lo, double hi, const std::string& unit);

}  // namespace mavloc::limits

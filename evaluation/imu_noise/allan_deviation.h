// Overlapping Allan deviation of a uniformly sampled rate series (gyroscope [rad/s] or
// accelerometer [m/s^2] samples), the measurement behind IMU noise parameters:
// IEEE Std 952-1997 (Annex C, "Allan variance method of data reduction") and IEEE Std 1554-2005;
// the estimator and its confidence intervals as in W. J. Riley, "Handbook of Frequency Stability
// Analysis", NIST Special Publication 1065 (2008): overlapping Allan variance, edf and
// confidence intervals.
//
// With y_i the samples (i = 1..n, period tau0) and x_k = tau0 * sum_{i<=k} y_i their cumulative sum
// (the "phase": angle for a gyroscope, velocity for an accelerometer; N = n + 1 phase points), the
// overlapping Allan variance at cluster size m, tau = m tau0, is (the phase form of SP 1065)
//
//   sigma^2(tau) = 1 / (2 tau^2 (N - 2m)) * sum_{k=0}^{N-2m-1} (x_{k+2m} - 2 x_{k+m} + x_k)^2,
//
// i.e. half the mean square difference of adjacent averages over m samples, taken at every start
// sample. With the cumulative sums each tau costs O(n); the cluster sizes are log-spaced
// (10 per decade by default) up to a quarter of the series and AllanOptions::max_tau_s, so a
// curve is O(n log n) overall. allan_streaming.h computes the same numbers from samples given one
// at a time, in memory bounded by max_tau_s.
//
// Confidence intervals: chi-square with the equivalent degrees of freedom (edf) of the simple
// approximation formulae for the overlapping Allan variance (Howe, Allan, Barnes 1981; NIST SP 1065
// Table 5), for the power-law noise identified from the curve's local slope mu (sigma ~ tau^mu):
//   mu < -1/4  white FM (IMU: rate white noise, slope -1/2; also used for steeper slopes, where
//              white PM (quantization) would give a larger edf: a slope below -3/4 at long tau is
//              mostly chance, and white PM's edf would claim a far too narrow interval)
//              edf = [3(N-1)/(2m) - 2(N-2)/N] * 4m^2/(4m^2+5)
//   mu < +1/4  flicker FM (IMU: bias instability, flat)
//              edf = 5N^2/(4m(N+3m)) (the table's m = 1 entry, 2(N-2)/(2.3N-4.9), is below 1 for
//              every N; the m >= 2 formula is used at m = 1 too)
//   otherwise  random walk FM (IMU: rate random walk, slope +1/2)
//              edf = (N-2)/m * ((N-1)^2 - 3m(N-1) + 4m^2)/(N-3)^2
// and sigma^2 edf / chi2_{1-a/2}(edf) <= sigma^2 <= sigma^2 edf / chi2_{a/2}(edf).
// The chi-square quantiles are exact (regularized incomplete gamma function, inverted by
// bisection), not the Wilson-Hilferty approximation, which fails for edf of a few.
//
// Numerical code: nothing here throws on bad data; a status with a reason says why a stream cannot
// be analysed (the CLI turns it into an InputError naming the file).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/imu.h"
#include "core/imu_gaps.h"

namespace mavloc {

struct AllanOptions {
  double clusters_per_decade = 10.0;   // log-spaced cluster sizes m = round(10^(j / this)), unique
  double max_cluster_fraction = 0.25;  // m <= this * n (tau up to a quarter of the series)
  // and m tau0 <= this: the longest tau (`mavloc imu-noise --max-tau`, allan_streaming.h); it
  // bounds the streaming form's memory.
  double max_tau_s = std::numeric_limits<double>::infinity();
  double confidence = 0.6827;  // two-sided confidence of [adev_low, adev_high] (1 sigma)
};

// Power-law noise types of the edf formulae, named by their IMU meaning (see above); white PM,
// edf = (N+1)(N-2m)/(2(N-m)), is available to AllanEquivalentDof but not chosen from a slope.
enum class AllanNoiseType { kWhitePhase, kWhiteRate, kFlickerRate, kRandomWalkRate };
const char* AllanNoiseTypeName(AllanNoiseType type);  // "white PM (angle/velocity white)", ...

struct AllanPoint {
  long cluster_size = 0;  // m
  double tau_s = 0.0;     // m * tau0
  double adev = 0.0;      // sigma(tau), in the unit of the samples
  double slope = 0.0;     // local d ln sigma / d ln tau (least squares within +-0.2 decade)
  AllanNoiseType noise = AllanNoiseType::kWhiteRate;  // from the slope, chooses the edf formula
  double edf = 0.0;
  double adev_low = 0.0;  // confidence interval of sigma(tau) (AllanOptions::confidence)
  double adev_high = 0.0;
};

struct AllanCurve {
  double sample_period_s = 0.0;    // tau0
  size_t samples = 0;              // n
  std::vector<AllanPoint> points;  // increasing tau
  // AllanOptions::max_tau_s, and whether it left out cluster sizes that a quarter of the series
  // would allow (the curve then stops at max_tau_s, not where the log's length ends it).
  double max_tau_s = std::numeric_limits<double>::infinity();
  bool cut_at_max_tau = false;
};

// The curve of `samples` (uniformly sampled with period sample_period_s). Needs at least
// kMinAllanSamples samples and sample_period_s > 0, else an empty curve. Adding a constant to the
// series does not change it (the mean is removed before the cumulative sum, which keeps it exact
// in double precision for 1e7 samples of a 9.81 m/s^2 accelerometer).
AllanCurve OverlappingAllanDeviation(const std::vector<double>& samples, double sample_period_s,
                                     const AllanOptions& options = {});

// The log-spaced cluster sizes of a series of `samples` samples of period sample_period_s:
// m = round(10^(j / clusters_per_decade)), unique, m <= max_cluster_fraction * samples and
// m sample_period_s <= max_tau_s; *cut (when not null) says whether max_tau_s removed any.
std::vector<long> AllanClusterSizes(size_t samples, double sample_period_s,
                                    const AllanOptions& options, bool* cut = nullptr);

// Fills slope, noise, edf and the confidence interval of every point with adev > 0 (a constant
// series has adev 0 everywhere: no slope, no interval), from the curve's points and `samples`.
void SetAllanConfidence(AllanCurve* curve, const AllanOptions& options);

// d ln sigma / d ln tau of a curve at point i: the least-squares slope over the points within
// +-half_width_decades of it (one-sided at the ends).
double AllanLocalSlope(const std::vector<AllanPoint>& points, size_t i,
                       double half_width_decades = 0.2);

// The equivalent degrees of freedom of NIST SP 1065 Table 5 for `phase_points` N = n + 1 phase
// points and cluster size m; at least 1.
double AllanEquivalentDof(AllanNoiseType noise, double phase_points, double cluster_size);

// Quantile of the chi-square distribution with `dof` > 0 degrees of freedom (0 < p < 1).
double ChiSquareQuantile(double p, double dof);

// Fewer samples than this are refused: the curve would have too few cluster sizes to show a slope.
constexpr size_t kMinAllanSamples = 1000;
// Samples a stream may lack (the count its duration and median interval imply, minus the count it
// has) before it is refused: Allan deviation indexes samples, so each missing sample shifts later
// ones by one period.
constexpr double kMaxAllanMissingFraction = 0.01;

// Whether a stamped stream is uniform enough for Allan deviation: rate from the median interval;
// refused (ok = false, reason says why) when it has fewer than kMinAllanSamples samples, a
// non-increasing stamp, a gap in the sense of core/imu_gaps.h (longer than 10 median intervals and
// 0.2 s: the data on either side were not recorded as one series), or more than
// kMaxAllanMissingFraction of its samples missing.
struct UniformSampling {
  bool ok = false;
  std::string reason;  // why not, when !ok
  size_t samples = 0;
  double rate_hz = 0.0;        // 1 / median interval
  double duration_s = 0.0;     // last stamp - first stamp
  size_t missing_samples = 0;  // round(duration / median interval) + 1 - samples, at least 0
  // The median interval is exact when this is 1 ns (every log mavloc has seen); else it is known
  // to within half of it (UniformSamplingCheck).
  int64_t median_resolution_ns = 1;
};
UniformSampling CheckUniformSampling(const std::vector<ImuSample>& samples);

// The streaming form of CheckUniformSampling: stamps one at a time, the same verdict and the same
// reason. Its memory does not grow with the number of samples: it keeps a histogram of the
// intervals up to kImuGapMinSeconds (exact while they take at most kMaxExactIntervals distinct
// values: EuRoC's stamps have a handful, PX4's microsecond stamps a few hundred; beyond, the bins
// are widened by powers of two and the median is known to within half a bin,
// UniformSampling::median_resolution_ns), the exact counts of the longer intervals (the
// candidates for gaps: at most duration / kImuGapMinSeconds of them), and the longer intervals
// that exceed every interval before them (the first gap is one of them, the longest the last).
class UniformSamplingCheck {
 public:
  static constexpr size_t kMaxExactIntervals = size_t{1} << 16;

  void Add(TimeNs t_ns);
  UniformSampling Finish() const;

 private:
  void AddInterval(TimeNs interval_ns, TimeNs from_ns, TimeNs to_ns);

  size_t samples_ = 0;
  TimeNs first_ns_ = 0, last_ns_ = 0;
  std::string not_increasing_;  // the reason, from the first stamp that does not come after
  int shift_ = 0;               // short intervals are binned as interval >> shift_
  std::unordered_map<TimeNs, uint64_t> short_bins_;
  TimeNs last_bin_ = -1;  // the bin of the last short interval and its count: a shortcut
  uint64_t* last_count_ = nullptr;
  std::map<TimeNs, uint64_t> long_intervals_;  // longer than kImuGapMinSeconds
  TimeNs longest_ns_ = 0;
  std::vector<ImuGap> records_;  // long intervals longer than every earlier interval
};

// The six curves of an IMU stream: gyro x, y, z [rad/s] and accel x, y, z [m/s^2].
struct ImuAllanDeviation {
  UniformSampling sampling;               // !sampling.ok: the curves are empty
  std::array<AllanCurve, 3> gyro, accel;  // axes x, y, z of B
};
// Through ComputeImuAllanDeviationStreaming (allan_streaming.h) over the vector: the numbers of
// OverlappingAllanDeviation on each axis.
ImuAllanDeviation ComputeImuAllanDeviation(const std::vector<ImuSample>& samples,
                                           const AllanOptions& options = {});

}  // namespace mavloc

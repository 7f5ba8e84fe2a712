#include "evaluation/imu_noise/noise_fit.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <tuple>
#include <utility>

namespace mavloc {
namespace {

// sqrt(2 ln 2 / pi): the flicker floor of the Allan deviation is 0.664 B (IEEE Std 952-1997,
// Annex C).
constexpr double kFlickerFloorFactor = 0.664;
// Cluster sizes below this are left out of the white-noise upper bound: the anti-aliasing filters
// of real IMUs lower the Allan deviation of the shortest taus below the white-noise line.
constexpr long kWhiteBoundMinCluster = 10;
// Points with fewer equivalent degrees of freedom (about +-22 % of scatter in sigma) do not count
// towards a flat floor or a random-walk slope: in the last half decade of a curve the scatter alone
// bends the local slope by +-0.3, enough to fake either regime.
constexpr double kMinRegimeEdf = 10.0;
// The curve has "turned up" after its minimum when its last point is this much above it.
constexpr double kTurnedUpRatio = 1.5;

struct AllanPointRun {
  size_t from = 0, to = 0;  // inclusive
};

// The run of consecutive points of [begin, points.size()) that satisfy `in_regime`, at least
// min_points long, with the largest total edf (the best-determined one).
template <typename Predicate>
std::optional<AllanPointRun> BestAllanRun(const std::vector<AllanPoint>& points, size_t begin,
                                          int min_points, Predicate in_regime) {
  std::optional<AllanPointRun> best;
  double best_weight = -1.0;
  size_t i = begin;
  while (i < points.size()) {
    if (!in_regime(points[i])) {
      ++i;
      continue;
    }
    size_t j = i;
    double weight = 0.0;
    while (j < points.size() && in_regime(points[j])) weight += points[j++].edf;
    if (static_cast<int>(j - i) >= min_points && weight > best_weight) {
      best = AllanPointRun{i, j - 1};
      best_weight = weight;
    }
    i = j;
  }
  return best;
}

// exp of the edf-weighted mean of ln sigma_i + exponent * ln(tau_i / tau_read): the line of slope
// -exponent through the run, read at tau_read.
double ReadAllanLineAt(const std::vector<AllanPoint>& points, const AllanPointRun& run,
                       double exponent, double tau_read_s) {
  double sum = 0.0, weights = 0.0;
  for (size_t i = run.from; i <= run.to; ++i) {
    sum += points[i].edf *
           (std::log(points[i].adev) + exponent * std::log(points[i].tau_s / tau_read_s));
    weights += points[i].edf;
  }
  return std::exp(sum / weights);
}

std::string TauText(double t_s) {
  return t_s < 1000.0 ? fmt::format("{:.3g} s", t_s) : fmt::format("{:.0f} s", t_s);
}

// A local slope of the log-log curve, "+0.48"; where the Allan deviation is 0 (a series that
// repeats itself at that cluster time) the slope has no value, and the text says so instead of
// printing "-nan".
std::string SlopeText(double slope) {
  if (!std::isfinite(slope)) return "undefined (the Allan deviation is 0 there)";
  return fmt::format("{:+.2f}", slope);
}

// "145.6 s", "25 min", "3.2 h".
std::string LogLengthText(double t_s) {
  if (t_s < 120.0) return fmt::format("{:.4g} s", t_s);
  if (t_s < 7200.0) return fmt::format("{:.0f} min", t_s / 60.0);
  return fmt::format("{:.1f} h", t_s / 3600.0);
}

const char* kImuAxisNames[3] = {"x", "y", "z"};

// Where the longest tau (`mavloc imu-noise --max-tau`) ended a curve that the log would let go on:
// ", where --max-tau (1000 s) stops it (a quarter of the 13.9 h log: 1.25e+04 s)".
std::string MaxTauStop(const AllanCurve& curve, double log_s) {
  return fmt::format(", where --max-tau ({}) stops it (a quarter of the {} log: {})",
                     TauText(curve.max_tau_s), LogLengthText(log_s), TauText(0.25 * log_s));
}

}  // namespace

AxisNoiseFit FitAllanNoise(const AllanCurve& curve, const NoiseFitOptions& options) {
  AxisNoiseFit fit;
  const std::vector<AllanPoint>& p = curve.points;
  const bool constant =
      std::all_of(p.begin(), p.end(), [](const AllanPoint& q) { return !(q.adev > 0.0); });
  if (p.size() < 2 || constant) {
    const std::string why = p.size() < 2 ? "the curve has fewer than two points"
                                         : "the series is constant (Allan deviation 0)";
    fit.white.note = fit.bias_instability.note = fit.random_walk.note = "not measured: " + why;
    return fit;
  }
  const size_t last = p.size() - 1;
  const double log_s = static_cast<double>(curve.samples) * curve.sample_period_s;
  size_t i_min = 0;
  for (size_t i = 1; i < p.size(); ++i)
    if (p[i].adev < p[i_min].adev) i_min = i;
  fit.min_adev = p[i_min].adev;
  fit.tau_at_min_s = p[i_min].tau_s;

  // Upper bounds: the Allan variances of independent terms add, so each term's own curve lies
  // below the measured one at every tau.
  double white_bound = std::numeric_limits<double>::infinity();
  double walk_bound = std::numeric_limits<double>::infinity();
  for (const AllanPoint& q : p) {
    if (q.cluster_size >= kWhiteBoundMinCluster || p.back().cluster_size < kWhiteBoundMinCluster)
      white_bound = std::min(white_bound, q.adev * std::sqrt(q.tau_s));
    walk_bound = std::min(walk_bound, q.adev * std::sqrt(3.0 / q.tau_s));
  }
  fit.white.upper_bound = white_bound;
  fit.random_walk.upper_bound = walk_bound;
  fit.bias_instability.upper_bound = fit.min_adev / kFlickerFloorFactor;
  // Where the curve ends: still falling (or flat) at its largest tau, or risen again after an
  // interior minimum.
  const bool turned_up = i_min > 0 && p[last].adev >= kTurnedUpRatio * fit.min_adev;

  // White noise: slope -1/2, N = sigma(1 s) on the line.
  const auto white_run = BestAllanRun(p, 0, options.min_points, [&](const AllanPoint& q) {
    return q.adev > 0.0 && std::abs(q.slope + 0.5) <= options.white_slope_tolerance;
  });
  if (white_run) {
    NoiseTerm& t = fit.white;
    t.measured = true;
    t.value = ReadAllanLineAt(p, *white_run, 0.5, 1.0);
    t.tau_from_s = p[white_run->from].tau_s;
    t.tau_to_s = p[white_run->to].tau_s;
    t.points = static_cast<int>(white_run->to - white_run->from + 1);
    t.note = fmt::format("slope -1/2 over tau {}..{} ({} points), read at tau = 1 s{}",
                         TauText(t.tau_from_s), TauText(t.tau_to_s), t.points,
                         t.tau_to_s < 1.0 ? " (extrapolated)" : "");
  } else {
    fit.white.value = white_bound;
    fit.white.note = fmt::format(
        "no -1/2 slope (no {} consecutive points with slope -1/2 +- {:g}; slope at the shortest "
        "tau {}: {}): upper bound only",
        options.min_points, options.white_slope_tolerance, TauText(p.front().tau_s),
        SlopeText(p.front().slope));
  }

  // Bias instability: the widest run of flat points (the global minimum alone is a poor guide: at
  // long tau the curve scatters by tens of percent and its lowest point may lie off the floor).
  std::optional<AllanPointRun> floor_run;
  double floor_decades = 0.0;
  for (size_t i = 0; i < p.size();) {
    const auto is_flat = [&](const AllanPoint& q) {
      return q.adev > 0.0 && q.edf >= kMinRegimeEdf &&
             std::abs(q.slope) <= options.flat_slope_tolerance;
    };
    if (!is_flat(p[i])) {
      ++i;
      continue;
    }
    size_t j = i;
    while (j + 1 < p.size() && is_flat(p[j + 1])) ++j;
    const double decades = std::log10(p[j].tau_s / p[i].tau_s);
    if (decades > floor_decades) {
      floor_decades = decades;
      floor_run = AllanPointRun{i, j};
    }
    i = j + 1;
  }
  {
    NoiseTerm& t = fit.bias_instability;
    if (floor_run && floor_decades >= options.flat_min_decades) {
      size_t lowest = floor_run->from;
      for (size_t i = floor_run->from; i <= floor_run->to; ++i)
        if (p[i].adev < p[lowest].adev) lowest = i;
      t.measured = true;
      t.value = p[lowest].adev / kFlickerFloorFactor;
      t.tau_from_s = p[floor_run->from].tau_s;
      t.tau_to_s = p[floor_run->to].tau_s;
      t.points = static_cast<int>(floor_run->to - floor_run->from + 1);
      t.note =
          fmt::format("flat floor over tau {}..{} ({:.2f} decades), its minimum {:.4g} at tau {}",
                      TauText(t.tau_from_s), TauText(t.tau_to_s), floor_decades, p[lowest].adev,
                      TauText(p[lowest].tau_s));
    } else {
      t.value = t.upper_bound;
      if (i_min == 0)
        t.note = "no minimum: the curve rises from the shortest tau: upper bound only";
      else if (!turned_up && curve.cut_at_max_tau)
        t.note = fmt::format(
            "not reached: the curve has not levelled off by its largest tau ({}, slope {}){}: "
            "raise --max-tau; upper bound only",
            TauText(p[last].tau_s), SlopeText(p[last].slope), MaxTauStop(curve, log_s));
      else if (!turned_up)
        t.note = fmt::format(
            "not reached: the curve has not levelled off by its largest tau ({}, slope {}); "
            "the log is {}: upper bound only",
            TauText(p[last].tau_s), SlopeText(p[last].slope), LogLengthText(log_s));
      else
        t.note = fmt::format(
            "no flat floor: the curve is flat (slope 0 +- {:g}) over at most {:.2f} decades (less "
            "than {:g}); its minimum ({:.4g} at tau {}) is where the falling and rising slopes "
            "meet: upper bound only",
            options.flat_slope_tolerance, floor_decades, options.flat_min_decades, fit.min_adev,
            TauText(fit.tau_at_min_s));
    }
  }

  // Rate random walk: slope +1/2 right of the minimum, K = sigma(3 s) on the line.
  const auto walk_run = BestAllanRun(p, i_min, options.min_points, [&](const AllanPoint& q) {
    return q.adev > 0.0 && q.edf >= kMinRegimeEdf &&
           std::abs(q.slope - 0.5) <= options.random_walk_slope_tolerance;
  });
  {
    NoiseTerm& t = fit.random_walk;
    if (walk_run) {
      t.measured = true;
      t.value = ReadAllanLineAt(p, *walk_run, -0.5, 3.0);
      t.tau_from_s = p[walk_run->from].tau_s;
      t.tau_to_s = p[walk_run->to].tau_s;
      t.points = static_cast<int>(walk_run->to - walk_run->from + 1);
      t.note = fmt::format("slope +1/2 over tau {}..{} ({} points), read at tau = 3 s",
                           TauText(t.tau_from_s), TauText(t.tau_to_s), t.points);
    } else {
      t.value = walk_bound;
      if (i_min > 0 && !turned_up && !fit.bias_instability.measured && curve.cut_at_max_tau)
        t.note = fmt::format(
            "not reached: the curve has not turned up by its largest tau ({}, slope {}){}; "
            "the +1/2 slope begins about a decade past the bias-instability minimum: raise "
            "--max-tau; upper bound only",
            TauText(p[last].tau_s), SlopeText(p[last].slope), MaxTauStop(curve, log_s));
      else if (i_min > 0 && !turned_up && !fit.bias_instability.measured)
        t.note = fmt::format(
            "not reached: the log is {} and the curve has not turned up by its largest tau ({}, "
            "slope {}); the +1/2 slope begins about a decade past the bias-instability "
            "minimum, which lies beyond {}: it needs a static log at least ~10 times longer (more "
            "than {}; MEMS IMUs: typically hours); upper bound only",
            LogLengthText(log_s), TauText(p[last].tau_s), SlopeText(p[last].slope),
            TauText(p[last].tau_s), LogLengthText(10.0 * log_s));
      else if (i_min == 0)
        t.note = fmt::format(
            "not found: the curve rises from the shortest tau but nowhere at slope +1/2 +- {:g} "
            "for {} points (slope at the largest tau {}: {}); upper bound only",
            options.random_walk_slope_tolerance, options.min_points, TauText(p[last].tau_s),
            SlopeText(p[last].slope));
      else {
        // The +1/2 slope starts about a decade past the end of the floor (or the minimum).
        const double floor_end_s =
            fit.bias_instability.measured ? fit.bias_instability.tau_to_s : fit.tau_at_min_s;
        const char* reference =
            fit.bias_instability.measured ? "bias-instability floor ending" : "minimum";
        if (curve.cut_at_max_tau && 10.0 * floor_end_s > p[last].tau_s)
          t.note = fmt::format(
              "not reached: with the {} at tau {} the +1/2 slope needs tau up to about 10 times "
              "that ({}), beyond the largest tau {}{}: raise --max-tau; upper bound only",
              reference, TauText(floor_end_s), TauText(10.0 * floor_end_s), TauText(p[last].tau_s),
              MaxTauStop(curve, log_s));
        else if (40.0 * floor_end_s > log_s)
          t.note = fmt::format(
              "not reached: the log is {} (largest tau {}, slope there {}); with the {} at "
              "tau {} the +1/2 slope needs tau up to about 10 times that ({}), i.e. a static log "
              "of about {} (cluster times go up to a quarter of the log); upper bound only",
              LogLengthText(log_s), TauText(p[last].tau_s), SlopeText(p[last].slope), reference,
              TauText(floor_end_s), TauText(10.0 * floor_end_s), LogLengthText(40.0 * floor_end_s));
        else
          t.note = fmt::format(
              "not found: no +1/2 slope up to the largest tau {} (slope there {}), although "
              "the {} is at tau {}: the random walk is too small to show in this {} log; upper "
              "bound only",
              TauText(p[last].tau_s), SlopeText(p[last].slope), reference, TauText(floor_end_s),
              LogLengthText(log_s));
      }
    }
  }
  return fit;
}

namespace {

// The point nearest tau = 1 s (the largest tau of a shorter curve).
double AdevNearOneSecond(const AllanCurve& curve) {
  double best = 0.0, best_distance = std::numeric_limits<double>::infinity();
  for (const AllanPoint& q : curve.points) {
    const double distance = std::abs(std::log(q.tau_s));
    if (distance < best_distance) {
      best_distance = distance;
      best = q.adev;
    }
  }
  return best;
}

// The largest of the three axes' values; measured when all three are.
NoiseTerm CombineAxes(const std::array<AxisNoiseFit, 3>& axes, NoiseTerm AxisNoiseFit::*term) {
  NoiseTerm combined;
  combined.measured = true;
  std::string bounded;
  int largest = 0;
  for (int a = 0; a < 3; ++a) {
    const NoiseTerm& t = axes[a].*term;
    combined.measured = combined.measured && t.measured;
    if (!t.measured) bounded += std::string(bounded.empty() ? "" : ", ") + kImuAxisNames[a];
    if (t.value > combined.value) {
      combined.value = t.value;
      largest = a;
    }
    combined.upper_bound = std::max(combined.upper_bound, t.upper_bound);
  }
  combined.note = fmt::format("largest of x, y, z: axis {}, {}", kImuAxisNames[largest],
                              (axes[largest].*term).note);
  if (!combined.measured) combined.note += " (not measured on axis " + bounded + ")";
  return combined;
}

SensorNoiseFit FitImuSensor(const std::array<AllanCurve, 3>& curves, double moving_limit,
                            const char* unit, const char* sensor, const NoiseFitOptions& options) {
  SensorNoiseFit s;
  for (int a = 0; a < 3; ++a) {
    s.axes[a] = FitAllanNoise(curves[a], options);
    s.adev_at_1s = std::max(s.adev_at_1s, AdevNearOneSecond(curves[a]));
  }
  if (s.adev_at_1s > moving_limit) {
    s.moving = true;
    s.motion_note = fmt::format(
        "the IMU was not static: the {} Allan deviation near tau = 1 s is {:.3g} {} (a static "
        "one: below {:g}); on a moving IMU the curve measures the motion and vibration, so every "
        "value is only an upper bound of the sensor's noise; record a static log",
        sensor, s.adev_at_1s, unit, moving_limit);
    for (AxisNoiseFit& axis : s.axes) {
      for (NoiseTerm* t : {&axis.white, &axis.bias_instability, &axis.random_walk}) {
        if (t->measured) t->note = "moving IMU, " + t->note;
        t->measured = false;
        t->value = t->upper_bound;
      }
    }
  }
  s.white = CombineAxes(s.axes, &AxisNoiseFit::white);
  s.bias_instability = CombineAxes(s.axes, &AxisNoiseFit::bias_instability);
  s.random_walk = CombineAxes(s.axes, &AxisNoiseFit::random_walk);
  return s;
}

}  // namespace

ImuNoiseFit FitImuNoise(const ImuAllanDeviation& curves, const NoiseFitOptions& options) {
  ImuNoiseFit fit;
  fit.gyro =
      FitImuSensor(curves.gyro, options.moving_gyro_adev_rad_s, "rad/s", "gyroscope", options);
  fit.accel =
      FitImuSensor(curves.accel, options.moving_accel_adev_m_s2, "m/s^2", "accelerometer", options);
  return fit;
}

ImuNoise KalibrNoise(const ImuNoiseFit& fit) {
  ImuNoise noise;
  noise.gyroscope_noise_density = fit.gyro.white.value;
  noise.gyroscope_random_walk = fit.gyro.random_walk.value;
  noise.accelerometer_noise_density = fit.accel.white.value;
  noise.accelerometer_random_walk = fit.accel.random_walk.value;
  return noise;
}

namespace {

std::string NoiseTermComment(const NoiseTerm& t) {
  return t.measured ? "measured, " + t.note : "UPPER BOUND only, " + t.note;
}

// One line of text as a YAML comment (no line breaks inside).
std::string YamlCommentLine(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  return text;
}

}  // namespace

std::string KalibrImuYaml(const ImuNoiseFit& fit, const ImuAllanDeviation& curves,
                          const std::string& source, const std::string& rostopic) {
  const UniformSampling& s = curves.sampling;
  std::string y;
  y += YamlCommentLine(fmt::format(
           "# mavloc imu-noise: overlapping Allan deviation (IEEE Std 952/1554) of {}: {} "
           "samples, {:.3f} Hz, {}; per sensor the largest of the x, y, z axes",
           source, s.samples, s.rate_hz, LogLengthText(s.duration_s))) +
       "\n";
  y += "# A value marked UPPER BOUND was not measured: the log does not show its regime (see the\n"
       "# note); the true density is lower. Kalibr suggests inflating measured values for real "
       "use.\n";
  for (const SensorNoiseFit* sensor : {&fit.gyro, &fit.accel})
    if (sensor->moving) y += "# " + YamlCommentLine(sensor->motion_note) + "\n";
  y += YamlCommentLine(fmt::format(
           "# bias instability (no Kalibr key): gyroscope {}{:.4e} rad/s, "
           "accelerometer {}{:.4e} m/s^2",
           fit.gyro.bias_instability.measured ? "" : "<= ", fit.gyro.bias_instability.value,
           fit.accel.bias_instability.measured ? "" : "<= ", fit.accel.bias_instability.value)) +
       "\n";
  const auto key = [&](const char* name, const NoiseTerm& t, const char* unit) {
    y += fmt::format("{}: {:.4e}  # [{}] {}\n", name, t.value, unit,
                     YamlCommentLine(NoiseTermComment(t)));
  };
  key("accelerometer_noise_density", fit.accel.white, "m/s^2/sqrt(Hz)");
  key("accelerometer_random_walk", fit.accel.random_walk, "m/s^3/sqrt(Hz)");
  key("gyroscope_noise_density", fit.gyro.white, "rad/s/sqrt(Hz)");
  key("gyroscope_random_walk", fit.gyro.random_walk, "rad/s^2/sqrt(Hz)");
  y += "rostopic: " + rostopic + "\n";
  y += fmt::format("update_rate: {:.3f}  # [Hz] 1 / median sample interval\n", s.rate_hz);
  return y;
}

std::string AllanDeviationCsv(const ImuAllanDeviation& curves) {
  std::string csv = "tau_s,cluster_size";
  for (const char* sensor : {"gyro", "accel"}) {
    const char* unit = sensor[0] == 'g' ? "rad_s" : "m_s2";
    for (const char* axis : kImuAxisNames)
      for (const char* what : {"adev", "low", "high"})
        csv += fmt::format(",{}_{}_{}_{}", sensor, axis, what, unit);
  }
  csv += "\n";
  const size_t rows = curves.gyro[0].points.size();
  for (size_t i = 0; i < rows; ++i) {
    csv += fmt::format("{:.9g},{}", curves.gyro[0].points[i].tau_s,
                       curves.gyro[0].points[i].cluster_size);
    for (const auto* sensor : {&curves.gyro, &curves.accel})
      for (const AllanCurve& curve : *sensor) {
        const AllanPoint& q = curve.points[i];
        csv += fmt::format(",{:.6e},{:.6e},{:.6e}", q.adev, q.adev_low, q.adev_high);
      }
    csv += "\n";
  }
  return csv;
}

std::string ImuNoiseTable(const ImuNoiseFit& fit, const ImuAllanDeviation& curves) {
  const UniformSampling& s = curves.sampling;
  std::string text = fmt::format(
      "Allan deviation of {} samples at {:.3f} Hz over {} (tau {:.3g}..{:.3g} s); '<=' marks an "
      "upper bound (regime not shown by the curve)\n",
      s.samples, s.rate_hz, LogLengthText(s.duration_s),
      curves.gyro[0].points.empty() ? 0.0 : curves.gyro[0].points.front().tau_s,
      curves.gyro[0].points.empty() ? 0.0 : curves.gyro[0].points.back().tau_s);
  if (curves.gyro[0].cut_at_max_tau)
    text += fmt::format(
        "tau stops at --max-tau {:g} s (a quarter of the log would reach {:.4g} s)\n",
        curves.gyro[0].max_tau_s,
        0.25 * static_cast<double>(curves.gyro[0].samples) * curves.gyro[0].sample_period_s);
  if (s.missing_samples > 0)
    text += fmt::format(
        "{} samples missing (dropped by the logger, {:.2f} %): analysed as {} consecutive "
        "samples\n",
        s.missing_samples,
        100.0 * static_cast<double>(s.missing_samples) /
            static_cast<double>(s.samples + s.missing_samples),
        s.samples);
  const auto cell = [](const NoiseTerm& t) {
    return fmt::format("{}{:.3e}", t.measured ? "   " : "<= ", t.value);
  };
  text += fmt::format("{:<10} {:>13} {:>13} {:>13}   min adev at tau\n", "", "white N",
                      "bias instab. B", "rand. walk K");
  for (const auto& [sensor, name, units] :
       {std::tuple{&fit.gyro, "gyro", "rad/s/sqrt(Hz), rad/s, rad/s^2/sqrt(Hz)"},
        std::tuple{&fit.accel, "accel", "m/s^2/sqrt(Hz), m/s^2, m/s^3/sqrt(Hz)"}}) {
    for (int a = 0; a < 3; ++a) {
      const AxisNoiseFit& axis = sensor->axes[a];
      text += fmt::format("{:<10} {:>13} {:>13} {:>13}   {:.3e} at {:.3g} s\n",
                          fmt::format("{} {}", name, kImuAxisNames[a]), cell(axis.white),
                          cell(axis.bias_instability), cell(axis.random_walk), axis.min_adev,
                          axis.tau_at_min_s);
    }
    text += fmt::format("{:<10} {:>13} {:>13} {:>13}   [{}]\n", fmt::format("{} max", name),
                        cell(sensor->white), cell(sensor->bias_instability),
                        cell(sensor->random_walk), units);
  }
  text += "notes:\n";
  for (const auto& [sensor, name] :
       {std::pair{&fit.gyro, "gyro"}, std::pair{&fit.accel, "accel"}}) {
    if (sensor->moving) text += fmt::format("  {}: {}\n", name, sensor->motion_note);
    for (int a = 0; a < 3; ++a) {
      const AxisNoiseFit& axis = sensor->axes[a];
      text += fmt::format("  {} {} N: {}\n", name, kImuAxisNames[a], axis.white.note);
      text += fmt::format("  {} {} B: {}\n", name, kImuAxisNames[a], axis.bias_instability.note);
      text += fmt::format("  {} {} K: {}\n", name, kImuAxisNames[a], axis.random_walk.note);
    }
  }
  return text;
}

}  // namespace mavloc

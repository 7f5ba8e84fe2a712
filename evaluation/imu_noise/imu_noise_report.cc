#include "evaluation/imu_noise/imu_noise_report.h"

#include <fmt/format.h>

namespace mavloc {

namespace {

nlohmann::json TermValue(const NoiseTerm& term) { return term.value; }
nlohmann::json TermKind(const NoiseTerm& term) {
  return term.measured ? "measured" : "upper bound";
}

// One sensor's table: rows x, y, z and the sensor's value (the largest axis).
ReportTable SensorTable(const std::string& name, const SensorNoiseFit& sensor,
                        const std::string& density_unit, const std::string& instability_unit,
                        const std::string& walk_unit) {
  ReportTable table;
  table.name = name;
  table.title = "Noise of the " + name +
                " by axis, and the value written to imu.yaml (the "
                "largest axis); a term the curve does not show is an upper bound.";
  table.columns = {{"axis", ""},
                   {"white noise density", density_unit},
                   {"white noise status", ""},
                   {"bias instability", instability_unit},
                   {"bias instability status", ""},
                   {"random walk", walk_unit},
                   {"random walk status", ""}};
  const auto row = [&](const std::string& axis, const NoiseTerm& n, const NoiseTerm& b,
                       const NoiseTerm& k) {
    table.rows.push_back(
        {axis, TermValue(n), TermKind(n), TermValue(b), TermKind(b), TermValue(k), TermKind(k)});
  };
  for (int axis = 0; axis < 3; ++axis) {
    const AxisNoiseFit& a = sensor.axes[axis];
    row(std::string(1, "xyz"[axis]), a.white, a.bias_instability, a.random_walk);
  }
  row("imu.yaml", sensor.white, sensor.bias_instability, sensor.random_walk);
  return table;
}

std::string MethodSection(const ImuNoiseReportInput& input, const ImuNoiseFit& fit,
                          const ImuAllanDeviation& curves) {
  std::string md = "Input: `" + input.source + "`" + input.window + ".\n\n";
  md +=
      "Overlapping Allan deviation (IEEE Std 952-1997 Annex C, IEEE Std 1554-2005), 68 % "
      "confidence intervals from the equivalent degrees of freedom of NIST SP 1065 Table 5 "
      "(`allan_deviation.csv`). White noise N is read at tau = 1 s on the slope -1/2, random "
      "walk K at tau = 3 s on the slope +1/2, bias instability B = min / 0.664 on a flat floor; "
      "a term the curve does not show is an upper bound. How to read it: "
      "docs/commands/imu-noise.md.\n\n";
  if (const AllanCurve& curve = curves.gyro[0]; curve.cut_at_max_tau)
    md += fmt::format(
        "Cluster times stop at --max-tau = {:g} s; a quarter of this log would reach {:.4g} s "
        "(the log was streamed twice, and the history the longest tau needs bounds the "
        "memory).\n\n",
        curve.max_tau_s, 0.25 * static_cast<double>(curve.samples) * curve.sample_period_s);
  for (const SensorNoiseFit* sensor : {&fit.gyro, &fit.accel})
    if (sensor->moving) md += "- " + sensor->motion_note + "\n";
  md += "\nKalibr `imu.yaml` (per sensor the largest axis):\n\n```yaml\n" +
        KalibrImuYaml(fit, curves, input.source, input.rostopic) + "```\n";
  if (!input.notes.empty()) {
    md += "\nReader notes:\n\n";
    for (const std::string& note : input.notes) md += "- " + note + "\n";
  }
  return md;
}

}  // namespace

Report ImuNoiseReport(const ImuNoiseReportInput& input, const ImuNoiseFit& fit,
                      const ImuAllanDeviation& curves) {
  Report report;
  report.kind = "imu-noise";
  report.title = "IMU noise by Allan deviation";
  report.provenance.input = input.source;
  report.tables.push_back(
      SensorTable("gyroscope", fit.gyro, "rad/s/sqrt(Hz)", "rad/s", "rad/s^2/sqrt(Hz)"));
  report.tables.push_back(
      SensorTable("accelerometer", fit.accel, "m/s^2/sqrt(Hz)", "m/s^2", "m/s^3/sqrt(Hz)"));
  report.sections.push_back({"Method and imu.yaml", MethodSection(input, fit, curves)});
  for (const SensorNoiseFit* sensor : {&fit.gyro, &fit.accel})
    if (sensor->moving) report.warnings.push_back(sensor->motion_note);
  report.files["imu.yaml"] = KalibrImuYaml(fit, curves, input.source, input.rostopic);
  report.files["allan_deviation.csv"] = AllanDeviationCsv(curves);
  return report;
}

}  // namespace mavloc

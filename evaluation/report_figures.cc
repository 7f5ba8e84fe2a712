#include "evaluation/report_figures.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/atomic_file.h"
#include "core/input_file.h"
#include "core/interrupt.h"
#include "core/subprocess.h"
#include "core/text.h"
#include "evaluation/report_figures_script.h"  // generated: kReportFiguresScript (CMakeLists.txt)
#include "evaluation/report_html.h"

namespace mavloc {
namespace {

namespace fs = std::filesystem;

constexpr const char* kDefaultPython = "/usr/bin/python3";
// The Markdown section this file appends (and replaces on a re-run) in report.md / eval.md.
constexpr const char* kFiguresMarker = "<!-- mavloc:figures -->";
// Exit code of the script when matplotlib or numpy cannot be imported.
constexpr int kMissingModuleExit = 3;
constexpr const char* kNoReportHere =
    "the folder holds no mavloc report (a report.json or eval.json naming its report_kind)";

bool Exists(const std::string& dir, const std::string& name) {
  std::error_code error;
  return fs::exists(fs::path(dir) / name, error);
}

std::string LastLines(const std::string& text, int count) {
  std::string trimmed = text;
  while (!trimmed.empty() && (trimmed.back() == '\n' || trimmed.back() == '\r')) trimmed.pop_back();
  size_t begin = trimmed.size();
  for (int k = 0; k < count && begin != std::string::npos && begin > 0; ++k)
    begin = trimmed.rfind('\n', begin - 1);
  return begin == std::string::npos ? trimmed : trimmed.substr(begin + 1);
}

std::string PythonPath() {
  const char* env = std::getenv("MAVLOC_PYTHON");
  return env && *env ? env : kDefaultPython;
}

std::string HowToGetFigures(const std::string& report_dir) {
  return "the figures need Python 3 with matplotlib: on Debian or Ubuntu `sudo apt-get install "
         "python3-matplotlib` (scripts/setup installs it), then `mavloc figures " +
         report_dir +
         "` draws them and rewrites report.html from this folder (or run the same mavloc command "
         "again). Another interpreter: set MAVLOC_PYTHON=/path/to/python3.";
}

struct ScriptRun {
  int exit_code = -1;
  std::string out, err;
};

// The files the script may read: the folder's regular files, not symbolic links (mavloc writes
// none) nor temporaries. A named pipe among them would block the script's open(); a link could
// point anywhere. `refused` gets each entry that is neither a file, a folder nor a link, with why.
std::vector<std::string> ScriptInputs(const std::string& report_dir,
                                      std::vector<std::string>* refused) {
  std::vector<std::string> names;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(report_dir, error)) {
    const std::string name = entry.path().filename().string();
    if (name.find(".tmp-") != std::string::npos) continue;
    const fs::file_type type = entry.symlink_status(error).type();
    if (type == fs::file_type::regular)
      names.push_back(name);
    else if (type != fs::file_type::directory && type != fs::file_type::symlink)
      refused->push_back(name + " " + NotARegularFile(entry.path().string()));
  }
  std::sort(names.begin(), names.end());
  std::sort(refused->begin(), refused->end());
  return names;
}

// Writes the embedded script to a private temporary file and runs it with the file names it is
// given: python SCRIPT DIR --kind KIND --out-dir STAGE --input NAME... The script reads only
// DIR/NAME and writes its PNG files into STAGE (each to a temporary name, then os.replace).
ScriptRun RunScript(const std::string& python, const std::string& report_dir,
                    const std::string& kind, const std::string& stage,
                    const std::vector<std::string>& inputs) {
  std::error_code error;
  const fs::path tmp = fs::temp_directory_path(error);
  const TemporaryFile script(error ? std::string("/tmp") : tmp.string(),
                             "mavloc_report_figures_script", ".py", kReportFiguresScript);
  std::vector<std::string> argv = {python, script.path(), report_dir, "--kind",
                                   kind,   "--out-dir",   stage};
  for (const std::string& name : inputs) {
    argv.push_back("--input");
    argv.push_back(name);
  }
  const ProgramRun program = RunProgram(argv);
  ScriptRun run;
  run.exit_code = program.started ? program.exit_code : 127;
  run.out = program.out;
  run.err = program.started ? program.err : program.error;
  return run;
}

// A figure the script announces must be a plain PNG name in its folder: no path, no hidden file.
bool IsFigureName(const std::string& name) {
  return !name.empty() && name.size() < 256 && name.front() != '.' &&
         name.find('/') == std::string::npos && EndsWith(name, ".png");
}

std::string MarkdownName(ReportKind) { return "report.md"; }

std::string WithoutFiguresSection(const std::string& markdown) {
  const auto at = markdown.find(kFiguresMarker);
  return at == std::string::npos ? markdown : markdown.substr(0, at);
}

std::string TitleOf(const std::string& markdown, const std::string& report_dir) {
  std::istringstream in(markdown);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("# ", 0) == 0) return line.substr(2);
  return "mavloc report: " + report_dir;
}

// The Markdown report says which figures there are (report.html holds them) or how to get them.
std::string FiguresSection(const FigureOutcome& outcome) {
  std::string text = std::string(kFiguresMarker) + "\n## Figures\n\n";
  if (outcome.figures.empty()) {
    text += "No figures: " + outcome.reason + "\n";
    if (!outcome.how_to_get_figures.empty())
      text += "\nTo get them: " + outcome.how_to_get_figures + "\n";
    return text;
  }
  text += "All tables and figures in one page: [report.html](report.html).\n\n";
  for (const auto& file : outcome.figures) text += "![" + file + "](" + file + ")\n\n";
  if (!outcome.reason.empty()) text += "Some figures are missing: " + outcome.reason + "\n";
  return text;
}

std::vector<std::string> DataFiles(const std::string& report_dir,
                                   const std::vector<std::string>& figures) {
  std::vector<std::string> files;
  std::error_code error;
  for (const auto& entry : fs::directory_iterator(report_dir, error)) {
    if (!entry.is_regular_file(error)) continue;
    const std::string name = entry.path().filename().string();
    if (name == "report.html" || name.find(".tmp-") != std::string::npos) continue;
    if (std::find(figures.begin(), figures.end(), name) != figures.end()) continue;
    files.push_back(name);
  }
  std::sort(files.begin(), files.end());
  return files;
}

// Draws the figures into `outcome` (figures, reason, how_to_get_figures).
// The texts name `shown_dir`, the folder the user will find the report in.
// The PNG files stay in `stage` and are added to `files`, which renames them into report_dir
// together with report.html.
void DrawFigures(const std::string& report_dir, const std::string& shown_dir,
                 const std::string& stage, AtomicFileSet* files, FigureOutcome* outcome,
                 std::vector<HtmlFigure>* html_figures) {
  const char* switch_env = std::getenv("MAVLOC_FIGURES");
  if (switch_env && (std::string(switch_env) == "0" || std::string(switch_env) == "off")) {
    outcome->reason = "figures switched off (MAVLOC_FIGURES=" + std::string(switch_env) + ")";
    outcome->how_to_get_figures = "unset MAVLOC_FIGURES and run `mavloc figures " + shown_dir + "`";
    return;
  }
  if (outcome->kind == ReportKind::kUnknown) {
    outcome->reason = kNoReportHere;
    return;
  }
  const std::string python = PythonPath();
  if (::access(python.c_str(), X_OK) != 0) {
    outcome->reason = "no Python interpreter at " + python;
    outcome->how_to_get_figures = HowToGetFigures(shown_dir);
    return;
  }
  std::vector<std::string> refused;
  const std::vector<std::string> inputs = ScriptInputs(report_dir, &refused);
  const ScriptRun run = RunScript(python, report_dir, ReportKindName(outcome->kind), stage, inputs);
  std::istringstream lines(run.out);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("figure\t", 0) != 0) continue;
    const auto tab = line.find('\t', 7);
    const std::string file = line.substr(7, tab == std::string::npos ? tab : tab - 7);
    const std::string caption = tab == std::string::npos ? "" : line.substr(tab + 1);
    if (!IsFigureName(file)) continue;
    if (std::find(outcome->figures.begin(), outcome->figures.end(), file) != outcome->figures.end())
      continue;
    const std::string drawn = (fs::path(stage) / file).string();
    const std::string bytes = ReadWholeFile(drawn);
    if (bytes.empty()) continue;
    files->AddWritten(drawn, (fs::path(report_dir) / file).string());
    outcome->figures.push_back(file);
    html_figures->push_back({file, caption, bytes});
  }
  if (run.exit_code == kMissingModuleExit) {
    outcome->reason =
        "matplotlib is not available to " + python + " (" + LastLines(run.err, 1) + ")";
    outcome->how_to_get_figures = HowToGetFigures(shown_dir);
  } else if (run.exit_code == 126 || run.exit_code == 127) {
    outcome->reason = python + " cannot be run: " + LastLines(run.err, 1);
    outcome->how_to_get_figures = HowToGetFigures(shown_dir);
  } else if (run.exit_code != 0) {
    outcome->reason = "the plotting script failed (exit code " + std::to_string(run.exit_code) +
                      "): " + LastLines(run.err, 1);
  } else if (outcome->figures.empty()) {
    outcome->reason = "nothing to plot in this " + ReportKindName(outcome->kind) + " report";
  }
  if (!refused.empty()) {
    std::string list;
    for (const std::string& entry : refused) list += (list.empty() ? "" : "; ") + entry;
    outcome->reason += (outcome->reason.empty() ? "" : "; ") + ("not read: " + list);
  }
}

}  // namespace

std::string ReportKindName(ReportKind kind) {
  switch (kind) {
    case ReportKind::kEval:
      return "eval";
    case ReportKind::kCompare:
      return "compare";
    case ReportKind::kRepro:
      return "repro";
    case ReportKind::kSweep:
      return "sweep";
    case ReportKind::kObstacles:
      return "obstacles";
    case ReportKind::kMatrix:
      return "matrix";
    case ReportKind::kImuNoise:
      return "imu-noise";
    case ReportKind::kUnknown:
      break;
  }
  return "unknown";
}

ReportKind DetectReportKind(const std::string& report_dir) {
  for (const char* name : {"report.json", "eval.json"}) {
    const std::string path = (fs::path(report_dir) / name).string();
    if (!Exists(report_dir, name)) continue;
    const nlohmann::json json = nlohmann::json::parse(ReadWholeFile(path), nullptr, false);
    if (!json.is_object() || !json.contains("report_kind") || !json["report_kind"].is_string())
      continue;
    const std::string kind = json["report_kind"].get<std::string>();
    for (const ReportKind k :
         {ReportKind::kEval, ReportKind::kCompare, ReportKind::kRepro, ReportKind::kSweep,
          ReportKind::kObstacles, ReportKind::kMatrix, ReportKind::kImuNoise})
      if (kind == ReportKindName(k)) return k;
  }
  return ReportKind::kUnknown;
}

FigureOutcome WriteReportFigures(const std::string& report_dir, const std::string& shown_dir) {
  const std::string& shown = shown_dir.empty() ? report_dir : shown_dir;
  FigureOutcome outcome;
  std::error_code error;
  if (!fs::is_directory(report_dir, error)) {
    outcome.reason = report_dir + ": not a folder";
    return outcome;
  }
  outcome.kind = DetectReportKind(report_dir);
  std::vector<HtmlFigure> html_figures;
  // The figures, report.html and the Markdown report appear together (AtomicFileSet): an
  // interrupt leaves the old set or the new one, never new figures that the page does not list.
  AtomicFileSet files;
  std::unique_ptr<TemporaryFolder> stage;
  try {
    stage = std::make_unique<TemporaryFolder>(report_dir, ".figures");
    DrawFigures(report_dir, shown, stage->path(), &files, &outcome, &html_figures);
  } catch (const std::exception& e) {  // e.g. temporary folder or pipe failures
    outcome.reason = std::string("figures not drawn: ") + e.what();
  }

  const std::string markdown_path = (fs::path(report_dir) / MarkdownName(outcome.kind)).string();
  const std::string markdown = WithoutFiguresSection(ReadWholeFile(markdown_path));
  HtmlPage page;
  page.title = TitleOf(markdown, shown);
  page.markdown = markdown;
  page.figures = std::move(html_figures);
  page.figures_note =
      "No figures: " + outcome.reason +
      (outcome.how_to_get_figures.empty() ? std::string()
                                          : "\n\nTo get them: " + outcome.how_to_get_figures);
  page.data_files = DataFiles(report_dir, outcome.figures);
  try {
    const std::string html_path = (fs::path(report_dir) / "report.html").string();
    files.Add(html_path, RenderReportHtml(page));
    if (!markdown.empty() || fs::exists(markdown_path, error)) {
      std::string with_section = markdown;
      while (!with_section.empty() && with_section.back() == '\n') with_section.pop_back();
      files.Add(markdown_path, with_section + "\n\n" + FiguresSection(outcome));
    }
    files.Commit();
    outcome.html_path = html_path;
  } catch (const std::exception& e) {
    outcome.reason +=
        std::string(outcome.reason.empty() ? "" : "; ") + "report.html not written: " + e.what();
  }
  return outcome;
}

std::string DescribeFigureOutcome(const FigureOutcome& outcome) {
  std::string text;
  if (!outcome.figures.empty()) {
    text = "figures:";
    for (size_t i = 0; i < outcome.figures.size(); ++i)
      text += (i ? ", " : " ") + outcome.figures[i];
  } else {
    text = "no figures: " + outcome.reason;
  }
  if (!outcome.html_path.empty()) text += "; all in " + outcome.html_path;
  if (!outcome.figures.empty() && !outcome.reason.empty()) text += " (" + outcome.reason + ")";
  if (!outcome.how_to_get_figures.empty())
    text += "\nto get the figures: " + outcome.how_to_get_figures;
  return text;
}

}  // namespace mavloc

#include "cli/report_renderer.hpp"

#include <cstdlib>
#include <string>
#include <vector>

#include "cli/child_process.hpp"
#include "core/error.hpp"
#include "io/data_directory.hpp"

namespace tofcomp::cli {
namespace {

// The script's exit status when Python lacks a module it needs (cli/report/diagnosis_report.py).
constexpr int kMissingModuleExit = 3;

std::vector<std::string> python_candidates() {
  const char* chosen = std::getenv("TOFCOMP_PYTHON");
  if (chosen != nullptr && *chosen != '\0') return {chosen};
  return {"python3", "/usr/bin/python3"};
}

std::string trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

// The first candidate Python that has matplotlib and numpy, asked by the script itself
// (--check); throws naming what each candidate lacks.
std::string python_with_matplotlib(const std::filesystem::path& script) {
  std::string lacks;
  for (const std::string& python : python_candidates()) {
    const ChildOutcome check =
        run_child({python, script.string(), "--check"}, ChildStdout::Capture);
    if (check.started && check.exit_code == 0) return python;
    lacks += "; " + python + ": ";
    if (!check.started) {
      lacks += "not found";
    } else if (check.exit_code == kMissingModuleExit) {
      lacks += trimmed(check.output);
    } else {
      lacks += "the check failed with exit code " + std::to_string(check.exit_code);
    }
  }
  throw core::Error(
      "cannot draw the report's figures: no Python 3 with matplotlib and numpy" + lacks +
      ". Install them with `apt-get install python3 python3-matplotlib python3-numpy` (Debian; "
      "tools/setup.sh does it), or set TOFCOMP_PYTHON to a Python 3 that has both");
}

// The script beside the binary (see the header); throws naming where it looked.
std::filesystem::path report_script_path() {
  const std::filesystem::path script = io::data_directory() / "report" / "diagnosis_report.py";
  if (!std::filesystem::is_regular_file(script)) {
    throw core::Error("cannot find the report renderer " + script.string() +
                      " (it is looked for in the data directory beside the tofcomp binary); "
                      "build the tofcomp target again, or install with cmake --install");
  }
  return script;
}

}  // namespace

ReportRenderer find_report_renderer() {
  ReportRenderer renderer;
  renderer.script = report_script_path();
  renderer.python = python_with_matplotlib(renderer.script);
  return renderer;
}

void ReportRenderer::render(const std::filesystem::path& directory, bool show_progress,
                            Rendering what) const {
  std::vector<std::string> argv{python, script.string(), directory.string()};
  if (what == Rendering::Figures) argv.push_back("--figures");
  if (!show_progress) argv.push_back("--quiet");
  const ChildOutcome run = run_child(argv, ChildStdout::ToStderr);
  if (!run.started || run.exit_code != 0) {
    throw core::Error("the report renderer " + script.string() + " failed on " +
                      directory.string() + " with exit code " + std::to_string(run.exit_code) +
                      " (its message is above)");
  }
}

}  // namespace tofcomp::cli

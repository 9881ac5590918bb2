// Running the report's renderer: cli/report/diagnosis_report.py, a Python 3 script that draws
// the figures with matplotlib (Agg) and writes DIR/index.html from the data in DIR/data/.
//
// Where the script is: in the data directory beside the binary (io/data_directory.hpp),
// <directory of tofcomp>/../share/tofcomp/report/. `cmake --install` puts it at
// PREFIX/share/tofcomp/report/ next to PREFIX/bin/tofcomp; the build copies it to
// build/share/tofcomp/report/ next to build/cli/tofcomp, so both find it the same way.
//
// Which Python: $TOFCOMP_PYTHON when set; otherwise `python3` on PATH, then /usr/bin/python3
// (Debian's, where python3-matplotlib installs), the first that imports matplotlib and numpy.
#pragma once

#include <filesystem>
#include <string>

namespace tofcomp::cli {

// What the renderer makes of a directory: the whole report (DIR/data/ of `diagnose --report`),
// or the paper's figures alone (DIR/data/ of `evaluate --figures`, no page).
enum class Rendering { Report, Figures };

struct ReportRenderer {
  std::filesystem::path script;
  std::string python;  // an interpreter that has matplotlib and numpy

  // Renders DIR (its data/ written beforehand) into DIR/figures/*.png and, for the report,
  // DIR/index.html. The script's progress (when show_progress) and errors go to stderr. Throws
  // core::Error when the script fails.
  void render(const std::filesystem::path& directory, bool show_progress,
              Rendering what = Rendering::Report) const;
};

// The renderer script as this binary finds it, and the Python to run it: found before any
// long work, so that a missing piece fails at once. Throws core::Error naming where the script
// was looked for, or what each Python lacks and how to install it.
ReportRenderer find_report_renderer();

}  // namespace tofcomp::cli

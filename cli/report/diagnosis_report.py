#!/usr/bin/env python3
"""The renderer of `tofcomp diagnose --report DIR` (cli/report_renderer.hpp runs it).

    diagnosis_report.py [--quiet] DIR   draws DIR/figures/*.png from DIR/data/ and writes
                                        DIR/index.html (progress on stderr unless --quiet)
    diagnosis_report.py [--quiet] --figures DIR
                                  draws the paper's figures the data of `tofcomp evaluate
                                  --figures DIR` allow into DIR/figures/*.png (no page)
    diagnosis_report.py --check   exits 0 when numpy and matplotlib import, 3 (naming what is
                                  missing) otherwise

Figures are drawn by matplotlib with the Agg backend (Debian: python3-matplotlib,
python3-numpy). Exit status: 0 done, 1 bad input (the message names the file), 2 bad command
line, 3 a Python module missing.
"""

import importlib
import os
import sys

sys.dont_write_bytecode = True  # nothing written beside the installed scripts

MISSING_MODULE_EXIT = 3
REQUIRED_MODULES = {"numpy": "python3-numpy", "matplotlib": "python3-matplotlib"}


def missing_modules():
    missing = []
    for module, package in REQUIRED_MODULES.items():
        try:
            importlib.import_module(module)
        except ImportError:
            missing.append(f"{module} (Debian package {package})")
    return missing


def render(directory, quiet, figures_only):
    """The report (or, figures_only, the paper's figures of `evaluate --figures`) of DIR."""
    from report_data import ReportInputError, load_figure_data, load_report_data
    from report_figures import draw_figures

    stage = "figures" if figures_only else "report"
    try:
        data = load_figure_data(directory) if figures_only else load_report_data(directory)
    except ReportInputError as e:
        print(f"diagnosis_report: error: {e}", file=sys.stderr)
        return 1

    def progress(message):
        if not quiet:
            print(f"{stage}: {message}", file=sys.stderr, flush=True)

    def drawing(message):
        progress(f"drawing {message}")

    if figures_only:
        figures, skipped = draw_figures(data, directory, drawing)
        progress(f"{len(figures)} figures of the paper in {os.path.join(directory, 'figures')} "
                 f"(Fig. {', '.join(skipped)} need `tofcomp diagnose --report`)")
        return 0
    from report_figures_findings import draw_finding_figures
    from report_figures_terms import draw_term_figures
    from report_html import write_page

    term_figures = draw_term_figures(data, directory, drawing)
    figures, skipped = draw_figures(data, directory, drawing)
    finding_figures = draw_finding_figures(data, directory, drawing)
    page = os.path.join(directory, "index.html")
    write_page(page, data, figures, skipped, finding_figures, term_figures)
    progress(f"wrote {page} with {len(term_figures)} figures of the search's terms, "
             f"{len(figures)} of the paper and {len(finding_figures)} of the residual tests")
    return 0


def main(argv):
    quiet = "--quiet" in argv[1:]
    figures_only = "--figures" in argv[1:]
    arguments = [a for a in argv[1:] if a not in ("--quiet", "--figures")]
    if len(arguments) != 1 or arguments[0] in ("-h", "--help"):
        print(__doc__, file=sys.stderr)
        return 2
    check = arguments[0] == "--check"
    missing = missing_modules()
    if missing:
        message = f"{sys.executable} lacks the Python module(s) {', '.join(missing)}"
        if check:
            print(message)
        else:
            print(f"diagnosis_report: error: {message}; install them with "
                  f"apt-get install python3-matplotlib python3-numpy", file=sys.stderr)
        return MISSING_MODULE_EXIT
    if check:
        return 0
    return render(arguments[0], quiet, figures_only)


if __name__ == "__main__":
    sys.exit(main(sys.argv))

"""Reading what `tofcomp diagnose --report DIR` wrote into DIR/data/ (cli/diagnosis_report.hpp).

Every CSV is read into a table: a dict of column name -> numpy array (float where every cell is a
number or empty, which becomes NaN; text otherwise). A file that is missing or malformed raises
ReportInputError naming the file, the line and the column.
"""

import csv
import json
import os
from dataclasses import dataclass, field

import numpy as np


class ReportInputError(Exception):
    """Input of the report that is missing or cannot be read; the message names the file."""


def _column(cells):
    try:
        return np.array([float(c) if c != "" else np.nan for c in cells], dtype=float)
    except ValueError:
        return np.array(cells, dtype=object)


def read_table(path):
    """The CSV at path as {column: array}; raises ReportInputError naming the file and line."""
    try:
        with open(path, newline="", encoding="utf-8") as f:
            rows = list(csv.reader(f))
    except OSError as e:
        raise ReportInputError(f"{path}: cannot read it: {e.strerror}") from e
    if not rows:
        raise ReportInputError(f"{path}: empty, a header row was expected")
    header, body = rows[0], rows[1:]
    for line, row in enumerate(body, start=2):
        if len(row) != len(header):
            raise ReportInputError(
                f"{path}:{line}: {len(row)} cells, the header has {len(header)}")
    return {name: _column([row[i] for row in body]) for i, name in enumerate(header)}


def require_columns(table, path, names):
    missing = [n for n in names if n not in table]
    if missing:
        raise ReportInputError(f"{path}: missing column(s) {', '.join(missing)}")


def read_json(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except OSError as e:
        raise ReportInputError(f"{path}: cannot read it: {e.strerror}") from e
    except json.JSONDecodeError as e:
        raise ReportInputError(f"{path}:{e.lineno}:{e.colno}: not JSON: {e.msg}") from e


@dataclass
class ReportData:
    """Everything DIR/data/ holds; optional parts are None when the data did not allow them."""
    directory: str
    context: dict
    diagnosis: dict
    samples: dict
    diagnosis_samples: dict  # the whole record under the trained model the tests ran under
    search_residuals: dict  # the whole record under the search's final calibration
    search_terms: list  # the figures of the search's terms: context's entry with its tables
    windows: dict = field(default_factory=dict)  # window length -> table
    thermal_fit: dict = None
    em_convergence: dict = None
    glr: dict = None
    em_test_trace: dict = None
    em_test_cost: dict = None
    moments: dict = None


def _optional_table(data_dir, name):
    path = os.path.join(data_dir, name)
    return read_table(path) if os.path.exists(path) else None


def _samples(data_dir):
    """samples.csv: per tested range, what the paper's figures of the ranges draw."""
    path = os.path.join(data_dir, "samples.csv")
    samples = read_table(path)
    require_columns(samples, path,
                    ["time_s", "range_mm", "junction_c", "bias_mm", "most_probable_mode",
                     "compensated_mm", "true_range_mm"])
    return samples


def _windows(data_dir, lengths):
    """windows_<W>.csv of each window length W that has one: length -> table."""
    windows = {}
    for length in sorted(lengths):
        table = _optional_table(data_dir, f"windows_{length}.csv")
        if table is not None:
            windows[int(length)] = table
    return windows


def load_report_data(directory):
    data_dir = os.path.join(directory, "data")
    if not os.path.isdir(data_dir):
        raise ReportInputError(f"{data_dir}: no such directory (run tofcomp diagnose --report)")
    context_path = os.path.join(data_dir, "context.json")
    context = read_json(context_path)
    if "diagnosis_samples" not in context:
        raise ReportInputError(f"{context_path}: no diagnosis_samples (what the C++ side "
                               f"computed for the findings' figures)")
    diagnosis_path = os.path.join(data_dir, "diagnosis.json")
    diagnosis = read_json(diagnosis_path)
    if not isinstance(diagnosis.get("search"), dict):
        raise ReportInputError(f"{diagnosis_path}: no search (the JSON of `tofcomp diagnose "
                               f"--json` has the model search under \"search\")")
    if "search_terms" not in context:
        raise ReportInputError(f"{context_path}: no search_terms (what the C++ side computed "
                               f"for the figures of the search's terms)")
    samples = _samples(data_dir)
    diagnosis_samples_path = os.path.join(data_dir, "diagnosis_samples.csv")
    diagnosis_samples = read_table(diagnosis_samples_path)
    require_columns(diagnosis_samples, diagnosis_samples_path,
                    ["time_s", "time_since_power_on_s", "range_mm", "true_range_mm",
                     "junction_c", "bias_mm", "residual_mm", "mode", "e_mm",
                     "heating_rate_c_per_min"])
    search_residuals_path = os.path.join(data_dir, "search_residuals.csv")
    search_residuals = read_table(search_residuals_path)
    require_columns(search_residuals, search_residuals_path,
                    ["time_s", "residual_mm", "mode", "e_mm"])
    windows = _windows(data_dir, set(context.get("windows", [])) |
                       set(context.get("moment_windows", [])))
    return ReportData(
        directory=directory,
        context=context,
        diagnosis=diagnosis,
        samples=samples,
        diagnosis_samples=diagnosis_samples,
        search_residuals=search_residuals,
        search_terms=[_term_tables(data_dir, entry) for entry in context["search_terms"]],
        windows=windows,
        thermal_fit=_optional_table(data_dir, "thermal_fit.csv"),
        em_convergence=_optional_table(data_dir, "em_convergence.csv"),
        glr=_optional_table(data_dir, "glr.csv"),
        em_test_trace=_optional_table(data_dir, "em_test_trace.csv"),
        em_test_cost=_optional_table(data_dir, "em_test_cost.csv"),
        moments=_optional_table(data_dir, "moments.csv"),
    )


def load_figure_data(directory):
    """The data of `tofcomp evaluate --figures DIR` (or `test --figures`): DIR/data/ holds the
    tables of cli/figure_data.hpp and a context.json of the training; no diagnosis. What the
    report draws from a diagnosis is then absent, and the figures that need it are left out."""
    data_dir = os.path.join(directory, "data")
    if not os.path.isdir(data_dir):
        raise ReportInputError(f"{data_dir}: no such directory (run tofcomp evaluate --figures)")
    context = read_json(os.path.join(data_dir, "context.json"))
    samples = _samples(data_dir)
    windows = _windows(data_dir, set(context.get("windows", [])))
    return ReportData(
        directory=directory,
        context=context,
        diagnosis={},
        samples=samples,
        diagnosis_samples=None,
        search_residuals=None,
        search_terms=[],
        windows=windows,
        thermal_fit=_optional_table(data_dir, "thermal_fit.csv"),
        em_convergence=_optional_table(data_dir, "em_convergence.csv"),
    )


# The columns of each table of a term's figure (cli/term_figure_tables.hpp).
TERM_COLUMNS = {
    "ranges": ["covariate", "partial_residual_mm", "mode", "in_term"],
    "curve": ["covariate", "fitted_mm"],
    "bins": ["bin", "low", "high", "covariate_mean", "mode", "ranges", "observed", "fitted",
             "held"],
    "runs": ["mode", "length", "observed", "chain", "independent"],
    "density": ["residual_mm", "total"],
}


def _term_tables(data_dir, entry):
    """The context's entry of one term with its tables read: entry["tables"][kind] = table."""
    tables = {}
    for kind, name in (entry.get("files") or {}).items():
        path = os.path.join(data_dir, name)
        table = read_table(path)
        require_columns(table, path, TERM_COLUMNS.get(kind, []))
        tables[kind] = table
    return dict(entry, tables=tables)


def mode_count(samples):
    return sum(1 for name in samples if name.startswith("posterior_mode"))


def most_probable_mode(samples):
    """Index (0-based) of each range's most probable mode (the Δ̂ of Eq. 22), as the C++ side
    chose it (cli/figure_data.hpp)."""
    return samples["most_probable_mode"].astype(int)

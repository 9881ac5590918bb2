"""The paper's figures (Alhashimi et al., Sensors 2015) on the data of a diagnosis report: which
figure each drawing function is, in the paper's order, and drawing them all into DIR/figures/.
The drawing functions live in report_figures_ranges, report_figures_em and
report_figures_windows; what they share in report_style.
"""

import os
import re

from report_figures_em import (em_testing_convergence, em_testing_cost, em_training_convergence,
                               glr_fourier, glr_polynomial)
from report_figures_ranges import (bias_against_temperature, distribution_before_after,
                                   histogram, mode_assignment, thermal_fit)
from report_figures_windows import (absolute_error_moments, error_moments, errors_over_time,
                                    estimates_by_window)


# In the paper's order: each paper figure number and the function that draws it.
FIGURES = [
    ("3", histogram),
    ("4", bias_against_temperature),
    ("8", thermal_fit),
    ("9", glr_polynomial),
    ("10", glr_fourier),
    ("11", mode_assignment),
    ("12", distribution_before_after),
    ("13", em_training_convergence),
    ("14", em_testing_convergence),
    ("15", em_testing_cost),
    ("16", estimates_by_window),
    ("17", errors_over_time),
    ("18", error_moments),
    ("19", absolute_error_moments),
]


def draw_figures(data, directory, progress):
    """Draws every figure the data allow; returns (figures, paper numbers left out). A figure
    of an earlier report in the same directory that these data do not allow is removed."""
    os.makedirs(os.path.join(directory, "figures"), exist_ok=True)
    figures, skipped = [], []
    for i, (number, draw) in enumerate(FIGURES):
        progress(f"Fig. {number} ({i + 1}/{len(FIGURES)})")
        figure = draw(data, directory)
        if figure is None:
            skipped.append(number)
        else:
            figure.number = number
            figures.append(figure)
    drawn = {os.path.basename(f.file) for f in figures}
    for name in os.listdir(os.path.join(directory, "figures")):
        if re.fullmatch(r"fig\d\d_\w+\.png", name) and name not in drawn:
            os.remove(os.path.join(directory, "figures", name))
    return figures, skipped

"""Measuring reconstructions against ground truth: metrics, aggregates, reports and figures.

Used by ``blender_scripts/eval.py`` (which adds Blender's 3-D renders) and usable on its own; no
``bpy`` here, and not part of the add-on's zip (the add-on never imports it). One module per concern:

- :mod:`.metrics`: angular, depth and light errors on the eroded ground-truth mask; a normal map's block grid;
- :mod:`.inputs`: the checks of what a run is given, and synthetic datasets written to disk;
- :mod:`.runner`: the methods run on one sample, on a dataset, and the paper's experiment;
- :mod:`.report`: means, ranking, Markdown tables and the result files;
- :mod:`.figures`: the strip of one sample;
- :mod:`.real`: real photographs (DiLiGenT), calibrated and estimated light, beside a flat plane;
- :mod:`.photographs`: several DiLiGenT photographs at once, beside plain least squares, and with the
  lights estimated.

A record is one (sample, method) pair: a flat dict of the metrics, or ``status == "failed"`` with
the error message. Angles are in degrees, depth in pixel units.
"""

from .figures import save_strip
from .inputs import EvaluationError, check_methods, prepare_output, read_manifest, write_synthetic_dataset
from .metrics import (ERODE_PIXELS, GRID_PERIODS, METRICS, THRESHOLDS, depth_errors, grid_step_ratio, light_error,
                      mask_parts, normal_errors, seam_pixels, seam_share)
from .photographs import ESTIMATED, PHOTOGRAPH_SETS, evaluate_sets, median_light_error, plain_least_squares, set_label
from .real import FLAT, evaluate_object, evaluate_real, find_objects, flat_record, import_objects
from .report import (CSV_COLUMNS, method_table, photographs_table, photographs_text, real_table, shape_table,
                     write_results)
from .summary import summarize
from .runner import PAPER_LIGHT, Evaluation, SampleResult, evaluate_dataset, evaluate_sample, paper_experiment

__all__ = [
    "CSV_COLUMNS",
    "ERODE_PIXELS",
    "ESTIMATED",
    "FLAT",
    "GRID_PERIODS",
    "METRICS",
    "PAPER_LIGHT",
    "PHOTOGRAPH_SETS",
    "THRESHOLDS",
    "Evaluation",
    "EvaluationError",
    "SampleResult",
    "check_methods",
    "find_objects",
    "grid_step_ratio",
    "flat_record",
    "import_objects",
    "depth_errors",
    "evaluate_dataset",
    "evaluate_object",
    "evaluate_real",
    "evaluate_sample",
    "evaluate_sets",
    "light_error",
    "mask_parts",
    "median_light_error",
    "method_table",
    "normal_errors",
    "paper_experiment",
    "photographs_table",
    "photographs_text",
    "plain_least_squares",
    "prepare_output",
    "read_manifest",
    "real_table",
    "save_strip",
    "shape_table",
    "seam_pixels",
    "set_label",
    "seam_share",
    "summarize",
    "write_results",
    "write_synthetic_dataset",
]

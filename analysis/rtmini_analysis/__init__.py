"""rtmini analysis: plots and reports from the apps' --timings/--summary files.

One command-line tool per product, run from the analysis/ directory (or with
analysis/ on PYTHONPATH) as ``/usr/bin/python3 -m rtmini_analysis.<tool>``:
rank_completion, scaling, accuracy, timing_report. Formats: ../FORMATS.md.
"""

__version__ = "0.1.0"

"""What every tool shares at its command line: bad input -> one line on stderr, exit 2."""

import importlib
import sys

from .io import FormatError


def run(main, argv=None):
    """Call main(argv); a FormatError becomes 'file[:line]: reason' and exit code 2."""
    try:
        return main(argv)
    except FormatError as err:
        print(err, file=sys.stderr)
        return 2


def _console_script(tool):
    """The installed command of one tool (analysis/pyproject.toml): run its main with run()."""

    def entry():
        module = importlib.import_module(f"rtmini_analysis.{tool}")
        sys.exit(run(module.main))

    entry.__name__ = tool
    return entry


TOOLS = ("rank_completion", "scaling", "accuracy", "timing_report", "sweep")
rank_completion = _console_script("rank_completion")
scaling = _console_script("scaling")
accuracy = _console_script("accuracy")
timing_report = _console_script("timing_report")
sweep = _console_script("sweep")

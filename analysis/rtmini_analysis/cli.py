"""What every tool shares at its command line: bad input -> one line on stderr, exit 2."""

import sys

from .io import FormatError


def run(main, argv=None):
    """Call main(argv); a FormatError becomes 'file[:line]: reason' and exit code 2."""
    try:
        return main(argv)
    except FormatError as err:
        print(err, file=sys.stderr)
        return 2

"""Compute the error atlas and fit its error model: ``python benchmarks/build_atlas.py [OUT]``.

The same as ``python -m validation atlas --out OUT`` (default ``atlas-out``); the run cache is
the command's default, so an interrupted build resumes.
"""

import sys

from validation.cli import main

if __name__ == "__main__":
    sys.exit(main(["atlas", *sys.argv[1:]]))

#!/usr/bin/env python3
"""Compare a prism scene with Mitsuba 3: see prism_tools/compare.py (`compare()` is importable
from there, or from this file)."""

import sys

from prism_tools.compare import Comparison, Settings, compare, main  # noqa: F401

if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Validate prism against Mitsuba 3 over every comparison scene; `--report` writes
docs/validation.md. See prism_tools/validate.py."""

import sys

from prism_tools.validate import main

if __name__ == "__main__":
    sys.exit(main())

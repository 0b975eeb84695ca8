"""prism's Python tools: compare prism with Mitsuba 3 and colour-science, statistically.

Modules:
- `images`: read and write EXR/PNG images (OpenImageIO), channel access.
- `stats`: bias tests that account for Monte Carlo noise, relMSE, confidence intervals.
"""

#!/usr/bin/env python3
"""Converts a refractiveindex.info database file (`tabulated nk`, wavelengths in µm) into a
prism metal table (`spectra/metals/<name>.txt`: `nm eta k`, wavelengths in nm, values as
published). The database is CC0 (https://github.com/polyanskiy/refractiveindex.info-database);
its REFERENCES and COMMENTS go into the table's header, so the source stays cited.

    tools/convert_refractiveindex.py database/data/main/Au/nk/McPeak.yml spectra/metals/Au_mcpeak.txt \
        --name Au_mcpeak --path database/data/main/Au/nk/McPeak.yml --commit ff11b589

`spectra/metals/{Au,Ag,Cu,Al}_mcpeak.txt` were made this way (McPeak et al. 2015, 300–1700 nm;
Al from 150 nm), from the database at commit ff11b589.
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path


def parse(text: str) -> tuple[str, str, list[tuple[float, str, str]]]:
    """(references, comments, rows) of a `tabulated nk` file; rows are (µm, n, k), n and k
    as the file writes them (copied digit for digit)."""
    blocks: dict[str, list[str]] = {}
    key = None
    rows: list[tuple[float, str, str]] = []
    in_data = False
    for line in text.splitlines():
        if line.startswith("#"):
            continue
        m = re.match(r"^([A-Z]+):\s*\|?\s*$", line)
        if m:
            key, in_data = m.group(1), False
            blocks[key] = []
            continue
        if re.match(r"^\s+- type:", line):
            if "tabulated nk" not in line:
                raise SystemExit(f"only `tabulated nk` data are supported, got: {line.strip()}")
            continue
        if re.match(r"^\s+data:\s*\|", line):
            in_data = True
            continue
        if in_data and line.strip():
            lam, n, k = line.split()
            float(n), float(k)  # must be numbers
            rows.append((float(lam), n, k))
        elif key and key != "DATA" and line.strip():
            blocks[key].append(line.strip())
    if not rows:
        raise SystemExit("no tabulated nk rows found")
    return " ".join(blocks.get("REFERENCES", [])), " ".join(blocks.get("COMMENTS", [])), rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("src", type=Path, help="the database's .yml file")
    ap.add_argument("dst", type=Path, help="the prism table to write")
    ap.add_argument("--name", required=True, help="the metal's name in prism (the file stem)")
    ap.add_argument("--path", required=True, help="the file's path inside the database (cited)")
    ap.add_argument("--commit", required=True, help="the database commit (cited)")
    a = ap.parse_args()
    refs, comments, rows = parse(a.src.read_text(encoding="utf-8"))
    refs = re.sub(r"<[^>]+>", "", refs)  # HTML tags of the citation
    refs = re.sub(r"[\[\]*]", "", refs)  # Markdown of the citation
    out = [
        f"# {a.name}: complex index of refraction eta + i k (relative to vacuum), measured.",
        "# Source: refractiveindex.info database (https://github.com/polyanskiy/refractiveindex.info-database,",
        f"# CC0 1.0, commit {a.commit}), {a.path}; converted by tools/convert_refractiveindex.py;",
        "# wavelengths converted from um to nm (x1000), values as published.",
        f"#   {refs}",
        f"#   {comments}",
        "# Units: wavelength nm; eta, k dimensionless.",
        "nm eta k",
    ]
    for lam, n, k in rows:
        out.append(f"{round(lam * 1000, 6):g} {n} {k}")
    tmp = a.dst.with_suffix(".tmp")
    tmp.write_text("\n".join(out) + "\n", encoding="utf-8")
    tmp.replace(a.dst)


if __name__ == "__main__":
    main()

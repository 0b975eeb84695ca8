"""Extract the 17 PhysLight camera sensitivities (measured by Weta Digital: Anders Langlands and
Luca Fascione, Apache-2.0) from pbrt-v4's `src/pbrt/util/spectrum.cpp` into
`spectra/cameras/<name>.txt` (measured data only; no code is carried over).

Run: `tools/.venv/bin/python tools/extract_physlight_cameras.py PATH/TO/pbrt-v4/src/pbrt/util/spectrum.cpp [COMMIT]`
"""

from __future__ import annotations

import pathlib
import re
import sys

import numpy as np

CAMERAS = [
    "canon_eos_100d", "canon_eos_1dx_mkii", "canon_eos_200d", "canon_eos_200d_mkii", "canon_eos_5d",
    "canon_eos_5d_mkii", "canon_eos_5d_mkiii", "canon_eos_5d_mkiv", "canon_eos_5ds", "canon_eos_m",
    "hasselblad_l1d_20c", "nikon_d810", "nikon_d850", "sony_ilce_6400", "sony_ilce_7m3",
    "sony_ilce_7rm3", "sony_ilce_9",
]
ROOT = pathlib.Path(__file__).resolve().parent.parent / "spectra" / "cameras"


def array(text: str, name: str) -> tuple[np.ndarray, np.ndarray]:
    m = re.search(r"const Float " + re.escape(name) + r"\[\] = \{(.*?)\};", text, re.S)
    if m is None:
        raise SystemExit(f"{name} not found")
    nums = [float(x) for x in re.findall(r"[-+]?\d+\.?\d*(?:[eE][-+]?\d+)?", m.group(1))]
    v = np.array(nums).reshape(-1, 2)
    return v[:, 0], v[:, 1]


def main() -> None:
    src = pathlib.Path(sys.argv[1]).read_text()
    commit = sys.argv[2] if len(sys.argv) > 2 else "unknown"
    ROOT.mkdir(parents=True, exist_ok=True)
    for cam in CAMERAS:
        cols = [array(src, f"{cam}_{c}") for c in "rgb"]
        wl = cols[0][0]
        assert all(np.array_equal(wl, c[0]) for c in cols), cam
        lines = [
            f"# {cam}: camera spectral sensitivities (relative), {wl[0]:g}-{wl[-1]:g} nm.",
            "# Source: PhysLight measurements by Anders Langlands and Luca Fascione, Copyright (c) 2020 Weta Digital,",
            "# Ltd., Apache-2.0; as shipped in pbrt-v4 (github.com/mmp/pbrt-v4, src/pbrt/util/spectrum.cpp,",
            f"# arrays {cam}_r/_g/_b, commit {commit}). Extracted by tools/extract_physlight_cameras.py.",
            "nm r g b",
        ]
        for i, w in enumerate(wl):
            lines.append(" ".join([f"{w:g}", *(f"{c[1][i]:.9g}" for c in cols)]))
        (ROOT / f"{cam}.txt").write_text("\n".join(lines) + "\n")
        print(f"wrote {cam} ({len(wl)} rows)")


if __name__ == "__main__":
    main()

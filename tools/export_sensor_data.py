"""Export the sensor data prism embeds (`spectra/cmf/CIE1964_10deg.txt`, `spectra/colorchecker.txt`,
`spectra/cameras/Nikon 5100 (NPL).txt`, `spectra/cameras/Sigma SDMerill (NPL).txt`) from
colour-science.

Run: `tools/.venv/bin/python tools/export_sensor_data.py` (colour-science 0.4.7). The PhysLight
cameras in `spectra/cameras/` come from pbrt-v4 instead (see spectra/README.md); this script
leaves them alone.
"""

from __future__ import annotations

import pathlib

import colour
import numpy as np

FILE = {"Nikon 5100 (NPL)": "nikon_d5100_npl", "Sigma SDMerill (NPL)": "sigma_sd_merrill_npl"}
ROOT = pathlib.Path(__file__).resolve().parent.parent / "spectra"
COLOUR = f"colour-science {colour.__version__}"


def write(path: pathlib.Path, source: str, columns: list[str], wl: np.ndarray, values: np.ndarray) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    values = values.reshape(len(wl), -1)
    lines = [f"# {line}" for line in source.strip().splitlines()]
    lines.append(" ".join(["nm", *columns]))
    for w, row in zip(wl, values):
        lines.append(" ".join([f"{w:g}", *(f"{v:.9g}" for v in row)]))
    path.write_text("\n".join(lines) + "\n")
    print(f"wrote {path.relative_to(ROOT.parent)} ({len(wl)} rows)")


def main() -> None:
    cmfs = colour.MSDS_CMFS["CIE 1964 10 Degree Standard Observer"]
    write(
        ROOT / "cmf" / "CIE1964_10deg.txt",
        "CIE 1964 10 degree standard observer colour-matching functions, 1 nm, 360-830 nm.\n"
        f"Source: {COLOUR}, MSDS_CMFS['CIE 1964 10 Degree Standard Observer'] (CIE 018:2019 / CVRL).\n"
        "Units: dimensionless.",
        ["x", "y", "z"],
        cmfs.wavelengths,
        cmfs.values,
    )
    for name in ["Nikon 5100 (NPL)", "Sigma SDMerill (NPL)"]:
        m = colour.MSDS_CAMERA_SENSITIVITIES[name]
        write(
            ROOT / "cameras" / f"{FILE[name]}.txt",
            f"{name} camera spectral sensitivities (relative), {m.shape.start:g}-{m.shape.end:g} nm, {m.shape.interval:g} nm.\n"
            f"Source: {COLOUR}, MSDS_CAMERA_SENSITIVITIES['{name}'] (measured by the National Physical\n"
            "Laboratory; Darrodi, Finlayson, Goodman, Mackiewicz 2015, JOSA A 32(3) 381-391). BSD-3-Clause.",
            ["r", "g", "b"],
            m.wavelengths,
            m.values,
        )
    # The 24 ColorChecker reflectances (the camera-matrix fit's training set), on the data's own
    # grid; prism holds the end values outside it, as tools/prism_tools/colorchecker.py does.
    cc = colour.SDS_COLOURCHECKERS["ColorChecker N Ohta"]
    names = list(cc.keys())
    wl = cc[names[0]].wavelengths
    vals = np.stack([cc[n].values for n in names], axis=1)
    write(
        ROOT / "colorchecker.txt",
        "ColorChecker (24 patches, row-major from dark skin to black) spectral reflectances, 380-780 nm, 5 nm.\n"
        f"Source: {COLOUR}, SDS_COLOURCHECKERS['ColorChecker N Ohta'] (N. Ohta, measured).\n"
        "Columns p01..p24: " + "; ".join(f"p{i + 1:02d} {n}" for i, n in enumerate(names)) + ".\n"
        "Units: reflectance.",
        [f"p{i + 1:02d}" for i in range(len(names))],
        wl,
        vals,
    )


if __name__ == "__main__":
    main()

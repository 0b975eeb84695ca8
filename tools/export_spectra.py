"""Regenerate prism's spectral data files (`spectra/`) from colour-science.

Run: `tools/.venv/bin/python tools/export_spectra.py` (needs colour-science 0.4.7; mitsuba 3.9.1 for
the 785-830 nm tail of CIE D65, which colour-science truncates at 780 nm, and for the measured
metal indices of refraction in its `data/ior/` folder).

Every file is plain text: `#` comment lines (source, units), one header line naming the columns,
then one row per wavelength in nm. prism embeds these files at build time.

Not generated here: `spectra/metals/Ti.txt`, `Fe.txt` and `Pt.txt` were transcribed by hand from
the refractiveindex.info database (CC0; Johnson & Christy 1974 for Ti and Fe, Rakic et al. 1998
for Pt), with wavelengths converted from um to nm; each file names its source. This script leaves
them alone.
"""

from __future__ import annotations

import pathlib

import colour
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent / "spectra"
COLOUR = f"colour-science {colour.__version__}"


def write(path: pathlib.Path, source: str, columns: list[str], wl: np.ndarray, values: np.ndarray) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    values = np.atleast_2d(values.T).T if values.ndim == 1 else values
    lines = [f"# {line}" for line in source.strip().splitlines()]
    lines.append(" ".join(["nm", *columns]))
    for w, row in zip(wl, values):
        lines.append(" ".join([f"{w:g}", *(f"{v:.9g}" for v in row)]))
    path.write_text("\n".join(lines) + "\n")
    print(f"wrote {path.relative_to(ROOT.parent)} ({len(wl)} rows)")


def export_cmfs() -> None:
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    write(
        ROOT / "cmf" / "CIE1931_2deg.txt",
        f"CIE 1931 2 degree standard observer colour-matching functions, 1 nm, 360-830 nm.\n"
        f"Source: {COLOUR}, MSDS_CMFS['CIE 1931 2 Degree Standard Observer'] (CIE 018:2019 / CVRL).\n"
        "Units: dimensionless.",
        ["x", "y", "z"],
        cmfs.wavelengths,
        cmfs.values,
    )


def d65_full() -> tuple[np.ndarray, np.ndarray]:
    """CIE D65 300-830 nm at 5 nm: colour-science's table to 780 nm, then the CIE values to 830 nm."""
    d65 = colour.SDS_ILLUMINANTS["D65"]
    wl = np.arange(300, 831, 5, dtype=float)
    vals = [d65[w] for w in wl if w <= 780]
    import mitsuba as mi  # only for the CIE S 014-2 tail (785-830 nm) that colour-science omits

    mi.set_variant("scalar_spectral")
    vals += [mi.cie_d65(float(w)) / mi.MI_CIE_D65_NORMALIZATION for w in wl if w > 780]
    return wl, np.array(vals)


def export_illuminants() -> None:
    out = ROOT / "illuminants"
    wl, d65 = d65_full()
    write(
        out / "D65.txt",
        "CIE standard illuminant D65, relative spectral power (100 at 560 nm), 300-830 nm, 5 nm.\n"
        f"Source: {COLOUR} SDS_ILLUMINANTS['D65'] for 300-780 nm; 785-830 nm from CIE S 014-2\n"
        "as tabulated in Mitsuba 3.9.1 (mi.cie_d65 / MI_CIE_D65_NORMALIZATION).",
        ["value"],
        wl,
        d65,
    )
    shape = colour.SpectralShape(300, 830, 5)
    a = colour.sd_CIE_standard_illuminant_A(shape)
    write(
        out / "A.txt",
        "CIE standard illuminant A (Planckian, 2856 K, c2 = 1.435e-2 m K), relative, 100 at 560 nm.\n"
        f"Source: {COLOUR} sd_CIE_standard_illuminant_A (CIE 015:2018 eq. 2.1).",
        ["value"],
        a.wavelengths,
        a.values,
    )
    write(
        out / "E.txt",
        "CIE equal-energy illuminant E: constant 100.",
        ["value"],
        np.array([300.0, 830.0]),
        np.array([100.0, 100.0]),
    )
    # D50, D55, D75: colour's CIE tables stop at 780 nm; the D-series basis (S0, S1, S2) reaches
    # 830 nm, so the whole curve comes from CIE 015:2018 eq. 4.9-4.11 at each one's CIE xy.
    xy = colour.CCS_ILLUMINANTS["CIE 1931 2 Degree Standard Observer"]
    for name in ("D50", "D55", "D60", "D75"):
        sd = colour.sd_CIE_illuminant_D_series(xy[name])
        table = colour.SDS_ILLUMINANTS.get(name)
        wl = sd.wavelengths
        vals = np.array([table[w] if table is not None and w <= table.wavelengths[-1] else sd[w] for w in wl])
        write(
            out / f"{name}.txt",
            f"CIE illuminant {name}, relative spectral power (100 at 560 nm), 300-830 nm, 5 nm.\n"
            f"Source: {COLOUR} SDS_ILLUMINANTS['{name}'] (CIE tables) where present; the remaining\n"
            "wavelengths from the CIE D-series basis (sd_CIE_illuminant_D_series at the CIE xy).",
            ["value"],
            wl,
            vals,
        )
    keys = [k for k in colour.SDS_ILLUMINANTS if k.startswith(("FL", "HP", "LED-"))]
    for key in sorted(keys):
        sd = colour.SDS_ILLUMINANTS[key]
        write(
            out / f"{key}.txt",
            f"CIE illuminant {key}, relative spectral power.\n"
            f"Source: {COLOUR} SDS_ILLUMINANTS['{key}'] (CIE 015:2018 tables).",
            ["value"],
            sd.wavelengths,
            sd.values,
        )


# prism's name -> the stem of Mitsuba's `<stem>.eta.spd` / `<stem>.k.spd`. Only elemental metals
# whose data cover at least 360-830 nm (the CIE range); Ni and V exist only as Palik's data there.
MITSUBA_METALS = {
    "Ag": "Ag",
    "Al": "Al",
    "Au": "Au",
    "Be": "Be",
    "Cr": "Cr",
    "Cu": "Cu",
    "Hg": "Hg",
    "Ir": "Ir",
    "Mo": "Mo",
    "Nb": "Nb",
    "Ni": "Ni_palik",
    "Rh": "Rh",
    "Ta": "Ta",
    "V": "V_palik",
    "W": "W",
}


def read_spd(path: pathlib.Path) -> tuple[list[str], np.ndarray, np.ndarray]:
    """A Mitsuba `.spd` file: its comment lines (without the `#` and LuxPop's `;`) and its columns
    (wavelength in nm, value)."""
    notes, rows = [], []
    for line in path.read_text().splitlines():
        line = line.strip()
        if line.startswith("#"):
            note = line.lstrip("#").strip().lstrip(";").strip()
            if note and not note.startswith("-") and not note.startswith("Lambda"):
                notes.append(note)
        elif line:
            rows.append([float(x) for x in line.split()])
    data = np.array(rows)
    return notes, data[:, 0], data[:, 1]


def merge_eta_k(eta: tuple[np.ndarray, np.ndarray], k: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """eta and k on one grid: the union of both grids where both are measured, each column
    linearly interpolated onto it (Mitsuba's pairs share one grid, so nothing is interpolated)."""
    lo, hi = max(eta[0][0], k[0][0]), min(eta[0][-1], k[0][-1])
    wl = np.union1d(eta[0], k[0])
    wl = wl[(wl >= lo) & (wl <= hi)]
    return wl, np.stack([np.interp(wl, *eta), np.interp(wl, *k)], axis=1)


def export_metals() -> None:
    import mitsuba as mi  # only for the location of its measured data

    ior = pathlib.Path(mi.__file__).parent / "data" / "ior"
    for name, stem in MITSUBA_METALS.items():
        notes, *eta = read_spd(ior / f"{stem}.eta.spd")
        _, *k = read_spd(ior / f"{stem}.k.spd")
        wl, values = merge_eta_k(tuple(eta), tuple(k))
        write(
            ROOT / "metals" / f"{name}.txt",
            f"{name}: complex index of refraction eta + i k (relative to vacuum), measured.\n"
            f"Source: Mitsuba {mi.__version__} data/ior/{stem}.eta.spd and {stem}.k.spd, whose header says:\n"
            + "".join(f"  {n}\n" for n in notes)
            + "Units: wavelength nm; eta, k dimensionless.",
            ["eta", "k"],
            wl,
            values,
        )


def export_reflectances() -> None:
    """Reflectance libraries for `prism dataset` (materials drawn from a named set): the
    ColorChecker and the CIE 1995 test colour samples, one column per patch (spaces in the
    patch names become underscores, since the header is space-separated)."""
    out = ROOT / "reflectances"
    sets = [
        (
            "colorchecker.txt",
            "ColorChecker Classic, 24 patches, spectral reflectance, 380-780 nm, 5 nm (row by row from\n"
            f"dark skin to black). Source: {COLOUR} SDS_COLOURCHECKERS['ColorChecker N Ohta'] (Ohta's\n"
            "measurements). Units: reflectance factor in [0, 1].",
            colour.SDS_COLOURCHECKERS["ColorChecker N Ohta"],
        ),
        (
            "cie1995_tcs.txt",
            "CIE 1995 test colour samples TCS01-TCS14 (CIE 13.3-1995, colour rendering index), spectral\n"
            f"reflectance, 360-830 nm, 5 nm. Source: {COLOUR} colour.quality.SDS_TCS['CIE 1995'].\n"
            "Units: reflectance factor in [0, 1].",
            colour.quality.SDS_TCS["CIE 1995"],
        ),
    ]
    for name, source, sds in sets:
        sds = list(sds.values())
        wl = sds[0].wavelengths
        cols = [sd.name.replace(" ", "_") for sd in sds]
        write(out / name, source, cols, wl, np.stack([sd.values for sd in sds], axis=1))


if __name__ == "__main__":
    export_cmfs()
    export_illuminants()
    export_metals()
    export_reflectances()

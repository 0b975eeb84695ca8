"""docs/validation.md must describe the code it is shipped with: it records a digest of its
inputs (the comparison scenes, src/, spectra/, the scenes' assets and the comparison tools;
tools/prism_tools/validate.py `inputs_digest`), and this test fails when any of them has
changed since (regenerate with `tools/.venv/bin/python tools/validate.py --report`). It also
checks that the report covers every comparison scene and that none failed."""

from __future__ import annotations

import re

from prism_tools import validate


def test_report_is_current():
    text = validate.REPORT.read_text()
    recorded = validate.recorded_digest(text)
    assert recorded, "docs/validation.md records no inputs digest: regenerate it (tools/validate.py --report)"
    assert recorded == validate.inputs_digest(), (
        "docs/validation.md is stale: its inputs changed since it was made; "
        "regenerate it with `tools/.venv/bin/python tools/validate.py --report`"
    )


def test_report_covers_every_scene_and_none_failed():
    text = validate.REPORT.read_text()
    for scene in validate.comparison_scenes():
        name = scene.relative_to(validate.ROOT).as_posix()
        assert f"| `{name}` |" in text, f"{name} is missing from docs/validation.md"
    m = re.search(r"\*\*(\d+) pass, (\d+) fail, (\d+) skipped\.\*\*", text)
    assert m and m.group(2) == "0", m and m.group(0)


def test_digest_sees_a_change(tmp_path):
    """The digest changes when a source file or a scene changes (copying a small tree)."""
    for d in ["scenes/materials", "src", "tests/data/mitsuba"]:
        (tmp_path / d).mkdir(parents=True)
    (tmp_path / "scenes/cornell.ron").write_text("()")
    (tmp_path / "scenes/materials/a.ron").write_text("(a)")
    (tmp_path / "src/lib.rs").write_text("// lib")
    base = validate.inputs_digest(tmp_path)
    (tmp_path / "src/lib.rs").write_text("// lib changed")
    changed_src = validate.inputs_digest(tmp_path)
    (tmp_path / "scenes/materials/a.ron").write_text("(b)")
    changed_scene = validate.inputs_digest(tmp_path)
    assert len({base, changed_src, changed_scene}) == 3

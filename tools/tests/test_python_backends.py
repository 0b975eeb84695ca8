"""prism_tools renders prism through the `prism` module or the binary (prism_tools/renderers.py):
the two give the same bits, and the choice follows $PRISM_BIN, an explicit binary and whether
the module imports."""

from __future__ import annotations

import sys

import numpy as np
import pytest
from prism_tools import renderers
from test_python_module import small_cornell


@pytest.fixture
def scene_file(tmp_path):
    p = tmp_path / "box.ron"
    p.write_text(small_cornell(spp=3))
    return p


def test_module_and_binary_give_the_same_bits(prism_bin, scene_file, monkeypatch):
    """Tolerance: none. Every channel (colour, bands, depth, normals, uint32 instance ids) at
    two seeds and an spp override, through the module (one scene load) and through `prism
    render` in a subprocess, is bit-identical; so are `render_prism`'s stacked channels."""
    module = renderers.PrismRenderer(scene_file, spp=2, via="module")
    binary = renderers.PrismRenderer(scene_file, spp=2, prism_bin=prism_bin)
    assert (module.backend, binary.backend) == ("module", "binary")
    for seed in (0, 5):
        a, b = module.channels(seed), binary.channels(seed)
        assert sorted(a) == sorted(b) and "instance.ID" in a
        for name in a:
            assert a[name].dtype == b[name].dtype, name
            np.testing.assert_array_equal(a[name], b[name], err_msg=name)
    monkeypatch.delenv("PRISM_BIN", raising=False)  # the default: the module
    np.testing.assert_array_equal(
        renderers.render_prism(None, scene_file, 5, 2), renderers.render_prism(prism_bin, scene_file, 5, 2)
    )


def test_the_backend_choice(monkeypatch, prism_bin):
    """A binary named (argument or $PRISM_BIN) is used; else the module where it imports;
    else the binary of this checkout."""
    monkeypatch.delenv("PRISM_BIN", raising=False)
    assert renderers.backend() == "module"
    assert renderers.backend(prism_bin) == "binary"
    monkeypatch.setenv("PRISM_BIN", str(prism_bin))
    assert renderers.backend() == "binary"
    monkeypatch.delenv("PRISM_BIN")
    monkeypatch.setitem(sys.modules, "prism", None)
    assert renderers.backend() == "binary"
    with pytest.raises(ValueError, match="use \"module\" or \"binary\""):
        renderers.PrismRenderer("x.ron", via="subprocess")

"""The README's Python examples run as written (paths made absolute; files go to a temporary folder)."""
import os
import re

import pytest

from conftest import MRI_T1, SHARED, SOURCE, need


def examples():
    text = (SOURCE / "README.md").read_text()
    section = text[text.index("## Python: the gdm module"):]
    section = section[:section.index("\n## ", 3)]
    return re.findall(r"```python\n(.*?)```", section, re.S)


def run(code, tmp_path):
    code = code.replace('"../shared/', f'"{SHARED}/').replace('"data/', f'"{SOURCE}/data/')
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        scope = {}
        exec(compile(code, "README.md", "exec"), scope)
        return scope
    finally:
        os.chdir(cwd)


def test_there_are_two_examples():
    assert len(examples()) == 2


def test_itk_style_five_lines(tmp_path):
    scope = run(examples()[1], tmp_path)
    assert (tmp_path / "crown.ply").exists() and scope["crown"].report["mesh"]["closed"]


def test_nibabel_and_meshio(tmp_path):
    need(MRI_T1, "the T1 MRI head (../shared/data/mri-head-t1/chris_t1.nii.gz)")
    pytest.importorskip("nibabel")
    meshio = pytest.importorskip("meshio")
    scope = run(examples()[0], tmp_path)
    head = scope["head"]
    m = head.report["mesh"]
    assert m["closed"] and m["manifold"] and m["genus"] == 0 and m["self_intersections"] == 0
    back = meshio.read(str(tmp_path / "head.ply"))
    assert back.cells_dict["triangle"].shape == head.faces.shape

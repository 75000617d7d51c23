"""The README's Python example, run as a newcomer runs it (issue 48, finding 22): on a grey photograph
and on a colour one, from a fresh folder."""

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import shadecut
from shadecut import synthetic

REPO = Path(__file__).resolve().parents[2]


def readme_python() -> str:
    text = (REPO / "README.md").read_text()
    return re.search(r"## Python\n\n```python\n(.*?)```", text, re.S).group(1)


@pytest.mark.parametrize("colour", [False, True], ids=["grey photograph", "colour photograph"])
def test_the_readme_example_runs_on_a_grey_and_a_colour_photograph(tmp_path, colour):
    """``loaded.colour`` is None for a grey file: the retinex line failed there ("got 0 dimension(s)")."""
    scene = synthetic.sphere(light=(1.0, 0.0, 1.0), size=48)
    image = np.dstack([scene.image * 0.9, scene.image * 0.6, scene.image * 0.3]) if colour else scene.image
    shadecut.save_image(tmp_path / "photo.png", image, scene.mask)
    assert (shadecut.load_image(tmp_path / "photo.png").colour is None) == (not colour)
    run = subprocess.run([sys.executable, "-c", readme_python()], cwd=tmp_path, capture_output=True, text=True,
                         timeout=600, env={"PYTHONPATH": str(REPO / "addon"), "PATH": "/usr/bin:/bin"})
    assert run.returncode == 0, run.stderr[-2000:]
    assert (tmp_path / "surface.ply").is_file()


def test_the_readme_several_photographs_example_runs(tmp_path):
    code = re.search(r"### Several photographs\n.*?```python\n(.*?)```", (REPO / "README.md").read_text(), re.S).group(1)
    scene = synthetic.bumps((0.0, 0.0, 1.0), size=48)
    for side in eval(re.search(r"sides = (\[.*?\])", code).group(1)):
        shadecut.save_image(tmp_path / f"{side}.png", shadecut.render(scene.normals, shadecut.light_from_side(side), 0.8))
    run = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=600,
                         env={"PYTHONPATH": str(REPO / "addon"), "PATH": "/usr/bin:/bin"})
    assert run.returncode == 0, run.stderr[-2000:]

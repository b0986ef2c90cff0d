import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

import thermolimb

ROOT = Path(__file__).resolve().parent.parent


def test_urdf_dir_in_checkout():
    assert thermolimb.urdf_dir() == ROOT / "urdf"


def test_urdf_dir_from_environment(tmp_path, monkeypatch):
    (tmp_path / "README.md").write_text("x")
    monkeypatch.setenv("THERMOLIMB_URDF_DIR", str(tmp_path))
    assert thermolimb.urdf_dir() == tmp_path


@pytest.mark.slow
def test_wheel_ships_urdf_where_the_resolver_looks(tmp_path):
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q",
                    "-w", str(tmp_path), str(ROOT)], check=True)
    wheel = next(tmp_path.glob("thermolimb-*.whl"))
    names = zipfile.ZipFile(wheel).namelist()
    assert any(n.endswith(".data/data/share/thermolimb/urdf/README.md") for n in names)
    assert "thermolimb/paths.py" in names and "demos/thermal_fit.py" in names

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
def test_wheel_ships_urdf_demos_and_every_package(tmp_path):
    """The wheel holds every package of the tree, the demos under their own name (no generic top-level ``demos``),
    and entry points that name modules it ships."""
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q",
                    "-w", str(tmp_path), str(ROOT)], check=True)
    wheel = next(tmp_path.glob("thermolimb-*.whl"))
    names = zipfile.ZipFile(wheel).namelist()
    assert any(n.endswith(".data/data/share/thermolimb/urdf/README.md") for n in names)
    assert "thermolimb/util/paths.py" in names and "thermolimb_demos/thermal_fit.py" in names
    assert not any(n.startswith("demos/") for n in names)
    for package in ("thermolimb", "hexapod_pb", "humanoid_pb"):
        for init in (ROOT / package).rglob("__init__.py"):
            assert init.relative_to(ROOT).as_posix() in names, init
    entry_points = next(n for n in names if n.endswith(".dist-info/entry_points.txt"))
    modules = [line.split("=")[1].strip() for line in zipfile.ZipFile(wheel).read(entry_points).decode().splitlines()
               if "=" in line and ":" not in line]
    assert len(modules) >= 10
    for module in modules:
        assert f"{module.replace('.', '/')}.py" in names or f"{module.replace('.', '/')}/__init__.py" in names, module

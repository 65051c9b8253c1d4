"""The package as users install it: a wheel built from the working tree, in a fresh venv
(tests/test_packaging.py, and the docs site's build in tests/test_docs.py)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PIP = [sys.executable, "-m", "pip", "--disable-pip-version-check", "-q"]


def no_checkout_env() -> dict[str, str]:
    """This environment without PYTHONPATH: a process that must not see the checkout."""
    return {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}


def build_wheel(dest: Path) -> Path:
    """The wheel built from the working tree's package sources (without results) in ``dest``."""
    src, dist = dest / "src", dest / "dist"
    src.mkdir(parents=True)
    for name in ("pyproject.toml", "README.md"):
        shutil.copy2(ROOT / name, src / name)
    ignore = shutil.ignore_patterns("__pycache__", "results", "*.egg-info")
    for name in ("unified_manip", "baselines"):
        shutil.copytree(ROOT / name, src / name, ignore=ignore)
    subprocess.run(
        [*PIP, "wheel", "--no-deps", "--no-build-isolation", str(src), "-w", str(dist)],
        check=True,
        capture_output=True,
        timeout=300,
    )
    (built,) = dist.glob("unified_manip-*.whl")
    return built


def fresh_venv(venv: Path) -> tuple[str, str]:
    """A fresh venv at ``venv`` without pip: its Python and its site directory."""
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True, timeout=120)
    python = str(venv / "bin" / "python")
    site = subprocess.run(
        [python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
        capture_output=True,
        text=True,
        check=True,
        timeout=120,
    ).stdout.strip()
    return python, site


def wheel_venv(wheel: Path, venv: Path, *paths: Path) -> str:
    """A fresh venv at ``venv`` with ``wheel`` installed (not editable), which sees this
    venv's third-party packages (no download) and ``paths`` through a .pth file; its Python.

    The .pth lines are bare paths: only a site directory's own .pth files run, so this
    venv's editable install of the checkout stays invisible there."""
    python, site = fresh_venv(venv)
    deps = [p for p in sys.path if p.endswith("site-packages")]  # this venv's and any it chains to
    Path(site, "_checkout_deps.pth").write_text("".join(f"{p}\n" for p in [*deps, *map(str, paths)]))
    subprocess.run(
        [*PIP, "--python", python, "install", "--no-deps", "--no-index", str(wheel)],
        check=True,
        capture_output=True,
        timeout=300,
        env=no_checkout_env(),
    )
    return python

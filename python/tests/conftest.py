"""Shared fixtures: the repository, the command line, case 1."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path
from typing import Any, Dict, List

import pytest

import kanestop

ROOT = Path(__file__).resolve().parents[2]
CASE01 = ROOT / "scenes" / "paper" / "case01.toml"


def cli() -> List[str]:
    """The kanestop command line: $KANESTOP_CLI, else target/release/kanestop, else cargo run."""
    exe = os.environ.get("KANESTOP_CLI")
    if exe:
        return [exe]
    built = ROOT / "target" / "release" / "kanestop"
    if built.exists():
        return [str(built)]
    if shutil.which("cargo") is None:
        pytest.skip("no kanestop command line (set KANESTOP_CLI)")
    return ["cargo", "run", "--release", "--quiet", "--manifest-path", str(ROOT / "Cargo.toml"), "--bin", "kanestop", "--"]


def run_cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([*cli(), *args], capture_output=True, text=True, cwd=ROOT, timeout=600)


def cli_json(*args: str) -> Dict[str, Any]:
    p = run_cli(*args)
    assert p.returncode in (0, 3), p.stderr
    return json.loads(p.stdout)  # type: ignore[no-any-return]


@pytest.fixture(scope="session")
def case01() -> kanestop.Scene:
    return kanestop.Scene.load(CASE01)


@pytest.fixture(scope="session")
def case01_result(case01: kanestop.Scene) -> kanestop.Result:
    return kanestop.run(case01)


def without_wall_time(summary: Dict[str, Any]) -> Dict[str, Any]:
    return {k: v for k, v in summary.items() if k not in ("wall_time", "cpu_time")}

"""The worked example of docs/PYTHON.md and the README's Python lines run and print what the
documents say."""
import os
import re
import subprocess
import sys

import pytest

import capz

from conftest import REPO

SAMPLE = os.path.join(REPO, "data", "EB015PI.c3d")


def block_after(doc, heading, lang):
    with open(os.path.join(REPO, doc)) as f:
        text = f.read()
    m = re.search(re.escape(heading) + r".*?```" + lang + r"\n(.*?)```", text, re.S)
    assert m, f"{doc}: no {lang} block after {heading!r}"
    return m.group(1), text[m.end():]


def run(code, cwd):
    os.makedirs(os.path.join(cwd, "data"), exist_ok=True)
    os.symlink(SAMPLE, os.path.join(cwd, "data", "EB015PI.c3d"))
    package = os.path.dirname(os.path.dirname(os.path.abspath(capz.__file__)))
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=package)
    r = subprocess.run([sys.executable, "-c", code], cwd=cwd, env=env, capture_output=True,
                       text=True)
    assert r.returncode == 0, r.stderr
    return r.stdout


def test_worked_example(tmp_path):
    pytest.importorskip("matplotlib")
    code, rest = block_after("docs/PYTHON.md", "## Worked example", "python")
    printed = re.search(r"```\n(.*?)```", rest, re.S).group(1)
    assert run(code, str(tmp_path)) == printed
    assert (tmp_path / "LTH1.png").stat().st_size > 10000


def test_readme_lines(tmp_path):
    code, _ = block_after("README.md", "## Python", "python")
    out = run(code, str(tmp_path))
    assert "max_error_per_coordinate" in out

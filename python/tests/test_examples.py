"""The examples/ scripts run (small settings), so that they do not rot."""

import glob
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import SOURCE_DIR

EXAMPLES = os.path.join(SOURCE_DIR, "examples")


def run(script, *args, cwd):
    r = subprocess.run([sys.executable, os.path.join(EXAMPLES, script), *args], cwd=cwd,
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    return r.stdout


def test_record_frames(tmp_path):
    out = run("record_frames.py", "--frames", "4", "--width", "96", "--height", "72", "--out",
              str(tmp_path / "f.npz"), cwd=tmp_path)
    assert "wrote" in out
    data = np.load(tmp_path / "f.npz")
    assert data["rgb"].shape == (4, 72, 96, 3) and data["mask"].dtype == np.uint16


@pytest.mark.skipif(len(glob.glob("/usr/share/man/man1/*.gz")) < 8,
                    reason="needs installed manual pages")
def test_lda_manpages(tmp_path):
    out = run("lda_manpages.py", "--pages", "8", "-k", "2", cwd=tmp_path)
    assert "topic 0:" in out and "perplexity" in out

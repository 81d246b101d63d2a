"""No tracked file may carry an absolute path of one machine (a checkout
directory or a home directory): the project must run from any clone."""
import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PATTERN = re.compile(r"(/work/|/root/|/home/[a-z_][a-z0-9_-]*/)")


def test_no_absolute_machine_paths_in_tracked_files():
    files = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True,
                           check=True).stdout.split()
    offenders = []
    for name in files:
        path = ROOT / name
        if path.suffix in {".png", ".h5", ".pdf"} or not path.is_file():
            continue
        text = path.read_text(errors="ignore")
        for lineno, line in enumerate(text.splitlines(), 1):
            if PATTERN.search(line) and name != "tests/python/test_no_machine_paths.py":
                offenders.append(f"{name}:{lineno}: {line.strip()[:100]}")
    assert not offenders, "machine paths in tracked files:\n" + "\n".join(offenders)

"""Runs an OpenSim tool from a setup file in a folder of its own: OpenSim's tools resolve the
names in a setup against the working directory."""
import contextlib
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path


def run_in(folder, tool_class, setup):
    """`tool_class(setup).run()` with `folder` as the working directory; exits on failure."""
    cwd = os.getcwd()
    os.chdir(folder)
    try:
        ok = tool_class(setup).run()
    finally:
        os.chdir(cwd)
    if not ok:
        raise SystemExit(f"{tool_class.__name__} failed on {setup}")


@contextlib.contextmanager
def tool_results(tool, inputs, setup_text):
    """Runs OpenSim's `tool` (e.g. "CMCTool") on `setup_text` in a temporary folder holding
    `inputs` ({name: source path}), in a Python process of its own (its log captured); yields the
    finished process and the folder of its results (`Results`); exits on failure."""
    with tempfile.TemporaryDirectory() as work:
        work = Path(work)
        for file, source in inputs.items():
            shutil.copy(source, work / file)
        (work / "setup.xml").write_text(setup_text)
        script = f"import sys, opensim as osim\nsys.exit(0 if osim.{tool}('setup.xml').run() else 1)\n"
        run = subprocess.run([sys.executable, "-c", script], cwd=work, capture_output=True, text=True)
        if run.returncode != 0:
            raise SystemExit(f"{tool} failed:\n{run.stdout[-3000:]}\n{run.stderr[-3000:]}")
        yield run, work / "Results"


def keep_results(results, out, suffixes):
    """Lists every file in `results` in `out`/files.txt and copies those ending in `suffixes`;
    returns the names."""
    written = sorted(p.name for p in results.iterdir())
    (out / "files.txt").write_text("\n".join(written) + "\n")
    for file in written:
        if file.endswith(suffixes):
            shutil.copy(results / file, out / file)
    return written


def repair_states(path):
    """OpenSim 4.6's tracking tools flush the states file early and print it again at the end over
    the same name, leaving pieces of the first header before the second's tail; keeps the table
    (from the last line of column labels) and writes a whole header for it."""
    lines = path.read_text().splitlines()
    start = max(i for i, line in enumerate(lines) if line.split()[:1] == ["time"] and len(line.split()) > 1)
    table = [line for line in lines[start:] if line.strip()]
    header = f"states\nversion=1\nnRows={len(table) - 1}\nnColumns={len(table[0].split())}\ninDegrees=no\nendheader\n"
    path.write_text(header + "\n".join(table) + "\n")

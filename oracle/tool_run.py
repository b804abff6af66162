"""Runs an OpenSim tool from a setup file in a folder of its own: OpenSim's tools resolve the
names in a setup against the working directory."""
import os


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

#!/usr/bin/env python3
"""`cargo xtask bench`'s OpenSim side of residual reduction: OpenSim 4.6's RRATool on each setup
of fixtures/golden/rra/ (inputs copied beside it, as gen_rra.py runs them) and on `second`, the
`walk` setup over 0.5–1.5 s. Writes nothing to the repository; prints `<case>_seconds=<wall
time>` per case (the tool's run alone).

    python3 oracle/bench_rra.py
"""
import shutil
import tempfile
import time
from pathlib import Path

import opensim as osim

from gen_rra import INPUTS, OUT

CASES = {"walk": ("walk", None), "filtered": ("filtered", None), "second": ("walk", (0.5, 1.5))}


def main():
    osim.Logger.setLevelString("error")
    for label, (case, times) in CASES.items():
        with tempfile.TemporaryDirectory() as work:
            work = Path(work)
            for file, source in INPUTS.items():
                shutil.copy(source, work / file)
            setup = (OUT / case / "setup.xml").read_text()
            if times:
                setup = setup.replace("<initial_time>0.75</initial_time>", f"<initial_time>{times[0]}</initial_time>")
                setup = setup.replace("<final_time>0.8</final_time>", f"<final_time>{times[1]}</final_time>")
            (work / "setup.xml").write_text(setup)
            tool = osim.RRATool(str(work / "setup.xml"))
            begin = time.perf_counter()
            if not tool.run():
                raise SystemExit(f"RRATool failed on {label}")
            print(f"{label}_seconds={time.perf_counter() - begin!r}", flush=True)


if __name__ == "__main__":
    main()

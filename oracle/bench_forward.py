#!/usr/bin/env python3
"""`cargo xtask bench`'s OpenSim side of the forward simulation: OpenSim 4.6 integrates each case
of gen_forward_simulation.py as that script does (prescribed coordinates, PrescribedController,
RungeKuttaMerson at accuracy 1e-10, states read at the golden's report times; its muscle moments
on the unprescribed copy are included), from the case's files in fixtures/golden/forward/.
Writes nothing; prints `<case>_seconds=<wall time>` per case.

    python3 oracle/bench_forward.py
"""
import csv
import time

import opensim as osim

from gen_forward_simulation import ACCURACY, OUT, REPO, simulate

CASES = {
    "arm26": REPO / "fixtures" / "models" / "arm26.osim",
    "arm26_degroote": REPO / "fixtures" / "models" / "arm26_degroote.osim",
    "arm26_degroote_rigid": REPO / "fixtures" / "models" / "arm26_degroote_rigid.osim",
    "gait2392_millard": REPO / "models" / "gait2392_millard2012muscle.osim",
    "rajagopal": REPO / "fixtures" / "models" / "Rajagopal2016.osim",
}


def main():
    osim.Logger.setLevelString("error")
    for case, model in CASES.items():
        folder = OUT / case
        with open(folder / "states.csv") as file:
            report_times = [float(row["time"]) for row in csv.DictReader(file)]
        start = time.perf_counter()
        simulate(model, folder, report_times, ACCURACY)
        print(f"{case}_seconds={time.perf_counter() - start!r}", flush=True)


if __name__ == "__main__":
    main()

"""Time OpenSim 4.6's ScaleTool (Python bindings) on the subject01 example: marker set, scale
factors, Model::scale and marker placement, as `osim-tune scale --setup` does.

Usage: python3 oracle/bench_scale.py GENERIC.osim SUBJECT01_FOLDER REPEATS
The setup names its model `gait2392_simbody.osim`, so the inputs are copied to a scratch
folder under that name. Prints `seconds_per_run=<float>` (median). Used by `cargo xtask bench`.
"""
import os
import shutil
import statistics
import sys
import tempfile
import time

import opensim


def main():
    generic, folder, repeats = sys.argv[1], sys.argv[2], int(sys.argv[3])
    opensim.Logger.setLevelString("error")
    with tempfile.TemporaryDirectory() as scratch:
        shutil.copy(generic, os.path.join(scratch, "gait2392_simbody.osim"))
        for name in ["subject01_Setup_Scale.xml", "gait2392_Scale_MarkerSet.xml", "subject01_static.trc"]:
            shutil.copy(os.path.join(folder, name), scratch)
        setup = os.path.join(scratch, "subject01_Setup_Scale.xml")
        times = []
        for _ in range(repeats):
            start = time.perf_counter()
            if not opensim.ScaleTool(setup).run():
                sys.exit("ScaleTool failed")
            times.append(time.perf_counter() - start)
    print(f"seconds_per_run={statistics.median(times)}")


if __name__ == "__main__":
    main()

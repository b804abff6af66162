#!/usr/bin/env python3
"""`cargo xtask bench`'s OpenSim side of the joint reactions: OpenSim 4.6's AnalyzeTool runs each
case of gen_joint_reaction.py (two JointReaction analyses, every joint) as that script does,
writing nothing kept. Prints `<case>_seconds=<wall time of AnalyzeTool.run>` per case.

    python3 oracle/bench_joint_reaction.py
"""
import opensim as osim

from gen_joint_reaction import CASES, run


def main():
    osim.Logger.setLevelString("error")
    for case in CASES:
        print(f"{case}_seconds={run(case, keep=False)!r}", flush=True)


if __name__ == "__main__":
    main()

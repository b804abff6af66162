"""Time OpenSim 4.6 (Python bindings) computing, per pose, the lengths of all muscles and their
moment arms about every coordinate each spans, for the poses of a golden poses.csv.

Usage: python3 oracle/bench_geometry.py MODEL.osim POSES.csv MUSCLE_COORDINATES.csv
Prints `seconds_per_pose=<float>` and `poses=<n>`. Used by `cargo xtask bench`.
"""
import csv
import sys
import time

import opensim


def main():
    model_file, poses_file, pairs_file = sys.argv[1:4]
    opensim.Logger.setLevelString("error")
    model = opensim.Model(model_file)
    state = model.initSystem()
    coordinates = model.getCoordinateSet()
    muscles = model.getMuscles()
    pairs = {}
    for row in csv.DictReader(open(pairs_file)):
        pairs.setdefault(row["muscle"], []).append(coordinates.get(row["coordinate"]))
    work = [(muscles.get(name), coords) for name, coords in pairs.items()]
    all_muscles = [muscles.get(i) for i in range(muscles.getSize())]
    poses = list(csv.DictReader(open(poses_file)))
    names = [c for c in poses[0].keys() if c != "pose_id"]
    handles = [coordinates.get(n) for n in names]
    start = time.perf_counter()
    for pose in poses:
        for handle, name in zip(handles, names):
            handle.setValue(state, float(pose[name]), False)
        model.realizePosition(state)
        for muscle in all_muscles:
            muscle.getLength(state)
        for muscle, coords in work:
            for coordinate in coords:
                muscle.computeMomentArm(state, coordinate)
    elapsed = time.perf_counter() - start
    print(f"seconds_per_pose={elapsed / len(poses)}")
    print(f"poses={len(poses)}")


if __name__ == "__main__":
    main()

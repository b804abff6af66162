"""Time OpenSim 4.6 (Python bindings) equilibrating all muscles of a model at activation 0.5,
pose after pose, for the poses of a golden poses.csv: set the coordinates, set every muscle's
activation, `equilibrateMuscles`. One warm-up sweep, then the median of five timed sweeps.

Usage: python3 oracle/bench_equilibrium.py MODEL.osim POSES.csv
Prints `seconds_per_pose=<float>` and `poses=<n>`. Used by `cargo xtask bench`.
"""
import csv
import statistics
import sys
import time

import opensim


def main():
    model_file, poses_file = sys.argv[1:3]
    opensim.Logger.setLevelString("error")
    model = opensim.Model(model_file)
    state = model.initSystem()
    coordinates = model.getCoordinateSet()
    muscles = [model.getMuscles().get(i) for i in range(model.getMuscles().getSize())]
    poses = list(csv.DictReader(open(poses_file)))
    names = [c for c in poses[0].keys() if c != "pose_id"]
    handles = [coordinates.get(n) for n in names]

    def sweep():
        start = time.perf_counter()
        for pose in poses:
            for handle, name in zip(handles, names):
                handle.setValue(state, float(pose[name]), False)
            for muscle in muscles:
                muscle.setActivation(state, 0.5)
            model.equilibrateMuscles(state)
        return (time.perf_counter() - start) / len(poses)

    sweep()
    print(f"seconds_per_pose={statistics.median(sweep() for _ in range(5))}")
    print(f"poses={len(poses)}")


if __name__ == "__main__":
    main()

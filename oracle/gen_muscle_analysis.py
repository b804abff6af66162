"""Golden for `osim-tune analyze`: OpenSim 4.6 muscle-tendon lengths, moment arms and marker
locations along a motion, computed the way MuscleAnalysis sees each row of a motion whose
dependents already follow their couplers (AnalyzeTool also assembles each row, which then
changes nothing; these models have no other constraints): the motion is read as
an OpenSim Storage, converted to radians by the model's SimbodyEngine, every coordinate column
set with Coordinate::setValue (no clamping enforcement beyond OpenSim's own), positions realized.

Usage: python3 oracle/gen_muscle_analysis.py MODEL.osim MOTION.mot OUT_DIR [EVERY_NTH_ROW]
Writes OUT_DIR/lengths.csv (time, muscles…), OUT_DIR/moment_arms_<coordinate>.csv for a few
coordinates, OUT_DIR/markers.csv (time, <marker>_tx/_ty/_tz…).
"""
import csv
import sys
from pathlib import Path

import opensim

COORDINATES = ["hip_flexion_r", "knee_angle_r", "ankle_angle_r", "lumbar_extension"]


def main():
    model_file, motion_file, out = sys.argv[1:4]
    every = int(sys.argv[4]) if len(sys.argv) > 4 else 10
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    opensim.Logger.setLevelString("error")
    model = opensim.Model(model_file)
    state = model.initSystem()
    motion = opensim.Storage(motion_file)
    if motion.isInDegrees():
        model.getSimbodyEngine().convertDegreesToRadians(motion)
    labels = [motion.getColumnLabels().get(i) for i in range(motion.getColumnLabels().getSize())]
    coordinate_set = model.getCoordinateSet()
    columns = [(i - 1, coordinate_set.get(name)) for i, name in enumerate(labels) if i > 0 and coordinate_set.contains(name)]
    muscles = [model.getMuscles().get(i) for i in range(model.getMuscles().getSize())]
    markers = [model.getMarkerSet().get(i) for i in range(model.getMarkerSet().getSize())]
    coordinates = [coordinate_set.get(name) for name in COORDINATES if coordinate_set.contains(name)]
    rows = {"lengths": [], "markers": []}
    for c in coordinates:
        rows["moment_arms_" + c.getName()] = []
    for r in range(0, motion.getSize(), every):
        vector = motion.getStateVector(r)
        time = vector.getTime()
        data = vector.getData()
        for index, coordinate in columns:
            coordinate.setValue(state, data.get(index), False)
        model.realizePosition(state)
        rows["lengths"].append([time] + [m.getLength(state) for m in muscles])
        for c in coordinates:
            rows["moment_arms_" + c.getName()].append([time] + [m.computeMomentArm(state, c) for m in muscles])
        located = []
        for marker in markers:
            p = marker.getLocationInGround(state)
            located += [p.get(0), p.get(1), p.get(2)]
        rows["markers"].append([time] + located)
    headers = {"markers": ["time"] + [f"{m.getName()}_{a}" for m in markers for a in ("tx", "ty", "tz")]}
    for name, table in rows.items():
        header = headers.get(name, ["time"] + [m.getName() for m in muscles])
        with open(out / f"{name}.csv", "w", newline="") as f:
            f.write(",".join(header) + "\n")
            for row in table:
                f.write(",".join(repr(float(v)) for v in row) + "\n")


if __name__ == "__main__":
    main()

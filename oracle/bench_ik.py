"""Time OpenSim 4.6 (Python bindings) solving inverse kinematics of a trial with the tasks,
weights, time range and accuracy of an InverseKinematicsTool setup:

- `seconds_tool`: `InverseKinematicsTool.run()` as a user runs it (loads the model and the
  trial, solves every frame, writes the .mot and the marker errors into a temporary folder);
- `seconds_per_frame`: the solver alone, `InverseKinematicsSolver.track` per frame after the
  initial `assemble`, on the same references the tool builds.

Usage: python3 oracle/bench_ik.py SETUP.xml MODEL.osim TRIAL.trc [--accuracy A] [--write DIR]
With --write DIR the tool's outputs are kept in DIR (e.g. a golden at a tighter accuracy).
Prints `seconds_tool=…`, `seconds_per_frame=…`, `frames=…`. Used by `cargo xtask bench`.
"""
import argparse
import os
import tempfile
import time
import xml.etree.ElementTree as ET

import opensim


def tasks(setup):
    """Marker weights, coordinate tasks (name, weight, value) and time range of the setup."""
    root = ET.parse(setup).getroot()
    markers, coordinates = [], []
    for task in root.iter("IKMarkerTask"):
        if task.findtext("apply", "true").strip() == "true":
            markers.append((task.get("name"), float(task.findtext("weight", "0"))))
    for task in root.iter("IKCoordinateTask"):
        if task.findtext("apply", "true").strip() == "true":
            manual = task.findtext("value_type", "default_value").strip() == "manual_value"
            value = float(task.findtext("value", "0")) if manual else None
            coordinates.append((task.get("name"), float(task.findtext("weight", "0")), value))
    start, end = (float(v) for v in root.findtext(".//time_range").split())
    return markers, coordinates, (start, end)


def run_tool(setup, model_file, trial, accuracy, folder):
    tool = opensim.InverseKinematicsTool(setup)
    tool.set_model_file(os.path.abspath(model_file))
    tool.set_marker_file(os.path.abspath(trial))
    tool.set_accuracy(accuracy)
    tool.set_results_directory(os.path.abspath(folder))
    tool.set_output_motion_file(os.path.join(os.path.abspath(folder), tool.getName() + "_ik.mot"))
    start = time.perf_counter()
    if not tool.run():
        raise SystemExit("InverseKinematicsTool failed")
    return time.perf_counter() - start


def solver_seconds_per_frame(setup, model_file, trial, accuracy):
    markers, coordinates, (start, end) = tasks(setup)
    model = opensim.Model(model_file)
    state = model.initSystem()
    weights = opensim.SetMarkerWeights()
    for name, weight in markers:
        weights.cloneAndAppend(opensim.MarkerWeight(name, weight))
    reference = opensim.MarkersReference(trial, weights)
    references = opensim.SimTKArrayCoordinateReference()
    for name, weight, value in coordinates:
        if value is None:
            value = model.getCoordinateSet().get(name).getDefaultValue()
        coordinate = opensim.CoordinateReference(name, opensim.Constant(value))
        coordinate.setWeight(weight)
        references.push_back(coordinate)
    solver = opensim.InverseKinematicsSolver(model, reference, references)
    solver.setAccuracy(accuracy)
    times = [t for t in reference.getMarkerTable().getIndependentColumn() if start - 1e-9 <= t <= end + 1e-9]
    state.setTime(times[0])
    solver.assemble(state)
    begin = time.perf_counter()
    for t in times:
        state.setTime(t)
        solver.track(state)
    return (time.perf_counter() - begin) / len(times), len(times)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("setup")
    parser.add_argument("model")
    parser.add_argument("trial")
    parser.add_argument("--accuracy", type=float, default=1e-5)
    parser.add_argument("--write")
    arguments = parser.parse_args()
    opensim.Logger.setLevelString("error")
    if arguments.write:
        os.makedirs(arguments.write, exist_ok=True)
        seconds_tool = run_tool(arguments.setup, arguments.model, arguments.trial, arguments.accuracy, arguments.write)
    else:
        with tempfile.TemporaryDirectory() as folder:
            seconds_tool = run_tool(arguments.setup, arguments.model, arguments.trial, arguments.accuracy, folder)
    per_frame, frames = solver_seconds_per_frame(arguments.setup, arguments.model, arguments.trial, arguments.accuracy)
    print(f"seconds_tool={seconds_tool}")
    print(f"seconds_per_frame={per_frame}")
    print(f"frames={frames}")


if __name__ == "__main__":
    main()

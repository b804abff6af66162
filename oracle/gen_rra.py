#!/usr/bin/env python3
"""OpenSim 4.6's RRATool (residual reduction) on subject01's walk: the scaled gait2392 model of
`golden/scale/`, its muscles replaced by opensim-core's gait2354 RRA actuators (residuals FX…MZ on
the pelvis, a CoordinateActuator per joint coordinate), the IK motion of `golden/ik/`, the
ground reaction forces, the gait2354 RRA tracking tasks (CMC_Joint per coordinate):

* `walk`: 0.75–0.80 s as opensim-core's RRA example runs it (no filtering, its control
  constraints, the torso's mass center adjusted over the run's time range);
* `filtered`: 0.62–0.70 s, the desired kinematics low-pass filtered at 6 Hz (FIR order 50), the
  mass center adjusted over 0.5–1.5 s, no control constraints (the actuators' own bounds),
  integrator tolerance 1e-5.

Writes fixtures/golden/rra/<case>/: setup.xml (inputs by plain name), files.txt (every file
OpenSim wrote), the controls' `ControlSet`, every .sto (the states file's header repaired: OpenSim 4.6 leaves an early
flush's header lines in it) and the average residuals it wrote, and summary.json: the adjusted
body's mass center in the model OpenSim wrote and the lines of its mass-adjustment report
(`* …` lines of the log: the COM change, recommended masses, average residuals before and
after the adjustment).

    python3 oracle/gen_rra.py [case ...]
"""
import json
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

from tool_run import keep_results, repair_states, tool_results

REPO = Path(__file__).resolve().parent.parent
OUT = REPO / "fixtures" / "golden" / "rra"
INPUTS = {
    "subject01_simbody.osim": REPO / "fixtures" / "golden" / "scale" / "subject01_simbody.osim",
    "subject01_walk1_ik.mot": REPO / "fixtures" / "golden" / "ik" / "subject01_walk1_ik.mot",
    "subject01_walk1_grf.xml": REPO / "fixtures" / "subject01" / "subject01_walk1_grf.xml",
    "subject01_walk1_grf.mot": REPO / "fixtures" / "subject01" / "subject01_walk1_grf.mot",
    "gait2354_RRA_Actuators.xml": REPO / "fixtures" / "subject01" / "gait2354_RRA_Actuators.xml",
    "gait2354_RRA_Tasks.xml": REPO / "fixtures" / "subject01" / "gait2354_RRA_Tasks.xml",
    "gait2354_RRA_ControlConstraints.xml": REPO / "fixtures" / "subject01" / "gait2354_RRA_ControlConstraints.xml",
}

SETUP = """<?xml version="1.0" encoding="UTF-8" ?>
<OpenSimDocument Version="40600">
\t<RRATool name="{name}">
\t\t<model_file>subject01_simbody.osim</model_file>
\t\t<replace_force_set>true</replace_force_set>
\t\t<force_set_files>gait2354_RRA_Actuators.xml</force_set_files>
\t\t<results_directory>Results</results_directory>
\t\t<output_precision>8</output_precision>
\t\t<initial_time>{start}</initial_time>
\t\t<final_time>{end}</final_time>
\t\t<solve_for_equilibrium_for_auxiliary_states>false</solve_for_equilibrium_for_auxiliary_states>
\t\t<maximum_number_of_integrator_steps>20000</maximum_number_of_integrator_steps>
\t\t<maximum_integrator_step_size>0.001</maximum_integrator_step_size>
\t\t<minimum_integrator_step_size>1e-08</minimum_integrator_step_size>
\t\t<integrator_error_tolerance>{tolerance}</integrator_error_tolerance>
\t\t<AnalysisSet name="Analyses">
\t\t\t<objects />
\t\t\t<groups />
\t\t</AnalysisSet>
\t\t<ControllerSet name="Controllers">
\t\t\t<objects />
\t\t\t<groups />
\t\t</ControllerSet>
\t\t<external_loads_file>subject01_walk1_grf.xml</external_loads_file>
\t\t<desired_points_file />
\t\t<desired_kinematics_file>subject01_walk1_ik.mot</desired_kinematics_file>
\t\t<task_set_file>gait2354_RRA_Tasks.xml</task_set_file>
\t\t<constraints_file>{constraints}</constraints_file>
\t\t<lowpass_cutoff_frequency>{cutoff}</lowpass_cutoff_frequency>
\t\t<optimizer_algorithm>ipopt</optimizer_algorithm>
\t\t<numerical_derivative_step_size>0.0001</numerical_derivative_step_size>
\t\t<optimization_convergence_tolerance>1e-05</optimization_convergence_tolerance>
\t\t<adjust_com_to_reduce_residuals>true</adjust_com_to_reduce_residuals>
\t\t<initial_time_for_com_adjustment>{com_start}</initial_time_for_com_adjustment>
\t\t<final_time_for_com_adjustment>{com_end}</final_time_for_com_adjustment>
\t\t<adjusted_com_body>torso</adjusted_com_body>
\t\t<output_model_file>Results/{name}_adjusted.osim</output_model_file>
\t\t<use_verbose_printing>false</use_verbose_printing>
\t</RRATool>
</OpenSimDocument>
"""
CASES = {
    "walk": dict(start=0.75, end=0.80, tolerance="0.0001", constraints="gait2354_RRA_ControlConstraints.xml", cutoff=-1, com_start=-1, com_end=-1),
    "filtered": dict(start=0.62, end=0.70, tolerance="1e-05", constraints="", cutoff=6, com_start=0.5, com_end=1.5),
}
def main():
    for case in sys.argv[1:] or CASES:
        out = OUT / case
        out.mkdir(parents=True, exist_ok=True)
        name = f"subject01_walk1_RRA_{case}"
        (out / "setup.xml").write_text(SETUP.format(name=name, **CASES[case]))
        with tool_results("RRATool", INPUTS, (out / "setup.xml").read_text()) as (run, results):
            written = keep_results(results, out, (".sto", ".txt", "_controls.xml"))
            repair_states(out / f"{name}_states.sto")
            model = ET.parse(results / f"{name}_adjusted.osim")
            body = next(b for b in model.iter("Body") if b.get("name") == "torso")
            report = [line.strip() for line in run.stdout.splitlines() if line.startswith("*  ") or line.startswith("* Mass Center") or line.startswith("* New COM")]
            summary = {
                "adjusted_body": "torso",
                "mass_center": [float(v) for v in body.find("mass_center").text.split()],
                "report": report,
            }
            (out / "summary.json").write_text(json.dumps(summary, indent=1) + "\n")
            print(case, "->", out, ", ".join(written))


if __name__ == "__main__":
    main()

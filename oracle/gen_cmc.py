#!/usr/bin/env python3
"""OpenSim 4.6's CMCTool (computed muscle control) on arm26 — the model of `fixtures/models/`,
opensim-core's arm26 CMC inputs (`fixtures/cmc/`: the reserve actuators added to the six Thelen
muscles, the IK motion, the two CMC_Joint tasks) — and on subject01's walk:

* `fast`: 0.40–0.65 s as opensim-core's arm26 CMC test runs it (the desired kinematics filtered
  at 6 Hz, the fast target, integrator tolerance 1e-5, windows of 0.01 s);
* `slow`: 0.20–0.40 s unfiltered, the slow target (`use_fast_optimization_target` false);
* `exclude`: `fast` with BRA and TRImed left out of CMC's control (`actuators_to_exclude`, with a
  name no actuator has, which OpenSim warns about and ignores);
* `prescribed`: `fast` with a `PrescribedController` in the setup's `ControllerSet` driving BRA
  (excluded from CMC's control) along a line in time and adding 0.05 to TRIlong's control (still
  CMC's): the model's controls are every controller's sum;
* `emg`: `fast` with opensim-core's EMG tracking tasks (a `MuscleStateTrackingTask` pulling
  BIClong's activation towards `muscle_emg.sto`, weight 100);
* `walk`: 0.80–0.86 s of subject01's walk on the scaled gait2392 (92 muscles; the scale and IK
  goldens, the ground reactions) with opensim-core's gait2354 CMC actuators (residuals and
  reserves), tasks and control constraints (`fixtures/subject01/`), filtered at 6 Hz, fast target.

Writes fixtures/golden/cmc/<case>/: setup.xml (inputs by plain name), files.txt (every file
OpenSim wrote) and every .sto and the controls' `ControlSet` it wrote (the states file's header
repaired: OpenSim 4.6 leaves an early flush's header lines in it; the position errors' labels
cut to its columns: a state task is labelled there without values), and initial.json: what the
verbose log (the run's copy of the setup with `use_verbose_printing` on) reports of
`computeInitialStates` — the muscles' states Z before and after each 0.2 s settling, and of each of
the first window's two solves the min and max forces, the desired forces and the target's
performance (printed to 6 significant digits, the performance to 17).

    python3 oracle/gen_cmc.py [case ...]
"""
import json
import re
import sys
from pathlib import Path

from tool_run import keep_results, repair_states, tool_results

REPO = Path(__file__).resolve().parent.parent
OUT = REPO / "fixtures" / "golden" / "cmc"
ARM26 = {
    "arm26.osim": REPO / "fixtures" / "models" / "arm26.osim",
    "arm26_InverseKinematics.mot": REPO / "fixtures" / "cmc" / "arm26_InverseKinematics.mot",
    "arm26_Reserve_Actuators.xml": REPO / "fixtures" / "cmc" / "arm26_Reserve_Actuators.xml",
    "arm26_ComputedMuscleControl_Tasks.xml": REPO / "fixtures" / "cmc" / "arm26_ComputedMuscleControl_Tasks.xml",
}
ARM26_EMG = dict(ARM26, **{name: REPO / "fixtures" / "cmc" / name for name in ("arm26_ComputedMuscleControl_Tasks_EMG.xml", "muscle_emg.sto")})
GAIT = {
    "subject01_simbody.osim": REPO / "fixtures" / "golden" / "scale" / "subject01_simbody.osim",
    "subject01_walk1_ik.mot": REPO / "fixtures" / "golden" / "ik" / "subject01_walk1_ik.mot",
    "subject01_walk1_grf.xml": REPO / "fixtures" / "subject01" / "subject01_walk1_grf.xml",
    "subject01_walk1_grf.mot": REPO / "fixtures" / "subject01" / "subject01_walk1_grf.mot",
    "gait2354_CMC_Actuators.xml": REPO / "fixtures" / "subject01" / "gait2354_CMC_Actuators.xml",
    "gait2354_CMC_Tasks.xml": REPO / "fixtures" / "subject01" / "gait2354_CMC_Tasks.xml",
    "gait2354_CMC_ControlConstraints.xml": REPO / "fixtures" / "subject01" / "gait2354_CMC_ControlConstraints.xml",
}

SETUP = """<?xml version="1.0" encoding="UTF-8" ?>
<OpenSimDocument Version="40600">
\t<CMCTool name="{name}">
\t\t<model_file>{model}</model_file>
\t\t<replace_force_set>false</replace_force_set>
\t\t<force_set_files>{actuators}</force_set_files>
\t\t<results_directory>Results</results_directory>
\t\t<output_precision>8</output_precision>
\t\t<initial_time>{start}</initial_time>
\t\t<final_time>{end}</final_time>
\t\t<solve_for_equilibrium_for_auxiliary_states>true</solve_for_equilibrium_for_auxiliary_states>
\t\t<maximum_number_of_integrator_steps>20000</maximum_number_of_integrator_steps>
\t\t<maximum_integrator_step_size>1</maximum_integrator_step_size>
\t\t<minimum_integrator_step_size>1e-08</minimum_integrator_step_size>
\t\t<integrator_error_tolerance>{tolerance}</integrator_error_tolerance>
\t\t<AnalysisSet name="Analyses">
\t\t\t<objects />
\t\t\t<groups />
\t\t</AnalysisSet>
\t\t<ControllerSet name="Controllers">
\t\t\t<objects>{controllers}</objects>
\t\t\t<groups />
\t\t</ControllerSet>
\t\t<external_loads_file>{loads}</external_loads_file>
\t\t<desired_points_file />
\t\t<desired_kinematics_file>{kinematics}</desired_kinematics_file>
\t\t<task_set_file>{tasks}</task_set_file>
\t\t<constraints_file>{constraints}</constraints_file>
\t\t<lowpass_cutoff_frequency>{cutoff}</lowpass_cutoff_frequency>
\t\t<cmc_time_window>0.01</cmc_time_window>
\t\t<use_fast_optimization_target>{fast}</use_fast_optimization_target>
\t\t<actuators_to_exclude>{exclude}</actuators_to_exclude>
\t\t<optimizer_algorithm>ipopt</optimizer_algorithm>
\t\t<numerical_derivative_step_size>0.0001</numerical_derivative_step_size>
\t\t<optimization_convergence_tolerance>1e-05</optimization_convergence_tolerance>
\t\t<optimizer_max_iterations>100</optimizer_max_iterations>
\t\t<use_verbose_printing>false</use_verbose_printing>
\t</CMCTool>
</OpenSimDocument>
"""
ARM = dict(model="arm26.osim", actuators="arm26_Reserve_Actuators.xml", loads="", kinematics="arm26_InverseKinematics.mot", tasks="arm26_ComputedMuscleControl_Tasks.xml", constraints="", tolerance="1e-05", exclude="", controllers="")
WALK = dict(model="subject01_simbody.osim", actuators="gait2354_CMC_Actuators.xml", loads="subject01_walk1_grf.xml", kinematics="subject01_walk1_ik.mot", tasks="gait2354_CMC_Tasks.xml", constraints="gait2354_CMC_ControlConstraints.xml", tolerance="1e-05", exclude="", controllers="")
# BRA, left out of CMC's control, driven by a line in time; TRIlong, still CMC's, given 0.05 more.
PRESCRIBED = ('<PrescribedController name="prescribed"><socket_actuators>/forceset/BRA /forceset/TRIlong</socket_actuators>'
              '<FunctionSet name="ControlFunctions"><objects><LinearFunction><coefficients> 0.5 0.1</coefficients></LinearFunction>'
              '<Constant><value>0.05</value></Constant></objects></FunctionSet></PrescribedController>')
CASES = {
    "fast": (ARM26, "arm26", dict(ARM, start=0.4, end=0.65, cutoff=6, fast="true")),
    "slow": (ARM26, "arm26", dict(ARM, start=0.2, end=0.4, cutoff=-1, fast="false")),
    "exclude": (ARM26, "arm26", dict(ARM, start=0.4, end=0.65, cutoff=6, fast="true", exclude="BRA TRImed r_elbow_flex")),
    "prescribed": (ARM26, "arm26", dict(ARM, start=0.4, end=0.65, cutoff=6, fast="true", exclude="BRA", controllers=PRESCRIBED)),
    "emg": (ARM26_EMG, "arm26", dict(ARM, start=0.4, end=0.65, cutoff=6, fast="true", tasks="arm26_ComputedMuscleControl_Tasks_EMG.xml")),
    "walk": (GAIT, "subject01_walk1", dict(WALK, start=0.8, end=0.86, cutoff=6, fast="true")),
}
def numbers(line, label):
    """The numbers of `line` after `label`."""
    return [float(v) for v in re.findall(r"[-+]?\d*\.?\d+(?:[eE][-+]?\d+)?", line.split(label, 1)[1])]


def initial_report(log):
    """The verbose log's report of computeInitialStates: Z (per muscle: activation, fiber length)
    of the guess and after each settling, and the first window's two solves."""
    lines = log.splitlines()
    z = []
    for i, line in enumerate(lines):
        if "CMC::computeInitialStates, guess" in line or "actuator equilibrium #" in line:
            z.append(numbers(next(l for l in lines[i:] if "-- Z =" in l), "-- Z ="))
    solves = []
    block = {}
    for line in lines:
        for key, label in (("min_forces", "Min forces:"), ("max_forces", "Max forces:"), ("desired_forces", "Desired actuator forces:")):
            if label in line:
                block[key] = numbers(line, label)
        if line.startswith("performance ="):
            block["performance"] = float(line.split("=")[1])
        if len(block) == 4:
            solves.append(block)
            block = {}
        if len(solves) == 2:
            break
    return {"z": {"guess": z[0], "settled": z[1:3]}, "first_window": solves}


def repair_position_errors(path):
    """OpenSim 4.6 labels `_pErr.sto` with every task's name, a MuscleStateTrackingTask's too,
    but writes values (and counts `nColumns`) for the joint tasks only; keeps as many labels as
    the header counts."""
    lines = path.read_text().splitlines()
    columns = int(next(line for line in lines if line.startswith("nColumns=")).split("=")[1])
    at = lines.index("endheader") + 1
    lines[at] = "\t".join(lines[at].split("\t")[:columns])
    path.write_text("\n".join(lines) + "\n")


def main():
    for case in sys.argv[1:] or CASES:
        out = OUT / case
        out.mkdir(parents=True, exist_ok=True)
        inputs, prefix, settings = CASES[case]
        name = f"{prefix}_CMC_{case}"
        (out / "setup.xml").write_text(SETUP.format(name=name, **settings).replace("<external_loads_file></external_loads_file>", "<external_loads_file />").replace("<constraints_file></constraints_file>", "<constraints_file />").replace("<actuators_to_exclude></actuators_to_exclude>", "<actuators_to_exclude />").replace("<objects></objects>", "<objects />"))
        verbose = (out / "setup.xml").read_text().replace("<use_verbose_printing>false", "<use_verbose_printing>true")
        with tool_results("CMCTool", inputs, verbose) as (run, results):
            written = keep_results(results, out, (".sto", "_controls.xml"))
            repair_states(out / f"{name}_states.sto")
            repair_position_errors(out / f"{name}_pErr.sto")
            (out / "initial.json").write_text(json.dumps(initial_report(run.stdout + run.stderr), indent=1) + "\n")
            print(case, "->", out, ", ".join(written))


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""OpenSim 4.6's AnalyzeTool running an InducedAccelerations analysis on subject01's walk with its
ground reaction forces replaced by contact constraints, the inputs of `gen_analyze_tool.py`'s
`loads` case (scaled gait2392 with Thelen muscles equilibrated, the residual and reserve
actuators of its static optimisation, the GRF external loads), 0.59–0.65 s — the right heel
striking (its force crossing the threshold) while the left foot is in stance:

* `induced_rolling`: RollingOnSurfaceConstraints on calcn_r and calcn_l (the force threshold 10 N), the
  accelerations of hip_flexion_r, knee_angle_r, ankle_angle_r, pelvis_tx and pelvis_tilt, of the
  bodies calcn_r and pelvis and of the mass center, in degrees, every contributor (`total`, each
  actuator, gravity, velocity) and the constraint reactions they induce;
* `induced_potentials`: `compute_potentials_only` (muscles at 1 N), PointConstraints replacing the feet's
  forces (OpenSim 4.6 cannot run a WeldConstraint here: its contact frames are added after the
  system is built), every coordinate in radians, tibia_r and the mass
  center, every second row, the constraint reactions.

Writes fixtures/golden/analyze_tool/<case>/ (beside `gen_analyze_tool.py`'s cases, which the
AnalyzeTool tests run): setup.xml (inputs named as in the `loads` case), files.txt (every file OpenSim wrote) and every
table.

    python3 oracle/gen_induced_accelerations.py [case ...]
"""
import sys

import opensim as osim
from gen_analyze_tool import OUT, run_setup

ROLLING = """\t\t\t\t\t\t\t<RollingOnSurfaceConstraint name="{name}">
\t\t\t\t\t\t\t\t<isEnforced>false</isEnforced>
\t\t\t\t\t\t\t\t<rolling_body>{body}</rolling_body>
\t\t\t\t\t\t\t\t<surface_body>ground</surface_body>
\t\t\t\t\t\t\t\t<surface_normal>0 1 0</surface_normal>
\t\t\t\t\t\t\t\t<friction_coefficient>0.65</friction_coefficient>
\t\t\t\t\t\t\t\t<contact_radius>0.01</contact_radius>
\t\t\t\t\t\t\t</RollingOnSurfaceConstraint>
"""
POINT = """\t\t\t\t\t\t\t<PointConstraint name="{name}">
\t\t\t\t\t\t\t\t<isEnforced>false</isEnforced>
\t\t\t\t\t\t\t\t<body_1>ground</body_1>
\t\t\t\t\t\t\t\t<body_2>{body}</body_2>
\t\t\t\t\t\t\t</PointConstraint>
"""
ANALYSIS = """\t\t\t\t<InducedAccelerations name="InducedAccelerations">
\t\t\t\t\t<on>true</on>
\t\t\t\t\t<step_interval>{step}</step_interval>
\t\t\t\t\t<in_degrees>{in_degrees}</in_degrees>
\t\t\t\t\t<coordinate_names>{coordinates}</coordinate_names>
\t\t\t\t\t<body_names>{bodies}</body_names>
\t\t\t\t\t<ConstraintSet name="">
\t\t\t\t\t\t<objects>
{constraints}\t\t\t\t\t\t</objects>
\t\t\t\t\t</ConstraintSet>
\t\t\t\t\t<force_threshold>10</force_threshold>
\t\t\t\t\t<compute_potentials_only>{potentials}</compute_potentials_only>
\t\t\t\t\t<report_constraint_reactions>true</report_constraint_reactions>
\t\t\t\t</InducedAccelerations>
"""
CASES = {
    "induced_rolling": ANALYSIS.format(step=1, in_degrees="true", coordinates="hip_flexion_r knee_angle_r ankle_angle_r pelvis_tx pelvis_tilt",
                               bodies="calcn_r pelvis center_of_mass", potentials="false",
                               constraints=ROLLING.format(name="right_foot", body="calcn_r") + ROLLING.format(name="left_foot", body="calcn_l")),
    "induced_potentials": ANALYSIS.format(step=2, in_degrees="false", coordinates="All", bodies="tibia_r center_of_mass", potentials="true",
                                  constraints=POINT.format(name="right_foot", body="calcn_r") + POINT.format(name="left_foot", body="calcn_l")),
}


def setup_text(analysis):
    return f"""<?xml version="1.0" encoding="UTF-8" ?>
<OpenSimDocument Version="40600">
\t<AnalyzeTool name="walk">
\t\t<model_file>subject01_simbody.osim</model_file>
\t\t<results_directory>Results</results_directory>
\t\t<initial_time>0.59</initial_time>
\t\t<final_time>0.65</final_time>
\t\t<solve_for_equilibrium_for_auxiliary_states>true</solve_for_equilibrium_for_auxiliary_states>
\t\t<force_set_files> gait2392_SO_Residual_Actuators.xml</force_set_files>
\t\t<replace_force_set>false</replace_force_set>
\t\t<external_loads_file>subject01_walk1_grf.xml</external_loads_file>
\t\t<AnalysisSet name="Analyses">
\t\t\t<objects>
{analysis}\t\t\t</objects>
\t\t</AnalysisSet>
\t\t<coordinates_file>subject01_walk1_ik.mot</coordinates_file>
\t\t<lowpass_cutoff_frequency_for_coordinates>6</lowpass_cutoff_frequency_for_coordinates>
\t</AnalyzeTool>
</OpenSimDocument>
"""


def main():
    osim.Logger.setLevelString("error")
    wanted = sys.argv[1:]
    for case in (c for c in CASES if not wanted or c in wanted):
        out = OUT / case
        out.mkdir(parents=True, exist_ok=True)
        (out / "setup.xml").write_text(setup_text(CASES[case]))
        run_setup(out, lambda name: True)
        print(case, "written", sorted(p.name for p in out.iterdir()))


if __name__ == "__main__":
    main()

"""Writes fixtures/golden/forward_tool/<case>/: OpenSim 4.6's ForwardTool run on a setup file
(setup.xml, inputs beside it) and the files it writes (<name>_states.sto, _controls.sto,
_states_degrees.mot), for `osim-tune simulate` / `run` to reproduce:
* `controls`: arm26 from its default state, muscles equilibrated, 0–0.3 s, its six muscles
  excited by a ControlSetController's ControlSet (ControlLinear nodes, one stepped);
* `states`: arm26 from the row of initial_states.sto (a copy of arm26_states.sto, OpenSim's own forward simulation, the
  AnalyzeTool golden's) at 0.1 s, not equilibrated, 0.1–0.3 s, with a CoordinateActuator on
  r_elbow_flex from a force-set file driven beside the muscles by a second controller.
The integrator tolerance is 1e-9, so OpenSim's states are within ~1e-7 of the exact solution;
the fixtures keep every 10th row OpenSim wrote (and the first and last).

Usage: python3 oracle/gen_forward_tool.py
"""
import shutil
from pathlib import Path

import opensim as osim

REPO = Path(__file__).resolve().parent.parent
OUT = REPO / "fixtures" / "golden" / "forward_tool"
MUSCLES = ["TRIlong", "TRIlat", "TRImed", "BIClong", "BICshort", "BRA"]


def control_linear(name, nodes, use_steps="false"):
    points = "".join(f"<ControlLinearNode><t>{t}</t><value>{v}</value></ControlLinearNode>" for t, v in nodes)
    return (f'<ControlLinear name="{name}"><extrapolate>true</extrapolate><use_steps>{use_steps}</use_steps>'
            f"<x_nodes>{points}</x_nodes></ControlLinear>")


def control_set(controls):
    return ('<?xml version="1.0" encoding="UTF-8" ?>\n<OpenSimDocument Version="40600">\n'
            f'<ControlSet name="controls"><objects>{"".join(controls)}</objects></ControlSet>\n</OpenSimDocument>\n')


def setup(name, final, initial=0.0, equilibrate=True, controllers=(), states="", force_sets=""):
    objects = "".join(f'<ControlSetController name="c{i}"><controls_file>{c}</controls_file></ControlSetController>' for i, c in enumerate(controllers))
    return f"""<?xml version="1.0" encoding="UTF-8" ?>
<OpenSimDocument Version="40600">
\t<ForwardTool name="{name}">
\t\t<model_file>arm26.osim</model_file>
\t\t<replace_force_set>false</replace_force_set>
\t\t<force_set_files>{force_sets}</force_set_files>
\t\t<results_directory>./</results_directory>
\t\t<output_precision>16</output_precision>
\t\t<initial_time>{initial}</initial_time>
\t\t<final_time>{final}</final_time>
\t\t<solve_for_equilibrium_for_auxiliary_states>{str(equilibrate).lower()}</solve_for_equilibrium_for_auxiliary_states>
\t\t<maximum_number_of_integrator_steps>20000</maximum_number_of_integrator_steps>
\t\t<maximum_integrator_step_size>1</maximum_integrator_step_size>
\t\t<minimum_integrator_step_size>1e-08</minimum_integrator_step_size>
\t\t<integrator_error_tolerance>1e-09</integrator_error_tolerance>
\t\t<AnalysisSet name="Analyses"><objects /></AnalysisSet>
\t\t<ControllerSet name="Controllers"><objects>{objects}</objects></ControllerSet>
\t\t<external_loads_file />
\t\t<states_file>{states}</states_file>
\t</ForwardTool>
</OpenSimDocument>
"""


ELBOW_ACTUATOR = """<?xml version="1.0" encoding="UTF-8" ?>
<OpenSimDocument Version="40600">
\t<ForceSet name="elbow">
\t\t<objects>
\t\t\t<CoordinateActuator name="elbow_motor">
\t\t\t\t<coordinate>r_elbow_flex</coordinate>
\t\t\t\t<optimal_force>10</optimal_force>
\t\t\t\t<min_control>-10</min_control>
\t\t\t\t<max_control>10</max_control>
\t\t\t</CoordinateActuator>
\t\t</objects>
\t</ForceSet>
</OpenSimDocument>
"""


def run(case, text, files):
    folder = OUT / case
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    shutil.copy(REPO / "fixtures" / "models" / "arm26.osim", folder / "arm26.osim")
    for name, content in files.items():
        (folder / name).write_text(content)
    (folder / "setup.xml").write_text(text)
    tool = osim.ForwardTool(str(folder / "setup.xml"))
    assert tool.run(), case
    (folder / "arm26.osim").unlink()
    (folder / "opensim.log").unlink(missing_ok=True)
    for output in ["arm26_states.sto", "arm26_controls.sto", "arm26_states_degrees.mot"]:
        thin(folder / output)
    print(case, sorted(p.name for p in folder.iterdir()))


def thin(path, every=10):
    """Keeps the header and the first, every `every`-th and the last row of a table OpenSim
    wrote (nRows and a SIMM header's datarows updated): the fixture stays small, and each kept row is OpenSim's."""
    lines = path.read_text().rstrip("\n").split("\n")
    header = next(i for i, line in enumerate(lines) if line.strip() == "endheader") + 2
    rows = lines[header:]
    kept = [row for i, row in enumerate(rows) if i % every == 0 or i == len(rows) - 1]
    counts = {"nRows=": f"nRows={len(kept)}", "datarows ": f"datarows {len(kept)}"}
    head = [next((new for key, new in counts.items() if line.startswith(key)), line) for line in lines[:header]]
    path.write_text("\n".join(head + kept) + "\n")


def main():
    excitations = [
        control_linear("TRIlong.excitation", [(0.0, 0.05), (0.1, 0.6), (0.3, 0.1)]),
        control_linear("TRIlat.excitation", [(0.0, 0.3), (0.15, 0.05)]),
        control_linear("TRImed.excitation", [(0.0, 0.2), (0.2, 0.4)], use_steps="true"),
        control_linear("BIClong.excitation", [(0.0, 0.1), (0.05, 0.9), (0.2, 0.2)]),
        control_linear("BICshort.excitation", [(0.0, 0.5)]),
        control_linear("BRA.excitation", [(0.0, 0.02), (0.3, 0.8)]),
    ]
    run("controls", setup("arm26", 0.3, controllers=["arm26_controls.xml"]), {"arm26_controls.xml": control_set(excitations)})
    states = (REPO / "fixtures" / "golden" / "analyze_tool" / "states" / "arm26_states.sto").read_text()
    motor = control_set([control_linear("elbow_motor", [(0.1, -2.0), (0.3, 3.0)])])
    run("states", setup("arm26", 0.3, initial=0.1, equilibrate=False, controllers=["arm26_controls.xml", "motor_controls.xml"], states="initial_states.sto", force_sets="elbow_actuator.xml"),
        {"arm26_controls.xml": control_set(excitations), "motor_controls.xml": motor, "initial_states.sto": states, "elbow_actuator.xml": ELBOW_ACTUATOR})


if __name__ == "__main__":
    main()

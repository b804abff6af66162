"""Writes fixtures/golden/forward_tool/<case>/: OpenSim 4.6's ForwardTool run on a setup file
(setup.xml, inputs beside it) and the files it writes (<name>_states.sto, _controls.sto,
_states_degrees.mot), for `osim-tune simulate` / `run` to reproduce:
* `controls`: arm26 from its default state, muscles equilibrated, 0–0.3 s, its six muscles
  excited by a ControlSetController's ControlSet (ControlLinear nodes, one stepped);
* `states`: arm26 from the row of initial_states.sto (a copy of arm26_states.sto, OpenSim's own forward simulation, the
  AnalyzeTool golden's) at 0.1 s, not equilibrated, 0.1–0.3 s, with a CoordinateActuator on
  r_elbow_flex from a force-set file driven beside the muscles by a second controller;
* `prescribed`: arm26_prescribed.osim (arm26 with a ControllerSet: a PrescribedController of
  three muscles through a Sine, a StepFunction and a PiecewiseLinearFunction, and one of `ALL`
  muscles through constants) from its equilibrated default, 0–0.3 s, with the setup's own
  PrescribedController (an inline LinearFunction for /forceset/BICshort and the columns of
  tool_controls.sto as linear GCV splines) and a point force on the hand from hand_load.xml;
* `ball_free`: ball_free.osim (built here: a top on a BallJoint below an offset in ground and a
  brick on a FreeJoint, both starting at angles and spinning; a CoordinateActuator on the ball's
  second coordinate driven by the model's PrescribedController through a Sine), 0–0.5 s under
  gravity — the angles' rates from the angular velocity, 3D rigid-body dynamics;
* `ellipsoid`: fixtures/models/ellipsoid_joints.osim (a scapula on a ScapulothoracicJoint, an arm
  on an EllipsoidJoint, a Millard muscle across both) falling from its default pose, muscle
  equilibrated, 0–0.3 s; its light bodies whirl at up to 17 rad/s, so the tolerance is 1e-12
  (at 1e-9 two correct integrators part by 2e-4 rad) and every 100th row is kept;
* `linked`: fixtures/models/linked_mechanisms.osim (a point, a constant-distance, a
  point-on-line and a weld constraint and a coupler closing loops of Ball, Free, Pin and Slider
  joints; Millard muscles) moving from its assembled default pose under gravity, muscles
  equilibrated, 0–0.3 s; every 20th row kept;
* `shoulder`: fixtures/models/ThoracoscapularShoulderModel.osim (33 Millard muscles wrapping over
  ellipsoids and cylinders, a ScapulothoracicJoint, the AC joint's PointConstraint) moving from
  its default pose under gravity, muscles equilibrated, 0–0.1 s; every 100th row kept, the
  degrees file left out (validate runs this case, not the tests: ~40 s with OpenSim, ~15 s
  with osim-tune).
The integrator tolerance is 1e-9 (1e-12 for `ellipsoid`), so OpenSim's states are within ~1e-7 of
the exact solution; the fixtures keep every 10th row OpenSim wrote (100th for `ellipsoid`; and the
first and last).

Usage: python3 oracle/gen_forward_tool.py [case ...]
"""
import os
import re
import shutil
import sys
import tempfile
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


def setup(name, final, initial=0.0, equilibrate=True, controllers=(), states="", force_sets="", model="arm26.osim", objects=None, loads="", tolerance="1e-09", steps=20000):
    if objects is None:
        objects = "".join(f'<ControlSetController name="c{i}"><controls_file>{c}</controls_file></ControlSetController>' for i, c in enumerate(controllers))
    return f"""<?xml version="1.0" encoding="UTF-8" ?>
<OpenSimDocument Version="40600">
\t<ForwardTool name="{name}">
\t\t<model_file>{model}</model_file>
\t\t<replace_force_set>false</replace_force_set>
\t\t<force_set_files>{force_sets}</force_set_files>
\t\t<results_directory>./</results_directory>
\t\t<output_precision>16</output_precision>
\t\t<initial_time>{initial}</initial_time>
\t\t<final_time>{final}</final_time>
\t\t<solve_for_equilibrium_for_auxiliary_states>{str(equilibrate).lower()}</solve_for_equilibrium_for_auxiliary_states>
\t\t<maximum_number_of_integrator_steps>{steps}</maximum_number_of_integrator_steps>
\t\t<maximum_integrator_step_size>1</maximum_integrator_step_size>
\t\t<minimum_integrator_step_size>1e-08</minimum_integrator_step_size>
\t\t<integrator_error_tolerance>{tolerance}</integrator_error_tolerance>
\t\t<AnalysisSet name="Analyses"><objects /></AnalysisSet>
\t\t<ControllerSet name="Controllers"><objects>{objects}</objects></ControllerSet>
\t\t<external_loads_file>{loads}</external_loads_file>
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


def run(case, text, files, every=10, degrees=True):
    if sys.argv[1:] and case not in sys.argv[1:]:
        return
    folder = OUT / case
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    model = re.search(r"<model_file>(.*)</model_file>", text).group(1)
    shared = REPO / "fixtures" / "models" / model
    if model not in files:
        shutil.copy(shared, folder / model)
    for name, content in files.items():
        (folder / name).write_text(content)
    (folder / "setup.xml").write_text(text)
    cwd = os.getcwd()
    os.chdir(folder)  # OpenSim reads a PrescribedController's controls_file from the working directory
    try:
        tool = osim.ForwardTool(str(folder / "setup.xml"))
        assert tool.run(), case
    finally:
        os.chdir(cwd)
    if model not in files:
        (folder / model).unlink()
    (folder / "opensim.log").unlink(missing_ok=True)
    for output in [*folder.glob("*_states.sto"), *folder.glob("*_controls.sto"), *folder.glob("*_states_degrees.mot")]:
        thin(output, every)
    if not degrees:
        for output in folder.glob("*_states_degrees.mot"):
            output.unlink()
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


def prescribed_model():
    """arm26 with two PrescribedControllers in its ControllerSet (4.0 file: `actuator_list`)."""
    functions = ('<Sine><amplitude>0.2</amplitude><omega>20</omega><phase>0.3</phase><offset>0.3</offset></Sine>'
                 '<StepFunction><transition_start_time>0.05</transition_start_time><transition_end_time>0.15</transition_end_time>'
                 '<start_value>0.1</start_value><end_value>0.7</end_value></StepFunction>'
                 '<PiecewiseLinearFunction><x> 0 0.1 0.3</x><y> 0.05 0.5 0.2</y></PiecewiseLinearFunction>')
    constants = "".join(f"<Constant><value>{v}</value></Constant>" for v in [0.01, 0.02, 0.03, 0.04, 0.05, 0.06])
    controllers = ('<ControllerSet name="controllerset"><objects>'
                   '<PrescribedController name="p_model"><actuator_list>TRIlong BIClong BRA</actuator_list>'
                   f'<FunctionSet name="ControlFunctions"><objects>{functions}</objects><groups /></FunctionSet></PrescribedController>'
                   '<PrescribedController name="p_all"><actuator_list>ALL</actuator_list>'
                   f'<FunctionSet name="ControlFunctions"><objects>{constants}</objects><groups /></FunctionSet></PrescribedController>'
                   '</objects><groups /></ControllerSet>')
    text = (REPO / "fixtures" / "models" / "arm26.osim").read_text()
    empty = '<ControllerSet name="controllerset">\n\t\t\t<objects />\n\t\t\t<groups />\n\t\t</ControllerSet>'
    assert empty in text
    return text.replace(empty, controllers)


TOOL_PRESCRIBED = ('<PrescribedController name="p_tool"><socket_actuators>/forceset/BICshort</socket_actuators>'
                   '<FunctionSet name="ControlFunctions"><objects><LinearFunction><coefficients> 1.5 0.1</coefficients></LinearFunction></objects></FunctionSet>'
                   '<controls_file>tool_controls.sto</controls_file></PrescribedController>')

TOOL_CONTROLS = """tool_controls
version=1
nRows=4
nColumns=3
inDegrees=no
endheader
time\tTRIlat\tTRImed
0\t0.2\t0.05
0.1\t0.05\t0.4
0.2\t0.6\t0.3
0.3\t0.3\t0.1
"""

HAND_LOAD = """<?xml version="1.0" encoding="UTF-8" ?>
<OpenSimDocument Version="40600">
\t<ExternalLoads name="hand_load">
\t\t<objects>
\t\t\t<ExternalForce name="push">
\t\t\t\t<applied_to_body>r_ulna_radius_hand</applied_to_body>
\t\t\t\t<force_expressed_in_body>ground</force_expressed_in_body>
\t\t\t\t<point_expressed_in_body>r_ulna_radius_hand</point_expressed_in_body>
\t\t\t\t<force_identifier>hand_force_v</force_identifier>
\t\t\t\t<point_identifier>hand_force_p</point_identifier>
\t\t\t\t<data_source_name>hand_load.mot</data_source_name>
\t\t\t</ExternalForce>
\t\t</objects>
\t\t<groups />
\t\t<datafile>hand_load.mot</datafile>
\t</ExternalLoads>
</OpenSimDocument>
"""


def hand_load_motion():
    """A force on the hand (N, in ground) at a point of it (m, in the hand), varying smoothly."""
    rows = []
    for i in range(31):
        t = i * 0.01
        rows.append("\t".join(f"{v:.10g}" for v in [t, 8 * t, -15 + 20 * t, 3.0, 0.01, -0.2 - 0.1 * t, 0.02]))
    labels = "time\thand_force_vx\thand_force_vy\thand_force_vz\thand_force_px\thand_force_py\thand_force_pz"
    return f"hand_load\nversion=1\nnRows={len(rows)}\nnColumns=7\ninDegrees=no\nendheader\n{labels}\n" + "\n".join(rows) + "\n"


def ball_free_model(folder):
    """The `ball_free` model, printed to `folder` (the file's text is returned)."""
    model = osim.Model()
    model.setName("ball_free")
    top = osim.Body("top", 2.0, osim.Vec3(0.02, -0.3, 0.01), osim.Inertia(0.02, 0.05, 0.03, 0.001, 0.002, -0.001))
    brick = osim.Body("brick", 1.5, osim.Vec3(0.01, 0.02, -0.01), osim.Inertia(0.01, 0.02, 0.03, 0.0, 0.001, 0.0))
    ball = osim.BallJoint("ball", model.getGround(), osim.Vec3(0, 1, 0), osim.Vec3(0.1, 0, 0), top, osim.Vec3(0, 0, 0), osim.Vec3(0, 0, 0))
    free = osim.FreeJoint("free", model.getGround(), osim.Vec3(0.5, 0, 0), osim.Vec3(0, 0, 0.2), brick, osim.Vec3(0, 0, 0), osim.Vec3(0, 0, 0))
    for body, joint in [(top, ball), (brick, free)]:
        model.addBody(body)
        model.addJoint(joint)
    for joint, values, speeds in [(ball, [0.3, -0.2, 0.4], [2.0, -1.0, 3.0]), (free, [0.1, 0.2, -0.3, 0.0, 1.0, 0.0], [5.0, 1.0, -2.0, 0.5, 2.0, 0.0])]:
        for k, (value, speed) in enumerate(zip(values, speeds)):
            coordinate = joint.upd_coordinates(k)
            coordinate.setDefaultValue(value)
            coordinate.setDefaultSpeedValue(speed)
    twist = osim.CoordinateActuator("ball_coord_1")
    twist.setName("twist")
    twist.setOptimalForce(2.0)
    twist.setMinControl(-10)
    twist.setMaxControl(10)
    model.addForce(twist)
    controller = osim.PrescribedController()
    controller.setName("twister")
    controller.addActuator(twist)
    controller.prescribeControlForActuator("twist", osim.Sine(1.5, 12.0, 0.4, 0.2))
    model.addController(controller)
    model.finalizeConnections()
    path = folder / "ball_free.osim"
    model.printToXML(str(path))
    return path.read_text()


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
    run("prescribed", setup("arm26", 0.3, model="arm26_prescribed.osim", objects=TOOL_PRESCRIBED, loads="hand_load.xml"),
        {"arm26_prescribed.osim": prescribed_model(), "tool_controls.sto": TOOL_CONTROLS, "hand_load.xml": HAND_LOAD, "hand_load.mot": hand_load_motion()})
    with tempfile.TemporaryDirectory() as scratch:
        model = ball_free_model(Path(scratch))
    run("ball_free", setup("ball_free", 0.5, equilibrate=False, model="ball_free.osim", objects=""), {"ball_free.osim": model})
    run("ellipsoid", setup("ellipsoid", 0.3, model="ellipsoid_joints.osim", objects="", tolerance="1e-12", steps=200000), {}, every=100)
    run("linked", setup("linked", 0.3, model="linked_mechanisms.osim", objects=""), {}, every=20)
    run("shoulder", setup("shoulder", 0.1, model="ThoracoscapularShoulderModel.osim", objects=""), {}, every=100, degrees=False)


if __name__ == "__main__":
    main()

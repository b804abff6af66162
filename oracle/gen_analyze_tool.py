#!/usr/bin/env python3
"""OpenSim 4.6's AnalyzeTool running MuscleAnalysis, Kinematics and BodyKinematics from a
coordinates file, as a lab runs them from a setup: subject01's scaled model and its IK motion
(the IK goldens'), four setups —

* `all`: a MuscleAnalysis of every muscle and coordinate, coordinates low-pass filtered at 6 Hz,
  0.5–0.6 s;
* `listed`: muscle_list `vas_lat_r rect_fem_r no_such_muscle bifemlh_r` (not the model's
  order, one unknown), moment_arm_coordinate_list `knee_angle_r no_such_coordinate
  hip_flexion_r`, step_interval 2, unfiltered, 0.5–0.7 s;
* `kinematics`: Kinematics and BodyKinematics of every coordinate and body, filtered at 6 Hz,
  0.5–0.6 s;
* `kinematics_listed`: Kinematics of `knee_angle_r pelvis_tx` in radians, BodyKinematics of
  `tibia_r center_of_mass femur_r` with velocities in the bodies' frames, both named otherwise
  (`coords`, `segments`), step_interval 2, unfiltered, 0.5–0.7 s;
* `points`: PointKinematics of a heel point, a shin point in the femur's frame (every second
  row) and an unnamed one with the defaults (ground's origin, `NONAME`), filtered at 6 Hz;
* `muscle_states`: a MuscleAnalysis of listed muscles (sar_r and semiten_r start below their
  minimum fiber length) and coordinates, ForceReporter, Actuation (every second row),
  StatesReporter and Kinematics (with the accelerations those states give), the muscles at their
  default states (Thelen), filtered at 6 Hz, 0.5–0.6 s;
* `equilibrium`: the same with `solve_for_equilibrium_for_auxiliary_states`;
* `millard`: the same analyses, equilibrated, on gait2392 with Millard muscles (models/);
* `rajagopal`: the same, equilibrated, on the scaled Rajagopal2016 model of the scale zoo
  (Millard muscles with rigid and compliant tendons and fiber damping, CoordinateActuators,
  coupler constraints; its knee's range clamps the walk's negative knee angles);
* `loads`: subject01's walk with its ground reaction forces (`external_loads_file`) and the
  residual and reserve actuators of its static optimisation (`force_set_files`: point, torque
  and coordinate actuators), equilibrated: ForceReporter, Actuation, Kinematics, BodyKinematics
  (pelvis, calcn_r, the whole model's mass center), a heel point's PointKinematics and a
  JointReaction without a forces file (the right hip, knee and ankle on their children, in the
  children's frames: the model's forces at the muscles' states);
* `controls`: the `loads` case driven by two `ControlSetController`s: `residual_controls.xml`
  (ControlLinear: FX linear, FY in steps, `FZ.excitation` held past its last node, MY) and
  `residual_controls.sto` (MX and MY, whose controls add up); MZ has none;
* `states`: arm26 from a `states_file` — OpenSim's forward simulation of it under constant
  excitations (`arm26_states.sto`, written here) — MuscleAnalysis, Kinematics, BodyKinematics,
  ForceReporter, Actuation, StatesReporter, JointReaction (every joint on its parent, in ground,
  no forces file), every third row;
* `degroote`: arm26 with DeGrooteFregly2016Muscles (explicit tendon dynamics) from the states
  of OpenSim's forward simulation of it (`arm26_degroote_states.sto`, written here: activation
  and normalized_tendon_force), the `states` analyses;
* `degroote_equilibrium`, `degroote_rigid`: the same analyses on arm26's coordinates
  (`arm26_motion.mot`), equilibrated, with compliant and with rigid tendons;
* `states_legacy`: the same states under OpenSim 3's labels (`r_shoulder_elev`,
  `r_shoulder_elev_u`, `TRIlong.activation`, `TRIlong.fiber_length`), equilibrated;
* `ball_free`: the ForwardTool golden's top on a BallJoint and brick on a FreeJoint from their
  simulated states, its CoordinateActuator driven by the model's PrescribedController (a Sine):
  the `states` analyses (angular-velocity speeds, the actuator's control from the controller);
* `ellipsoid`: the ForwardTool golden's ScapulothoracicJoint and EllipsoidJoint from their
  simulated states (the Millard muscle's activation state driven below 0, which OpenSim clamps),
  the `states` analyses — the scapulothoracic reaction on the thorax as OpenSim takes it, about
  the child frame's origin (the weld carrying the scapula on a massless winging body);
* `ellipsoid_equilibrium`: the same, equilibrated — OpenSim equilibrates the muscle at the
  clamped activation too;
* `linked`: the ForwardTool golden's linked_mechanisms (point, distance, point-on-line and weld
  constraints closing loops) from its simulated states, the `states` analyses but the
  MuscleAnalysis (OpenSim's moment arms about a coordinate a weld holds are NaN or arbitrary):
  the accelerations and joint reactions with the links' constraint forces.

Writes fixtures/golden/analyze_tool/<case>/: setup.xml (model and motion names relative, as the
test copies them next to it), files.txt (every file OpenSim wrote), and of its tables: Length and
the MomentArm tables of knee_angle_r, hip_flexion_r, lumbar_extension (which no muscle spans) and
pelvis_tx (`all`), every MuscleAnalysis table (`listed` and the muscle-state cases), the q, u,
u̇, position, velocity and acceleration tables (the kinematics and points cases; the
accelerations are OpenSim's forward dynamics with the muscles at their default states), every
reporter table.

    python3 oracle/gen_analyze_tool.py [case ...]   (named cases only: their inputs as they stand)
"""
import shutil
import sys
import tempfile
from pathlib import Path

import opensim as osim
from tool_run import run_in

REPO = Path(__file__).resolve().parent.parent
OUT = REPO / "fixtures" / "golden" / "analyze_tool"
INPUTS = {
    "subject01_simbody.osim": REPO / "fixtures" / "golden" / "scale" / "subject01_simbody.osim",
    "gait2392_millard2012muscle.osim": REPO / "models" / "gait2392_millard2012muscle.osim",
    "Rajagopal2016_scaled.osim": REPO / "fixtures" / "golden" / "scale_zoo" / "Rajagopal2016_scaled.osim",
    "gait2392_SO_Residual_Actuators.xml": REPO / "fixtures" / "subject01" / "gait2392_SO_Residual_Actuators.xml",
    "subject01_walk1_grf.xml": REPO / "fixtures" / "subject01" / "subject01_walk1_grf.xml",
    "subject01_walk1_grf.mot": REPO / "fixtures" / "subject01" / "subject01_walk1_grf.mot",
    "arm26.osim": REPO / "fixtures" / "models" / "arm26.osim",
    "arm26_degroote.osim": REPO / "fixtures" / "models" / "arm26_degroote.osim",
    "arm26_degroote_rigid.osim": REPO / "fixtures" / "models" / "arm26_degroote_rigid.osim",
    "arm26_motion.mot": REPO / "fixtures" / "golden" / "static_optimization" / "arm26" / "arm26_motion.mot",
    "arm26_degroote_states.sto": OUT / "degroote" / "arm26_degroote_states.sto",
    "residual_controls.xml": OUT / "controls" / "residual_controls.xml",
    "residual_controls.sto": OUT / "controls" / "residual_controls.sto",
    "arm26_states.sto": OUT / "states" / "arm26_states.sto",
    "arm26_states_legacy.sto": OUT / "states_legacy" / "arm26_states_legacy.sto",
    "ball_free.osim": REPO / "fixtures" / "golden" / "forward_tool" / "ball_free" / "ball_free.osim",
    "ball_free_states.sto": REPO / "fixtures" / "golden" / "forward_tool" / "ball_free" / "ball_free_states.sto",
    "ellipsoid_joints.osim": REPO / "fixtures" / "models" / "ellipsoid_joints.osim",
    "ellipsoid_states.sto": REPO / "fixtures" / "golden" / "forward_tool" / "ellipsoid" / "ellipsoid_states.sto",
    "linked_mechanisms.osim": REPO / "fixtures" / "models" / "linked_mechanisms.osim",
    "linked_states.sto": REPO / "fixtures" / "golden" / "forward_tool" / "linked" / "linked_states.sto",
    "arm26_probes.osim": REPO / "fixtures" / "models" / "arm26_probes.osim",
}
ARM = """\t\t\t\t<MuscleAnalysis name="MuscleAnalysis"><on>true</on><step_interval>3</step_interval></MuscleAnalysis>
\t\t\t\t<Kinematics name="Kinematics"><on>true</on><step_interval>3</step_interval></Kinematics>
\t\t\t\t<BodyKinematics name="BodyKinematics"><on>true</on><step_interval>3</step_interval></BodyKinematics>
\t\t\t\t<ForceReporter name="ForceReporter"><on>true</on><step_interval>3</step_interval></ForceReporter>
\t\t\t\t<Actuation name="Actuation"><on>true</on><step_interval>3</step_interval></Actuation>
\t\t\t\t<StatesReporter name="StatesReporter"><on>true</on><step_interval>3</step_interval></StatesReporter>
\t\t\t\t<JointReaction name="JointReaction"><on>true</on><step_interval>3</step_interval><joint_names> ALL</joint_names><apply_on_bodies> parent</apply_on_bodies><express_in_frame> ground</express_in_frame></JointReaction>
"""
LINKED = "".join(line + "\n" for line in ARM.splitlines() if "MuscleAnalysis" not in line)
MOTION = REPO / "fixtures" / "golden" / "ik" / "subject01_walk1_ik.mot"
KEPT = ["Length", "MomentArm_knee_angle_r", "MomentArm_hip_flexion_r", "MomentArm_lumbar_extension", "MomentArm_pelvis_tx"]

MUSCLES = """\t\t\t\t<MuscleAnalysis name="MuscleAnalysis">
\t\t\t\t\t<on>true</on>
\t\t\t\t\t<step_interval>{step}</step_interval>
\t\t\t\t\t<muscle_list> {muscles}</muscle_list>
\t\t\t\t\t<moment_arm_coordinate_list> {coordinates}</moment_arm_coordinate_list>
\t\t\t\t\t<compute_moments>true</compute_moments>
\t\t\t\t</MuscleAnalysis>
"""
KINEMATICS = """\t\t\t\t<Kinematics name="{kinematics_name}">
\t\t\t\t\t<on>true</on>
\t\t\t\t\t<step_interval>{step}</step_interval>
\t\t\t\t\t<in_degrees>{in_degrees}</in_degrees>
\t\t\t\t\t<coordinates> {coordinates}</coordinates>
\t\t\t\t</Kinematics>
\t\t\t\t<BodyKinematics name="{bodies_name}">
\t\t\t\t\t<on>true</on>
\t\t\t\t\t<step_interval>{step}</step_interval>
\t\t\t\t\t<bodies> {bodies}</bodies>
\t\t\t\t\t<express_results_in_body_local_frame>{local}</express_results_in_body_local_frame>
\t\t\t\t</BodyKinematics>
"""
POINTS = """\t\t\t\t<PointKinematics name="heel"><on>true</on><body_name>calcn_r</body_name><point>0.01 0.02 -0.03</point><point_name>heel_r</point_name></PointKinematics>
\t\t\t\t<PointKinematics name="knee_in_femur"><on>true</on><step_interval>2</step_interval><body_name>tibia_r</body_name><point>0.0 -0.1 0.02</point><point_name>shin</point_name><relative_to_body_name>femur_r</relative_to_body_name></PointKinematics>
\t\t\t\t<PointKinematics><on>true</on></PointKinematics>
"""
REPORTERS = """\t\t\t\t<ForceReporter name="ForceReporter"><on>true</on></ForceReporter>
\t\t\t\t<Actuation name="Actuation"><on>true</on><step_interval>2</step_interval></Actuation>
\t\t\t\t<StatesReporter name="StatesReporter"><on>true</on></StatesReporter>
\t\t\t\t<Kinematics name="Kinematics"><on>true</on></Kinematics>
"""
GAIT_MUSCLES = MUSCLES.format(step=1, muscles="sar_r semiten_r bifemsh_r glut_med1_r rect_fem_r vas_lat_r soleus_r med_gas_r",
                              coordinates="knee_angle_r ankle_angle_r hip_flexion_r") + REPORTERS
RAJAGOPAL_MUSCLES = MUSCLES.format(step=1, muscles="bflh_r semiten_r recfem_r vasint_r soleus_r gaslat_r tibpost_r sart_r bfsh_r",
                                   coordinates="knee_angle_r ankle_angle_r") + REPORTERS
LOADED = """\t\t\t\t<ForceReporter name="ForceReporter"><on>true</on></ForceReporter>
\t\t\t\t<Actuation name="Actuation"><on>true</on></Actuation>
\t\t\t\t<Kinematics name="Kinematics"><on>true</on></Kinematics>
\t\t\t\t<BodyKinematics name="BodyKinematics"><on>true</on><bodies> pelvis calcn_r center_of_mass</bodies></BodyKinematics>
\t\t\t\t<PointKinematics name="heel"><on>true</on><body_name>calcn_r</body_name><point>0.01 0.02 -0.03</point><point_name>heel_r</point_name></PointKinematics>
\t\t\t\t<JointReaction name="JointReaction"><on>true</on><joint_names> hip_r knee_r ankle_r</joint_names><apply_on_bodies> child</apply_on_bodies><express_in_frame> child</express_in_frame></JointReaction>
"""
CASES = {
    "all": dict(range=(0.5, 0.6), cutoff=6, analyses=MUSCLES.format(step=1, muscles="all", coordinates="all")),
    "listed": dict(range=(0.5, 0.7), cutoff=-1, analyses=MUSCLES.format(step=2, muscles="vas_lat_r rect_fem_r no_such_muscle bifemlh_r",
                                                                         coordinates="knee_angle_r no_such_coordinate hip_flexion_r")),
    "kinematics": dict(range=(0.5, 0.6), cutoff=6, analyses=KINEMATICS.format(kinematics_name="Kinematics", bodies_name="BodyKinematics", step=1,
                                                                               in_degrees="true", coordinates="all", bodies="all", local="false")),
    "kinematics_listed": dict(range=(0.5, 0.7), cutoff=-1, analyses=KINEMATICS.format(kinematics_name="coords", bodies_name="segments", step=2, in_degrees="false",
                                                                                       coordinates="knee_angle_r pelvis_tx", bodies="tibia_r center_of_mass femur_r", local="true")),
    "points": dict(range=(0.5, 0.6), cutoff=6, analyses=POINTS),
    "muscle_states": dict(range=(0.5, 0.6), cutoff=6, analyses=GAIT_MUSCLES),
    "equilibrium": dict(range=(0.5, 0.6), cutoff=6, equilibrium=True, analyses=GAIT_MUSCLES),
    "millard": dict(range=(0.5, 0.6), cutoff=6, equilibrium=True, model="gait2392_millard2012muscle.osim", analyses=GAIT_MUSCLES),
    "rajagopal": dict(range=(0.5, 0.6), cutoff=6, equilibrium=True, model="Rajagopal2016_scaled.osim", analyses=RAJAGOPAL_MUSCLES),
    "loads": dict(range=(0.5, 0.6), cutoff=6, equilibrium=True, analyses=LOADED,
                  extra="\t\t<force_set_files> gait2392_SO_Residual_Actuators.xml</force_set_files>\n\t\t<replace_force_set>false</replace_force_set>\n"
                        "\t\t<external_loads_file>subject01_walk1_grf.xml</external_loads_file>\n"),
    "controls": dict(range=(0.5, 0.6), cutoff=6, equilibrium=True, analyses=LOADED,
                     extra="\t\t<force_set_files> gait2392_SO_Residual_Actuators.xml</force_set_files>\n\t\t<replace_force_set>false</replace_force_set>\n"
                           "\t\t<external_loads_file>subject01_walk1_grf.xml</external_loads_file>\n"
                           "\t\t<ControllerSet name=\"Controllers\"><objects>"
                           "<ControlSetController name=\"xml\"><controls_file>residual_controls.xml</controls_file></ControlSetController>"
                           "<ControlSetController name=\"sto\"><controls_file>residual_controls.sto</controls_file></ControlSetController>"
                           "</objects></ControllerSet>\n"),
    "states": dict(range=(0.05, 0.25), cutoff=-1, model="arm26.osim", analyses=ARM, states="arm26_states.sto"),
    "degroote": dict(range=(0.05, 0.25), cutoff=-1, model="arm26_degroote.osim", analyses=ARM, states="arm26_degroote_states.sto"),
    "degroote_equilibrium": dict(range=(0.2, 0.4), cutoff=-1, equilibrium=True, model="arm26_degroote.osim", analyses=ARM, coordinates="arm26_motion.mot"),
    "degroote_rigid": dict(range=(0.2, 0.4), cutoff=-1, equilibrium=True, model="arm26_degroote_rigid.osim", analyses=ARM, coordinates="arm26_motion.mot"),
    "states_legacy": dict(range=(0.05, 0.25), cutoff=-1, equilibrium=True, model="arm26.osim", analyses=ARM, states="arm26_states_legacy.sto"),
    "ball_free": dict(range=(0.0, 0.5), cutoff=-1, model="ball_free.osim", analyses=ARM, states="ball_free_states.sto"),
    "ellipsoid": dict(range=(0.0, 0.3), cutoff=-1, model="ellipsoid_joints.osim", analyses=ARM, states="ellipsoid_states.sto"),
    "ellipsoid_equilibrium": dict(range=(0.0, 0.3), cutoff=-1, equilibrium=True, model="ellipsoid_joints.osim", analyses=ARM, states="ellipsoid_states.sto"),
    "linked": dict(range=(0.0, 0.3), cutoff=-1, model="linked_mechanisms.osim", analyses=LINKED, states="linked_states.sto"),
}


STATE_CASES = ("muscle_states", "equilibrium", "millard", "rajagopal", "loads", "controls", "states", "states_legacy", "degroote", "degroote_equilibrium", "degroote_rigid", "ball_free", "ellipsoid", "ellipsoid_equilibrium", "linked")


def kept(case, table):
    """Whether OpenSim's table `table` (the file name without the tool and analysis names) is kept."""
    if case == "all":
        return table in KEPT
    if case == "listed" or case in STATE_CASES:
        return True
    return table in ("q", "u", "dudt", "pos_global", "vel_global", "vel_bodyLocal", "acc_global", "acc_bodyLocal") or table.endswith(("_pos", "_vel", "_acc"))


def setup_text(case):
    c = CASES[case]
    inputs = f"\t\t<states_file>{c['states']}</states_file>" if "states" in c else f"\t\t<coordinates_file>{c.get('coordinates', 'subject01_walk1_ik.mot')}</coordinates_file>"
    equilibrium = "\t\t<solve_for_equilibrium_for_auxiliary_states>true</solve_for_equilibrium_for_auxiliary_states>\n" if c.get("equilibrium") else ""
    return f"""<?xml version="1.0" encoding="UTF-8" ?>
<OpenSimDocument Version="40600">
\t<AnalyzeTool name="walk">
\t\t<model_file>{c.get('model', 'subject01_simbody.osim')}</model_file>
\t\t<results_directory>Results</results_directory>
\t\t<initial_time>{c['range'][0]}</initial_time>
\t\t<final_time>{c['range'][1]}</final_time>
{equilibrium}{c.get('extra', '')}\t\t<AnalysisSet name="Analyses">
\t\t\t<objects>
{c['analyses']}\t\t\t</objects>
\t\t</AnalysisSet>
{inputs}
\t\t<lowpass_cutoff_frequency_for_coordinates>{c['cutoff']}</lowpass_cutoff_frequency_for_coordinates>
\t</AnalyzeTool>
</OpenSimDocument>
"""


def simulate(model_file):
    """The states table of `model_file` simulated for 0.3 s from its equilibrated default state
    under constant excitations (0.1 to 0.6)."""
    model = osim.Model(str(INPUTS[model_file]))
    controller = osim.PrescribedController()
    for i in range(model.getActuators().getSize()):
        actuator = model.getActuators().get(i)
        controller.addActuator(actuator)
        controller.prescribeControlForActuator(actuator.getName(), osim.Constant(0.1 + 0.1 * i))
    model.addController(controller)
    state = model.initSystem()
    model.equilibrateMuscles(state)
    manager = osim.Manager(model)
    manager.setIntegratorAccuracy(1e-4)
    manager.initialize(state)
    manager.integrate(0.3)
    return manager.getStatesTable()


def write_states():
    """arm26's simulated states with OpenSim 4's labels and with OpenSim 3's, and arm26 with
    DeGroote muscles'."""
    (OUT / "degroote").mkdir(parents=True, exist_ok=True)
    osim.STOFileAdapter.write(simulate("arm26_degroote.osim"), str(OUT / "degroote" / "arm26_degroote_states.sto"))
    table = simulate("arm26.osim")
    for case, name in (("states", "arm26_states.sto"), ("states_legacy", "arm26_states_legacy.sto")):
        (OUT / case).mkdir(parents=True, exist_ok=True)
        osim.STOFileAdapter.write(table, str(OUT / case / name))
    legacy = OUT / "states_legacy" / "arm26_states_legacy.sto"
    lines = legacy.read_text().split("\n")
    header = lines.index("endheader") + 1

    def old_label(label):
        parts = label.split("/")
        if label.startswith("/jointset/"):
            return parts[3] if parts[4] == "value" else parts[3] + "_u"
        return label if label == "time" else parts[2] + "." + parts[3]

    lines[header] = "\t".join(old_label(l) for l in lines[header].split("\t"))
    legacy.write_text("\n".join(lines))


def control_linear(name, nodes, use_steps="false", extrapolate="true"):
    points = "".join(f"<ControlLinearNode><t>{t}</t><value>{v}</value></ControlLinearNode>" for t, v in nodes)
    return (f'<ControlLinear name="{name}"><extrapolate>{extrapolate}</extrapolate><use_steps>{use_steps}</use_steps>'
            f"<x_nodes>{points}</x_nodes></ControlLinear>")


def write_controls():
    """The residual actuators' controls of the `controls` case, as a ControlSet and a table."""
    folder = OUT / "controls"
    folder.mkdir(parents=True, exist_ok=True)
    controls = [
        control_linear("FX", [(0.45, 2.0), (0.55, -3.0), (0.65, 1.0)]),
        control_linear("FY", [(0.45, 1.0), (0.526, 4.0), (0.56, -2.0), (0.7, 3.0)], use_steps="true"),
        control_linear("FZ.excitation", [(0.40, 0.5), (0.55, 2.5)], extrapolate="false"),
        control_linear("MY", [(0.5, 1.5), (0.6, 0.5)]),
    ]
    (folder / "residual_controls.xml").write_text('<?xml version="1.0" encoding="UTF-8" ?>\n<OpenSimDocument Version="40600">\n'
                                                  f'<ControlSet name="residuals"><objects>{"".join(controls)}</objects></ControlSet>\n</OpenSimDocument>\n')
    rows = "".join(f"{t:.3f}\t{0.2 + 3 * t:.6f}\t{1 - t:.6f}\n" for t in (0.45, 0.5, 0.55, 0.6, 0.65))
    (folder / "residual_controls.sto").write_text(f"controls\nversion=1\nnRows=5\nnColumns=3\ninDegrees=no\nendheader\ntime\tMX\tMY\n{rows}")


def main():
    osim.Logger.setLevelString("error")
    wanted = sys.argv[1:]
    if not wanted:
        write_states()
        write_controls()
    for case in (c for c in CASES if not wanted or c in wanted):
        out = OUT / case
        out.mkdir(parents=True, exist_ok=True)
        (out / "setup.xml").write_text(setup_text(case))
        # An unnamed analysis' files: "walk__NONAME_pos.sto".
        run_setup(out, lambda name: kept(case, name.removeprefix("walk_").split("_", 1)[1].removesuffix(".sto")))
        print(case, "written", sorted(p.name for p in out.iterdir()))


def run_setup(out, keep):
    """Runs OpenSim's AnalyzeTool on `out`/setup.xml in a folder holding every input, writes the
    names of the files it wrote to `out`/files.txt and copies those `keep(name)` accepts."""
    with tempfile.TemporaryDirectory() as work:
        work = Path(work)
        for name, source in INPUTS.items():
            shutil.copy(source, work / name)
        shutil.copy(MOTION, work / "subject01_walk1_ik.mot")
        shutil.copy(out / "setup.xml", work / "setup.xml")
        run_in(work, osim.AnalyzeTool, "setup.xml")
        written = sorted(p.name for p in (work / "Results").iterdir())
        (out / "files.txt").write_text("\n".join(written) + "\n")
        for name in written:
            if keep(name):
                shutil.copy(work / "Results" / name, out / name)


if __name__ == "__main__":
    main()

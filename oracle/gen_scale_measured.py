"""OpenSim 4.6's ScaleTool by measurements, with MarkerPlacer, on leg6dof9musc and a synthetic
static trial: writes fixtures/golden/scale_measured/ (setup, trial, OpenSim's outputs), and
again with a `from_file` coordinate task in the MarkerPlacer following `coordinates.mot`
(setup_from_file.xml, OpenSim's placed_from_file.osim and static_pose_from_file.mot).

The trial: leg6dof9musc scaled by anisotropic factors per body (the 'subject'), held near one
pose for 6 frames at 60 Hz (each coordinate wobbling by <= 0.01 rad or m), its 12 markers read
in ground and given seeded Gaussian noise of 1.5 mm, written in mm. The setup measures marker
pairs within and across bodies, scales the patella with the femur and the toes with the foot,
and places the markers by IK over the whole trial (one task weighted 10, one not applied).
Run from the repository root: python3 oracle/gen_scale_measured.py
"""
import math
import random
from pathlib import Path

import opensim as osim

from gen_scale_zoo import run_scale_tool

MODEL = Path("fixtures/models/leg6dof9musc.osim")
OUT = Path("fixtures/golden/scale_measured")
SUBJECT_FACTORS = {"pelvis": (1.06, 1.03, 1.09), "femur_r": (1.04, 1.11, 1.02), "patella_r": (1.04, 1.11, 1.02),
                   "tibia_r": (0.97, 1.08, 1.01), "talus_r": (0.97, 1.08, 1.01), "calcn_r": (1.05, 0.98, 1.03),
                   "toes_r": (1.05, 0.98, 1.03)}
POSE = {"pelvis_tilt": 0.05, "pelvis_tx": 0.1, "pelvis_ty": 0.98, "hip_flexion_r": 0.2, "knee_angle_r": -0.3, "ankle_angle_r": 0.1}
MEASUREMENTS = [
    ("pelvis", [("R.ASIS", "L.ASIS"), ("R.ASIS", "V.Sacral"), ("L.ASIS", "V.Sacral")], ["pelvis"], "X Y Z"),
    ("thigh", [("R.ASIS", "R.Thigh.Rear"), ("R.Thigh.Upper", "R.Thigh.Front")], ["femur_r", "patella_r"], "X Y Z"),
    ("shank", [("R.Shank.Upper", "R.Shank.Rear"), ("R.Shank.Front", "R.Shank.Rear")], ["tibia_r", "talus_r"], "X Y Z"),
    ("foot", [("R.Heel", "R.Toe.Tip")], ["calcn_r", "toes_r"], "X"),
    ("foot_width", [("R.Heel", "R.Midfoot.Lat")], ["calcn_r", "toes_r"], "Y Z"),
]


def subject_markers():
    model = osim.Model(str(MODEL))
    state = model.initSystem()
    scales = osim.ScaleSet()
    for body, factors in SUBJECT_FACTORS.items():
        scale = osim.Scale()
        scale.setSegmentName(body)
        scale.setScaleFactors(osim.Vec3(*factors))
        scale.setApply(True)
        scales.cloneAndAppend(scale)
    model.scale(state, scales, True, -1.0)
    state = model.initSystem()
    rng = random.Random(20261122)
    frames = []
    for k in range(6):
        for name, value in POSE.items():
            model.getCoordinateSet().get(name).setValue(state, value + 0.01 * math.sin(k + len(name)), False)
        model.assemble(state)
        model.realizePosition(state)
        markers = model.getMarkerSet()
        frames.append([[1000.0 * (markers.get(i).getLocationInGround(state)[j] + rng.gauss(0.0, 0.0015)) for j in range(3)]
                       for i in range(markers.getSize())])
    names = [model.getMarkerSet().get(i).getName() for i in range(model.getMarkerSet().getSize())]
    return names, frames


def write_trc(path, names, frames):
    rate = 60.0
    lines = [f"PathFileType\t4\t(X/Y/Z)\t{path.name}",
             "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\tOrigNumFrames",
             f"{rate:.1f}\t{rate:.1f}\t{len(frames)}\t{len(names)}\tmm\t{rate:.1f}\t1\t{len(frames)}",
             "Frame#\tTime\t" + "\t\t\t".join(names) + "\t\t",
             "\t\t" + "\t".join(f"X{i + 1}\tY{i + 1}\tZ{i + 1}" for i in range(len(names))), ""]
    for k, frame in enumerate(frames):
        lines.append(f"{k + 1}\t{k / rate:.6f}\t" + "\t".join(f"{v:.5f}" for p in frame for v in p))
    path.write_text("\n".join(lines) + "\n")


def measurement_xml(name, pairs, bodies, axes):
    """A `<Measurement>` of marker `pairs` scaling `bodies` along `axes` (e.g. "X Y Z")."""
    pair_xml = "".join(f"<MarkerPair><markers> {a} {b}</markers></MarkerPair>" for a, b in pairs)
    body_xml = "".join(f"<BodyScale name=\"{b}\"><axes> {axes}</axes></BodyScale>" for b in bodies)
    return (f"<Measurement name=\"{name}\"><apply>true</apply><MarkerPairSet><objects>{pair_xml}</objects></MarkerPairSet>"
            f"<BodyScaleSet><objects>{body_xml}</objects></BodyScaleSet></Measurement>\n")


def measured_scale_setup(tool, mass, model_file, measurements, trial_file, time_range, output, placer=""):
    """A ScaleTool setup scaling by `measurements` (XML) with mass distribution preserved, then
    `placer` (a `<MarkerPlacer>` element, or none)."""
    return f"""<?xml version="1.0" encoding="UTF-8" ?>
<OpenSimDocument Version="40000">
<ScaleTool name="{tool}">
<mass>{mass}</mass>
<GenericModelMaker><model_file>{model_file}</model_file></GenericModelMaker>
<ModelScaler>
<apply>true</apply>
<scaling_order> measurements</scaling_order>
<MeasurementSet><objects>
{measurements}</objects></MeasurementSet>
<marker_file>{trial_file}</marker_file>
<time_range> {time_range}</time_range>
<preserve_mass_distribution>true</preserve_mass_distribution>
<output_model_file>{output}</output_model_file>
</ModelScaler>
{placer}</ScaleTool>
</OpenSimDocument>
"""


def setup_xml(model_file, names, from_file=False):
    """The setup; `from_file`: its MarkerPlacer also pulls knee_angle_r toward
    FROM_FILE_COORDINATES (weight 5) over 0.05–0.1 s, with its outputs named `*_from_file`."""
    def task(name):
        weight = 10.0 if name == "R.Toe.Tip" else 1.0
        apply = "false" if name == "R.Midfoot.Lat" else "true"
        return f"<IKMarkerTask name=\"{name}\"><apply>{apply}</apply><weight>{weight}</weight></IKMarkerTask>\n"
    knee = "<IKCoordinateTask name=\"knee_angle_r\"><apply>true</apply><weight>5</weight><value_type>from_file</value_type></IKCoordinateTask>\n"
    suffix = "_from_file" if from_file else ""
    placer = f"""<MarkerPlacer>
<apply>true</apply>
<IKTaskSet><objects>
{"".join(task(n) for n in names)}{knee if from_file else ""}</objects></IKTaskSet>
<marker_file>static.trc</marker_file>
{"<coordinate_file>" + FROM_FILE_COORDINATES + "</coordinate_file>" + chr(10) if from_file else ""}<time_range> {"0.05" if from_file else "0"} 0.1</time_range>
<output_motion_file>static_pose{suffix}.mot</output_motion_file>
<output_model_file>placed{suffix}.osim</output_model_file>
<max_marker_movement>-1</max_marker_movement>
</MarkerPlacer>
"""
    measurements = "".join(measurement_xml(*m) for m in MEASUREMENTS)
    return measured_scale_setup("leg6dof9musc_subject", 28.5, model_file, measurements, "static.trc", "0 0.1", "scaledOnly.osim", placer)


FROM_FILE_COORDINATES = "coordinates.mot"


def write_coordinates(path):
    """knee_angle_r over 0–0.2 s, −40° + 150°/s·t, in degrees: the placer evaluates it at its
    time range's start."""
    rows = [f"{0.02 * k:.2f}\t{-40.0 + 150.0 * 0.02 * k:.6f}\t{10.0:.6f}" for k in range(11)]
    header = ["Coordinates", "version=1", f"nRows={len(rows)}", "nColumns=3", "inDegrees=yes", "endheader",
              "time\tknee_angle_r\thip_flexion_r"]
    path.write_text("\n".join(header + rows) + "\n")


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    names, frames = subject_markers()
    write_trc(OUT / "static.trc", names, frames)
    run_scale_tool(setup_xml(MODEL.name, names), [MODEL, OUT / "static.trc"],
                   {name: OUT / name for name in ["scaledOnly.osim", "placed.osim", "static_pose.mot"]})
    (OUT / "setup.xml").write_text(setup_xml("../../models/leg6dof9musc.osim", names))
    write_coordinates(OUT / FROM_FILE_COORDINATES)
    run_scale_tool(setup_xml(MODEL.name, names, from_file=True), [MODEL, OUT / "static.trc", OUT / FROM_FILE_COORDINATES],
                   {name: OUT / name for name in ["placed_from_file.osim", "static_pose_from_file.mot"]})
    (OUT / "setup_from_file.xml").write_text(setup_xml("../../models/leg6dof9musc.osim", names, from_file=True))
    print("written", sorted(p.name for p in OUT.iterdir()))


if __name__ == "__main__":
    main()

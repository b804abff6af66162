"""OpenSim 4.6's ScaleTool (manual scale factors; no MarkerPlacer element, since a
MarkerPlacer with apply false makes ScaleTool.run() return false) on the example models
leg6dof9musc, joint_zoo, Rajagopal2016 (42 muscles wrapping over WrapCylinders), arm26
(TRIlong and BIClong also over WrapEllipsoids), wrap_zoo (spheres, ellipsoids, tori) and
ellipsoid_joints (a ScapulothoracicJoint's thoracic radii and winging origin, an EllipsoidJoint's
radii) and station_frames (the stations of StationDefinedFrames), and on the 2.x/3.x documents of
arm26, leg6dof9musc and the abdbonepin shoulder model (which OpenSim converts to its 4.x format as
it loads them): writes fixtures/golden/scale_zoo/<model>_setup.xml and <model>_scaled.osim.

Each body gets anisotropic factors in 0.90-1.12 that differ from body to body, drawn from a
seeded generator; the subject mass is 1.15 x the model's, with the mass distribution preserved for
leg6dof9musc, Rajagopal2016, arm26 and wrap_zoo and the masses scaled with the volumes for
joint_zoo.
Run from the repository root: python3 oracle/gen_scale_zoo.py [model ...] (only the named models)
"""
import random
import shutil
import sys
import tempfile
from pathlib import Path

import opensim as osim
from tool_run import run_in

MODELS = ["leg6dof9musc", "joint_zoo", "Rajagopal2016", "arm26", "wrap_zoo", "ellipsoid_joints", "station_frames",
          "arm26_v20303", "leg6dof9musc_v20303", "abdbonepin_v30000"]
# Models outside fixtures/models, by their path under fixtures/.
SOURCES = {"arm26_v20303": "legacy/arm26_v20303.osim", "leg6dof9musc_v20303": "legacy/leg6dof9musc_v20303.osim",
           "abdbonepin_v30000": "ik_point_constraint/subject1_abdbonepin.osim"}
OUT = Path("fixtures/golden/scale_zoo")


def setup_xml(model_file, bodies, mass, preserve, output):
    rng = random.Random(len(bodies) * 1000 + int(mass))
    scales = "".join(
        "\t\t\t\t\t<Scale>\n\t\t\t\t\t\t<scales> %.4f %.4f %.4f</scales>\n\t\t\t\t\t\t<segment>%s</segment>\n"
        "\t\t\t\t\t\t<apply>true</apply>\n\t\t\t\t\t</Scale>\n"
        % (rng.uniform(0.9, 1.12), rng.uniform(0.9, 1.12), rng.uniform(0.9, 1.12), body)
        for body in bodies)
    return f"""<?xml version="1.0" encoding="UTF-8" ?>
<OpenSimDocument Version="40000">
\t<ScaleTool name="zoo">
\t\t<mass>{mass:.6f}</mass>
\t\t<GenericModelMaker>
\t\t\t<model_file>{model_file}</model_file>
\t\t</GenericModelMaker>
\t\t<ModelScaler>
\t\t\t<apply>true</apply>
\t\t\t<scaling_order> manualScale</scaling_order>
\t\t\t<ScaleSet>
\t\t\t\t<objects>
{scales}\t\t\t\t</objects>
\t\t\t</ScaleSet>
\t\t\t<preserve_mass_distribution>{"true" if preserve else "false"}</preserve_mass_distribution>
\t\t\t<output_model_file>{output}</output_model_file>
\t\t</ModelScaler>
\t</ScaleTool>
</OpenSimDocument>
"""


def run_scale_tool(setup_text, inputs, outputs):
    """Runs ScaleTool on `setup_text` in a temporary folder holding copies of `inputs` (paths),
    then copies its outputs {name in that folder: destination}."""
    with tempfile.TemporaryDirectory() as work:
        work = Path(work)
        for path in inputs:
            shutil.copy(path, work / Path(path).name)
        (work / "setup.xml").write_text(setup_text)
        run_in(work, osim.ScaleTool, "setup.xml")
        for name, destination in outputs.items():
            shutil.copy(work / name, destination)


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    for name in sys.argv[1:] or MODELS:
        source = Path("fixtures") / SOURCES.get(name, f"models/{name}.osim")
        model = osim.Model(str(source))
        model.initSystem()
        bodies = [model.getBodySet().get(i).getName() for i in range(model.getBodySet().getSize())]
        mass = sum(model.getBodySet().get(i).getMass() for i in range(model.getBodySet().getSize()))
        preserve = name != "joint_zoo"
        run_scale_tool(setup_xml(source.name, bodies, 1.15 * mass, preserve, "scaled.osim"), [source],
                       {"scaled.osim": OUT / f"{name}_scaled.osim"})
        (OUT / f"{name}_setup.xml").write_text(setup_xml("../../" + SOURCES.get(name, f"models/{name}.osim"), bodies, 1.15 * mass, preserve, f"{name}_scaled.osim"))
        print(name, len(bodies), "bodies, mass", mass)


if __name__ == "__main__":
    main()

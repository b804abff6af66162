#!/usr/bin/env python3
"""Models as OpenSim 4.6's API writes them, for the model reader:

- fixtures/models/leg6dof9musc_crank.osim: OpenSim's leg6dof9musc example (a knee whose
  translations follow splines of its angle, a patella coupled to it) with a dynamometer crank
  added as a lab would add one: a body `crank` (2 kg) on a PinJoint `crank_joint` to ground
  about the ground's z axis through (0, 0.45, 0.1) m, its origin 0.25 m from the axis. OpenSim
  writes the new coordinate `crank_angle`, whose properties all have their defaults, as an
  empty element.
- fixtures/models/sliding_mass.osim: `ModelFactory.createSlidingPointMass()` (Moco's example),
  whose body and joint `Model::addComponent` put in the model's `<components>`, not in the sets,
  with a Millard muscle from ground to the mass added there too.
- fixtures/models/sliding_mass_components.osim: the same with a second mass coupled to the
  first, a marker, a CoordinateLimitForce and the CoordinateCouplerConstraint, all in
  `<components>`; fixtures/golden/model_components.json: the marker in ground at position 0.3 m.

    python3 oracle/gen_api_models.py
"""
import json
from pathlib import Path

import opensim as osim

REPO = Path(__file__).resolve().parent.parent


def main():
    model = osim.Model(str(REPO / "fixtures" / "models" / "leg6dof9musc.osim"))
    crank = osim.Body("crank", 2.0, osim.Vec3(0.02, -0.01, 0.015), osim.Inertia(0.004, 0.02, 0.021, 0.0005, 0.0002, 0.0001))
    model.addBody(crank)
    joint = osim.PinJoint("crank_joint", model.getGround(), osim.Vec3(0.0, 0.45, 0.1), osim.Vec3(0, 0, 0), crank, osim.Vec3(-0.25, 0, 0), osim.Vec3(0, 0, 0))
    joint.updCoordinate().setName("crank_angle")
    model.addJoint(joint)
    model.finalizeConnections()
    write(model, "leg6dof9musc_crank.osim")
    sliding = osim.ModelFactory.createSlidingPointMass()
    sliding.finalizeFromProperties()
    muscle = osim.Millard2012EquilibriumMuscle("muscle", 100.0, 0.1, 0.2, 0.0)
    muscle.addNewPathPoint("origin", sliding.getGround(), osim.Vec3(-0.29, 0, 0))
    muscle.addNewPathPoint("insertion", osim.PhysicalFrame.safeDownCast(sliding.getComponent("/body")), osim.Vec3(0, 0, 0))
    sliding.addComponent(muscle)
    sliding.finalizeConnections()
    state = sliding.initSystem()
    print(f"sliding_mass: the muscle's path is {muscle.getLength(state)} m at position 0")
    write(sliding, "sliding_mass.osim")
    components_model()


def components_model():
    """createSlidingPointMass with a second mass coupled to the first (follower = 2·position),
    a marker, a CoordinateLimitForce and the coupler, all through `Model::addComponent`; the
    marker's location in ground at position 0.3 m goes to the golden."""
    model = osim.ModelFactory.createSlidingPointMass()
    model.finalizeFromProperties()
    follower = osim.Body("follower", 0.5, osim.Vec3(0), osim.Inertia(0))
    model.addComponent(follower)
    slider = osim.SliderJoint("follower_slider", model.getGround(), osim.Vec3(0, 0.1, 0), osim.Vec3(0), follower, osim.Vec3(0), osim.Vec3(0))
    slider.updCoordinate().setName("follower_position")
    model.addComponent(slider)
    marker = osim.Marker("tip", follower, osim.Vec3(0.05, 0.02, 0))
    model.addComponent(marker)
    limit = osim.CoordinateLimitForce("position", 0.5, 100.0, -0.5, 100.0, 1.0, 0.01)
    limit.setName("position_limit")
    model.addComponent(limit)
    coupling = osim.LinearFunction(2.0, 0.0)
    independent = osim.ArrayStr()
    independent.append("position")
    coupler = osim.CoordinateCouplerConstraint()
    coupler.setName("follower_coupler")
    coupler.setIndependentCoordinateNames(independent)
    coupler.setDependentCoordinateName("follower_position")
    coupler.setFunction(coupling)
    model.addComponent(coupler)
    model.finalizeConnections()
    state = model.initSystem()
    coordinates = model.getCoordinateSet()
    coordinates.get("position").setValue(state, 0.3, False)
    coordinates.get("follower_position").setValue(state, 2.0 * 0.3, False)
    model.realizePosition(state)
    assert abs(state.getQErr().get(0)) < 1e-15, "the coupler holds"
    tip = marker.getLocationInGround(state)
    write(model, "sliding_mass_components.osim")
    golden = REPO / "fixtures" / "golden" / "model_components.json"
    golden.write_text(json.dumps({"position": 0.3, "follower_position": coordinates.get("follower_position").getValue(state), "tip_in_ground": [tip.get(i) for i in range(3)]}, indent=1) + "\n")
    print(f"{golden.relative_to(REPO)}: done")


def write(model, name):
    out = REPO / "fixtures" / "models" / name
    model.printToXML(str(out))
    print(f"{out.relative_to(REPO)}: done")


if __name__ == "__main__":
    main()

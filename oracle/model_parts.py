"""Pieces the model-building generators share (not a generator)."""
import opensim as osim


def add_millard_muscle(model, name, max_force, optimal_length, slack_length, pennation, points):
    """A Millard2012EquilibriumMuscle through `points` — (point name, frame, Vec3 location) in
    path order — added to `model`."""
    muscle = osim.Millard2012EquilibriumMuscle(name, max_force, optimal_length, slack_length, pennation)
    for point, frame, location in points:
        muscle.addNewPathPoint(point, frame, location)
    model.addForce(muscle)


def write_model(model, path):
    """Connects `model`'s sockets and prints it to `path`."""
    model.finalizeConnections()
    model.printToXML(str(path))

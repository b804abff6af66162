#!/usr/bin/env python3
"""Forward-simulation goldens: OpenSim 4.6 integrates the muscle states (activation, fiber length)
of a model whose every coordinate follows a prescribed motion, its muscles driven by prescribed
excitations.

    python3 oracle/gen_forward_simulation.py [case ...]

With no argument every case below is generated; naming cases generates only those.

Each case writes fixtures/golden/forward/<case>/ with the inputs it used, so a test can rebuild
them from the folder alone, and OpenSim's result:

* `motion.mot` — the coordinate samples (time, then one column per coordinate, degrees for the
  rotational ones, inDegrees=yes). Each unlocked coordinate the motion names is prescribed
  (`Coordinate::setPrescribedFunction`, `setDefaultIsPrescribed(true)`) by a quintic GCVSpline
  with error variance 0 (`GCVSpline(5, n, times, values)`, built here from its XML so it is exactly
  the spline a model file would give) through these samples, degrees turned into radians by
  `math.radians` (x · π/180); an unlocked coordinate the motion lacks would be held at its default
  value (`Constant`); locked coordinates stay locked, coordinates a CoordinateCouplerConstraint
  makes dependent are left to it (arm26 and gait2392_millard have none of these three, rajagopal
  all three).
* `excitations.sto` — OpenSim storage (header ending `endheader`, then `time` and one column per
  muscle, named after it): each muscle's excitation, interpolated piecewise linearly
  (`PiecewiseLinearFunction`) by a `PrescribedController` driving every muscle.
* `states.csv` — comma-separated, one header row, numbers as Python's repr (17 significant
  digits survive): `time`; for each muscle in ForceSet order `<muscle>.activation`,
  `<muscle>.fiber_length` (m) and `<muscle>.tendon_force` (N); then for each unlocked coordinate
  in CoordinateSet order `<coordinate>.muscle_moment` = Σ over muscles of tendon force × moment
  arm (N·m, or N for a translation). A coupler's dependent coordinate is unlocked and has its
  column: the MomentArmSolver's coupling vector is divided by that coordinate's own speed, so
  rajagopal's `knee_angle_r_beta`/`knee_angle_l_beta` columns equal `knee_angle_r`/`knee_angle_l`'s
  (within 1.4e-13). For a rigid-tendon Millard muscle (`ignore_tendon_compliance`) the fiber
  length is not a state but the one its path length implies.

The simulation: `initSystem`, time set to the first motion time t0, every prescribed coordinate's
value and speed set to its spline's value and first derivative at t0, each coupler's dependent
coordinate's value and speed to the coupler's (q_d = s·f(q_i), q̇_d = s·Σ ∂f/∂q_i q̇_i, s its
scale_factor; Millard's equilibrium is static, so the speed only keeps the state consistent),
each muscle's activation set to its excitation at t0, `equilibrateMuscles`; then a `Manager`
with the RungeKuttaMerson integrator, accuracy 1e-10 (constraint tolerance left at its default),
`initialize`, and `integrate(t)` for each report time t of a 10 ms grid from t0 (each call
continuing from the last), the state realized to Dynamics at each report time (t0 included). The
moment arms come from `computeMomentArm` on a second, unprescribed copy of the model posed at the
simulated q (the whole Q vector, dependent coordinates included): OpenSim's MomentArmSolver
projects speeds onto the model's constraints to find the coordinates' coupling, and on the
prescribed model those constraints are the prescribed motions themselves, which would spoil the
coupling.

Cases:

* `arm26` — fixtures/models/arm26.osim (6 Thelen2003Muscles, paths wrapping over cylinders and
  ellipsoids); a synthetic motion at 100 Hz over 0–1 s, degrees: r_shoulder_elev =
  56 + 12 sin(2πt), r_elbow_flex = 70 + 45 sin(2π·1.5t + 0.3) (gen_static_optimization.py's elbow;
  its shoulder, 30 + 25 sin(2πt), cannot be simulated: OpenSim's hybrid ellipsoid wraps make
  BIClong's force directions NaN at shoulder 31.26° (and 91.14°) — the integrator lands there
  and every state turns NaN — and its length jump by 8.7 cm at 29.50° and 29.64°, by 1.7 mm at
  31.27°, TRIlong's by 2 mm at 41.61° and 2.7 mm at 70.83°; 44–68° stays between them, the
  paths there moving by at most 1.4 µm jumps); excitations at the same 101 times, muscle
  k = 0, 1, … (ForceSet order) u = 0.4 + 0.3 sin(2π(1 + 0.25k)t + k); report times
  0, 0.01, …, 1.
* `arm26_degroote` — arm26 with its muscles replaced by DeGrooteFregly2016Muscles
  (`DeGrooteFregly2016Muscle.replaceMuscles`: F_max, L_opt, L_ts, pennation, v_max and the time
  constants τ_a = 0.01 s, τ_d = 0.04 s kept; compliant tendons in OpenSim's default explicit mode,
  whose state is the normalized tendon force; fiber damping 0; activation_dynamics_smoothing
  0.1), written to fixtures/models/arm26_degroote.osim; arm26's motion, excitations and report
  times. OpenSim 4.6 reads a DeGroote muscle's τ_a, τ_d and smoothing into function-local
  statics, so all its DeGroote muscles use the first one's: the script checks they are equal.
  Its equilibrateMuscles bisects the normalized tendon force (to 1e-10) for the implicit
  residual with the path's lengthening speed and a zero tendon-force derivative.
* `arm26_degroote_rigid` — the same with rigid tendons (`ignore_tendon_compliance`), written to
  fixtures/models/arm26_degroote_rigid.osim: the fiber follows the path and its force takes the
  path's lengthening speed.
* `gait2392_millard` — models/gait2392_millard2012muscle.osim (the generic, unscaled gait2392 with
  92 Millard2012EquilibriumMuscles, compliant tendons, fiber damping 0.1); the subject01 walk's IK
  golden (fixtures/golden/ik/subject01_walk1_ik.mot, all 23 coordinates, ≈60 Hz), only its rows
  from 0.1 s (first time + 0.1 s) to 0.4 s inclusive (19 rows); excitations at those rows' times,
  muscle k u = 0.3 + 0.2 sin(2π(1 + 0.05k)(t − t0) + 0.7k) with t0 = 0.1 s; report times 0.10,
  0.11, …, 0.40.
* `rajagopal` — fixtures/models/Rajagopal2016.osim (80 Millard2012EquilibriumMuscles, 34 of them
  with rigid tendons (`ignore_tendon_compliance`), fiber damping 0.1; the patellae's
  knee_angle_r_beta and knee_angle_l_beta follow the knees by CoordinateCouplerConstraints
  (linear, slope 1), the quadriceps' paths run over the patellae; the gastrocnemii wrap over two
  cylinders each; subtalar, mtp and wrist coordinates locked; its 17 CoordinateActuators get no
  control); a synthetic motion at 100 Hz over 0–0.5 s, degrees: hip_flexion_r =
  20 + 25 sin(2π·1.2t), knee_angle_r = 40 + 35 sin(2π·1.5t + 0.4), ankle_angle_r =
  5 + 12 sin(2π·1.8t + 1.0), the left ones the same with π added inside each sine (within the
  ranges, checked: hip −5…45° of −30…120°, knee 5…75° of 0…120°, ankle −7…17° of −40…30°); the
  other unlocked coordinates held at their defaults (pelvis_ty 0.94 m, the rest 0); excitations at
  the 51 motion times, muscle k u = 0.3 + 0.2 sin(2π(1 + 0.04k)t + 0.9k); report times 0, 0.01,
  …, 0.5.

After writing a case the script reruns it with accuracy 1e-12 (nothing written) and prints the
largest differences in activation, fiber length, tendon force and muscle moment between the two
runs — OpenSim's own integration error — with each run's wall time. At generation (OpenSim 4.6):
arm26 3.9e-9 (activation), 3.0e-9 m, 1.0e-3 N, 2.3e-5 N·m, 1.4 s; gait2392_millard 3.5e-8,
2.5e-9 m, 4.2e-4 N, 1.7e-5 N·m, 26 s; rajagopal 3.5e-7, 1.4e-8 m, 1.3e-3 N, 6.3e-5 N·m, 46 s
(105 s at 1e-12); the coordinates follow their splines within 5e-12, rajagopal's patellae their
knees within 2.6e-12 (values and speeds). In the gait case semimem_r sits at its minimum fiber
length with a slack tendon (tendon force 0) from 0.10 to 0.35 s, and lat_gas_r's tendon is slack
(force 0) from 0.15 to 0.20 s; the pelvis coordinates' muscle moments are rounding (< 1e-12).
In the rajagopal case no fiber reaches its minimum length, no compliant tendon goes slack and no
rigid tendon is shorter than its slack length (tendon forces 22–3704 N); its largest activation
difference is addmagIsch_l's at 0.05 s, just after its excitation fell below its activation,
where Millard's activation time constant jumps (the activation form for u > a, the deactivation
form otherwise). OpenSim's moment arms of gaslat and gasmed about the knee (each wrapping over
Gastroc_at_condyles on the femur and a Gas*_at_shank cylinder on the tibia) differ from
−∂(path length)/∂q by up to 0.016 m at some of the poses, and their unit-tension forces do not
balance there: the pelvis rotations' muscle moments reach 0.34 N·m (the translations' are
rounding, < 3e-13).
"""
import math
import sys
import time
from pathlib import Path

import opensim as osim

from gen_functions import load_xml

REPO = Path(__file__).resolve().parent.parent
OUT = REPO / "fixtures" / "golden" / "forward"
IK_MOTION = REPO / "fixtures" / "golden" / "ik" / "subject01_walk1_ik.mot"
RAJAGOPAL = REPO / "fixtures" / "models" / "Rajagopal2016.osim"
ACCURACY = 1e-10
CHECK_ACCURACY = 1e-12


def numbers(values):
    return " ".join(repr(float(v)) for v in values)


def gcv_spline(times, values):
    """GCVSpline(5, n, times, values): quintic (half order 3), error variance 0."""
    return load_xml(f"<GCVSpline><half_order>3</half_order><error_variance>0.0</error_variance>"
                         f"<x>{numbers(times)}</x><y>{numbers(values)}</y></GCVSpline>")


def piecewise_linear(times, values):
    return load_xml(f"<PiecewiseLinearFunction><x>{numbers(times)}</x><y>{numbers(values)}</y></PiecewiseLinearFunction>")


def write_table(path, name, labels, times, columns, in_degrees):
    """OpenSim storage: tab-separated, time first, every number as its repr."""
    rows = ["\t".join(repr(float(v)) for v in [t] + [c[i] for c in columns]) for i, t in enumerate(times)]
    header = (f"{name}\nversion=1\nnRows={len(rows)}\nnColumns={len(labels) + 1}\n"
              f"inDegrees={'yes' if in_degrees else 'no'}\nendheader\n")
    path.write_text(header + "\t".join(["time"] + labels) + "\n" + "\n".join(rows) + "\n")


def read_table(path):
    """(labels without time, times, columns, inDegrees) of an OpenSim .mot/.sto."""
    lines = path.read_text().splitlines()
    end = next(i for i, line in enumerate(lines) if line.strip() == "endheader")
    in_degrees = any(line.strip().lower() == "indegrees=yes" for line in lines[:end])
    labels = lines[end + 1].split("\t")
    assert labels[0].strip() == "time", labels[0]
    rows = [[float(v) for v in line.split()] for line in lines[end + 2:] if line.strip()]
    times = [r[0] for r in rows]
    columns = [[r[j] for r in rows] for j in range(1, len(labels))]
    return [label.strip() for label in labels[1:]], times, columns, in_degrees


def arm26_inputs(folder):
    times = [k / 100 for k in range(101)]
    shoulder = [56 + 12 * math.sin(2 * math.pi * t) for t in times]
    elbow = [70 + 45 * math.sin(2 * math.pi * 1.5 * t + 0.3) for t in times]
    write_table(folder / "motion.mot", "arm26_motion", ["r_shoulder_elev", "r_elbow_flex"], times, [shoulder, elbow], True)
    model = osim.Model(str(REPO / "fixtures" / "models" / "arm26.osim"))
    muscles = [model.getMuscles().get(i).getName() for i in range(model.getMuscles().getSize())]
    excitations = [[0.4 + 0.3 * math.sin(2 * math.pi * (1 + 0.25 * k) * t + k) for t in times] for k in range(len(muscles))]
    write_table(folder / "excitations.sto", "arm26_excitations", muscles, times, excitations, False)
    return times


def arm26_degroote_model(rigid=False):
    """arm26 with DeGroote–Fregly muscles (with rigid tendons if `rigid`), printed to
    fixtures/models/arm26_degroote.osim (arm26_degroote_rigid.osim)."""
    model = osim.Model(str(REPO / "fixtures" / "models" / "arm26.osim"))
    osim.DeGrooteFregly2016Muscle.replaceMuscles(model)
    name = "arm26_degroote_rigid" if rigid else "arm26_degroote"
    model.setName(name)
    model.finalizeConnections()
    muscles = model.getMuscles()
    constants = set()
    for i in range(muscles.getSize()):
        muscle = osim.DeGrooteFregly2016Muscle.safeDownCast(muscles.get(i))
        constants.add((muscle.get_activation_time_constant(), muscle.get_deactivation_time_constant(), muscle.get_activation_dynamics_smoothing()))
        muscle.set_ignore_tendon_compliance(rigid)
    assert len(constants) == 1, f"OpenSim would use the first muscle's time constants for all: {constants}"
    path = REPO / "fixtures" / "models" / f"{name}.osim"
    model.printToXML(str(path))
    return path


def gait_inputs(folder, start=0.1, length=0.3):
    labels, times, columns, in_degrees = read_table(IK_MOTION)
    assert in_degrees
    t0 = times[0] + start
    t1 = t0 + length
    keep = [i for i, t in enumerate(times) if t0 - 1e-9 <= t <= t1 + 1e-9]
    times = [times[i] for i in keep]
    assert abs(times[0] - t0) < 1e-9 and abs(times[-1] - t1) < 1e-9, (times[0], times[-1])
    t0 = times[0]
    write_table(folder / "motion.mot", "subject01_walk1_ik_window", labels, times,
                [[c[i] for i in keep] for c in columns], True)
    model = osim.Model(str(REPO / "models" / "gait2392_millard2012muscle.osim"))
    muscles = [model.getMuscles().get(i).getName() for i in range(model.getMuscles().getSize())]
    excitations = [[0.3 + 0.2 * math.sin(2 * math.pi * (1 + 0.05 * k) * (t - t0) + 0.7 * k) for t in times]
                   for k in range(len(muscles))]
    write_table(folder / "excitations.sto", "gait2392_millard_excitations", muscles, times, excitations, False)
    first = round(t0 * 100)
    last = round(t1 * 100)
    return [k / 100 for k in range(first, last + 1)]


def couplers(model):
    """The model's CoordinateCouplerConstraints."""
    constraints = model.getConstraintSet()
    found = [osim.CoordinateCouplerConstraint.safeDownCast(constraints.get(i)) for i in range(constraints.getSize())]
    return [coupler for coupler in found if coupler is not None]


def coupled(model, state, coupler):
    """(value, speed) of the coupler's dependent coordinate at the state's independent values and
    speeds: q_d = s·f(q_i), q̇_d = s·Σ ∂f/∂q_i q̇_i (s its scale_factor)."""
    names = coupler.getIndependentCoordinateNames()
    independents = [model.getCoordinateSet().get(names.get(j)) for j in range(names.getSize())]
    x = osim.Vector(len(independents), 0.0)
    for j, coordinate in enumerate(independents):
        x.set(j, coordinate.getValue(state))
    scale = osim.PropertyHelper.getValueDouble(coupler.getPropertyByName("scale_factor"))
    f = coupler.getFunction()
    speed = sum(f.calcDerivative(osim.StdVectorInt([j]), x) * coordinate.getSpeedValue(state)
                for j, coordinate in enumerate(independents))
    return scale * f.calcValue(x), scale * speed


def rajagopal_inputs(folder):
    times = [k / 100 for k in range(51)]
    labels, columns = [], []
    for side, phase in [("r", 0.0), ("l", math.pi)]:
        labels += [f"hip_flexion_{side}", f"knee_angle_{side}", f"ankle_angle_{side}"]
        columns += [[20 + 25 * math.sin(2 * math.pi * 1.2 * t + phase) for t in times],
                    [40 + 35 * math.sin(2 * math.pi * 1.5 * t + 0.4 + phase) for t in times],
                    [5 + 12 * math.sin(2 * math.pi * 1.8 * t + 1.0 + phase) for t in times]]
    model = osim.Model(str(RAJAGOPAL))
    for label, values in zip(labels, columns):
        coordinate = model.getCoordinateSet().get(label)
        low, high = math.degrees(coordinate.getRangeMin()), math.degrees(coordinate.getRangeMax())
        assert low <= min(values) and max(values) <= high, (label, min(values), max(values), low, high)
    write_table(folder / "motion.mot", "rajagopal_motion", labels, times, columns, True)
    muscles = [model.getMuscles().get(i).getName() for i in range(model.getMuscles().getSize())]
    excitations = [[0.3 + 0.2 * math.sin(2 * math.pi * (1 + 0.04 * k) * t + 0.9 * k) for t in times]
                   for k in range(len(muscles))]
    write_table(folder / "excitations.sto", "rajagopal_excitations", muscles, times, excitations, False)
    return times


def prescribe(model, folder):
    """Prescribe the unlocked, independent coordinates by GCVSplines through motion.mot (radians
    for rotations), the ones the motion lacks at their default; returns {coordinate: spline}."""
    labels, times, columns, in_degrees = read_table(folder / "motion.mot")
    dependent = {coupler.getDependentCoordinateName() for coupler in couplers(model)}
    splines = {}
    coordinates = model.getCoordinateSet()
    for i in range(coordinates.getSize()):
        coordinate = coordinates.get(i)
        name = coordinate.getName()
        if coordinate.getDefaultLocked() or name in dependent:
            print(f"  {name}: {'locked' if coordinate.getDefaultLocked() else 'dependent'}, not prescribed")
            continue
        if name in labels:
            values = columns[labels.index(name)]
            if in_degrees and coordinate.getMotionType() == osim.Coordinate.Rotational:
                values = [math.radians(v) for v in values]
            function = gcv_spline(times, values)
        else:
            print(f"  {name}: not in the motion, held at {coordinate.getDefaultValue()!r}")
            function = osim.Constant(coordinate.getDefaultValue())
        coordinate.setPrescribedFunction(function)
        coordinate.setDefaultIsPrescribed(True)
        splines[name] = function.clone()
    return splines


def add_controller(model, folder):
    labels, times, columns, _ = read_table(folder / "excitations.sto")
    controller = osim.PrescribedController()
    controller.setName("excitations")
    functions = {}
    for i in range(model.getMuscles().getSize()):
        muscle = model.getMuscles().get(i)
        values = columns[labels.index(muscle.getName())]
        controller.addActuator(muscle)
        controller.prescribeControlForActuator(muscle.getName(), piecewise_linear(times, values))
        functions[muscle.getName()] = piecewise_linear(times, values)
    model.addController(controller)
    return functions


def minimum_fiber_length(muscle):
    for cls in [osim.Millard2012EquilibriumMuscle, osim.Thelen2003Muscle]:
        concrete = cls.safeDownCast(muscle)
        if concrete is not None:
            return concrete.getMinimumFiberLength()
    return 0.0


def simulate(model_path, folder, report_times, accuracy):
    """(header, rows, notes) of OpenSim's forward simulation of the case in folder."""
    model = osim.Model(str(model_path))
    splines = prescribe(model, folder)
    excitations = add_controller(model, folder)
    state = model.initSystem()
    t0 = report_times[0]
    state.setTime(t0)
    at = osim.Vector(1, t0)
    first = osim.StdVectorInt([0])
    coordinates = model.getCoordinateSet()
    for name, f in splines.items():
        coordinates.get(name).setValue(state, f.calcValue(at), False)
        coordinates.get(name).setSpeedValue(state, f.calcDerivative(first, at))
    for coupler in couplers(model):
        # the dependent coordinates' value and speed from their independents', so that the state
        # equilibrateMuscles sees is consistent (the integrator would only project it onto the
        # constraints in Manager.initialize; initSystem's assembly fixes the values at time 0 only)
        value, speed = coupled(model, state, coupler)
        coordinates.get(coupler.getDependentCoordinateName()).setValue(state, value, False)
        coordinates.get(coupler.getDependentCoordinateName()).setSpeedValue(state, speed)
    model.realizeVelocity(state)
    muscles = [model.getMuscles().get(i) for i in range(model.getMuscles().getSize())]
    for muscle in muscles:
        muscle.setActivation(state, excitations[muscle.getName()].calcValue(at))
    model.equilibrateMuscles(state)
    minimum = {m.getName(): minimum_fiber_length(m) for m in muscles}

    # Moment arms on an unprescribed copy posed at the simulated q (see the module docstring).
    geometry = osim.Model(str(model_path))
    geometry_state = geometry.initSystem()
    geometry_muscles = [geometry.getMuscles().get(m.getName()) for m in muscles]
    unlocked = [coordinates.get(i).getName() for i in range(coordinates.getSize())
                if not coordinates.get(i).getDefaultLocked()]
    geometry_coordinates = [geometry.getCoordinateSet().get(name) for name in unlocked]

    manager = osim.Manager(model)
    manager.setIntegratorMethod(osim.Manager.IntegratorMethod_RungeKuttaMerson)
    manager.setIntegratorAccuracy(accuracy)
    manager.initialize(state)
    header = ["time"]
    for muscle in muscles:
        header += [f"{muscle.getName()}.{kind}" for kind in ["activation", "fiber_length", "tendon_force"]]
    header += [f"{name}.muscle_moment" for name in unlocked]
    rows = []
    notes = {"prescription_error": 0.0, "coupler_error": 0.0 if couplers(model) else None,
             "at_minimum_fiber_length": set()}
    for t in report_times:
        if t > t0:
            state = manager.integrate(t)
        model.realizeDynamics(state)
        assert state.getTime() == t, (state.getTime(), t)
        at = osim.Vector(1, t)
        for name, f in splines.items():
            error = abs(coordinates.get(name).getValue(state) - f.calcValue(at))
            notes["prescription_error"] = max(notes["prescription_error"], error)
            assert not math.isnan(error), f"{name} is NaN at {t!r}"
        for coupler in couplers(model):
            value, speed = coupled(model, state, coupler)
            dependent = coordinates.get(coupler.getDependentCoordinateName())
            error = max(abs(dependent.getValue(state) - value), abs(dependent.getSpeedValue(state) - speed))
            notes["coupler_error"] = max(notes["coupler_error"], error)
            assert not math.isnan(error), f"{dependent.getName()} is NaN at {t!r}"
        geometry_state.setTime(t)
        geometry_state.setQ(state.getQ())
        geometry.realizePosition(geometry_state)
        row = [t]
        forces = []
        for muscle in muscles:
            force = muscle.getTendonForce(state)
            forces.append(force)
            row += [muscle.getActivation(state), muscle.getFiberLength(state), force]
            if muscle.getFiberLength(state) <= minimum[muscle.getName()] * (1 + 1e-9):
                notes["at_minimum_fiber_length"].add(muscle.getName())
        for coordinate in geometry_coordinates:
            row.append(sum(force * m.computeMomentArm(geometry_state, coordinate)
                           for force, m in zip(forces, geometry_muscles)))
        assert not any(math.isnan(v) for v in row), f"NaN in the states at {t!r}"
        rows.append(row)
    return header, rows, notes


def write_states(path, header, rows):
    path.write_text(",".join(header) + "\n" + "".join(",".join(repr(float(v)) for v in row) + "\n" for row in rows))


def largest_differences(header, rows, other):
    out = {}
    for kind in ["activation", "fiber_length", "tendon_force", "muscle_moment"]:
        columns = [j for j, label in enumerate(header) if label.endswith("." + kind)]
        out[kind] = max(abs(a[j] - b[j]) for a, b in zip(rows, other) for j in columns)
    return out


def run(case, model_path, inputs):
    folder = OUT / case
    folder.mkdir(parents=True, exist_ok=True)
    report_times = inputs(folder)
    print(f"{case}: {len(report_times)} report times {report_times[0]!r}–{report_times[-1]!r}")
    start = time.perf_counter()
    header, rows, notes = simulate(model_path, folder, report_times, ACCURACY)
    elapsed = time.perf_counter() - start
    write_states(folder / "states.csv", header, rows)
    coupler = "" if notes["coupler_error"] is None else \
        f", largest |q − coupler| of the dependent coordinates (and speeds) {notes['coupler_error']:.3g}"
    print(f"{folder.relative_to(REPO)}: done in {elapsed:.1f} s, "
          f"largest |q − spline| {notes['prescription_error']:.3g}{coupler}, at minimum fiber length: "
          f"{sorted(notes['at_minimum_fiber_length']) or 'none'}")
    start = time.perf_counter()
    check_header, check_rows, _ = simulate(model_path, folder, report_times, CHECK_ACCURACY)
    elapsed = time.perf_counter() - start
    assert check_header == header
    differences = largest_differences(header, rows, check_rows)
    print(f"{case}: accuracy {CHECK_ACCURACY:g} rerun in {elapsed:.1f} s; largest "
          f"differences from {ACCURACY:g}: " + ", ".join(f"{k} {v:.3g}" for k, v in differences.items()))


CASES = {
    "arm26": (lambda: REPO / "fixtures" / "models" / "arm26.osim", arm26_inputs),
    "arm26_degroote": (arm26_degroote_model, arm26_inputs),
    "arm26_degroote_rigid": (lambda: arm26_degroote_model(rigid=True), arm26_inputs),
    "gait2392_millard": (lambda: REPO / "models" / "gait2392_millard2012muscle.osim", gait_inputs),
    "rajagopal": (lambda: RAJAGOPAL, rajagopal_inputs),
}


def main(cases):
    unknown = [c for c in cases if c not in CASES]
    if unknown:
        raise SystemExit(f"unknown case(s) {unknown}; cases: {list(CASES)}")
    osim.Logger.setLevelString("warn")  # the Manager's per-call summaries; warnings still show
    for case in cases or CASES:
        model, inputs = CASES[case]
        run(case, model(), inputs)


if __name__ == "__main__":
    main(sys.argv[1:])

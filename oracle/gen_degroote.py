#!/usr/bin/env python3
"""Goldens for `mechanics::muscle::DeGrooteFregly2016Muscle`: OpenSim 4.6 evaluates the
DeGrooteFregly2016Muscle curves, its static equilibrium and its explicit-mode fiber velocity.

    python3 oracle/gen_degroote.py        (from the repository root; needs `import opensim`, 4.6)

Builds, with the opensim Python API, a bench model: for every muscle M of MUSCLES one body
`block_M` on a SliderJoint from ground whose coordinate `M_length` is the path length (path from
the ground origin to the block origin), and a DeGrooteFregly2016Muscle M with the properties
listed below (a default muscle, pennate ones, a long and a short tendon, a wide active curve with
non-default strains, a rigid tendon, no passive force, fiber damping, implicit tendon dynamics,
F_max 5000 N). The model is printed and loaded back; every number below comes from the loaded
model.

Writes (paths relative to the repository root, resolved from this file):
    fixtures/models/degroote_bench.osim
    fixtures/golden/muscle/degroote/
      README.md        OpenSim version, procedures, observed solver imbalance
      parameters.csv   muscle, the muscle's properties (as getters return them), coordinate
      curves.csv       function, set_id, x, value, derivative: the calc* curve functions of a
                       DeGrooteFregly2016Muscle with the parameters of curve set set_id
                       (curve_sets.csv); derivative = the matching calc*Derivative, NaN where
                       OpenSim exposes none
      curve_sets.csv   set_id, active_force_width_scale, passive_fiber_strain_at_one_norm_force,
                       tendon_strain_at_one_norm_force
      equilibrium.csv  the columns of ../shared/reference/muscle/*/equilibrium.csv (pose_id =
                       length sample id): for every sample every slider is set to its muscle's
                       sample length, every muscle's activation to a, model.equilibrateMuscles(s),
                       model.realizeDynamics(s), then the Muscle getters. When equilibrateMuscles
                       throws, each muscle is equilibrated alone on a copy of the state and the
                       ones that throw get status `equilibrium_failed:<message>` (their numbers
                       are then those of the default normalized tendon force, not an equilibrium)
      fiber_velocity.csv  muscle, activation, mt_length, normalized_tendon_force (state set),
                       fiber_length, fiber_velocity, normalized_fiber_velocity,
                       force_velocity_multiplier at speed 0 for the compliant muscles, at fiber
                       lengths 0.7, 1.0, 1.3 L_opt with the path length and tendon force that
                       give an explicit force-velocity multiplier of 0.3, 0.9 or 1.5: explicit
                       mode, the forward-simulation state derivative (OpenSim leaves
                       fiber_damping out of it); implicit mode, the velocity at which
                       calcEquilibriumResidual vanishes (damping included), found by bisection
                       on the normalized tendon force derivative
"""
import math
from pathlib import Path

import opensim as osim

REPO = Path(__file__).resolve().parent.parent
MODEL_FILE = REPO / "fixtures" / "models" / "degroote_bench.osim"
OUT_DIR = REPO / "fixtures" / "golden" / "muscle" / "degroote"

ACTIVATIONS = [0.05, 0.5, 0.8, 1.0]
N_INSIDE = 10  # path length samples per muscle between the too-short and too-long ends

# name: (max_isometric_force, optimal_fiber_length, tendon_slack_length,
#        pennation_angle_at_optimal, {other property: value})
MUSCLES = {
    "default": (1000.0, 0.1, 0.2, 0.0, {}),
    "pennate": (2500.0, 0.06, 0.25, 0.35, {}),
    "long_tendon": (3000.0, 0.05, 0.4, 0.1, {}),
    "short_tendon": (400.0, 0.12, 0.03, 0.0, {}),
    "wide_stiff": (800.0, 0.09, 0.15, 0.2, {"active_force_width_scale": 1.6,
                                             "passive_fiber_strain_at_one_norm_force": 0.45,
                                             "tendon_strain_at_one_norm_force": 0.035}),
    "rigid": (1200.0, 0.1, 0.18, 0.25, {"ignore_tendon_compliance": True}),
    "no_passive": (600.0, 0.08, 0.12, 0.15, {"ignore_passive_fiber_force": True}),
    "damped": (1500.0, 0.1, 0.22, 0.1, {"fiber_damping": 0.1,
                                         "passive_fiber_strain_at_one_norm_force": 0.8,
                                         "tendon_strain_at_one_norm_force": 0.06}),
    "implicit": (900.0, 0.07, 0.2, 0.3, {"tendon_compliance_dynamics_mode": "implicit",
                                          "fiber_damping": 0.05}),
    "strong": (5000.0, 0.11, 0.3, 0.05, {"active_force_width_scale": 1.2}),
}

CURVE_SETS = [  # (active_force_width_scale, passive strain, tendon strain)
    (1.0, 0.6, 0.049),
    (1.6, 0.45, 0.035),
    (3.0, 1.2, 0.1),
]

PARAMETER_GETTERS = [
    "max_isometric_force", "optimal_fiber_length", "tendon_slack_length",
    "pennation_angle_at_optimal", "max_contraction_velocity", "ignore_tendon_compliance",
    "ignore_activation_dynamics", "active_force_width_scale", "fiber_damping",
    "ignore_passive_fiber_force", "passive_fiber_strain_at_one_norm_force",
    "tendon_strain_at_one_norm_force", "tendon_compliance_dynamics_mode",
]

EQ_COLUMNS = [
    ("mt_length", "getLength"),
    ("fiber_length", "getFiberLength"),
    ("normalized_fiber_length", "getNormalizedFiberLength"),
    ("pennation_angle", "getPennationAngle"),
    ("cos_pennation_angle", "getCosPennationAngle"),
    ("fiber_length_along_tendon", "getFiberLengthAlongTendon"),
    ("tendon_length", "getTendonLength"),
    ("tendon_strain", "getTendonStrain"),
    ("tendon_force", "getTendonForce"),
    ("active_fiber_force", "getActiveFiberForce"),
    ("passive_fiber_force", "getPassiveFiberForce"),
    ("fiber_force", "getFiberForce"),
    ("fiber_force_along_tendon", "getFiberForceAlongTendon"),
    ("active_force_length_multiplier", "getActiveForceLengthMultiplier"),
    ("passive_force_multiplier", "getPassiveForceMultiplier"),
    ("force_velocity_multiplier", "getForceVelocityMultiplier"),
    ("normalized_fiber_velocity", "getNormalizedFiberVelocity"),
]


def fmt(x):
    """Shortest round-trip decimal of a double (NaN / inf / -inf spelled out)."""
    if isinstance(x, bool):
        return str(int(x))
    if isinstance(x, str):
        return x
    x = float(x)
    if math.isnan(x):
        return "NaN"
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return repr(x)


def write_csv(path, header, rows):
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="\n") as f:
        f.write(",".join(header) + "\n")
        for row in rows:
            f.write(",".join(fmt(v) for v in row) + "\n")


def linspace(a, b, n):
    return [a + (b - a) * i / (n - 1) for i in range(n)]


# ---------------------------------------------------------------------------------------
# Curves
# ---------------------------------------------------------------------------------------
def curve_muscle(width, passive_strain, tendon_strain, ignore_passive=False):
    m = osim.DeGrooteFregly2016Muscle()
    m.set_active_force_width_scale(width)
    m.set_passive_fiber_strain_at_one_norm_force(passive_strain)
    m.set_tendon_strain_at_one_norm_force(tendon_strain)
    m.set_ignore_passive_fiber_force(ignore_passive)
    m.finalizeFromProperties()
    return m


def curve_rows(set_id, m, tendon_strain):
    """(function, set_id, x, value, derivative) over and beyond each curve's domain."""
    nan = float("nan")
    M = osim.DeGrooteFregly2016Muscle
    samples = [
        # function, xs, value, derivative
        ("calcActiveForceLengthMultiplier", linspace(0.0, 2.4, 61),
         m.calcActiveForceLengthMultiplier, m.calcActiveForceLengthMultiplierDerivative),
        ("calcPassiveForceMultiplier", linspace(0.0, 2.2, 45),
         m.calcPassiveForceMultiplier, m.calcPassiveForceMultiplierDerivative),
        ("calcPassiveForceMultiplierIntegral", linspace(0.0, 2.2, 23),
         m.calcPassiveForceMultiplierIntegral, None),
        ("calcTendonForceMultiplier", linspace(0.9, 1.0 + 2.5 * tendon_strain, 41),
         m.calcTendonForceMultiplier, m.calcTendonForceMultiplierDerivative),
        ("calcTendonForceMultiplierIntegral", linspace(0.95, 1.0 + 2.5 * tendon_strain, 21),
         m.calcTendonForceMultiplierIntegral, None),
        ("calcTendonForceLengthInverseCurve", linspace(-0.19, 5.5, 31),
         m.calcTendonForceLengthInverseCurve, None),
    ]
    if set_id == 0:  # the force-velocity curves have no parameters
        samples += [
            ("calcForceVelocityMultiplier", linspace(-1.5, 1.5, 61), M.calcForceVelocityMultiplier, None),
            ("calcForceVelocityInverseCurve", linspace(-0.2, 2.0, 45), M.calcForceVelocityInverseCurve, None),
        ]
    rows = []
    for name, xs, value, derivative in samples:
        for x in xs:
            rows.append([name, str(set_id), x, value(x), derivative(x) if derivative else nan])
    return rows


def write_curves():
    rows, set_rows = [], []
    for set_id, (width, e0, et) in enumerate(CURVE_SETS):
        rows += curve_rows(set_id, curve_muscle(width, e0, et), et)
        set_rows.append([str(set_id), width, e0, et])
    write_csv(OUT_DIR / "curves.csv", ["function", "set_id", "x", "value", "derivative"], rows)
    write_csv(OUT_DIR / "curve_sets.csv",
              ["set_id", "active_force_width_scale", "passive_fiber_strain_at_one_norm_force",
               "tendon_strain_at_one_norm_force"], set_rows)
    return len(rows)


# ---------------------------------------------------------------------------------------
# Bench model
# ---------------------------------------------------------------------------------------
def build_model():
    model = osim.Model()
    model.setName("degroote_bench")
    for name, (fmax, lopt, lts, alpha, extra) in MUSCLES.items():
        body = osim.Body("block_" + name, 1.0, osim.Vec3(0), osim.Inertia(0.01, 0.01, 0.01))
        joint = osim.SliderJoint("slider_" + name, model.getGround(), body)
        coordinate = joint.updCoordinate()
        coordinate.setName(name + "_length")
        coordinate.setRangeMin(0.0)
        coordinate.setRangeMax(10.0)
        coordinate.setDefaultValue(lts + lopt)
        model.addBody(body)
        model.addJoint(joint)
        muscle = osim.DeGrooteFregly2016Muscle()
        muscle.setName(name)
        muscle.set_max_isometric_force(fmax)
        muscle.set_optimal_fiber_length(lopt)
        muscle.set_tendon_slack_length(lts)
        muscle.set_pennation_angle_at_optimal(alpha)
        for property_name, value in extra.items():
            getattr(muscle, "set_" + property_name)(value)
        muscle.addNewPathPoint("origin", model.updGround(), osim.Vec3(0, 0, 0))
        muscle.addNewPathPoint("insertion", body, osim.Vec3(0, 0, 0))
        model.addForce(muscle)
    model.finalizeConnections()
    MODEL_FILE.parent.mkdir(parents=True, exist_ok=True)
    model.printToXML(str(MODEL_FILE))


def load_model():
    model = osim.Model(str(MODEL_FILE))
    model.initSystem()
    muscles = []
    for name in MUSCLES:
        muscles.append(osim.DeGrooteFregly2016Muscle.safeDownCast(model.getMuscles().get(name)))
    return model, muscles


def length_samples(m):
    """Path lengths of muscle m: one below tendon_slack_length (OpenSim finds no equilibrium),
    N_INSIDE from just above it to a stretched fiber, one beyond 5 F_max of passive force."""
    lopt, lts = m.get_optimal_fiber_length(), m.get_tendon_slack_length()
    tendon_at_fmax = 1.0 + m.get_tendon_strain_at_one_norm_force()
    inside = linspace(lts + 0.04 * lopt, lts * tendon_at_fmax + 1.7 * lopt, N_INSIDE)
    return [lts - 0.02 * lopt] + inside + [lts * tendon_at_fmax + 2.4 * lopt]


def write_parameters(muscles):
    rows = []
    for m in muscles:
        rows.append([m.getName()] + [getattr(m, "get_" + p)() for p in PARAMETER_GETTERS]
                    + [m.getName() + "_length"])
    write_csv(OUT_DIR / "parameters.csv", ["muscle"] + PARAMETER_GETTERS + ["coordinate"], rows)


def first_line(exception):
    return str(exception).strip().splitlines()[0].replace(",", ";")[:160]


def posed_state(model, muscles, sample, activation):
    """A fresh state (a copy: initializeState returns the model's working state) with every
    slider at its muscle's length sample, every activation a, realized to Velocity."""
    s = osim.State(model.initializeState())
    for m in muscles:
        coordinate = model.getCoordinateSet().get(m.getName() + "_length")
        coordinate.setValue(s, length_samples(m)[sample], False)
        m.setActivation(s, activation)
    model.realizeVelocity(s)
    return s


def write_equilibrium(model, muscles):
    header = (["pose_id", "muscle", "activation", "activation_readback"]
              + [c for c, _ in EQ_COLUMNS]
              + ["ignore_tendon_compliance", "ignore_activation_dynamics", "status"])
    rows, failures, worst_velocity = [], 0, 0.0
    for sample in range(N_INSIDE + 2):
        for a in ACTIVATIONS:
            s = posed_state(model, muscles, sample, a)
            status = {m.getName(): "ok" for m in muscles}
            try:
                model.equilibrateMuscles(s)
            except Exception:  # noqa: BLE001  find which muscles failed
                for m in muscles:
                    alone = posed_state(model, muscles, sample, a)
                    try:
                        m.computeEquilibrium(alone)
                    except Exception as e:  # noqa: BLE001
                        status[m.getName()] = "equilibrium_failed:" + first_line(e)
                        failures += 1
            model.realizeDynamics(s)
            for m in muscles:
                row = ["L%02d" % sample, m.getName(), a, m.getActivation(s)]
                row += [getattr(m, getter)(s) for _, getter in EQ_COLUMNS]
                row += [m.get_ignore_tendon_compliance(), m.get_ignore_activation_dynamics(),
                        status[m.getName()]]
                rows.append(row)
                if status[m.getName()] == "ok":
                    worst_velocity = max(worst_velocity, abs(m.getNormalizedFiberVelocity(s)))
    write_csv(OUT_DIR / "equilibrium.csv", header, rows)
    return len(rows), failures, worst_velocity


def implicit_derivative_root(m, mt_length, activation, norm_tendon_force):
    """The normalized tendon force derivative at which OpenSim's implicit residual
    (calcEquilibriumResidual, speed 0) vanishes: bisection to adjacent doubles (the residual
    increases with the derivative)."""
    def residual(derivative):
        return m.calcEquilibriumResidual(mt_length, 0.0, activation, norm_tendon_force, derivative)
    lo, hi = -1.0, 1.0
    while residual(lo) > 0:
        lo *= 2.0
    while residual(hi) < 0:
        hi *= 2.0
    while True:
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            return lo if abs(residual(lo)) <= abs(residual(hi)) else hi
        if residual(mid) < 0:
            lo = mid
        else:
            hi = mid


def velocity_state_inputs(m, normalized_fiber_length, activation, force_velocity_multiplier):
    """(mt_length, normalized tendon force) at which a fiber of the given normalized length,
    without damping, carries a f_L f_V + f_PE along the tendon: the explicit state whose
    fiber velocity is f_V^-1(force_velocity_multiplier)."""
    lopt, width = m.get_optimal_fiber_length(), m.get_optimal_fiber_length() * math.sin(m.get_pennation_angle_at_optimal())
    fiber_length = normalized_fiber_length * lopt
    along_tendon = math.sqrt(fiber_length ** 2 - width ** 2)
    fiber_force = (activation * m.calcActiveForceLengthMultiplier(normalized_fiber_length) * force_velocity_multiplier
                   + m.calcPassiveForceMultiplier(normalized_fiber_length))
    norm_tendon_force = fiber_force * along_tendon / fiber_length
    tendon_length = m.get_tendon_slack_length() * m.calcTendonForceLengthInverseCurve(norm_tendon_force)
    return tendon_length + along_tendon, norm_tendon_force


def write_fiber_velocity(model, muscles):
    """Fiber velocity at fiber lengths 0.7, 1.0, 1.3 L_opt and tendon forces that make the
    explicit force-velocity multiplier 0.3, 0.9 or 1.5 (velocities within +-1 v_max), speed 0:
    explicit mode = the forward-simulation state derivative; implicit mode = the velocity at
    which the implicit residual vanishes (the discrete derivative variable set to the root)."""
    header = ["muscle", "activation", "mt_length", "normalized_tendon_force", "fiber_length",
              "fiber_velocity", "normalized_fiber_velocity", "force_velocity_multiplier"]
    rows = []
    derivative_name = osim.DeGrooteFregly2016Muscle.getImplicitDynamicsDerivativeName()
    for m in (m for m in muscles if not m.get_ignore_tendon_compliance()):
        coordinate = model.getCoordinateSet().get(m.getName() + "_length")
        for normalized_fiber_length in (0.7, 1.0, 1.3):
            for a in (0.05, 0.5, 1.0):
                for multiplier in (0.3, 0.9, 1.5):
                    mt_length, norm_tendon_force = velocity_state_inputs(m, normalized_fiber_length, a, multiplier)
                    s = posed_state(model, muscles, 1, a)
                    coordinate.setValue(s, mt_length, False)
                    m.setNormalizedTendonForce(s, norm_tendon_force)
                    if m.get_tendon_compliance_dynamics_mode() == "implicit":
                        root = implicit_derivative_root(m, mt_length, a, norm_tendon_force)
                        m.setDiscreteVariableValue(s, derivative_name, root)
                    model.realizeDynamics(s)
                    assert m.getLength(s) == mt_length
                    rows.append([m.getName(), a, m.getLength(s), m.getNormalizedTendonForce(s),
                                 m.getFiberLength(s), m.getFiberVelocity(s),
                                 m.getNormalizedFiberVelocity(s), m.getForceVelocityMultiplier(s)])
    write_csv(OUT_DIR / "fiber_velocity.csv", header, rows)
    return len(rows)


def write_readme(counts):
    n_curves, n_eq, n_fail, worst_velocity, n_fv = counts
    text = f"""# DeGrooteFregly2016Muscle goldens

Written by `oracle/gen_degroote.py` with OpenSim {osim.GetVersionAndDate()} (Python bindings)
from the bench model `fixtures/models/degroote_bench.osim`; see the script's docstring for the
procedures and columns.

- curves.csv: {n_curves} samples; curve_sets.csv: the parameters of each set.
- equilibrium.csv: {n_eq} rows, {n_fail} with status `equilibrium_failed` (OpenSim's bisection
  on normalized tendon force in [0, 5] finds no sign change: the path is shorter than the tendon
  slack length, or longer than a fiber pulling 5 F_max allows). The rigid-tendon muscle needs no
  solve and is `ok` even below its tendon slack length (L00), where OpenSim reports a fiber
  pointing backwards (cos_pennation_angle < 0).
- fiber_velocity.csv: {n_fv} rows.

OpenSim's equilibrium (`computeInitialFiberEquilibrium`) bisects the normalized tendon force on
[0, 5] until the bracket is narrower than 1e-10 and returns the last midpoint, so its normalized
tendon force is within 1e-10 of the root: the tendon force within 1e-10 F_max (5e-7 N for the
5000 N muscle). The getters then evaluate the explicit model, which turns that imbalance into a
fiber velocity: the largest |normalized_fiber_velocity| over the `ok` rows is {worst_velocity:.3g}
(0 for the rigid and implicit muscles), and force_velocity_multiplier differs from f_V(0)
accordingly. Agreement with an exact root is limited by this, not by the curves.
"""
    (OUT_DIR / "README.md").write_text(text)


def main():
    print("OpenSim", osim.GetVersionAndDate(), flush=True)
    OUT_DIR.mkdir(parents=True, exist_ok=True)
    n_curves = write_curves()
    build_model()
    model, muscles = load_model()
    write_parameters(muscles)
    n_eq, n_fail, worst_velocity = write_equilibrium(model, muscles)
    n_fv = write_fiber_velocity(model, muscles)
    write_readme((n_curves, n_eq, n_fail, worst_velocity, n_fv))
    print(f"curves {n_curves}, equilibrium {n_eq} rows ({n_fail} failed), worst |v_norm| "
          f"{worst_velocity:.3g}, fiber velocity {n_fv} rows")


if __name__ == "__main__":
    main()

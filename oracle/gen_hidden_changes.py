"""Writes fixtures/dynamometry/hidden/hid01..hid30/: synthetic dynamometry subjects made by
OpenSim 4.6 from the scaled subject01 model with ONE deficiency hidden (issue 6's hidden effect
and the diagnosis mission's candidates), as the shared oracle makes the public subjects
(dynamometry_lib.generate_subject). Per subject, numpy default_rng(SEED + k) draws it:
- hid01–10, one knee muscle's parameter (muscle uniform over the eight estimated ones, sign ±
  with p 0.5): L_ts by U(0.02, 0.06) in hid01–06, L_opt by U(0.05, 0.15) in hid07–08, F_max by
  U(0.10, 0.25) in hid09–10;
- hid11–12, a knee angle offset: the .mot records the simulated angle plus e = ±U(3, 8)°;
- hid13–14, the agonists of one direction (extension or flexion, p 0.5) simulated at
  U(0.80, 0.95) times the recorded activation;
- hid15–16, one factor ±U(0.02, 0.05) on the L_ts of a group: the vasti (hid15), all eight
  estimated muscles (hid16);
- hid17–18, one knee muscle's pennation angle at L_opt changed by ±U(0.06, 0.14) rad (the sign
  flipped where the angle would fall below 0); its true value joins true_parameters;
- hid19–20, the knee's axis moved by U(3, 8) mm in the X-Y plane of its parent frame, at an angle
  U(0, 360°) from X: knee_r's femur_r_offset and tibia_r_offset (both at the body origin, and the
  joint's rotation zero at rest) translated by the same vector, so the bones are unchanged at rest;
- hid21–22, the agonists of every trial simulated at U(0.80, 0.95) times the recorded activation;
- hid23–24, one agonist (uniform over the eight) simulated at U(0.70, 0.90) times its recorded
  activation;
- hid25–26, every measured moment offset by ±U(2, 6) N·m;
- hid27–30, the hip (hid27–28) or the ankle (hid29–30) standing ±U(3, 8)° off the posture the
  trials record (a dynamometer seat or foot plate misaligned).
The moment noise is σ = 0 (hid01–02, 07, 09, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29), 5 (hid03–04,
08, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30) and 10 N·m (hid05–06), noise seed SEED + 1000 + k.
ground_truth.json keeps what was hidden and the true parameters; the fit never reads it
(tests/functional_hidden.rs compares against it afterwards).

Usage: python3 oracle/gen_hidden_changes.py /path/to/shared
(HIDDEN_SEED=N HIDDEN_OUT=DIR: another draw into DIR, e.g. a blind batch for `cargo xtask
diagnose-study DIR`; the fixtures are the default, N = 31000.)
"""
import json
import os
import re
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np

SHARED = Path(sys.argv[1]).resolve()
sys.path.insert(0, str(SHARED / "tools" / "oracle"))
import dynamometry_generate_public as G  # noqa: E402
import dynamometry_lib as L  # noqa: E402

OUT = Path(os.environ.get("HIDDEN_OUT", Path(__file__).resolve().parent.parent / "fixtures" / "dynamometry" / "hidden"))
# draws seed base (noise seeds: base + 1000 + k); another base makes a blind batch for a study
SEED = int(os.environ.get("HIDDEN_SEED", "31000"))
TS, OPT, FMAX, PA = "tendon_slack_length", "optimal_fiber_length", "max_isometric_force", "pennation_angle_at_optimal"
# subject number: (changed property, magnitude range, moment noise sd in N m)
SUBJECTS = {1: (TS, (0.02, 0.06), 0.0), 2: (TS, (0.02, 0.06), 0.0), 3: (TS, (0.02, 0.06), 5.0),
            4: (TS, (0.02, 0.06), 5.0), 5: (TS, (0.02, 0.06), 10.0), 6: (TS, (0.02, 0.06), 10.0),
            7: (OPT, (0.05, 0.15), 0.0), 8: (OPT, (0.05, 0.15), 5.0),
            9: (FMAX, (0.10, 0.25), 0.0), 10: (FMAX, (0.10, 0.25), 5.0)}
OFFSETS = {11: 0.0, 12: 5.0}
ACTIVATIONS = {13: 0.0, 14: 5.0}
ALL_ACTIVATIONS = {21: 0.0, 22: 5.0}
MUSCLE_ACTIVATIONS = {23: 0.0, 24: 5.0}
MOMENT_OFFSETS = {25: 0.0, 26: 5.0}
# subject number: (group name, its muscles, moment noise sd in N m)
PENNATIONS = {17: 0.0, 18: 5.0}
AXES = {19: 0.0, 20: 5.0}
# subject number: (offset coordinate, moment noise sd in N m)
POSTURES = {27: ("hip_flexion_r", 0.0), 28: ("hip_flexion_r", 5.0), 29: ("ankle_angle_r", 0.0), 30: ("ankle_angle_r", 5.0)}
GROUPS = {15: ("vasti", ["vas_int_r", "vas_lat_r", "vas_med_r"], 0.0), 16: ("estimated muscles", L.EST_MUSCLES, 5.0)}


class ScaledAgonists(L.KneeSim):
    """KneeSim whose `agonists` trials (every trial when None) run at `factor` times the requested
    activation."""

    def __init__(self, model_path, agonists, factor):
        super().__init__(model_path)
        self.scaled, self.factor = agonists, factor

    def trial(self, knee_deg, agonists, level=L.ACTIVATION, **kwargs):
        if self.scaled is None or agonists == self.scaled:
            level = level * self.factor
        return super().trial(knee_deg, agonists, level=level, **kwargs)


class ScaledAgonist(L.KneeSim):
    """KneeSim whose agonist `muscle` runs at `factor` times the requested activation."""

    def __init__(self, model_path, muscle, factor):
        super().__init__(model_path)
        self.muscle, self.factor = muscle, factor

    def set_activations(self, agonists, level):
        super().set_activations(agonists, level)
        if self.muscle in agonists:
            self.muscles.get(self.muscle).setActivation(self.state, level * self.factor)


class OffsetMoments(L.KneeSim):
    """KneeSim whose knee moments carry a constant `offset` (N m)."""

    def __init__(self, model_path, offset):
        super().__init__(model_path)
        self.offset = offset

    def trial(self, *args, **kwargs):
        result = super().trial(*args, **kwargs)
        result["knee_moment_Nm"] += self.offset
        return result


class OffsetPosture(L.KneeSim):
    """KneeSim whose hip or ankle (`coordinate`) stands `offset` degrees below what the trials
    record (recorded − true = offset)."""

    def __init__(self, model_path, coordinate, offset):
        super().__init__(model_path)
        self.keyword, self.offset = {"hip_flexion_r": "hip_deg", "ankle_angle_r": "ankle_deg"}[coordinate], offset

    def trial(self, *args, **kwargs):
        recorded = kwargs.get(self.keyword, L.HIP_DEG if self.keyword == "hip_deg" else L.ANKLE_DEG)
        kwargs[self.keyword] = recorded - self.offset
        return super().trial(*args, **kwargs)


def moved_knee_axis(scratch, offset):
    """The scaled model with knee_r's offset frames translated by `offset` (m), written in scratch."""
    text = G.SCALED.read_text()
    start = text.index('<CustomJoint name="knee_r">')
    end = text.index("</CustomJoint>", start)
    joint, count = re.subn(r"(<PhysicalOffsetFrame name=\"(?:femur|tibia)_r_offset\">.*?<translation>)0 0 0(</translation>)",
                           lambda m: m.group(1) + " ".join(repr(float(c)) for c in offset) + m.group(2), text[start:end], flags=re.S)
    assert count == 2, count
    path = Path(scratch) / "moved_knee_axis.osim"
    path.write_text(text[:start] + joint + text[end:])
    return path


def hidden_change(k, magnitude):
    """(muscle, factor) of subject k."""
    rng = np.random.default_rng(SEED + k)
    muscle = L.EST_MUSCLES[int(rng.integers(len(L.EST_MUSCLES)))]
    sign = 1.0 if rng.random() < 0.5 else -1.0
    return muscle, 1.0 + sign * float(rng.uniform(*magnitude))


def write(scratch, k, sim, sd, truth, recorded=None, pennation=None):
    """Generates subject k into fixtures/, keeping the scoring fields and `truth` (and the true
    pennation angle of muscle `pennation`)."""
    sid = "hid%02d" % k
    L.generate_subject(Path(scratch) / sid, sid, sim, base_model_file=G.SCALED.name,
                       base_model_path_in_shared=G.rel_to_shared(G.SCALED), noise_sd=sd,
                       noise_seed=SEED + 1000 + k if sd > 0 else None, recorded_angle_sets=recorded,
                       extra_truth=truth, log=lambda *a: None)
    source, target = Path(scratch) / sid, OUT / sid
    shutil.rmtree(target, ignore_errors=True)
    shutil.copytree(source, target, ignore=shutil.ignore_patterns("ground_truth.json"))
    full = json.loads((source / "ground_truth.json").read_text())
    kept = {"note": "scoring fields of the generator's ground_truth.json (oracle/gen_hidden_changes.py)"}
    kept.update({key: full[key] for key in ["subject", "noise_sd_Nm", "noise_seed", "true_parameters"]})
    kept.update(truth)
    if pennation is not None:
        kept["true_parameters"][pennation][PA] = sim.muscle_params()[pennation][PA]
    (target / "ground_truth.json").write_text(json.dumps(kept, indent=1))
    print(sid, truth, sd, flush=True)


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    base_p = L.KneeSim(G.SCALED).muscle_params()
    with tempfile.TemporaryDirectory() as scratch:
        for k, (prop, magnitude, sd) in SUBJECTS.items():
            muscle, factor = hidden_change(k, magnitude)
            sim = L.KneeSim(G.SCALED, overrides={muscle: {prop: base_p[muscle][prop] * factor}})
            write(scratch, k, sim, sd, {"hidden_muscle": muscle, "hidden_parameter": prop, "factor": factor})
        for k, sd in OFFSETS.items():
            rng = np.random.default_rng(SEED + k)
            offset = (1.0 if rng.random() < 0.5 else -1.0) * float(rng.uniform(3.0, 8.0))
            recorded = {name: [a + offset for a in angles] for name, angles in L.TRIAL_SETS.items()}
            truth = {"hidden_coordinate": L.KNEE, "recorded_minus_true_deg": offset}
            write(scratch, k, L.KneeSim(G.SCALED), sd, truth, recorded)
        for k, sd in ACTIVATIONS.items():
            rng = np.random.default_rng(SEED + k)
            direction = "extension" if rng.random() < 0.5 else "flexion"
            factor = float(rng.uniform(0.80, 0.95))
            sim = ScaledAgonists(G.SCALED, L.DIRECTIONS[direction], factor)
            write(scratch, k, sim, sd, {"hidden_activation_direction": direction, "activation_factor": factor})
        for k, sd in ALL_ACTIVATIONS.items():
            factor = float(np.random.default_rng(SEED + k).uniform(0.80, 0.95))
            sim = ScaledAgonists(G.SCALED, None, factor)
            write(scratch, k, sim, sd, {"hidden_activation_direction": "both", "activation_factor": factor})
        for k, sd in MUSCLE_ACTIVATIONS.items():
            rng = np.random.default_rng(SEED + k)
            muscle = L.EST_MUSCLES[int(rng.integers(len(L.EST_MUSCLES)))]
            factor = float(rng.uniform(0.70, 0.90))
            sim = ScaledAgonist(G.SCALED, muscle, factor)
            write(scratch, k, sim, sd, {"hidden_activation_muscle": muscle, "activation_factor": factor})
        for k, sd in MOMENT_OFFSETS.items():
            rng = np.random.default_rng(SEED + k)
            offset = (1.0 if rng.random() < 0.5 else -1.0) * float(rng.uniform(2.0, 6.0))
            write(scratch, k, OffsetMoments(G.SCALED, offset), sd, {"hidden_moment_offset_Nm": offset})
        for k, sd in PENNATIONS.items():
            rng = np.random.default_rng(SEED + k)
            muscle = L.EST_MUSCLES[int(rng.integers(len(L.EST_MUSCLES)))]
            change = (1.0 if rng.random() < 0.5 else -1.0) * float(rng.uniform(0.06, 0.14))
            if base_p[muscle][PA] + change < 0.0:
                change = -change
            sim = L.KneeSim(G.SCALED, overrides={muscle: {PA: base_p[muscle][PA] + change}})
            truth = {"hidden_muscle": muscle, "hidden_parameter": PA, "change_rad": change}
            write(scratch, k, sim, sd, truth, pennation=muscle)
        for k, sd in AXES.items():
            rng = np.random.default_rng(SEED + k)
            distance, angle = float(rng.uniform(3.0, 8.0)), float(rng.uniform(0.0, 2.0 * np.pi))
            offset = [distance * np.cos(angle), distance * np.sin(angle), 0.0]
            sim = L.KneeSim(str(moved_knee_axis(scratch, [c / 1000.0 for c in offset])))
            truth = {"hidden_joint": "knee_r", "axis_offset_in_parent_mm": offset, "axis_offset_in_child_mm": offset}
            write(scratch, k, sim, sd, truth)
        for k, (coordinate, sd) in POSTURES.items():
            rng = np.random.default_rng(SEED + k)
            offset = (1.0 if rng.random() < 0.5 else -1.0) * float(rng.uniform(3.0, 8.0))
            truth = {"hidden_coordinate": coordinate, "recorded_minus_true_deg": offset}
            write(scratch, k, OffsetPosture(G.SCALED, coordinate, offset), sd, truth)
        for k, (group, muscles, sd) in GROUPS.items():
            rng = np.random.default_rng(SEED + k)
            factor = 1.0 + (1.0 if rng.random() < 0.5 else -1.0) * float(rng.uniform(0.02, 0.05))
            sim = L.KneeSim(G.SCALED, overrides={m: {TS: base_p[m][TS] * factor} for m in muscles})
            truth = {"hidden_group": group, "hidden_group_muscles": muscles, "hidden_parameter": TS, "factor": factor}
            write(scratch, k, sim, sd, truth)


if __name__ == "__main__":
    main()

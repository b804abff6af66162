"""Writes fixtures/dynamometry/generated/gen01..gen19/: noisy synthetic dynamometry subjects made
exactly as the public ones (the shared oracle's dynamometry_generate_public.make_perturbed_subject:
an OpenSim 4.6 model with its eight knee muscles' L_opt and L_ts perturbed), with other
perturbation and noise seeds, for the held-out accuracy study of `cargo xtask validate`.
gen01..gen12 perturb the scaled subject01 model, as the public subjects do; gen13..gen18 perturb
the generic gait2392_millard2012muscle model (models/ holds the same file), a second base model.
gen19 is not held out: it is a generic-model subject of a development run (seeds 77104/88104) on
which Garner & Pandy's fit needed 1110 iterations, kept as that fit's regression case.
ground_truth.json keeps only the scoring fields (true parameters, factors, seeds, σ).

Usage: python3 oracle/gen_dynamometry_subjects.py /path/to/shared
"""
import json
import shutil
import sys
import tempfile
from pathlib import Path

SHARED = Path(sys.argv[1]).resolve()
sys.path.insert(0, str(SHARED / "tools" / "oracle"))
import dynamometry_generate_public as G  # noqa: E402

OUT = Path(__file__).resolve().parent.parent / "fixtures" / "dynamometry" / "generated"
KEEP = ["subject", "noise_sd_Nm", "noise_seed", "perturbation_seed", "true_parameters", "perturbation_factors"]


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as scratch:
        subjects = [("gen%02d" % k, G.SCALED if k <= 12 else G.GENERIC, 13000 + k,
                     5.0 if k <= 6 or 13 <= k <= 15 else 10.0, 23000 + k) for k in range(1, 19)]
        subjects.append(("gen19", G.GENERIC, 77104, 5.0, 88104))
        for sid, base, perturbation_seed, sd, noise_seed in subjects:
            G.make_perturbed_subject(Path(scratch), sid, base, perturbation_seed, sd, noise_seed, log=lambda *a: None)
            source, target = Path(scratch) / sid, OUT / sid
            shutil.rmtree(target, ignore_errors=True)
            shutil.copytree(source, target, ignore=shutil.ignore_patterns("ground_truth.json"))
            truth = json.loads((source / "ground_truth.json").read_text())
            kept = {"note": "scoring fields of the generator's ground_truth.json (oracle/gen_dynamometry_subjects.py)"}
            kept.update({key: truth[key] for key in KEEP})
            (target / "ground_truth.json").write_text(json.dumps(kept, indent=1))
            print(sid, sd, flush=True)


if __name__ == "__main__":
    main()

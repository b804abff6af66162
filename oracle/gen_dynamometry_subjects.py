"""Writes fixtures/dynamometry/generated/gen01..gen12/: noisy synthetic dynamometry subjects made
exactly as the public ones (the shared oracle's dynamometry_generate_public.make_perturbed_subject:
the OpenSim 4.6 subject01 model with its eight knee muscles' L_opt and L_ts perturbed), with other
perturbation and noise seeds, for the held-out accuracy study of `cargo xtask validate`.
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
        for k in range(1, 13):
            sid, sd = "gen%02d" % k, (5.0 if k <= 6 else 10.0)
            G.make_perturbed_subject(Path(scratch), sid, G.SCALED, 13000 + k, sd, 23000 + k, log=lambda *a: None)
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

"""Copy OpenSim 4.6's inverse dynamics and static optimisation outputs of the subject01 walk into
fixtures/ (the pipeline goldens of ../shared/reference/pipelines/gait2392_subject01/, made by
../shared/tools/oracle/pipeline_gait2392_subject01.py): the InverseDynamicsTool table whole,
the StaticOptimization activation and force tables every 5th row (rows 0, 5, …, 90; `nRows`
rewritten), the rest of each file byte for byte.

Usage: python3 oracle/slice_pipeline_dynamics.py [REFERENCE_DIR]
"""
import shutil
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
REFERENCE = Path(sys.argv[1]) if len(sys.argv) > 1 else REPO.parent / "shared" / "reference"
SOURCE = REFERENCE / "pipelines" / "gait2392_subject01"
EVERY = 5


def slice_rows(source, target):
    lines = source.read_text().split("\n")
    end = lines.index("endheader")
    header, labels, rows = lines[:end + 1], lines[end + 1], [l for l in lines[end + 2:] if l]
    kept = rows[::EVERY]
    header = [f"nRows={len(kept)}" if l.startswith("nRows=") else l for l in header]
    target.write_text("\n".join(header + [labels] + kept) + "\n")


def main():
    inverse = REPO / "fixtures" / "golden" / "inverse_dynamics"
    inverse.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(SOURCE / "subject01_walk1_InverseDynamics.sto", inverse / "subject01_walk1_InverseDynamics.sto")
    static = REPO / "fixtures" / "golden" / "static_optimization"
    static.mkdir(parents=True, exist_ok=True)
    for kind in ["activation", "force"]:
        name = f"subject01_walk1_StaticOptimization_{kind}.sto"
        slice_rows(SOURCE / name, static / name)


if __name__ == "__main__":
    main()

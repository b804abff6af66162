"""Copy a representative slice of the OpenSim 4.6 muscle goldens into fixtures/.

The full goldens live in ../shared/reference/muscle/<stem>/ (made by ../shared/tools/oracle/
gen_muscle.py with OpenSim 4.6). `cargo test` reads this slice; `cargo xtask validate` sweeps the
full files when ../shared/reference is present.

Slice: parameters.csv and curve_sets.csv whole; every 4th curve sample (plus both ends of each
curve); equilibrium rows of the first, middle and last angle of each knee/elbow sweep and the
Thelen minimum-fiber-length rows (semimem_r at knee_h00_k-080).

Usage: python3 oracle/slice_muscle.py [REFERENCE_DIR]
"""
import shutil
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
REFERENCE = Path(sys.argv[1]) if len(sys.argv) > 1 else REPO.parent / "shared" / "reference"
STEMS = ["gait2392_millard2012muscle", "gait2392_thelen2003muscle", "arm26", "Rajagopal2016"]


def sweep_picks(pose_ids):
    picks = set()
    for prefix in sorted({p.rsplit("_", 1)[0] for p in pose_ids}):
        members = [p for p in pose_ids if p.startswith(prefix + "_")]
        picks |= {members[0], members[len(members) // 2], members[-1]}
    return picks


def slice_curves(source, target):
    lines = open(source).read().splitlines()
    header, rows = lines[0], lines[1:]
    by_curve = {}
    for row in rows:
        key = tuple(row.split(",")[:3]) if "activation" in header else tuple(row.split(",")[:2])
        by_curve.setdefault(key, []).append(row)
    with open(target, "w") as out:
        out.write(header + "\n")
        for members in by_curve.values():
            keep = members[::4] + ([members[-1]] if (len(members) - 1) % 4 else [])
            out.write("".join(r + "\n" for r in keep))


def slice_equilibrium(source, target):
    lines = open(source).read().splitlines()
    header, rows = lines[0], lines[1:]
    pose_ids = list(dict.fromkeys(r.split(",", 1)[0] for r in rows))
    keep = sweep_picks(pose_ids) | {"knee_h00_k-080"}
    with open(target, "w") as out:
        out.write(header + "\n")
        for row in rows:
            pose, muscle = row.split(",")[:2]
            if pose in keep and (pose != "knee_h00_k-080" or muscle == "semimem_r" or pose in sweep_picks(pose_ids)):
                out.write(row + "\n")
    return len(keep)


def main():
    for stem in STEMS:
        source, target = REFERENCE / "muscle" / stem, REPO / "fixtures" / "golden" / "muscle" / stem
        target.mkdir(parents=True, exist_ok=True)
        for name in ["parameters.csv", "curve_sets.csv"]:
            shutil.copyfile(source / name, target / name)
        slice_curves(source / "curves.csv", target / "curves.csv")
        poses = slice_equilibrium(source / "equilibrium.csv", target / "equilibrium.csv")
        print(stem, poses, "poses")


if __name__ == "__main__":
    main()

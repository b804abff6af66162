"""Copy a representative slice of the OpenSim 4.6 geometry goldens into fixtures/.

The full goldens live in ../shared/reference/geometry/<stem>/ (made by the oracle scripts of
../shared/tools/oracle/ with OpenSim 4.6). `cargo test` reads this slice from the repository;
`cargo xtask validate` sweeps the full files when ../shared/reference is present.

Usage: python3 oracle/slice_geometry.py [REFERENCE_DIR]
"""
import csv
import shutil
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
REFERENCE = Path(sys.argv[1]) if len(sys.argv) > 1 else REPO.parent / "shared" / "reference"
STEMS = ["gait2392_millard2012muscle", "gait2354_simbody", "subject01_simbody", "leg6dof9musc", "arm26", "Rajagopal2016"]
SLICED = ["poses.csv", "lengths.csv", "bodies.csv", "markers.csv", "moment_arms.csv"]
WHOLE = ["coordinates.csv", "muscle_coordinates.csv"]


def chosen_poses(poses_file):
    ids = [row["pose_id"] for row in csv.DictReader(open(poses_file))]
    randoms = [i for i in ids if i.startswith("rand_")][::8]
    sweeps = [i for i in ids if not i.startswith("rand_")]
    # first, middle and last angle of each sweep
    picks = []
    for prefix in sorted({s.rsplit("_", 1)[0] for s in sweeps}):
        members = [s for s in sweeps if s.startswith(prefix + "_")]
        picks += [members[0], members[len(members) // 2], members[-1]]
    return set(randoms + picks)


def main():
    for stem in STEMS:
        source, target = REFERENCE / "geometry" / stem, REPO / "fixtures" / "golden" / "geometry" / stem
        target.mkdir(parents=True, exist_ok=True)
        keep = chosen_poses(source / "poses.csv")
        for name in WHOLE:
            if (source / name).exists():
                shutil.copyfile(source / name, target / name)
        for name in SLICED:
            if not (source / name).exists():
                continue
            with open(source / name) as src, open(target / name, "w", newline="") as dst:
                header = src.readline()
                dst.write(header)
                for line in src:
                    if line.split(",", 1)[0] in keep:
                        dst.write(line)
        print(stem, len(keep), "poses")


if __name__ == "__main__":
    main()

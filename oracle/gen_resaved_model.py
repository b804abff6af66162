#!/usr/bin/env python3
"""arm26 (a 4.0 document) read and printed by OpenSim 4.6, as a lab's model is re-saved when
opened in a newer OpenSim: fixtures/golden/resaved/arm26_opensim46.osim. OpenSim 4.5's conversion
names each force's GeometryPath `path` (`Force::updateFromXMLNode`), and the version becomes 40600.

    python3 oracle/gen_resaved_model.py
"""
from pathlib import Path

import opensim as osim

REPO = Path(__file__).resolve().parent.parent
OUT = REPO / "fixtures" / "golden" / "resaved"


def main():
    osim.Logger.setLevelString("error")
    OUT.mkdir(parents=True, exist_ok=True)
    model = osim.Model(str(REPO / "fixtures" / "models" / "arm26.osim"))
    model.printToXML(str(OUT / "arm26_opensim46.osim"))
    print("written", OUT / "arm26_opensim46.osim")


if __name__ == "__main__":
    main()

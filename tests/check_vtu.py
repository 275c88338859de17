#!/usr/bin/env python3
"""Checks the cms driver's mode-shape files load in VTK (doc/user-guide.md,
"Mode shapes"): python3 check_vtu.py <directory> <name> <modes>

Each <name>-mode-<k>.vtu is read with VTK's own XML reader (python3-vtk9):
points, cells, and finite displacement arrays must be there, and the .pvd
collection must list every mode. Exit 0 on success, 1 on a failed check,
77 (CTest's skip code) when VTK's Python module is not installed.
"""
import math
import os
import sys
import xml.etree.ElementTree as ET

try:
    import vtk
except ImportError:
    print("check_vtu: python3-vtk9 is not installed; skipped")
    sys.exit(77)


def main(directory, name, modes):
    pvd = ET.parse(os.path.join(directory, f"{name}-modes.pvd")).getroot()
    files = [d.get("file") for d in pvd.iter("DataSet")]
    if len(files) != modes:
        print(f"check_vtu: the .pvd lists {len(files)} data sets, expected {modes}")
        return 1
    for f in files:
        reader = vtk.vtkXMLUnstructuredGridReader()
        reader.SetFileName(os.path.join(directory, f))
        reader.Update()
        grid = reader.GetOutput()
        if grid.GetNumberOfPoints() == 0 or grid.GetNumberOfCells() == 0:
            print(f"check_vtu: {f}: VTK read no points or cells")
            return 1
        for array in ("displacement_real", "displacement_imag", "rotation_real", "rotation_imag"):
            a = grid.GetPointData().GetArray(array)
            if a is None or a.GetNumberOfTuples() != grid.GetNumberOfPoints():
                print(f"check_vtu: {f}: point data {array} missing or of the wrong length")
                return 1
            if any(not math.isfinite(a.GetComponent(i, c)) for i in range(a.GetNumberOfTuples()) for c in range(3)):
                print(f"check_vtu: {f}: {array} has a non-finite value")
                return 1
        print(f"check_vtu: {f}: {grid.GetNumberOfPoints()} points, {grid.GetNumberOfCells()} cells")
    return 0


if __name__ == "__main__":
    if len(sys.argv) != 4:
        print(__doc__)
        sys.exit(2)
    sys.exit(main(sys.argv[1], sys.argv[2], int(sys.argv[3])))

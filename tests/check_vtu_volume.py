#!/usr/bin/env python3
"""Checks a mode-shape file of hexahedral cells without VTK's Python module
(doc/user-guide.md, "Mode shapes"): python3 check_vtu_volume.py <file.vtu>
<cells> <volume>

Every cell must be an 8-node hexahedron (VTK type 12), every point must be
used by a cell, every cell's corner parallelepiped (edges 0-1, 0-3, 0-4)
must have positive volume, and on a mesh of straight-edged bricks in an
axis-aligned box the cells' volumes must add up to <volume> within 1e-12
relative (rounding of a few thousand products). A Lagrange brick of order k
is written as k^3 such cells (packages/io/src/ModeShapeFiles.cpp): a node
out of place folds a cell (negative volume) or leaves a gap or an overlap
(the sum is off). Exit 0 on success, 1 on a failed check.
"""
import sys
import xml.etree.ElementTree as ET


def main():
    path, cells, volume = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
    root = ET.parse(path).getroot()
    arrays = {}
    for a in root.iter("DataArray"):
        arrays.setdefault(a.get("Name"), a)
    coords = [float(x) for x in root.find(".//Points/DataArray").text.split()]
    points = [coords[3 * i:3 * i + 3] for i in range(len(coords) // 3)]
    conn = [int(x) for x in arrays["connectivity"].text.split()]
    offsets = [int(x) for x in arrays["offsets"].text.split()]
    types = [x for x in arrays["types"].text.split()]
    failures = []
    if len(offsets) != cells:
        failures.append(f"{len(offsets)} cells, expected {cells}")
    if set(types) != {"12"} or offsets != [8 * (c + 1) for c in range(len(offsets))]:
        failures.append("not every cell is an 8-node hexahedron")
    if len(set(conn)) != len(points):
        failures.append(f"{len(set(conn))} of {len(points)} points used by the cells")

    def sub(a, b):
        return [a[i] - b[i] for i in range(3)]

    total, folded = 0.0, 0
    for c in range(len(conn) // 8):
        v = [points[conn[8 * c + k]] for k in range(8)]
        a, b, d = sub(v[1], v[0]), sub(v[3], v[0]), sub(v[4], v[0])
        det = (a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0])
               + a[2] * (b[0] * d[1] - b[1] * d[0]))
        folded += det <= 0
        total += det
    if folded:
        failures.append(f"{folded} cells with non-positive volume")
    if abs(total - volume) > 1e-12 * volume:
        failures.append(f"cells' volume {total!r}, expected {volume!r}")
    print(f"{path}: {len(offsets)} hexahedra, {len(points)} points, volume {total!r}")
    for f in failures:
        print("check_vtu_volume:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Reads back the VTK files of a cdpowder output folder with an XML parser of Python's
standard library and checks them against particles.csv and contacts.csv: every array has
the declared length, points are the sphere centres, radii match, the contact network
holds exactly the closed contacts with force and normal vectors that agree with their
normal and tangential forces, and the walls (the cell's edges, the bottom wall and the
piston) are where they belong. Usage: check_vtk.py OUTPUT_DIR. Exit status 0 = valid.
"""
import base64
import csv
import json
import math
import struct
import sys
import xml.etree.ElementTree as ET
from pathlib import Path


def fail(message):
    print(f"check_vtk: {message}", file=sys.stderr)
    sys.exit(1)


BINARY_TYPES = {"Float64": "d", "Int64": "q", "Int32": "i"}


def array_values(path, root, array):
    """The values of a <DataArray>: inline text (format="ascii") or, for format="appended",
    its block in the base64 <AppendedData>: the byte count (UInt64) and the bytes, encoded
    as one block starting at the array's offset."""
    if array.get("format") == "ascii":
        return [float(v) for v in (array.text or "").split()]
    if array.get("format") != "appended":
        fail(f"{path}: array {array.get('Name')} has format {array.get('format')}")
    appended = root.find("AppendedData")
    if appended is None or appended.get("encoding") != "base64" or \
            root.get("header_type") != "UInt64" or root.get("byte_order") != "LittleEndian":
        fail(f"{path}: expected base64 appended data with UInt64 little-endian headers")
    text = (appended.text or "").strip()
    if not text.startswith("_"):
        fail(f"{path}: appended data does not start with '_'")
    start = 1 + int(array.get("offset"))
    (size,) = struct.unpack("<Q", base64.b64decode(text[start:start + 12])[:8])
    chars = 4 * ((8 + size + 2) // 3)
    block = base64.b64decode(text[start:start + chars])
    code = BINARY_TYPES.get(array.get("type"))
    if code is None or len(block) < 8 + size or size % struct.calcsize(code) != 0:
        fail(f"{path}: array {array.get('Name')}: a block of {size} bytes of {array.get('type')}")
    count = size // struct.calcsize(code)
    return [float(v) for v in struct.unpack(f"<{count}{code}", block[8:8 + size])]


def read_polydata(path):
    """Returns (piece attributes, {array name: list of tuples}) of a .vtp file."""
    root = ET.parse(path).getroot()
    if root.tag != "VTKFile" or root.get("type") != "PolyData":
        fail(f"{path}: not a VTK PolyData file")
    piece = root.find("PolyData/Piece")
    if piece is None:
        fail(f"{path}: no Piece")
    arrays = {}
    for array in piece.iter("DataArray"):
        components = int(array.get("NumberOfComponents", "1"))
        values = array_values(path, root, array)
        if len(values) % components != 0:
            fail(f"{path}: array {array.get('Name')} has {len(values)} values, "
                 f"not a multiple of {components}")
        arrays[array.get("Name")] = [tuple(values[i:i + components])
                                     for i in range(0, len(values), components)]
    return piece.attrib, arrays


def check_cells(path, arrays, cells, size):
    """Connectivity 0, 1, 2, … and end offsets size, 2 size, … of `cells` cells."""
    connectivity = [int(v[0]) for v in arrays.get("connectivity", [])]
    offsets = [int(v[0]) for v in arrays.get("offsets", [])]
    if connectivity != list(range(cells * size)):
        fail(f"{path}: connectivity is not 0 … {cells * size - 1}")
    if offsets != [(k + 1) * size for k in range(cells)]:
        fail(f"{path}: offsets are not the ends of {cells} cells of {size} points")


def read_cell_sections(path):
    """{section: (connectivity, offsets)} of the Verts, Lines and Polys of a .vtp file."""
    root = ET.parse(path).getroot()
    piece = root.find("PolyData/Piece")
    sections = {}
    for name in ("Verts", "Lines", "Polys"):
        section = piece.find(name)
        if section is None:
            continue
        arrays = {a.get("Name"): [int(v) for v in array_values(path, root, a)]
                  for a in section.iter("DataArray")}
        sections[name] = (arrays.get("connectivity", []), arrays.get("offsets", []))
    return sections


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def check_particles(out):
    spheres = read_csv(out / "particles.csv")
    attributes, arrays = read_polydata(out / "particles.vtp")
    n = len(spheres)
    if int(attributes["NumberOfPoints"]) != n or int(attributes["NumberOfVerts"]) != n:
        fail(f"particles.vtp: {attributes['NumberOfPoints']} points for {n} spheres")
    for name in ("Points", "id", "radius", "velocity", "angular_velocity", "coordination",
                 "connectivity", "offsets"):
        if len(arrays.get(name, [])) != n:
            fail(f"particles.vtp: array {name} has {len(arrays.get(name, []))} entries, not {n}")
    check_cells("particles.vtp", arrays, n, 1)
    for i, row in enumerate(spheres):
        centre = (float(row["x"]), float(row["y"]), float(row["z"]))
        if any(abs(a - b) > 1e-6 * max(1.0, abs(b)) for a, b in zip(arrays["Points"][i], centre)):
            fail(f"particles.vtp: point {i} is {arrays['Points'][i]}, particles.csv says {centre}")
        if abs(arrays["radius"][i][0] - float(row["r"])) > 1e-9:
            fail(f"particles.vtp: radius {i} differs from particles.csv")
    return n


def check_contacts(out):
    rows = read_csv(out / "contacts.csv")
    closed = [r for r in rows if r["state"] == "closed"]
    attributes, arrays = read_polydata(out / "contacts.vtp")
    lines = int(attributes["NumberOfLines"])
    if lines != len(closed):
        fail(f"contacts.vtp: {lines} lines, contacts.csv has {len(closed)} closed contacts")
    if int(attributes["NumberOfPoints"]) != 2 * lines or len(arrays.get("Points", [])) != 2 * lines:
        fail("contacts.vtp: expected two points per line")
    check_cells("contacts.vtp", arrays, lines, 2)
    for name in ("normal_force", "force", "normal", "tensile", "tangential_force", "cohesive",
                 "kind"):
        if len(arrays.get(name, [])) != lines:
            fail(f"contacts.vtp: cell array {name} has the wrong length")
    for k in range(lines):
        force = arrays["normal_force"][k][0]
        if int(arrays["tensile"][k][0]) != (1 if force < 0 else 0):
            fail(f"contacts.vtp: line {k} tensile flag disagrees with its force {force}")
        # the vectors: n a unit vector, R = R_n n + R_t with R_t ⟂ n and |R_t| the tangential force
        n, vector = arrays["normal"][k], arrays["force"][k]
        if abs(math.hypot(*n) - 1.0) > 1e-6:
            fail(f"contacts.vtp: line {k} normal {n} is not a unit vector")
        along = sum(a * b for a, b in zip(vector, n))
        across = math.hypot(*(v - along * c for v, c in zip(vector, n)))
        scale = max(1.0, abs(force), arrays["tangential_force"][k][0])
        if abs(along - force) > 1e-6 * scale or \
                abs(across - arrays["tangential_force"][k][0]) > 1e-6 * scale:
            fail(f"contacts.vtp: line {k} force {vector} disagrees with its normal force {force} "
                 f"and tangential force {arrays['tangential_force'][k][0]}")
        a, b = arrays["Points"][2 * k], arrays["Points"][2 * k + 1]
        if math.dist(a, b) > 2.5:  # at most R_a + R_b (+ d_coh) for unit spheres
            fail(f"contacts.vtp: line {k} spans {math.dist(a, b)} R: wrong periodic image?")
    forces_csv = sorted(float(r["normal_force"]) for r in closed)
    forces_vtp = sorted(f[0] for f in arrays["normal_force"])
    if any(abs(x - y) > 1e-6 * max(1.0, abs(x)) for x, y in zip(forces_csv, forces_vtp)):
        fail("contacts.vtp: normal forces differ from contacts.csv")
    return lines


def check_walls(path, piston_height=None):
    """The cell's four vertical edges, then the bottom wall and the piston as squares."""
    attributes, arrays = read_polydata(path)
    polys = int(attributes["NumberOfPolys"])
    if int(attributes["NumberOfLines"]) != 4 or polys not in (0, 1, 2):
        fail(f"{path}: expected 4 cell edges and at most 2 planes")
    if int(attributes["NumberOfPoints"]) != 8 + 4 * polys:
        fail(f"{path}: expected 8 + 4 × {polys} points")
    sections = read_cell_sections(path)
    if sections["Lines"] != (list(range(8)), [2, 4, 6, 8]):
        fail(f"{path}: the cell edges are not lines of points 0 … 7")
    if sections["Polys"] != (list(range(8, 8 + 4 * polys)), [4 * (k + 1) for k in range(polys)]):
        fail(f"{path}: the planes are not squares of the points after the edges")
    kinds = [int(k[0]) for k in arrays["kind"]]
    if kinds[:4] != [2, 2, 2, 2] or not set(kinds[4:]) <= {0, 1} or len(kinds) != 4 + polys:
        fail(f"{path}: kinds {kinds}: expected four edges (2), then bottom (0) and piston (1)")
    points = arrays["Points"]
    for k, kind in enumerate(kinds[4:]):
        heights = {p[2] for p in points[8 + 4 * k: 12 + 4 * k]}
        expected = 0.0 if kind == 0 else piston_height
        # the files hold 9 significant digits
        if len(heights) != 1 or (expected is not None and
                                 abs(heights.pop() - expected) > 1e-8 * max(1.0, abs(expected))):
            fail(f"{path}: plane {k} (kind {kind}) is not flat at z = {expected}")
    return polys


def check_collection(out):
    pvd = out / "particles.pvd"
    if not pvd.exists():
        return 0
    root = ET.parse(pvd).getroot()
    datasets = root.findall("Collection/DataSet")
    times = [float(d.get("timestep")) for d in datasets]
    if times != sorted(times):
        fail("particles.pvd: time steps are not increasing")
    for d in datasets:
        read_polydata(out / d.get("file"))
    for d in ET.parse(out / "contacts.pvd").getroot().findall("Collection/DataSet"):
        read_polydata(out / d.get("file"))
    walls = ET.parse(out / "walls.pvd").getroot().findall("Collection/DataSet")
    if [float(d.get("timestep")) for d in walls] != times:
        fail("walls.pvd: not the time steps of particles.pvd")
    for d in walls:
        check_walls(out / d.get("file"))
    return len(datasets)


def main():
    if len(sys.argv) != 2:
        fail("usage: check_vtk.py OUTPUT_DIR")
    out = Path(sys.argv[1])
    spheres = check_particles(out)
    lines = check_contacts(out)
    # the final piston, from the summary the run wrote with the files
    summary = json.loads((out / "summary.json").read_text())
    piston = summary.get("piston", {})
    planes = check_walls(out / "walls.vtp",
                         piston.get("height") if piston.get("enabled") else None)
    snapshots = check_collection(out)
    print(f"check_vtk: {spheres} spheres, {lines} contact lines, {planes} wall planes, "
          f"{snapshots} snapshots: valid")


if __name__ == "__main__":
    main()

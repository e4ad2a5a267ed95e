#!/usr/bin/env python3
"""The VTK files of a short compaction, read back with VTK itself (Debian's python3-vtk9), in
the three formats (run.vtk_format = "ascii", "binary" and "zlib"), and the README's glyph recipe
run on them; the default ("auto") on deposits of 9 999 and 10 000 spheres.

    vtk_readback_test.py --cdpowder BIN --source-dir DIR

Checks: VTK's own reader loads particles.vtp, contacts.vtp and walls.vtp of every format with
the arrays the files declare; the binary files hold the ASCII files' values (which have 9
significant digits) and the exact sphere centres of particles.csv; the zlib-compressed files
hold the binary files' values to the last bit; the README's recipe (Glyph
filter, sphere glyphs of radius 0.5, scaled by the "radius" array with a scale factor of 2)
draws every sphere at its true radius (every vertex of a glyph at distance r from its centre); walls.vtp holds
the cell's four edges and the bottom wall and the piston, the piston at the summary's height.
Exit status 0 = all hold.
"""
import argparse
import csv
import json
import subprocess
import sys
import tempfile
from pathlib import Path

try:
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
except ImportError:
    print("vtk_readback_test: needs VTK's Python module: apt-get install python3-vtk9 "
          "(tools/install_deps.sh installs it)", file=sys.stderr)
    sys.exit(1)
import numpy as np


def fail(message):
    print(f"vtk_readback_test: {message}", file=sys.stderr)
    sys.exit(1)


def read_vtp(path):
    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(str(path))
    reader.Update()
    if reader.GetErrorCode() != 0 or reader.GetOutput().GetNumberOfPoints() == 0:
        fail(f"{path}: VTK could not read it")
    return reader.GetOutput()


def arrays_of(data):
    """{name: numpy array} of the point and cell data."""
    out = {}
    for attributes in (data.GetPointData(), data.GetCellData()):
        for i in range(attributes.GetNumberOfArrays()):
            out[attributes.GetArrayName(i)] = vtk_to_numpy(attributes.GetArray(i)).astype(float)
    out["Points"] = vtk_to_numpy(data.GetPoints().GetData()).astype(float)
    return out


def compact(cdpowder, source, out, vtk_format):
    command = [cdpowder, "compact", str(source / "examples/quick/scene.toml"), "--out", str(out),
               "--quiet", "--set", "run.max_duration=20", "--set", "run.snapshot_every=200",
               "--set", f'run.vtk_format="{vtk_format}"']
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode not in (0, 4):  # 4: not blocked within the short duration
        fail(f"{' '.join(command)} exited {result.returncode}: {result.stderr}")


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


def check_same_values(ascii_dir, binary_dir):
    for name in ("particles.vtp", "contacts.vtp", "walls.vtp"):
        a = arrays_of(read_vtp(ascii_dir / name))
        b = arrays_of(read_vtp(binary_dir / name))
        if set(a) != set(b):
            fail(f"{name}: the ASCII file has arrays {sorted(a)}, the binary one {sorted(b)}")
        for key in a:
            if a[key].shape != b[key].shape:
                fail(f"{name}: {key} has shape {a[key].shape} in ASCII, {b[key].shape} in binary")
            scale = np.maximum(1.0, np.abs(b[key]))
            if a[key].size and np.max(np.abs(a[key] - b[key]) / scale) > 1e-8:
                fail(f"{name}: {key} differs between the ASCII and the binary file")
    # binary: the centres of particles.csv to the last bit
    spheres = read_csv(binary_dir / "particles.csv")
    centres = np.array([[float(r["x"]), float(r["y"]), float(r["z"])] for r in spheres])
    points = arrays_of(read_vtp(binary_dir / "particles.vtp"))["Points"]
    if not np.array_equal(points, centres):
        fail("particles.vtp (binary): the points are not the centres of particles.csv")
    return len(spheres)


def check_same_bits(binary_dir, zlib_dir):
    for name in ("particles.vtp", "contacts.vtp", "walls.vtp"):
        a = arrays_of(read_vtp(binary_dir / name))
        b = arrays_of(read_vtp(zlib_dir / name))
        if set(a) != set(b) or any(not np.array_equal(a[key], b[key]) for key in a):
            fail(f"{name}: the zlib-compressed file does not hold the binary file's values")


def check_glyphs(out):
    """The README's recipe: sphere glyphs (radius 0.5) scaled by "radius" × 2."""
    particles = read_vtp(out / "particles.vtp")
    source = vtk.vtkSphereSource()  # ParaView's sphere glyph: radius 0.5
    glyph = vtk.vtkGlyph3D()
    glyph.SetInputData(particles)
    glyph.SetSourceConnection(source.GetOutputPort())
    glyph.SetInputArrayToProcess(0, 0, 0, vtk.vtkDataObject.FIELD_ASSOCIATION_POINTS, "radius")
    glyph.SetScaleModeToScaleByScalar()
    glyph.SetScaleFactor(2.0)
    glyph.OrientOff()
    glyph.Update()
    drawn = vtk_to_numpy(glyph.GetOutput().GetPoints().GetData())
    source.Update()
    per_glyph = source.GetOutput().GetNumberOfPoints()
    arrays = arrays_of(particles)
    n = len(arrays["radius"])
    if len(drawn) != n * per_glyph:
        fail(f"the glyph filter drew {len(drawn)} points for {n} spheres of {per_glyph}")
    # the sphere source's vertices lie on its sphere, so a glyph at the true radius has every
    # vertex at distance r from the centre (its bounds are a polygon's, a little inside)
    for i in range(n):
        glyph_points = drawn[i * per_glyph:(i + 1) * per_glyph]
        radius, centre = arrays["radius"][i], arrays["Points"][i]
        distances = np.linalg.norm(glyph_points - centre, axis=1)
        if np.max(np.abs(distances - radius)) > 1e-5 * radius:
            fail(f"sphere {i}: its glyph's vertices are {distances.min()} … {distances.max()} "
                 f"from its centre, its radius is {radius}")
    return n


def check_walls(out):
    walls = read_vtp(out / "walls.vtp")
    kinds = arrays_of(walls)["kind"].astype(int).tolist()
    if kinds != [2, 2, 2, 2, 0, 1]:
        fail(f"walls.vtp: cell kinds {kinds}, expected four edges, the bottom wall and the piston")
    piston = json.loads((out / "summary.json").read_text())["piston"]["height"]
    plane = vtk.vtkIdList()
    walls.GetCellPoints(5, plane)
    heights = {walls.GetPoint(plane.GetId(k))[2] for k in range(plane.GetNumberOfIds())}
    # (ASCII files hold 9 significant digits)
    if len(heights) != 1 or abs(heights.pop() - piston) > 1e-8 * piston:
        fail(f"walls.vtp: the piston is not drawn flat at z = {piston}, the summary's height")


def check_auto_format(cdpowder, source, scratch):
    """run.vtk_format = "auto" (the default): text below 10 000 spheres, zlib from there on,
    read back by VTK with every sphere."""
    for spheres, compressed in ((9999, False), (10000, True)):
        out = Path(scratch) / f"auto_{spheres}"
        command = [cdpowder, "deposit", str(source / "examples/paper/scene.toml"), "--out",
                   str(out), "--quiet", "--set", f"deposition.spheres={spheres}",
                   "--set", "system.lx=80", "--set", "system.ly=80"]
        result = subprocess.run(command, capture_output=True, text=True)
        if result.returncode != 0:
            fail(f"{' '.join(command)} exited {result.returncode}: {result.stderr}")
        text = (out / "particles.vtp").read_bytes()
        if (b'compressor="vtkZLibDataCompressor"' in text) != compressed:
            fail(f"{out}/particles.vtp: {spheres} spheres should be "
                 f"{'zlib' if compressed else 'text'} by default")
        if read_vtp(out / "particles.vtp").GetNumberOfPoints() != spheres:
            fail(f"{out}/particles.vtp: VTK does not read {spheres} spheres")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cdpowder", required=True)
    parser.add_argument("--source-dir", required=True, type=Path)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="cdpowder_vtk_") as scratch:
        dirs = {f: Path(scratch) / f for f in ("ascii", "binary", "zlib")}
        for vtk_format, out in dirs.items():
            compact(args.cdpowder, args.source_dir, out, vtk_format)
        spheres = check_same_values(dirs["ascii"], dirs["binary"])
        check_same_bits(dirs["binary"], dirs["zlib"])
        for out in dirs.values():
            check_glyphs(out)
            check_walls(out)
        check_auto_format(args.cdpowder, args.source_dir, scratch)
    print(f"vtk_readback_test: {spheres} spheres; VTK reads the three formats alike, the "
          "glyphs and walls are where they belong, and \"auto\" compresses from 10 000 spheres")


if __name__ == "__main__":
    main()

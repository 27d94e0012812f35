"""The FE formats snert writes, read back by readers that are not snert's: meshio for Gmsh MSH
4.1 and Abaqus INP, VTK's own legacy reader for .vtk. Each must give the same vertex and
triangle counts, the same coordinates and the same triangles as the OFF file of the same mesh
(exact: OFF, MSH and INP write every float coordinate as the double it is), and the .vtk's cell
arrays must hold what their names say: quality and angles recomputed here from the coordinates,
and distances whose mean is the face accuracy `snert compare` reports. $SNERT is the binary."""

import json
import os
import subprocess
import sys
import tempfile

import meshio
import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOLegacy import vtkPolyDataReader

SNERT = os.environ["SNERT"]
INPUT = ["phantom:sphere", "--size", "24", "--iterations", "10"]
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


def snert(*args):
    subprocess.run([SNERT, *args], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)


def read_off(path):
    with open(path) as f:
        words = f.read().split()
    assert words[0] == "OFF"
    v, t = int(words[1]), int(words[2])
    points = np.array(words[4:4 + 3 * v], dtype=float).reshape(v, 3)
    faces = np.array(words[4 + 3 * v:], dtype=np.int64).reshape(t, 4)
    assert (faces[:, 0] == 3).all()
    return points, faces[:, 1:]


def triangles_of(mesh):
    blocks = [c for c in mesh.cells if c.type == "triangle"]
    check(len(mesh.cells) == 1 and len(blocks) == 1, "one block of triangles")
    return blocks[0].data


def same_mesh(what, points, triangles, ref_points, ref_triangles, exact=True):
    check(points.shape == ref_points.shape, f"{what}: {len(points)} points, "
          f"want {len(ref_points)}")
    check(triangles.shape == ref_triangles.shape, f"{what}: {len(triangles)} triangles, "
          f"want {len(ref_triangles)}")
    if points.shape == ref_points.shape:
        if exact:
            check((points == ref_points).all(), f"{what}: coordinates differ")
        else:  # float32 in the file: the same floats
            check((points.astype(np.float32) == ref_points.astype(np.float32)).all(),
                  f"{what}: coordinates differ")
    if triangles.shape == ref_triangles.shape:
        check((triangles == ref_triangles).all(), f"{what}: triangles differ")


def angles_deg(points, triangles):
    p = points[triangles]  # (T, 3 corners, 3)
    result = []
    for k in range(3):
        u = p[:, (k + 1) % 3] - p[:, k]
        v = p[:, (k + 2) % 3] - p[:, k]
        cross = np.linalg.norm(np.cross(u, v), axis=1)
        result.append(np.degrees(np.arctan2(cross, (u * v).sum(axis=1))))
    return np.stack(result, axis=1)


def main():
    with tempfile.TemporaryDirectory() as tmp:
        out = lambda name: os.path.join(tmp, name)
        for ext in ["off", "msh", "inp", "vtk"]:
            snert("export", *INPUT, "--method", "snert", "--out", out("m." + ext))
        snert("export", *INPUT, "--method", "snert", "--abaqus-element", "sfm3d3",
              "--out", out("sfm.inp"))
        snert("compare", *INPUT, "--mode", "snert", "--json", out("c.json"))
        ref_points, ref_triangles = read_off(out("m.off"))
        check(len(ref_triangles) > 1000, "the sphere has triangles")

        msh = meshio.read(out("m.msh"))
        same_mesh("msh", msh.points, triangles_of(msh), ref_points, ref_triangles)
        check("snert" in msh.field_data and list(msh.field_data["snert"]) == [1, 2],
              f"msh: physical surface 'snert' (tag 1, dim 2), got {msh.field_data}")
        physical = msh.cell_data.get("gmsh:physical")
        check(physical is not None and (physical[0] == 1).all(),
              "msh: every triangle in physical group 1")

        inp = meshio.read(out("m.inp"), file_format="abaqus")
        same_mesh("inp", inp.points, triangles_of(inp), ref_points, ref_triangles)
        check("snert" in inp.cell_sets, f"inp: ELSET snert, got {list(inp.cell_sets)}")
        with open(out("m.inp")) as s3, open(out("sfm.inp")) as sfm:
            check(sfm.read() == s3.read().replace("TYPE=S3", "TYPE=SFM3D3"),
                  "inp: --abaqus-element sfm3d3 changes the element type only")

        reader = vtkPolyDataReader()
        reader.SetFileName(out("m.vtk"))
        reader.ReadAllScalarsOn()
        reader.Update()
        poly = reader.GetOutput()
        points = vtk_to_numpy(poly.GetPoints().GetData()).astype(float)
        polys = vtk_to_numpy(poly.GetPolys().GetData()).reshape(-1, 4)
        check((polys[:, 0] == 3).all(), "vtk: triangles only")
        same_mesh("vtk", points, polys[:, 1:], ref_points, ref_triangles, exact=False)
        cells = poly.GetCellData()
        arrays = {cells.GetArrayName(i): vtk_to_numpy(cells.GetArray(i))
                  for i in range(cells.GetNumberOfArrays())}
        check(sorted(arrays) == ["distance", "max_angle", "min_angle", "quality"],
              f"vtk: cell arrays {sorted(arrays)}")
        if len(arrays) == 4 and len(ref_triangles) == len(arrays["quality"]):
            angles = angles_deg(ref_points, ref_triangles)
            smallest, largest = angles.min(axis=1), angles.max(axis=1)
            check(np.abs(arrays["min_angle"] - smallest).max() < 1e-3, "vtk: min_angle")
            check(np.abs(arrays["max_angle"] - largest).max() < 1e-3, "vtk: max_angle")
            check(np.abs(arrays["quality"] - smallest / largest).max() < 1e-5, "vtk: quality")
            with open(out("c.json")) as f:
                report = json.load(f)
            faces = report["snert"]["accuracy_faces"]
            mean = float(arrays["distance"].astype(float).mean())
            check((arrays["distance"] >= 0).all(), "vtk: distances are unsigned")
            check(abs(mean - faces) <= 1e-4 * faces + 1e-7,
                  f"vtk: mean distance {mean} is not compare's accuracy_faces {faces}")
    if failures:
        print(f"{len(failures)} failures")
        return 1
    print("fe_formats: msh, inp and vtk read back by meshio and VTK")
    return 0


if __name__ == "__main__":
    sys.exit(main())

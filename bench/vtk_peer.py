#!/usr/bin/python3
"""The peer of snert_bench: VTK's vtkFlyingEdges3D, single-threaded, on the volumes snert_bench
times. Prints one JSON object: per case, the median wall time of 5 runs (ms) after an untimed one, and
the triangles.

    vtk_peer.py [--ct CT.nrrd] [--size 256] [--runs 5]

The sphere is snert's phantom (src/core/phantom.cpp): size^3 float32 samples
r - |p - c|, c = (size - 1) / 2 per axis, r = 0.35 size, iso 0. The CT is read with
vtkNrrdReader and contoured at 200 (bone) and -500 (skin). Only the geometry is asked for
(no normals, gradients or scalars: snert's Marching Cubes makes positions and indices only).
Needs Debian's python3-vtk9 and python3-numpy.
"""
import argparse, json, statistics, time

import numpy as np
# Only the modules used: `import vtk` loads every module, and vtkIOParallel's factory then turns
# vtkNrrdReader into vtkPNrrdReader, which fails without an MPI controller.
from vtkmodules.vtkCommonCore import vtkMultiThreader, vtkSMPTools, vtkVersion
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkFiltersCore import vtkFlyingEdges3D
from vtkmodules.vtkIOImage import vtkNrrdReader
from vtkmodules.util import numpy_support as ns


def sphere_image(size):
    c = (size - 1) * 0.5
    r = 0.35 * size
    i = np.arange(size, dtype=np.float64) - c
    z, y, x = np.meshgrid(i, i, i, indexing="ij")  # x fastest in C order, as snert stores it
    a = (r - np.sqrt(x * x + y * y + z * z)).astype(np.float32)
    image = vtkImageData()
    image.SetDimensions(size, size, size)
    arr = ns.numpy_to_vtk(a.ravel(), deep=1)
    arr.SetName("scalars")
    image.GetPointData().SetScalars(arr)
    return image


def time_fe(image, iso, runs):
    times, triangles = [], 0
    for run in range(runs + 1):  # the first untimed, as snert bench's runs in kept memory
        fe = vtkFlyingEdges3D()
        fe.SetInputData(image)
        fe.SetValue(0, iso)
        fe.ComputeNormalsOff()
        fe.ComputeGradientsOff()
        fe.ComputeScalarsOff()
        t0 = time.perf_counter()
        fe.Update()
        if run > 0:
            times.append((time.perf_counter() - t0) * 1e3)
        triangles = fe.GetOutput().GetNumberOfCells()
        del fe
    return {"ms": statistics.median(times), "runs_ms": times, "triangles": triangles}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ct")
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--runs", type=int, default=5)
    args = ap.parse_args()

    vtkSMPTools.Initialize(1)
    vtkMultiThreader.SetGlobalMaximumNumberOfThreads(1)
    out = {"vtk": vtkVersion.GetVTKVersion(), "smp_backend": vtkSMPTools.GetBackend(),
           "threads": vtkSMPTools.GetEstimatedNumberOfThreads(), "cases": {}}

    out["cases"][f"sphere{args.size}/iso:0"] = time_fe(sphere_image(args.size), 0.0, args.runs)
    if args.ct:
        reader = vtkNrrdReader()
        reader.SetFileName(args.ct)
        reader.Update()
        image = reader.GetOutput()
        out["ct_dims"] = list(image.GetDimensions())
        for iso in (200, -500):
            out["cases"][f"ct/iso:{iso}"] = time_fe(image, float(iso), args.runs)
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()

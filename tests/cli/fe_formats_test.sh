#!/usr/bin/env bash
# The FE formats read back by independent readers: meshio for Gmsh MSH 4.1 and Abaqus INP, VTK
# for the legacy .vtk with its cell data (fe_formats_test.py). $SNERT is the binary. Runs the
# first Python 3 that has both modules (Debian's python3-meshio and python3-vtk9 install into
# the system interpreter, which another python3 earlier on PATH may hide); exit 77 (skipped)
# when none has them.
set -u
here=$(cd "$(dirname "$0")" && pwd)
for python in python3 /usr/bin/python3; do
    if command -v "$python" >/dev/null &&
        "$python" -c "import meshio, numpy, vtkmodules.vtkIOLegacy" 2>/dev/null; then
        exec "$python" "$here/fe_formats_test.py"
    fi
done
echo "fe_formats: no Python 3 with meshio and vtk (Debian python3-meshio, python3-vtk9), skipped"
exit 77

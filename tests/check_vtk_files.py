#!/usr/bin/env python3
"""ParaView-readiness of a driver's output: runs EXE (a driver) with ARGS into OUT, then reads
every .vtu, .vtp and .pvd file there with VTK's own XML readers (Debian's python3-vtk9) and
checks that each has points, cells and arrays, that every data array has one tuple per point or
cell, that no value is NaN, that sub-contact files carry every declared law state field, that every file is in the reference configuration with a
"displacement" point array, and that each quantity has one name across files.
    check_vtk_files.py EXE OUT [ARGS...]
Prints "skipped" and exits 0 when the vtk module is missing (the packaged CI installs it)."""
import math
import os
import subprocess
import sys

try:
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
except ImportError:
    print("check_vtk_files: python3-vtk9 is not installed; skipped")
    sys.exit(0)

exe, out, args = sys.argv[1], sys.argv[2], sys.argv[3:]
subprocess.run([exe, *args, "--out", out], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
files = sorted(f for f in os.listdir(out) if f.endswith((".vtu", ".vtp", ".pvd")))
assert any(f.endswith(".vtu") for f in files) and any(f.endswith(".vtp") for f in files), files
synonyms = {"damage": "tensile_damage", "opening_m": "u_n_m"}  # names that would split one quantity across files
# Sub-contact files carry every field law::cohesive_frictional declares (io/vtk_contacts.hpp).
contact_arrays = ["normal", "area_m2", "status", "tensile_damage", "sigma_n_Pa", "tau_Pa", "u_n_m", "u_p_m",
                  "u_soft_m", "dissipated_tension_J_per_m2", "dissipated_shear_J_per_m2",
                  "dissipated_compression_J_per_m2"]
failures = []
for name in files:
    path = os.path.join(out, name)
    if name.endswith(".pvd"):
        # A series: every data set it names exists and is read below.
        import xml.etree.ElementTree as ET
        for ds in ET.parse(path).getroot().iter("DataSet"):
            if not os.path.exists(os.path.join(out, ds.get("file"))):
                failures.append(f"{name}: names missing file {ds.get('file')}")
        continue
    reader = vtk.vtkXMLUnstructuredGridReader() if name.endswith(".vtu") else vtk.vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    data = reader.GetOutput()
    points, cells = data.GetNumberOfPoints(), data.GetNumberOfCells()
    if points == 0 or cells == 0:
        failures.append(f"{name}: {points} points, {cells} cells")
        continue
    for kind, fields, count in (("point", data.GetPointData(), points), ("cell", data.GetCellData(), cells)):
        for k in range(fields.GetNumberOfArrays()):
            array = fields.GetArray(k)
            label = f"{name}: {kind} array {array.GetName()}"
            if array.GetName() in synonyms:
                failures.append(f"{label}: use the name {synonyms[array.GetName()]}")
            if array.GetNumberOfTuples() != count:
                failures.append(f"{label}: {array.GetNumberOfTuples()} tuples for {count} {kind}s")
            values = vtk_to_numpy(array).ravel()
            if values.dtype.kind == "f" and any(math.isnan(v) for v in values):
                failures.append(f"{label}: NaN")
    if "contacts" in name:
        for required in contact_arrays:
            if data.GetPointData().GetArray(required) is None:
                failures.append(f"{name}: no point array '{required}'")
    if data.GetPointData().GetArray("displacement") is None:
        failures.append(f"{name}: no point array 'displacement' (reference configuration + displacement)")
    print(f"{name}: {points} points, {cells} cells, {data.GetPointData().GetNumberOfArrays()} point and "
          f"{data.GetCellData().GetNumberOfArrays()} cell arrays")
if failures:
    print("\n".join(failures))
    sys.exit(1)
print(f"check_vtk_files: {len(files)} files read with VTK {vtk.vtkVersion.GetVTKVersion()}")

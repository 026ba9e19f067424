"""Opens a Tumble XDMF series with ParaView's reader (run by pvpython) and checks what it sees.
Usage: pvpython open_in_paraview.py SNAPSHOTS.xdmf N_EXPECTED_TIMESTEPS"""
import sys

from paraview import servermanager
from paraview.simple import XDMFReader

reader = XDMFReader(FileNames=[sys.argv[1]])
reader.UpdatePipelineInformation()
steps = reader.TimestepValues
assert len(steps) == int(sys.argv[2]), f"ParaView sees {len(steps)} timesteps"
reader.UpdatePipeline(steps[-1])
data = servermanager.Fetch(reader)
names = {data.GetPointData().GetArrayName(i) for i in range(data.GetPointData().GetNumberOfArrays())}
assert {"id", "species", "radius", "v", "w", "x_tumbler"} <= names, names
assert data.GetNumberOfPoints() > 1000
print("ok:", len(steps), "timesteps,", data.GetNumberOfPoints(), "points")

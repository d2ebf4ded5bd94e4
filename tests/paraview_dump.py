"""Run by pvpython (tests/test_paraview.py): open a dpmpm .xmf with ParaView's XDMF
reader and save, for every time step and block, the block name and the point arrays
(with the points) as seen by ParaView, in one .npz file.

Usage: pvpython paraview_dump.py FILE.xmf OUT.npz
"""
import sys

import numpy as np
from paraview import servermanager
from paraview.simple import XDMFReader
from vtkmodules.util.numpy_support import vtk_to_numpy

reader = XDMFReader(FileNames=[sys.argv[1]])
out = {"times": np.array(reader.TimestepValues, dtype=float)}
for k, t in enumerate(reader.TimestepValues):
    reader.UpdatePipeline(t)
    data = servermanager.Fetch(reader)
    # One set: the reader returns its cloud itself (no blocks, no name); several: one
    # named block per set, empty (None) at a time the set has no cloud.
    if data.IsA("vtkMultiBlockDataSet"):
        blocks = [(data.GetMetaData(b).Get(data.NAME()), data.GetBlock(b))
                  for b in range(data.GetNumberOfBlocks())]
    else:
        blocks = [("", data)]
    blocks = [(name, block) for name, block in blocks if block is not None]
    for b, (name, block) in enumerate(blocks):
        key = f"t{k}/b{b}"
        out[key + "/name"] = np.array(name)
        out[key + "/points"] = vtk_to_numpy(block.GetPoints().GetData())
        pd = block.GetPointData()
        for i in range(pd.GetNumberOfArrays()):
            out[key + "/" + pd.GetArrayName(i)] = vtk_to_numpy(pd.GetArray(i))
np.savez(sys.argv[2], **out)

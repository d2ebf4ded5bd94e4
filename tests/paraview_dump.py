"""Run by pvpython (tests/test_paraview.py): open a dpmpm .xmf with each of ParaView's XDMF
readers (XDMFReader, the Xdmf2 one; Xdmf3ReaderS; Xdmf3ReaderT) and save, per reader, its
time steps and, for every time step and every dataset it shows there, the names of the
blocks above and at that dataset and its point arrays (with the points), in one .npz file.

Usage: pvpython paraview_dump.py FILE.xmf OUT.npz
"""
import os
import sys

import numpy as np
from paraview import servermanager, simple
from vtkmodules.util.numpy_support import vtk_to_numpy

READERS = ("XDMFReader", "Xdmf3ReaderS", "Xdmf3ReaderT")


def leaves(data, names):
    """(block names from the root down, dataset) of every dataset under data."""
    if data is None:
        return []
    if data.IsA("vtkMultiBlockDataSet") or data.IsA("vtkMultiPieceDataSet"):
        pieces = data.IsA("vtkMultiPieceDataSet")
        found = []
        for b in range(data.GetNumberOfPieces() if pieces else data.GetNumberOfBlocks()):
            name = ""
            if data.HasMetaData(b) and data.GetMetaData(b).Has(data.NAME()):
                name = data.GetMetaData(b).Get(data.NAME())
            child = data.GetPiece(b) if pieces else data.GetBlock(b)
            found += leaves(child, names + [name])
        return found
    return [(names, data)]


def dump(reader_name, path, out):
    # The Xdmf3 readers resolve the .h5 beside the .xmf only from an absolute path.
    path = os.path.abspath(path)
    if reader_name == "XDMFReader":
        reader = simple.XDMFReader(FileNames=[path])
    else:
        reader = getattr(simple, reader_name)(FileName=[path])
    # One time step comes as a number, several as a list.
    times = reader.TimestepValues
    times = list(times) if isinstance(times, (list, tuple)) or hasattr(times, "__len__") \
        else [times]
    out[reader_name + "/times"] = np.array(times, dtype=float)
    for k, t in enumerate(times):
        reader.UpdatePipeline(t)
        found = [(names, block) for names, block in leaves(servermanager.Fetch(reader), [])
                 if block.GetNumberOfPoints() > 0]
        for b, (names, block) in enumerate(found):
            key = f"{reader_name}/t{k}/b{b}"
            out[key + "/names"] = np.array(names + [""])
            out[key + "/points"] = np.array([block.GetPoint(i)
                                             for i in range(block.GetNumberOfPoints())])
            pd = block.GetPointData()
            for i in range(pd.GetNumberOfArrays()):
                # A copy: the view would point into memory the next update frees.
                out[key + "/" + pd.GetArrayName(i)] = vtk_to_numpy(pd.GetArray(i)).copy()
    simple.Delete(reader)


out = {}
for name in READERS:
    dump(name, sys.argv[1], out)
np.savez(sys.argv[2], **out)

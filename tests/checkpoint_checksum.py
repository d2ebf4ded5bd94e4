"""The checksum of a dataset of a dpmpm checkpoint, written here from its definition in
src/base/dpmpm_checksum.f90 (not from the C code), for tests that change a checkpoint on
purpose and must stamp it again so that only the change they mean is found.

The checksum of a dataset of n columns (points: the first index of the array h5py reads, the
last of the Fortran shape) is the exclusive or over the columns j of the 64-bit FNV-1a hash of
j (8 bytes, least significant first) followed by the bytes of column j as the file stores them,
kept as a signed 64-bit attribute 'checksum' of the dataset.
"""
import numpy as np

FNV_OFFSET = 14695039346656037925
FNV_PRIME = 1099511628211
MASK = (1 << 64) - 1


def checksum(values):
    """The checksum of an array as h5py reads it (the file's byte order kept)."""
    a = np.ascontiguousarray(values)
    rows = a.reshape(a.shape[0], -1) if a.ndim > 1 else a.reshape(-1, 1)
    total = 0
    for j in range(rows.shape[0]):
        h = FNV_OFFSET
        for b in j.to_bytes(8, "little") + rows[j].tobytes():
            h = ((h ^ b) * FNV_PRIME) & MASK
        total ^= h
    return total - (1 << 64) if total >= 1 << 63 else total


def restamp(f):
    """Store the checksum of every dataset at the root of the open h5py file f."""
    for name, obj in f.items():
        if hasattr(obj, "dtype"):
            obj.attrs.create("checksum", checksum(obj[...]), dtype="<i8")

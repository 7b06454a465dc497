"""File helpers shared by the report scripts: HDF5 opened with the path in every error, atomic writes."""
import os

import h5py


def open_hdf5(path):
    """h5py.File(path) for reading; its errors name the file (h5py's own messages do not)."""
    try:
        return h5py.File(path, "r")
    except OSError as error:
        raise OSError(f"{path}: not a readable HDF5 file ({error})") from None


def write_atomically(path, text):
    """Writes PATH.tmp-<pid>, then renames it: an interrupted run never leaves a file that looks finished."""
    temporary = f"{path}.tmp-{os.getpid()}"
    with open(temporary, "w") as file:
        file.write(text)
    os.replace(temporary, path)

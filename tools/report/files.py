"""File helpers shared by the report scripts: HDF5 opened with the path in every error, atomic writes."""
import os

import h5py

# three.js as npm installs it (make report-npm; package-lock.json pins it): what the report's and the watch
# page's player draw with.
THREE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "node_modules", "three", "build", "three.cjs")


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

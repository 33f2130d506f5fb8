"""Argument checks of the package's functions: paths, 3-vectors and pose arrays, refused with a ValueError
or TypeError that names the argument before any work is done."""

import os
import numbers

import numpy as np

POSE_COLUMNS = ("time_s", "tip_x_m", "tip_y_m", "tip_z_m", "q_w", "q_x", "q_y", "q_z", "buttons", "pressure")


def path(value, name):
    """A str or os.PathLike as a str; a TypeError otherwise."""
    if isinstance(value, (str, os.PathLike)):
        return os.fspath(value)
    raise TypeError(f"{name}: expected a path (str or os.PathLike), got {type(value).__name__}")


def existing_file(value, name):
    """path(), and the file must exist (FileNotFoundError naming it)."""
    p = path(value, name)
    if not os.path.isfile(p):
        raise FileNotFoundError(f"{name}: {p}: no such file")
    return p


def vector3(value, name):
    """Three finite numbers as a tuple of floats."""
    v = np.asarray(value, dtype=float)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{name}: expected 3 finite numbers, got {value!r}")
    return tuple(float(x) for x in v)


def number(value, name):
    """A real number (not a bool) as a float."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name}: expected a number, got {value!r}")
    return float(value)


def poses(value, name):
    """An N x 10 float64 array of poses (the trace's columns: POSE_COLUMNS), C-contiguous."""
    a = np.ascontiguousarray(value, dtype=np.float64)
    if a.ndim == 1 and a.shape[0] == len(POSE_COLUMNS):
        a = a.reshape(1, len(POSE_COLUMNS))
    if a.ndim != 2 or a.shape[1] != len(POSE_COLUMNS):
        raise ValueError(f"{name}: expected an N x 10 array of poses ({', '.join(POSE_COLUMNS)}), got shape {a.shape}")
    if a.shape[0] == 0:
        raise ValueError(f"{name}: no poses")
    return a

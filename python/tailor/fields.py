"""Result fields as meshio meshes and matplotlib figures (docs/python.md, "Fields").

A field set is a dict of NumPy arrays with the mesh: "rest_positions" (num_vertices x dim) and
"elements" (num_elements x (dim + 1), int32), plus per-vertex arrays (num_vertices rows:
displacement, positions) and per-element arrays (num_elements rows: youngs_modulus, stresses).
A report's fields (Report.fields) and a functional's fields at a design (Functional.fields(z))
are such sets. A point set without "elements" (the nodes of a meshless solid) is written as one
vertex cell per point; its "samples" and "sample_*" arrays index another point set and are left
out (pass {"rest_positions": f["samples"], "displacement": f["sample_displacement"]} for those).
meshio (Debian python3-meshio) and matplotlib (python3-matplotlib) are imported only when used.
"""
from __future__ import annotations

import numpy as np

_POINT_NAMES = {"displacement", "positions", "rest_positions"}
_CELL_TYPES = {(2, 3): "triangle", (3, 4): "tetra", (2, 1): "vertex", (3, 1): "vertex"}


def _mesh(fields):
    """(points, elements): elements are one vertex cell per point for a point set (no "elements")."""
    if "rest_positions" not in fields:
        raise ValueError("these fields have no mesh or points (rest_positions); "
                         "only reports of simulate and run, and the functionals' fields(z), have one")
    points = np.asarray(fields["rest_positions"], dtype=np.float64)
    if "elements" not in fields:
        return points, np.arange(points.shape[0]).reshape(-1, 1)
    elements = np.asarray(fields["elements"])
    return points, elements


def split(fields):
    """(point_data, cell_data): the arrays of `fields` by what their rows index."""
    points, elements = _mesh(fields)
    point_set = "elements" not in fields  # its per-point arrays are point data
    point_data, cell_data = {}, {}
    for name, value in fields.items():
        if name in ("rest_positions", "elements") or not isinstance(value, np.ndarray) or value.ndim == 0:
            continue
        if name == "samples" or name.startswith("sample_"):
            continue
        rows = value.shape[0]
        if rows == points.shape[0] and (point_set or name in _POINT_NAMES or rows != elements.shape[0]):
            point_data[name] = value
        elif rows == elements.shape[0]:
            cell_data[name] = value
    return point_data, cell_data


def to_meshio(fields):
    """The fields as a meshio.Mesh: rest positions (padded to 3D), the simplices (a vertex cell
    per point for a point set), per-vertex arrays as point data and per-element arrays as cell
    data."""
    import meshio

    points, elements = _mesh(fields)
    dim = points.shape[1]
    cell_type = _CELL_TYPES.get((dim, elements.shape[1]))
    if cell_type is None:
        raise ValueError(f"no meshio cell type for {elements.shape[1]}-node elements in {dim}D")
    padded = np.zeros((points.shape[0], 3))
    padded[:, :dim] = points
    point_data, cell_data = split(fields)
    return meshio.Mesh(padded, [(cell_type, elements.astype(np.int64))],
                       point_data={k: np.ascontiguousarray(v) for k, v in point_data.items()},
                       cell_data={k: [np.ascontiguousarray(v)] for k, v in cell_data.items()})


def write(fields, path):
    """Writes the fields with meshio (the format from the file name: .vtu, .xdmf, ...)."""
    to_meshio(fields).write(str(path))


def plot(fields, name="youngs_modulus", ax=None, deformed=True):
    """A matplotlib picture of one per-element field: 2D meshes drawn whole (tripcolor, on the
    deformed shape when the fields have a displacement and deformed is true); 3D meshes as the
    elements whose centroid lies within a slab around the middle of the last axis, seen along
    it, as the CLI's PNG slices. Returns the Axes."""
    import matplotlib.pyplot as plt

    points, elements = _mesh(fields)
    if "elements" not in fields:
        raise ValueError("plot draws per-element fields of a mesh; these fields are a point set")
    values = np.asarray(fields[name])
    if values.ndim != 1 or values.shape[0] != elements.shape[0]:
        raise ValueError(f"{name!r} is not a per-element scalar field")
    if ax is None:
        ax = plt.figure().add_subplot()
    if deformed and "displacement" in fields:
        points = points + np.asarray(fields["displacement"])
    dim = points.shape[1]
    if dim == 2:
        drawn = ax.tripcolor(points[:, 0], points[:, 1], elements, facecolors=values)
    else:
        centroids = points[elements].mean(axis=1)
        middle = 0.5 * (centroids[:, -1].min() + centroids[:, -1].max())
        slab = np.abs(centroids[:, -1] - middle) <= 0.1 * np.ptp(centroids[:, -1]) + 1e-12
        drawn = ax.scatter(centroids[slab, 0], centroids[slab, 1], c=values[slab], s=12, marker="s")
    ax.set_aspect("equal")
    ax.set_title(name)
    ax.figure.colorbar(drawn, ax=ax)
    return ax


def plot_history(history, ax=None):
    """The convergence plot of tailor's PNGs: objective and gradient norm per iteration (log
    scale) from a history (a run report's "history", or scipy_minimize's result.history).
    Returns the Axes."""
    import matplotlib.pyplot as plt

    if ax is None:
        ax = plt.figure().add_subplot()
    iterations = [h["iteration"] for h in history]
    ax.semilogy(iterations, [h["objective"] for h in history], label="objective")
    ax.semilogy(iterations, [h["gradient_norm"] for h in history], label="gradient norm")
    ax.set_xlabel("iteration")
    ax.legend()
    return ax

"""tailor from Python: scenes, the command line's verbs and reduced functionals.

    import tailor
    bar = tailor.load("scenes/two_material_bar_inverse.json")   # or a dict in the scene format
    report = bar.simulate()                 # report.json of `tailor simulate`, as a dict
    u = report["fields"]["displacement"]    # NumPy (num_vertices x dim), no copy
    J = bar.functional()                    # J(z), dJ/dz, H v, bounds, taylor_test()
    result = tailor.scipy_minimize(J)       # scipy.optimize.minimize on J
    print(J.design_values(result.x))        # the moduli found

docs/python.md describes the API.
"""
from __future__ import annotations

import json
import os
import shutil
import tempfile

from . import _blas_core
from ._interpreter import EXECUTABLE as _BUILT_FOR, VERSION as _BUILT_VERSION

_blas_core.choose()  # before NumPy and the compiled module load OpenBLAS


def _interpreter_message(version, executable):
    """What an import from an interpreter other than the one the module was built for says."""
    built = ".".join(map(str, _BUILT_VERSION))
    running = ".".join(map(str, version[:2]))
    return (f"tailor's compiled module was built for Python {built} ({_BUILT_FOR}) with NumPy; "
            f"this is Python {running} ({executable}). Run it with {_BUILT_FOR}, or configure "
            f"tailor with -DPython3_EXECUTABLE={executable} and rebuild (docs/python.md)")


try:
    import numpy as np

    from ._tailor import EvaluationError, MeshError, SceneError, __version__
    from ._tailor import Functional as _Functional
    from ._tailor import DynamicFunctional as _DynamicFunctional
    from ._tailor import CellFunctional as _CellFunctional
    from ._tailor import RodFunctional as _RodFunctional
    from ._tailor import MeshlessFunctional as _MeshlessFunctional
    from ._tailor import Scene as _Scene
except ImportError as _error:
    import sys as _sys
    raise ImportError(_interpreter_message(_sys.version_info, _sys.executable) + f" [{_error}]") from _error
from . import fields
from .optimize import scipy_minimize
from .studio import studio

__all__ = [
    "CellFunctional", "DynamicFunctional", "EvaluationError", "Functional", "MeshError", "MeshlessFunctional", "Report", "RodFunctional", "Scene",
    "SceneError", "__version__",
    "fields", "gradcheck", "homogenize", "load", "modes", "run", "scipy_minimize", "simulate",
]


class Report(dict):
    """The JSON file a verb wrote (report.json, or gradcheck.json for gradcheck), as a dict.

    The bindings add one key, "fields": NumPy arrays of the result (displacement, per-element
    moduli, ...; which ones depends on the verb), views of the C++ result without copies. The
    attributes say how the verb ended: exit_code is the command line's (0 success, 1 the solve,
    check or optimization failed), ok is exit_code == 0, and out_dir is the folder the files
    are in (None when the verb wrote into a temporary folder that is gone).
    """

    def __init__(self, content, fields, exit_code, out_dir):
        super().__init__(content)
        self["fields"] = fields
        self.fields = fields
        self.exit_code = exit_code
        self.ok = exit_code == 0
        self.out_dir = out_dir

    def __repr__(self):
        keys = ", ".join(k for k in self if k != "fields")
        fields = ", ".join(self.fields) if isinstance(self.fields, dict) else ""
        return f"tailor.Report(exit_code={self.exit_code}, keys=[{keys}], fields=[{fields}])"

    def to_meshio(self):
        """The fields on the mesh as a meshio.Mesh (simulate and run reports; tailor.fields)."""
        from .fields import to_meshio
        return to_meshio(self.fields)

    def write(self, path):
        """Writes the fields with meshio (format from the file name: .vtu, .xdmf, ...), with no
        out_dir needed (tailor.fields.write)."""
        from .fields import write
        write(self.fields, path)

    def to_json(self, **kwargs):
        """The report as JSON text, fields included (arrays as nested lists); keyword arguments
        go to json.dumps (indent=1, ...)."""
        def plain(value):
            if isinstance(value, np.ndarray):
                return value.tolist()
            if isinstance(value, np.generic):
                return value.item()
            raise TypeError(f"{type(value).__name__} is not JSON serializable")
        return json.dumps(self, default=plain, **kwargs)


class _FunctionalBase:
    """What every scene kind's functional offers: J, its gradient, the state and its
    vector-Jacobian product, the design's size, x0, labels and counters, the rows of the state
    (the compiled functional is self._f)."""

    size = property(lambda self: self._f.size)
    x0 = property(lambda self: self._f.x0, doc="the initial design z0")
    design_labels = property(lambda self: self._f.design_labels, doc="one name per design variable")
    counters = property(lambda self: self._f.counters, doc="evaluations, forward and adjoint solves")
    rest_positions = property(lambda self: self._f.rest_positions, doc="the rows of state(): num_vertices x dim")

    def value(self, z):
        return self._f.value(z)

    def gradient(self, z):
        return self._f.gradient(z)

    def value_and_gradient(self, z):
        return self._f.value_and_gradient(z)

    def state(self, z):
        """The state at z as the class describes it (float64, a new array)."""
        return self._f.state(z)

    def vjp(self, z, dL_du):
        """(du/dz)^T dL_du: the design gradient of any scalar L of the state, given dL/du of the
        state's shape, by one adjoint solve (or backward pass) at z."""
        return self._f.vjp(z, np.asarray(dL_du, dtype=np.float64))


class _StaticProducts:
    """What the static equilibria's functionals (FEM and rods) add: Hessian-vector and
    Gauss-Newton products, the tangent, the Taylor test of both, the optimizer section."""

    optimizer = property(lambda self: self._f.optimizer,
                         doc="the scene's inverse.optimizer section: backend, max_iterations, tolerances")
    has_hessian_vector = property(lambda self: self._f.has_hessian_vector)
    has_gauss_newton_vector = property(lambda self: self._f.has_gauss_newton_vector,
                                       doc="whether the objective is least squares (J = |r|^2 / 2)")

    def hessian_vector_product(self, z, v):
        return self._f.hessian_vector_product(z, v)

    def gauss_newton_vector_product(self, z, v):
        """(dr/dz)^T (dr/dz) v for a least-squares objective J = |r(z)|^2 / 2: the curvature the
        newton_cg back-end uses (one tangent and one adjoint back-solve, no third derivatives);
        positive semidefinite, equal to the Hessian where r = 0."""
        return self._f.gauss_newton_vector_product(z, v)

    def jvp(self, z, dz):
        """(du/dz) dz: the state's directional derivative along dz, in the rows of state(), by
        one tangent solve."""
        return self._f.jvp(z, dz)

    def taylor_test(self, z=None, seed=None, min_rate=None, hessian=False):
        """Taylor test of J at z (default x0), as `tailor gradcheck` (docs/methods.md): a dict
        with status, passed, rate0, rate1, message, rows and table. seed and min_rate default to
        the scene's; hessian=True tests the Hessian-vector products instead."""
        return self._f.taylor_test(z=z, seed=seed, min_rate=min_rate, hessian=hessian)


class Functional(_FunctionalBase, _StaticProducts):
    """J(z) of a scene's inverse problem, as the optimizer back-ends of `tailor run` see it.

    z is the design (the scene's inverse.design: log E per variable with the log map); value,
    gradient and hessian_vector_product take NumPy vectors of length size. bounds is
    (lower, upper) or None, x0 the scene's initial design. taylor_test() is `tailor gradcheck`.
    The state is the equilibrium: state(z) gives the displacements from the rest positions,
    num_vertices x dim; vjp(z, dL_du) takes dL/du of that shape (one adjoint solve), jvp(z, dz)
    returns it (one tangent solve).
    """

    def __init__(self, scene):
        self._f = _Functional(scene._doc)
        self._name, self._source = scene.name, scene.source

    bounds = property(lambda self: self._f.bounds, doc="(lower, upper) arrays in z, or None")
    truth = property(lambda self: self._f.truth, doc="per-element true E when the scene knows it")
    poisson_ratio = property(lambda self: self._f.poisson_ratio, doc="nu per element (the scene's)")
    elements = property(lambda self: self._f.elements, doc="the mesh: num_elements x (dim + 1) vertex ids")

    def residuals(self, z):
        """r(z) of a least-squares objective, J(z) = |r(z)|^2 / 2 (float64 vector)."""
        return self._f.residuals(z)

    def objective_terms(self, z):
        """Each objective term at z as report.json's objective.terms: key, type, weight,
        coefficient and value (weighted; they sum to J(z))."""
        return self._f.objective_terms(z)

    def report(self, z):
        """A Report of the design z without running anything but its forward solve: content
        kind "design", scene, objective (value and terms), design (labels, values), mesh;
        fields design (z), design_values, youngs_modulus and poisson_ratio (per element),
        displacement and positions (per vertex), rest_positions and elements. to_meshio(),
        write(path) and to_json() work on it; exit_code 0 and out_dir None."""
        z = np.array(z, dtype=np.float64)
        value = self.value(z)
        terms = self.objective_terms(z)
        u = self.state(z)
        labels = self.design_labels
        values = self.design_values(z)
        content = {
            "kind": "design",
            "scene": {"name": self._name, "source": self._source},
            "objective": {"value": value, "terms": terms},
            "design": {"size": int(z.size), "labels": list(labels),
                       "values": values.tolist() if values.size == len(labels) else None},
            "mesh": {"vertices": int(self.rest_positions.shape[0]), "elements": int(self.elements.shape[0]),
                     "dim": int(self.rest_positions.shape[1])},
        }
        fields = {"design": z, "design_values": values, "youngs_modulus": self.youngs_modulus(z),
                  "poisson_ratio": self.poisson_ratio, "displacement": u,
                  "positions": self.rest_positions + u, "rest_positions": self.rest_positions,
                  "elements": self.elements}
        return Report(content, fields, 0, None)

    def fields(self, z):
        """The result fields at design z, as a Report's: displacement (num_vertices x dim),
        youngs_modulus (per element), rest_positions and elements; for tailor.fields.to_meshio,
        write and plot."""
        return {"displacement": self.state(z), "youngs_modulus": self.youngs_modulus(z),
                "rest_positions": self.rest_positions, "elements": self.elements}

    def design_values(self, z):
        """E per design variable at z."""
        return self._f.design_values(z)

    def youngs_modulus(self, z):
        """E per element at z."""
        return self._f.youngs_modulus(z)


class RodFunctional(_FunctionalBase, _StaticProducts):
    """J(z) of a rod scene's inverse problem (docs/rods.md, "Inverse design scenes"), as
    `tailor run` and `tailor gradcheck` see it: value, gradient, Hessian-vector and (for the
    shape misfit, a least-squares objective) Gauss-Newton products, taylor_test().

    The state is the rods' vertex positions: state(z) gives their displacements from the drawn
    positions (rest_positions), one row per vertex of every rod in the scene's order
    (num_vertices x 3, float64), and vjp(z, dL_du) / jvp(z, dz) act on those rows through the
    same static adjoint and tangent solve. The edges' twist angles are part of the equilibrium
    but not of these rows: dL_du acts on positions only. The design is unbounded (bounds None).
    """

    bounds = None

    def __init__(self, scene):
        self._f = _RodFunctional(scene._doc)
        self._name, self._source = scene.name, scene.source


class MeshlessFunctional(_FunctionalBase, _StaticProducts):
    """J(z) of a meshless scene's inverse problem (docs/meshless.md, "Scenes"), as `tailor run`
    and `tailor gradcheck` see it: z is log E per region (the first variable the nodes outside
    every region) or per node, J the observations' misfit (plus the regularization); value,
    gradient, Hessian-vector and Gauss-Newton products, taylor_test(). The design is unbounded.

    The state is the MLS field's displacement at the nodes, u(X_b) = sum_a phi_a(X_b) (x_a - X_a),
    one row per node (num_nodes x 3, float64; rest_positions are the nodes). The DOFs x_a are
    coefficients, not values (MLS shape functions do not interpolate); vjp(z, dL_du) and jvp(z, dz)
    act on the values through that linear map. fields(z) adds the coefficients, the samples with
    their displacement and E per node.
    """

    bounds = None

    def __init__(self, scene):
        self._f = _MeshlessFunctional(scene._doc)
        self._name, self._source = scene.name, scene.source

    def fields(self, z):
        """The fields at the equilibrium of z, as simulate()'s (float64 copies): rest_positions,
        displacement and positions (num_nodes x 3, the field's values at the nodes),
        coefficient_displacement (x_a - X_a), youngs_modulus (per node), samples and
        sample_displacement (num_samples x 3)."""
        return self._f.fields(np.asarray(z, dtype=np.float64))

    def youngs_modulus(self, z):
        """E per node at z."""
        return self.fields(z)["youngs_modulus"]


class DynamicFunctional(_FunctionalBase):
    """J(z) of a dynamic scene's trajectory objective (dynamics.objective, docs/scenes.md), as
    `tailor gradcheck` tests it: the design is log E and log density per element and, with
    Rayleigh damping, alpha and beta (design_labels); J and dJ/dz come from the time-dependent
    adjoint over all the scene's steps.

    The state is the trajectory: state(z) is the displacement of every state n = 0 ... steps from
    the rest positions, shape (steps + 1, num_vertices, dim) (float64), and vjp(z, dL_dU) the design
    gradient of any scalar L of it, given dL/dU of the same shape, by one backward pass over the
    same trajectory; jvp(z, dz) is the trajectory's directional derivative, of the same shape, by
    one forward tangent pass through the steps (its exact transpose). There are no bounds.
    """

    bounds = None
    elements = property(lambda self: self._f.elements, doc="the mesh: num_elements x (dim + 1) vertex ids")

    def __init__(self, scene):
        self._f = _DynamicFunctional(scene._doc)
        self._name, self._source = scene.name, scene.source

    def jvp(self, z, dz):
        """(dU/dz) dz: the trajectory's directional derivative along dz, shape (steps + 1,
        num_vertices, dim), by one forward tangent pass through the steps (each step's Jacobian
        solved as the backward pass solves it). Refused (ValueError) for example-based damping."""
        return self._f.jvp(z, dz)

    def taylor_test(self, z=None, seed=None, min_rate=None):
        """Taylor test of J at z (default x0), as `tailor gradcheck` on the scene."""
        return self._f.taylor_test(z=z, seed=seed, min_rate=min_rate)


class CellFunctional(_FunctionalBase):
    """J(z) of a periodic cell's density design (a "periodic_cell" scene with a "design" section,
    docs/homogenization.md), as `tailor run` minimizes it: z is one density per element in
    [0, 1] (bounds), filtered, projected with the first projection stage's beta, SIMP moduli,
    J of the effective tensor C^H. x0 is the scene's initial design (its seed and perturbation).
    The volume constraint is separate: volume_fraction(z) gives (value, gradient) and
    max_volume_fraction its bound.

    The state is the cell's periodic fluctuations: state(z)[I] is the displacement u~_I of the
    cell's vertices under the unit macro strain I (Voigt order: 2D 11, 22, 12; 3D 11, 22, 33, 23,
    13, 12; engineering shear) beyond the affine part eps_I X, shape (voigt_size, num_vertices,
    dim) (float64). vjp(z, dL_du) takes dL/du~ of that shape (one adjoint back-solve per load case
    with one factorization), jvp(z, dz) returns it. stiffness(z) is C^H.
    """

    elements = property(lambda self: self._f.elements, doc="the mesh: num_elements x (dim + 1) vertex ids")
    bounds = property(lambda self: self._f.bounds, doc="(zeros, ones): densities in [0, 1]")
    optimizer = property(lambda self: self._f.optimizer, doc="the scene's design.optimizer section")
    max_volume_fraction = property(lambda self: self._f.max_volume_fraction,
                                   doc="the design's bound on volume_fraction(z)")

    def __init__(self, scene):
        self._f = _CellFunctional(scene._doc)
        self._name, self._source = scene.name, scene.source

    def jvp(self, z, dz):
        """(du~/dz) dz: the fluctuations' directional derivative along dz, in the shape of
        state(z), by one back-solve per load case."""
        return self._f.jvp(z, dz)

    def stiffness(self, z):
        """C^H at z: the effective elasticity tensor in Voigt notation (3 x 3 in 2D, 6 x 6 in 3D;
        in the units of the design material's Young's modulus)."""
        return self._f.stiffness(z)

    def youngs_modulus(self, z):
        """E per element at z (after filter, projection and SIMP)."""
        return self._f.youngs_modulus(z)

    def volume_fraction(self, z):
        """(volume fraction of the filtered density, its gradient in z)."""
        return self._f.volume_fraction(z)

    def taylor_test(self, z=None, seed=None, min_rate=None):
        """Taylor test of J at z (default x0); seed defaults to the design's."""
        return self._f.taylor_test(z=z, seed=seed, min_rate=min_rate)


def _per_element(name, value):
    """A per-element parameter as a float64 vector (None stays None); the values are checked
    against the mesh and their range by the bindings."""
    if value is None:
        return None
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as error:
        raise ValueError(f"{name}: expected one number per element, got {type(value).__name__} ({error})") \
            from None
    if array.ndim != 1:
        raise ValueError(f"{name}: expected a vector of one value per element, got an array of shape "
                         f"{array.shape}")
    return array


class _OutDir:
    """out_dir as given, or a temporary folder that is removed once the report is read."""

    def __init__(self, out_dir):
        self.temporary = out_dir is None
        self.path = tempfile.mkdtemp(prefix="tailor-") if self.temporary else os.fspath(out_dir)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        if self.temporary:
            shutil.rmtree(self.path, ignore_errors=True)

    def report(self, result, names=("report.json",)):
        exit_code, fields = result
        content = {}
        for name in names:
            path = os.path.join(self.path, name)
            if os.path.isfile(path):
                with open(path) as f:
                    content = json.load(f)
                break
        return Report(content, dict(fields), exit_code, None if self.temporary else self.path)


class Scene:
    """A scene document (docs/scenes.md). Make one with tailor.load."""

    def __init__(self, doc):
        self._doc = doc

    kind = property(lambda self: self._doc.kind, doc='"static", "dynamic", "rods", ...')
    source = property(lambda self: self._doc.source, doc="the name in messages: the file, or as given")
    name = property(lambda self: self._doc.name(), doc="the scene's name (default: the file's stem)")

    @property
    def document(self):
        """The scene as a dict (a copy)."""
        return json.loads(self._doc.text)

    def __repr__(self):
        return f"tailor.Scene({self.source!r}, kind={self.kind!r})"

    def simulate(self, out_dir=None, log=None, youngs_modulus=None, poisson_ratio=None):
        """`tailor simulate`: static equilibrium or time integration; the report as a Report.
        Static scenes' fields: displacement, positions, stresses, youngs_modulus, poisson_ratio,
        density, rest_positions, elements. Meshless scenes': rest_positions (the nodes),
        displacement and positions (the MLS field at the nodes), coefficient_displacement,
        youngs_modulus (per node), samples and sample_displacement. log: a file-like object for the solver's output (None: quiet).
        youngs_modulus, poisson_ratio: per-element values (float64 vectors of one entry per
        element; E > 0, nu in (-1, 0.5)) replacing the scene's for this solve (static scenes;
        a ValueError names the first bad entry)."""
        overrides = {name: _per_element(name, value) for name, value in
                     (("youngs_modulus", youngs_modulus), ("poisson_ratio", poisson_ratio))}
        with _OutDir(out_dir) as d:
            return d.report(self._doc.simulate(d.path, log=log, **overrides))

    def modes(self, count=10, out_dir=None, log=None):
        """`tailor modes`: the count lowest vibration modes. Fields: frequencies (Hz),
        eigenvalues, modes (num_dofs x count), rigid_modes. Meshless scenes: frequencies,
        eigenvalues, damping_ratios (Rayleigh), modes (3 nodes x count: each mode's MLS
        displacement at the nodes, interleaved), rest_positions (the nodes), samples,
        sample_modes (3 samples x count) and rigid_modes (how many were left out)."""
        with _OutDir(out_dir) as d:
            return d.report(self._doc.modes(d.path, count=count, log=log))

    def gradcheck(self, out_dir=None, seed=None, hessian=False, log=None):
        """`tailor gradcheck`: the Taylor test of the inverse problem's gradient (and Hessian);
        the content of gradcheck.json."""
        with _OutDir(out_dir) as d:
            return d.report(self._doc.gradcheck(d.path, seed=seed, hessian=hessian, log=log),
                            names=("gradcheck.json", "report.json"))

    def run(self, out_dir=None, log=None, progress=None, checkpoint_every=None, resume=None):
        """`tailor run`: minimizes the objective with the scene's back-end. Fields: design (z),
        design_values, youngs_modulus (per element), displacement, rest_positions, elements;
        fields["status"] is the optimizer's status ("interrupted" after Ctrl-C: the run stops
        and still reports). Meshless scenes: simulate()'s fields at the best design, design
        and status.
        progress: one line per iteration to log (default: when log is given)."""
        if progress is None:
            progress = log is not None
        with _OutDir(out_dir) as d:
            return d.report(self._doc.run(d.path, log=log, progress=progress,
                                          checkpoint_every=checkpoint_every, resume=resume))

    def homogenize(self, out_dir=None, log=None):
        """`tailor homogenize`: the effective elasticity of a periodic cell (docs/homogenization.md);
        the report as a Report, without fields."""
        with _OutDir(out_dir) as d:
            return d.report(self._doc.homogenize(d.path, log=log))

    def check(self, seed=1, log=None):
        """`tailor check`: derivative checks of every energy term; True when none failed."""
        return self._doc.check(seed=seed, log=log) == 0

    def functional(self):
        """The reduced functional of the scene's inverse problem: a Functional for static FEM
        scenes, a RodFunctional for rod scenes, a MeshlessFunctional for meshless scenes (each
        with an "inverse" section), a
        DynamicFunctional for dynamic scenes (of their dynamics.objective), a CellFunctional for
        periodic cells with a "design" section; other kinds are a SceneError naming the
        supported ones."""
        if self.kind == "static":
            return Functional(self)
        if self.kind == "rods":
            return RodFunctional(self)
        if self.kind == "dynamic":
            return DynamicFunctional(self)
        if self.kind == "cell_design":
            return CellFunctional(self)
        if self.kind == "meshless":
            return MeshlessFunctional(self)
        raise SceneError(f"{self.source}: functional() needs a static FEM, a rods or a meshless scene with an "
                         f"\"inverse\" section, a dynamic scene with a dynamics.objective, or a periodic cell with a "
                         f"\"design\" section; this is a {self.kind} scene (its designs run through run() and "
                         f"gradcheck(), docs/python.md)")


def load(scene, directory=None, name=None):
    """A scene from a file path or from a dict in the scene format.

    For a dict, name is what messages call it (default "(scene)") and directory the folder its
    relative paths (mesh files) start from (default: the current folder). Bad JSON is a
    SceneError (a ValueError) naming the file, line and column; bad keys are found when a verb
    builds the scene, as SceneErrors naming the key path.
    """
    if isinstance(scene, (str, os.PathLike)):
        if directory is not None or name is not None:
            raise TypeError("tailor.load: directory and name are for a scene given as a dict")
        return Scene(_Scene.from_file(os.fspath(scene)))
    if isinstance(scene, dict):
        text = json.dumps(scene, allow_nan=False)
        return Scene(_Scene.from_json(text, name or "(scene)",
                                      "" if directory is None else os.fspath(directory)))
    if isinstance(scene, Scene):
        return scene
    raise TypeError(f"tailor.load: expected a path or a dict, got {type(scene).__name__}")


def simulate(scene, **kwargs):
    """tailor.load(scene).simulate(**kwargs)"""
    return load(scene).simulate(**kwargs)


def modes(scene, **kwargs):
    """tailor.load(scene).modes(**kwargs)"""
    return load(scene).modes(**kwargs)


def gradcheck(scene, **kwargs):
    """tailor.load(scene).gradcheck(**kwargs)"""
    return load(scene).gradcheck(**kwargs)


def run(scene, **kwargs):
    """tailor.load(scene).run(**kwargs)"""
    return load(scene).run(**kwargs)


def homogenize(scene, **kwargs):
    """tailor.load(scene).homogenize(**kwargs)"""
    return load(scene).homogenize(**kwargs)

"""tailor.scipy_minimize: a reduced functional handed to scipy.optimize.minimize."""
from __future__ import annotations

import time

import numpy as np

# The methods of scipy.optimize.minimize that take bounds, and those that use Hessian-vector products.
_BOUNDED = {"l-bfgs-b", "tnc", "slsqp", "powell", "trust-constr", "nelder-mead", "cobyla"}
_HESSP = {"newton-cg", "trust-ncg", "trust-krylov", "trust-constr"}
# Those without bounds: scipy_minimize holds them to the scene's bounds by active-set rounds.
_NEWTON_WITHOUT_BOUNDS = {"newton-cg", "trust-ncg", "trust-krylov"}
# Methods whose options take a gradient tolerance named gtol (an infinity norm for L-BFGS-B, BFGS
# and CG, as tailor's; trust-constr and the trust-region methods use the 2-norm).
_GTOL = {"l-bfgs-b", "bfgs", "cg", "tnc", "trust-constr", "trust-ncg", "trust-krylov", "trust-exact"}


def scene_method(functional):
    """The scipy.optimize.minimize method closest to the scene's back-end (method="scene"):
    "trust-ncg" for newton_cg (a trust-region Newton-CG on curvature products, as tailor's
    Steihaug-Toint back-end) where the functional has the products it uses, "SLSQP" for a
    periodic cell's density design (bounds and the volume constraint, as nlopt_mma there),
    "L-BFGS-B" for the others."""
    if _volume_constrained(functional):
        return "SLSQP"
    newton = functional.optimizer["backend"] == "newton_cg" and scene_curvature(functional) is not None
    return "trust-ncg" if newton else "L-BFGS-B"


def _volume_constrained(functional):
    return hasattr(functional, "volume_fraction") and hasattr(functional, "max_volume_fraction")


def volume_constraint(functional):
    """A periodic cell design's volume constraint, volume_fraction(z) <= max_volume_fraction, as
    minimize's inequality constraint (fun >= 0) with its gradient."""
    return {"type": "ineq",
            "fun": lambda z: functional.max_volume_fraction - functional.volume_fraction(z)[0],
            "jac": lambda z: -functional.volume_fraction(z)[1]}


def scene_curvature(functional):
    """The curvature products the scene's newton_cg back-end uses, as a hessp function: the
    Gauss-Newton products where the objective is least squares (curvature "automatic" or
    "gauss_newton"), else the exact Hessian-vector products; None where it has neither."""
    curvature = functional.optimizer.get("curvature", "automatic")
    if functional.has_gauss_newton_vector and curvature in ("automatic", "gauss_newton"):
        return functional.gauss_newton_vector_product
    if functional.has_hessian_vector and curvature in ("automatic", "exact"):
        return functional.hessian_vector_product
    return None


def scene_options(functional, method, value0):
    """The scene's inverse.optimizer section as options of minimize's method: max_iterations as
    maxiter, gradient_tolerance as gtol, and for L-BFGS-B the objective tolerance as ftol. tailor's
    objective_tolerance is absolute and SciPy's ftol relative to max(|f|, 1), so ftol is
    objective_tolerance / max(|J(z0)|, 1) (0 when the scene has none: no objective test, as tailor)."""
    settings = functional.optimizer
    name = method.lower() if isinstance(method, str) else ""
    options = {"maxiter": settings["max_iterations"]}
    if name in _GTOL:
        options["gtol"] = settings["gradient_tolerance"]
    if name in ("l-bfgs-b", "slsqp"):
        options["ftol"] = settings["objective_tolerance"] / max(abs(value0), 1.0)
    if name == "l-bfgs-b":
        options["maxfun"] = 20 * settings["max_iterations"]
    return options


def _projected_gradient_norm(z, gradient, bounds):
    """Infinity norm of the gradient projected onto the box (tailor's convergence measure)."""
    if bounds is None:
        return float(np.max(np.abs(gradient), initial=0.0))
    lower, upper = np.asarray(bounds.lb, dtype=float), np.asarray(bounds.ub, dtype=float)
    projected = np.clip(z - gradient, lower, upper) - z
    return float(np.max(np.abs(projected), initial=0.0))


def _with_active_set(minimize, fun, z0, box, method, options, record, kwargs, max_rounds=20):
    """A method without bounds (trust-ncg) held to the box as newton_cg holds its steps: rounds
    of minimize over the free variables, the others fixed on the bound they press against (the
    gradient points out of the box). A round whose result leaves the box ends at the last point
    of the segment from its start to that result, projected onto the box, where the objective
    has not risen (halving), and the next round frees or fixes variables from there. Stops after
    a round that ends inside the box with the same variables pressed against their bounds as at
    its start, at a corner of the box, after max_rounds, or when the rounds together have made
    options["maxiter"] iterations."""
    import scipy.optimize

    lower, upper = np.asarray(box[0], dtype=float), np.asarray(box[1], dtype=float)
    z = np.clip(z0, lower, upper)
    hessp = kwargs.get("hessp")
    rest = {k: v for k, v in kwargs.items() if k != "hessp"}
    rounds, iterations, messages = 0, 0, []
    while True:
        rounds += 1
        value, gradient = fun(z)
        fixed = ((z <= lower) & (gradient > 0)) | ((z >= upper) & (gradient < 0))
        free = ~fixed
        if not free.any():  # every variable pressed against its bound: a corner of the box
            settled = True
            result = scipy.optimize.OptimizeResult(success=True, nit=0)
            messages.append("every variable on a bound")
            break

        def full(y, at=z, free=free):
            x = at.copy()
            x[free] = y
            return x

        def sub_fun(y):
            v, g = fun(full(y))
            return v, g[free]

        sub = dict(rest)
        if hessp is not None:
            def sub_hessp(y, p):
                direction = np.zeros_like(z)
                direction[free] = p
                return hessp(full(y), direction)[free]
            sub["hessp"] = sub_hessp
        round_options = dict(options)
        if "maxiter" in options:  # the iteration limit is the run's, not each round's
            round_options["maxiter"] = options["maxiter"] - iterations
        result = minimize(sub_fun, z[free], jac=True, method=method, options=round_options,
                          callback=lambda y, *args: record(full(y)), **sub)
        iterations += result.nit
        messages.append(result.message)
        end = full(result.x)
        inside = bool(np.all(end >= lower) and np.all(end <= upper))
        if not inside:  # back along the segment until the projection does not rise above J(z)
            t = 1.0
            while t > 1e-12:
                trial = np.clip(z + t * (end - z), lower, upper)
                if fun(trial)[0] <= value:
                    break
                t *= 0.5
            end = trial if t > 1e-12 else z
        z = end
        value, gradient = fun(z)
        pressed = ((z <= lower) & (gradient > 0)) | ((z >= upper) & (gradient < 0))
        settled = inside and np.array_equal(fixed, pressed)
        out_of_iterations = "maxiter" in options and iterations >= options["maxiter"]
        if settled or rounds == max_rounds or out_of_iterations or not np.isfinite(value):
            break
    on_bound = int(np.count_nonzero((z <= lower) | (z >= upper)))
    return scipy.optimize.OptimizeResult(
        x=z, fun=value, jac=gradient, nit=iterations, success=bool(result.success and settled),
        message=(f"{messages[-1]} ({method} on the free variables; {rounds} active-set round"
                 f"{'s' if rounds > 1 else ''}, {on_bound} variables on a bound)"))


def scipy_minimize(functional, x0=None, method="scene", bounds="scene", hessp="auto",
                   penalize_failures=True, settings="scene", callback=None, options=None, **kwargs):
    """Minimizes functional (a tailor.Functional) with scipy.optimize.minimize.

    x0 defaults to the scene's initial design.
    method: "scene" picks the method closest to the scene's back-end (scene_method: trust-ncg
    with the back-end's curvature products for newton_cg, L-BFGS-B otherwise), or any method
    name minimize takes.
    bounds: "scene" (the design's min and max, when it has them), None, or anything minimize
    takes. The methods that take bounds get them; Newton-CG, trust-ncg and trust-krylov, which
    do not, are held to them by active-set rounds (_with_active_set), as newton_cg is.
    hessp: "auto" hands curvature products to the methods that use them: with method="scene"
    the scene's (scene_curvature: Gauss-Newton products where newton_cg would use them), else
    the Hessian-vector products; "gauss_newton" or "exact" choose; or a function, or None.
    settings: "scene" takes the iteration limit and tolerances from the scene's
    inverse.optimizer section (scene_options); entries of options override them; None leaves
    SciPy's defaults.
    With penalize_failures, a point where the forward solve fails (tailor.EvaluationError) is
    worth +inf with a zero gradient, so that the line search steps back (as tailor's own
    back-ends do); otherwise the error propagates. callback(z) is called after every iteration.
    Other keyword arguments go to minimize (tol, ...). A periodic cell's density design
    (tailor.CellFunctional) gets its volume constraint (volume_constraint) unless constraints are
    given; a method that takes no constraints is refused for it (ValueError).

    Returns minimize's OptimizeResult with SciPy's own message and three more entries: history
    (per iteration: iteration, objective, gradient_norm (projected, infinity norm), seconds),
    tailor_converged (tailor's test: projected gradient norm <= the scene's gradient_tolerance)
    and tailor_message.
    """
    import scipy.optimize
    from . import EvaluationError

    z0 = np.array(functional.x0 if x0 is None else x0, dtype=float)
    if z0.shape != (functional.size,):
        raise ValueError(f"scipy_minimize: x0 has shape {z0.shape}, "
                         f"the design has {functional.size} entries")
    from_scene = isinstance(method, str) and method == "scene"
    if from_scene:
        method = scene_method(functional)
    name = method.lower() if isinstance(method, str) else ""
    if _volume_constrained(functional) and "constraints" not in kwargs:
        if name not in ("slsqp", "trust-constr", "cobyla"):
            raise ValueError(f"scipy_minimize: {method!r} takes no constraints, and this cell design has a volume "
                             f"constraint; use SLSQP, trust-constr or COBYLA, or pass constraints")
        kwargs["constraints"] = [volume_constraint(functional)]
    scene_bounds = None
    if isinstance(bounds, str) and bounds == "scene":
        scene_bounds = functional.bounds
        bounds = None
        if scene_bounds is not None and name in _BOUNDED:
            bounds = scipy.optimize.Bounds(scene_bounds[0], scene_bounds[1])
        if scene_bounds is not None:
            z0 = np.clip(z0, scene_bounds[0], scene_bounds[1])
    if isinstance(hessp, str):
        if hessp not in ("auto", "gauss_newton", "exact"):
            raise ValueError(f'scipy_minimize: hessp must be "auto", "gauss_newton", "exact", a function '
                             f'or None, got {hessp!r}')
        if name not in _HESSP:
            hessp = None
        elif hessp == "gauss_newton":
            hessp = functional.gauss_newton_vector_product
        elif hessp == "exact":
            hessp = functional.hessian_vector_product
        elif from_scene:
            hessp = scene_curvature(functional)
        else:
            hessp = functional.hessian_vector_product if functional.has_hessian_vector else None

    def fun(z):
        try:
            value, gradient = functional.value_and_gradient(z)
        except EvaluationError:
            if not penalize_failures:
                raise
            return np.inf, np.zeros_like(z)
        return value, gradient

    merged = {}
    if isinstance(settings, str) and settings == "scene":
        merged = scene_options(functional, method, fun(z0)[0])
    elif settings is not None:
        raise ValueError(f'scipy_minimize: settings must be "scene" or None, got {settings!r}')
    merged.update(options or {})

    # tailor's measure projects onto the bounds the result is held to.
    box = bounds if isinstance(bounds, scipy.optimize.Bounds) else None
    if box is None and name in _NEWTON_WITHOUT_BOUNDS and scene_bounds is not None:
        box = scipy.optimize.Bounds(scene_bounds[0], scene_bounds[1])
    start = time.perf_counter()
    history = []

    def record(z, *args):
        value, gradient = fun(z)
        history.append({"iteration": len(history) + 1, "objective": float(value),
                        "gradient_norm": _projected_gradient_norm(z, gradient, box),
                        "seconds": time.perf_counter() - start})
        if callback is not None:
            callback(z)

    if hessp is not None:
        kwargs["hessp"] = hessp
    if bounds is not None:
        kwargs["bounds"] = bounds
    if name in _NEWTON_WITHOUT_BOUNDS and bounds is None and scene_bounds is not None:
        result = _with_active_set(scipy.optimize.minimize, fun, z0, scene_bounds, method, merged, record, kwargs)
    else:
        result = scipy.optimize.minimize(fun, z0, jac=True, method=method, options=merged, callback=record,
                                         **kwargs)
    value, gradient = fun(result.x)
    norm = _projected_gradient_norm(result.x, gradient, box)
    tolerance = functional.optimizer["gradient_tolerance"]
    result.history = history
    result.tailor_converged = bool(norm <= tolerance)
    result.tailor_message = (f"projected gradient norm {norm:.3g} "
                             f"{'<=' if result.tailor_converged else '>'} gradient_tolerance {tolerance:.3g}")
    return result

"""tailor.scipy_minimize: a reduced functional handed to scipy.optimize.minimize."""
from __future__ import annotations

import time

import numpy as np

# The methods of scipy.optimize.minimize that take bounds, and those that use Hessian-vector products.
_BOUNDED = {"l-bfgs-b", "tnc", "slsqp", "powell", "trust-constr", "nelder-mead", "cobyla"}
_HESSP = {"newton-cg", "trust-ncg", "trust-krylov", "trust-constr"}
# Methods whose options take a gradient tolerance named gtol (an infinity norm for L-BFGS-B, BFGS
# and CG, as tailor's; trust-constr and the trust-region methods use the 2-norm).
_GTOL = {"l-bfgs-b", "bfgs", "cg", "tnc", "trust-constr", "trust-ncg", "trust-krylov", "trust-exact"}


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
    if name == "l-bfgs-b":
        options["ftol"] = settings["objective_tolerance"] / max(abs(value0), 1.0)
        options["maxfun"] = 20 * settings["max_iterations"]
    return options


def _projected_gradient_norm(z, gradient, bounds):
    """Infinity norm of the gradient projected onto the box (tailor's convergence measure)."""
    if bounds is None:
        return float(np.max(np.abs(gradient), initial=0.0))
    lower, upper = np.asarray(bounds.lb, dtype=float), np.asarray(bounds.ub, dtype=float)
    projected = np.clip(z - gradient, lower, upper) - z
    return float(np.max(np.abs(projected), initial=0.0))


def scipy_minimize(functional, x0=None, method="L-BFGS-B", bounds="scene", hessp="auto",
                   penalize_failures=True, settings="scene", callback=None, options=None, **kwargs):
    """Minimizes functional (a tailor.Functional) with scipy.optimize.minimize.

    x0 defaults to the scene's initial design. bounds: "scene" (the design's min and max, when
    it has them and the method takes bounds), None, or anything minimize takes. hessp: "auto"
    hands the Hessian-vector products to the methods that use them. settings: "scene" takes the
    iteration limit and tolerances from the scene's inverse.optimizer section (scene_options);
    entries of options override them; None leaves SciPy's defaults. With penalize_failures, a
    point where the forward solve fails (tailor.EvaluationError) is worth +inf with a zero
    gradient, so that the line search steps back (as tailor's own back-ends do); otherwise the
    error propagates. callback(z) is called after every iteration. Other keyword arguments go
    to minimize (tol, ...).

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
    name = method.lower() if isinstance(method, str) else ""
    if isinstance(bounds, str) and bounds == "scene":
        given = functional.bounds
        bounds = None
        if given is not None and name in _BOUNDED:
            bounds = scipy.optimize.Bounds(given[0], given[1])
            z0 = np.clip(z0, given[0], given[1])
    if isinstance(hessp, str) and hessp == "auto":
        hessp = (functional.hessian_vector_product
                 if functional.has_hessian_vector and name in _HESSP else None)

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

    box = bounds if isinstance(bounds, scipy.optimize.Bounds) else None
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

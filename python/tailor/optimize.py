"""tailor.scipy_minimize: a reduced functional handed to scipy.optimize.minimize."""
from __future__ import annotations

import numpy as np

# The methods of scipy.optimize.minimize that take bounds, and those that use Hessian-vector products.
_BOUNDED = {"l-bfgs-b", "tnc", "slsqp", "powell", "trust-constr", "nelder-mead", "cobyla"}
_HESSP = {"newton-cg", "trust-ncg", "trust-krylov", "trust-constr"}


def scipy_minimize(functional, x0=None, method="L-BFGS-B", bounds="scene", hessp="auto",
                   penalize_failures=True, **kwargs):
    """Minimizes functional (a tailor.Functional) with scipy.optimize.minimize.

    x0 defaults to the scene's initial design. bounds: "scene" (the design's min and max, when
    it has them and the method takes bounds), None, or anything minimize takes. hessp: "auto"
    hands the Hessian-vector products to the methods that use them. With penalize_failures, a
    point where the forward solve fails (tailor.EvaluationError) is worth +inf with a zero
    gradient, so that the line search steps back (as tailor's own back-ends do); otherwise the
    error propagates. Other keyword arguments go to minimize (tol, options, callback, ...).
    Returns minimize's OptimizeResult.
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

    if hessp is not None:
        kwargs["hessp"] = hessp
    if bounds is not None:
        kwargs["bounds"] = bounds
    return scipy.optimize.minimize(fun, z0, jac=True, method=method, **kwargs)

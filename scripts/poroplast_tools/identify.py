"""Identifiability at a fit's start point, from its first Jacobian: how much each parameter moves
the fitted curve, and which pairs move it alike.

J holds dr_i/d(ln θ_k) (the calibration's log parameters), so 0.1 J[:, k] is, to first order, the
change of the curve at the data points when θ_k grows by 10%. A parameter whose column is zero
(no data point moved by the finite-difference step) cannot be identified at all; two parameters
whose columns are nearly parallel (|cos| above 0.99: a change of one the other can undo) only in
combination. Some pairs have a known cause and remedy (`PAIRS`), added to their warning."""
import math

import numpy as np

NO_EFFECT = 1e-12      # a column this small relative to the largest counts as zero
COLLINEAR = 0.99       # |cos| between two columns above this: a near-collinear pair
# Near-collinear pairs with a known cause: {frozenset of the two keys (without @NAME): the hint}.
PAIRS = {
    frozenset({"surface.tension", "material.remodelling.sigma_y"}):
        "both hold up the force that is left after the relaxation, and at one compression in the same "
        "proportion; fit force curves at two compressions (e.g. 15% and 30%, --experiments) whose shares of "
        "the two differ (docs/howto-fit.md, \"Fitting the surface tension\")",
}


def hint(a, b):
    """The known cause and remedy of the near-collinear pair of keys a, b (with or without
    @NAME), or None."""
    return PAIRS.get(frozenset({a.split("@")[0], b.split("@")[0]}))


def report(jac, keys, scale, unit=""):
    """(lines of the sensitivity table, refusals, warnings) for the Jacobian `jac` (n × p) of
    the parameters `keys`; `scale` is the data's typical magnitude (e.g. their RMS), that the
    effect of a 10% change is compared with; `unit` the curve's (printed with the changes)."""
    jac = np.asarray(jac, dtype=float)
    n = jac.shape[0]
    norms = np.linalg.norm(jac, axis=0)
    top = float(norms.max()) if norms.size else 0.0
    lines = [f"sensitivity at the start point (RMS change of the curve over {n} data points for +10%):"]
    refusals, warnings = [], []
    for k, key in enumerate(keys):
        rms = 0.1 * float(norms[k]) / math.sqrt(n)
        rel = rms / scale if scale > 0 else math.nan
        lines.append(f"  {key}: {rms:.3g}{' ' + unit if unit else ''} ({100 * rel:.3g}% of the data's RMS)")
        if norms[k] <= NO_EFFECT * max(top, 1e-300):
            refusals.append(key)
    for a in range(len(keys)):
        for b in range(a + 1, len(keys)):
            if keys[a] in refusals or keys[b] in refusals:
                continue
            cos = float(jac[:, a] @ jac[:, b]) / (norms[a] * norms[b])
            if abs(cos) > COLLINEAR:
                why = hint(keys[a], keys[b])
                warnings.append(f"{keys[a]} and {keys[b]} move the curve alike (cos {cos:+.4f}): "
                                "the data determine a combination of them, and their errors are strongly correlated"
                                + (f": {why}" if why else ""))
    return lines, refusals, warnings

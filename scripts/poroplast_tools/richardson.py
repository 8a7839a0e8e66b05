"""Observed orders of convergence and Richardson extrapolation.

`solve_order` finds the order p of errors C h^p from three levels (the limit unknown) or from two
levels and a known limit; `correction` is the Richardson correction of the finest of two levels;
`extrapolate` combines a mesh sequence and a step sequence whose errors add, Q(h, s) = Q* +
E_h(h) + E_t(s): Richardson on the mesh sequence (at the step level S) gives A = Q* + E_t(S),
on the step sequence (on the mesh H) B = Q* + E_h(H), so Q* = A + B − Q(H, S). The error bar is
1.25 × the two corrections (Roache's grid convergence index with observed orders); where an
order is not observed (the differences do not shrink monotonically, or it falls outside
[0.5, 4]) the formal order is used, the safety factor is 3 and the bar is at least the spread
of the two finest levels.
"""
import math


def solve_order(q, r, limit=None):
    """Observed order of convergence of the values q (coarse → fine) on levels with ratios r
    (h_i / h_{i+1}), errors C h^p assumed. Without `limit`: from three values (Richardson: the
    limit unknown), NaN if the differences do not shrink monotonically. With the limit known
    (an exact solution): from the last two values' errors against it."""
    if limit is not None:
        e0, e1 = abs(q[-2] - limit), abs(q[-1] - limit)
        return math.log(e0 / e1) / math.log(r[-1]) if e0 > 0 and e1 > 0 else float("nan")
    d1, d2 = q[0] - q[1], q[1] - q[2]
    if d1 == 0 or d2 == 0 or d1 * d2 < 0 or abs(d2) >= abs(d1) * 1.0:
        return float("nan")
    # (r1^p − 1) r2^p / (r2^p − 1) = d1/d2 (constant C h^p errors); bisection in p.
    f = lambda p: (r[0] ** p - 1) * r[1] ** p / (r[1] ** p - 1) - abs(d1 / d2)
    lo, hi = 0.05, 8.0
    if f(lo) > 0 or f(hi) < 0:
        return float("nan")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if f(mid) < 0 else (lo, mid)
    return 0.5 * (lo + hi)


def correction(q_coarse, q_fine, ratio, p):
    """The Richardson correction to add to q_fine (levels `ratio` apart, order p; NaN without p)."""
    if math.isnan(p):
        return float("nan")
    return (q_fine - q_coarse) / (ratio ** p - 1)


def extrapolate(qh, qt, q_junction, hs, ss, formal_h, formal_t):
    """Richardson on the mesh sequence qh (levels hs, at the step level S) and the step sequence qt
    (levels ss, on the mesh H), with q_junction = Q(H, S): Q*, its error bar, the observed orders
    and which orders were used (see the module docs)."""
    p_h = solve_order(qh[-3:], (hs[-3] / hs[-2], hs[-2] / hs[-1]))
    p_t = solve_order(qt[-3:], (ss[-3] / ss[-2], ss[-2] / ss[-1]))
    ok = lambda p: 0.5 <= p <= 4.0  # NaN is not
    use_h, use_t = (p_h if ok(p_h) else formal_h), (p_t if ok(p_t) else formal_t)
    c_h = correction(qh[-2], qh[-1], hs[-2] / hs[-1], use_h)
    c_t = correction(qt[-2], qt[-1], ss[-2] / ss[-1], use_t)
    extrap = (qh[-1] + c_h) + (qt[-1] + c_t) - q_junction
    fs_h, fs_t = (1.25 if ok(p_h) else 3.0), (1.25 if ok(p_t) else 3.0)
    bar = fs_h * abs(c_h) + fs_t * abs(c_t)
    if not ok(p_h):
        bar = max(bar, abs(qh[-1] - qh[-2]))
    if not ok(p_t):
        bar = max(bar, abs(qt[-1] - qt[-2]))
    return {"extrapolated": extrap, "error_bar": bar, "p_h": p_h, "p_t": p_t,
            "order_h": "observed" if ok(p_h) else "formal", "order_t": "observed" if ok(p_t) else "formal",
            "finest": qh[-1]}


def converge(values, hs, ss, H, S, formal_h=2.0, formal_t=1.0):
    """Extrapolates one observable from {(h, s): value} (NaN for a failed case) of a cross: the
    mesh levels hs at the step level S, the step levels ss on the mesh H."""
    q = lambda h, s: values.get((h, s), float("nan"))
    return extrapolate([q(h, S) for h in hs], [q(H, s) for s in ss], q(H, S), hs, ss, formal_h, formal_t)
